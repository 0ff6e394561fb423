#!/usr/bin/python3
"""How much a run's Corvis readings move across the plausible range of the
definitions the device does not publish.

The Corvis ST's software names its parameters but does not publish the
rules behind several of them (docs/physics.md section 9, "Definitions and
their sources"): the applanation length's flatness tolerance, the window of
the highest-concavity radius's fit, where the whole-eye movement is read,
and the time zero of its clock. This script recomputes those readings from
a run's frames (RUN/profiles.csv, RUN/frames.csv), independently of
cpp/biomarkers, at nct's defaults (a cross-check of the run's summary.json)
and across each definition's plausible range, and prints Markdown tables.

- Applanation: A1 (A2) where the apex curvature b of y = a + b x^2 over
  |x| <= 1 mm turns positive (negative) before (after) HC; the length is
  the flat segment about the axis within `flatness` of the apex height.
- HC radius: the circle fitted (least squares) to the profile between its
  two highest points at HC, the whole concavity (nct's default,
  `puff.radius_rule = "concavity"`); or 1 / (2 b) of the same parabola fit
  over |x| <= `window`; or the circle through the apex and the two peaks.
- Integrated radius: the inverse concave radius summed from A1 to A2 with
  time in frames (trapezoids, 0 at A1 and A2), in 1/mm as the device.
- DA ratio: the apex's deformation over the mean deformation at x = +-d in
  fixed image columns, its largest from A1 to A2 (nct), at HC, or over
  every frame whose flanks moved by more than 0.02 mm.
- Whole-eye movement: the axial displacement of the anterior profile in the
  fixed image column x = +-d (mean of both sides), as a camera sees it;
  the deflection amplitude is the deformation amplitude less it at HC.
- Time zero: the device's clock starts an unknown time before the pulse's
  onset (nct's zero); the offset that puts each of A1, HC and A2 on the
  normal eyes' mean is printed (an offset of the clock moves all three
  alike; the intervals do not depend on it).

Usage: cases/clinic/definition-sensitivity.py RUN [--check]
(--check: exit 1 unless every recomputed reading agrees with summary.json
to 1e-6 mm or ms, relative 1e-5.)
"""
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "python"))
from nct.clinic import NORMAL_TIMES  # noqa: E402
from nct.folders import Run  # noqa: E402


FLATNESS = 0.014  # mm: nct's default puff.flatness, one pixel of the 8 mm, 576-pixel image


def read_profiles(run):
    """The frames' times and anterior profiles (x, y), sorted by x."""
    p = run.profiles
    return p.t_ms, [p.curve(k, "anterior") for k in range(len(p))]


def height(p, x):
    return float(np.interp(x, p[0], p[1]))


def curvature(p, half_width):
    """b of the least-squares y = a + b x^2 over |x| <= half_width."""
    x, y = p
    m = np.abs(x) <= half_width
    return float(np.polyfit(x[m] ** 2, y[m], 1)[0])


def at(t, profiles, time):
    """The profile at `time`, each sample linear between the frames."""
    i = min(max(int(np.searchsorted(t, time)) - 1, 0), len(t) - 2)
    s = (time - t[i]) / (t[i + 1] - t[i])
    (x0, y0), (x1, y1) = profiles[i], profiles[i + 1]
    return ((1 - s) * x0 + s * x1, (1 - s) * y0 + s * y1)


def concavity_radius(p, depth=None):
    """The least-squares circle through the samples between the two highest
    points (each refined by a parabola through its neighbours), or None
    unless the apex lies more than `depth` (the flatness) below both."""
    depth = FLATNESS if depth is None else depth
    x, y = p
    peaks = []
    for side in (1, -1):
        idx = np.where(side * x > 0)[0]
        i = idx[np.argmax(y[idx])]
        if 0 < i < len(x) - 1:
            a, b, _ = np.polyfit(x[i - 1:i + 2], y[i - 1:i + 2], 2)
            peaks.append(min(max(-b / (2 * a), x[i - 1]), x[i + 1]) if a != 0 else x[i])
        else:
            peaks.append(x[i])
    right, left = peaks
    y0 = height(p, 0.0)
    if y0 + depth >= min(height(p, right), height(p, left)):
        return None
    m = (x >= left) & (x <= right)
    if m.sum() < 5:
        return None
    A = np.c_[2 * x[m], 2 * (y[m] - y0), np.ones(m.sum())]
    a, b, c = np.linalg.lstsq(A, x[m] ** 2 + (y[m] - y0) ** 2, rcond=None)[0]
    return float(np.sqrt(c + a * a + b * b)) if b > 0 else None


def three_point_radius(p):
    """The circle through the apex and the two highest points, or None
    unless the apex lies more than the flatness below them."""
    x, y = p
    r, l = (np.where(x > 0)[0], np.where(x < 0)[0])
    ir, il = r[np.argmax(y[r])], l[np.argmax(y[l])]
    c, sag = 0.5 * (x[ir] - x[il]), 0.5 * (y[ir] + y[il]) - height(p, 0.0)
    return (c * c + sag * sag) / (2 * sag) if sag > FLATNESS else None


def parabola_radius(p, window):
    b = curvature(p, window)
    return 1 / (2 * b) if b > 0 else None


def integrated(t, profiles, a1, a2, radius, dt):
    """The inverse radius summed from A1 to A2, time in frames."""
    inv = [1 / r if r else 0.0 for r in (radius(q) for q in profiles)]
    inside = [(ti, fi) for ti, fi in zip(t, inv) if a1 < ti < a2]
    pts = [(a1, 0.0)] + inside + [(a2, 0.0)]
    area = sum(0.5 * (f0 + f1) * (t1 - t0) for (t0, f0), (t1, f1) in zip(pts, pts[1:]))
    return area / dt, max(inv)


def flat_length(p, tolerance):
    x, y = p
    y0 = height(p, 0.0)
    ends = []
    for side in (1, -1):
        idx = np.where(side * x > 0)[0]
        idx = idx[np.argsort(side * x[idx])]
        inner_x, inner_dy, end = 0.0, 0.0, None
        for i in idx:
            dy = abs(y[i] - y0)
            if dy > tolerance:
                end = inner_x + (x[i] - inner_x) * (tolerance - inner_dy) / (dy - inner_dy)
                break
            inner_x, inner_dy = x[i], dy
        ends.append(inner_x if end is None else end)
    return ends[0] - ends[1]


def crossing(t, f, upward, before=None, after=None):
    for i in range(len(t) - 1):
        ok = f[i] < 0 <= f[i + 1] if upward else f[i] > 0 >= f[i + 1]
        if ok:
            time = t[i] + (t[i + 1] - t[i]) * f[i] / (f[i] - f[i + 1])
            if (before is None or time <= before) and (after is None or time >= after):
                return time
    return None


def main():
    run = sys.argv[1]
    summary = Run(run).summary
    t, profiles = read_profiles(Run(run))
    rest = profiles[0]
    apex = np.array([height(p, 0.0) - height(rest, 0.0) for p in profiles])
    hc_i = int(np.argmin(apex))
    # HC refined by a parabola through the deepest frame and its neighbours.
    i = min(max(hc_i, 1), len(t) - 2)
    a, b, c = np.polyfit(t[i - 1:i + 2], apex[i - 1:i + 2], 2)
    hc = -b / (2 * a)
    deformation = -(c - b * b / (4 * a))
    b_apex = np.array([curvature(p, 1.0) for p in profiles])
    a1 = crossing(t, b_apex, True, before=hc)
    a2 = crossing(t, b_apex, False, after=hc)

    print(f"# Definitions: {run}\n")
    print("nct's defaults recomputed from the frames, against summary.json:\n")
    print("| reading | recomputed | summary.json |")
    print("|---|---|---|")
    rows = [("HC time [ms]", hc, summary.get("hc_time_ms")),
            ("deformation amplitude [mm]", deformation, summary.get("deformation_amplitude_mm")),
            ("A1 time [ms]", a1, summary.get("a1_time_ms")),
            ("A2 time [ms]", a2, summary.get("a2_time_ms")),
            ("A1 length [mm]", flat_length(at(t, profiles, a1), FLATNESS) if a1 else None,
             summary.get("a1_length_mm")),
            ("A2 length [mm]", flat_length(at(t, profiles, a2), FLATNESS) if a2 else None,
             summary.get("a2_length_mm"))]
    rows.append(("HC radius [mm]", concavity_radius(at(t, profiles, hc)),
                 summary.get("hc_radius_mm")))
    dt = float(t[1] - t[0])
    if a1 and a2:
        ir, max_inv = integrated(t, profiles, a1, a2, concavity_radius, dt)
        rows += [("integrated radius [1/mm]", ir, summary.get("integrated_radius_per_mm")),
                 ("max inverse radius [1/mm]", max_inv, summary.get("max_inverse_radius_per_mm"))]
    disagree = []
    for name, mine, theirs in rows:
        f = (lambda v: "-" if v is None else f"{v:.4f}")
        print(f"| {name} | {f(mine)} | {f(theirs)} |")
        if (mine is None) != (theirs is None) or (
                mine is not None and abs(mine - theirs) > 1e-6 + 1e-5 * abs(theirs)):
            disagree.append(name)

    if a1 and a2:
        print("\nApplanation length against the flatness tolerance:\n")
        print("| flatness [mm] | A1 length [mm] | A2 length [mm] |")
        print("|---|---|---|")
        for tol in (0.005, 0.01, FLATNESS, 0.02, 0.03, 0.05):
            print(f"| {tol} | {flat_length(at(t, profiles, a1), tol):.3f} | "
                  f"{flat_length(at(t, profiles, a2), tol):.3f} |")

    print("\nThe concave radius against its rule: at HC, and each frame's inverse "
          "radius summed from A1 to A2 (time in frames) and its largest:\n")
    print("| rule | HC radius [mm] | integrated radius [1/mm] | max inverse radius [1/mm] |")
    print("|---|---|---|---|")
    rules = [("circle over the concavity (nct)", concavity_radius),
             ("circle through the apex and the peaks", three_point_radius)]
    rules += [(f"parabola over +-{w} mm", (lambda q, w=w: parabola_radius(q, w)))
              for w in (1.0, 1.5, 2.0, 2.5, 3.0)]
    f = (lambda v: "-" if v is None else f"{v:.3f}")
    for name, rule in rules:
        ir = integrated(t, profiles, a1, a2, rule, dt) if a1 and a2 else (None, None)
        print(f"| {name} | {f(rule(at(t, profiles, hc)))} | {f(ir[0])} | {f(ir[1])} |")

    print("\nThe DA ratio against its time window (deformations in fixed image columns "
          "from the first frame):\n")
    print("| window | DA ratio 1 mm | DA ratio 2 mm |")
    print("|---|---|---|")

    def ratios(keep):
        out = []
        for d in (1.0, 2.0):
            best = None
            for ti, q in zip(t, profiles):
                flank = 0.5 * (height(rest, d) + height(rest, -d) - height(q, d) - height(q, -d))
                if keep(ti, flank) and flank > 0:
                    r = (height(rest, 0.0) - height(q, 0.0)) / flank
                    best = r if best is None else max(best, r)
            out.append(best)
        return out
    windows = [("A1 to A2 (nct)", lambda ti, fl: a1 is not None and a1 <= ti <= a2),
               ("the frame nearest HC", lambda ti, fl: abs(ti - t[hc_i]) < 1e-9),
               ("every frame, flanks moved > 0.02 mm", lambda ti, fl: fl > 0.02)]
    for name, keep in windows:
        r1, r2 = ratios(keep)
        print(f"| {name} | {f(r1)} | {f(r2)} |")

    print("\nWhole-eye movement read in the image columns x = +-d:\n")
    print("| d [mm] | movement at HC [mm, + outwards] | largest inward [mm] | at [ms] | "
          "deflection amplitude [mm] |")
    print("|---|---|---|---|---|")
    for d in (3.0, 3.5, 4.0, 4.5):
        w = np.array([0.5 * (height(p, d) + height(p, -d) - height(rest, d) - height(rest, -d))
                      for p in profiles])
        w_hc = float(np.interp(hc, t, w))
        k = int(np.argmin(w))
        print(f"| {d} | {w_hc:+.4f} | {-w[k]:.4f} | {t[k]:.2f} | {deformation + w_hc:.4f} |")

    print("\nTime zero: the device-clock offset that puts each time on the normal eyes' "
          "mean:\n")
    print("| time | run [ms] | normal mean [ms] | offset [ms] |")
    print("|---|---|---|---|")
    for name, v in (("A1", a1), ("HC", hc), ("A2", a2)):
        if v is not None:
            print(f"| {name} | {v:.2f} | {NORMAL_TIMES[name]} | {NORMAL_TIMES[name] - v:+.2f} |")
    if "--check" in sys.argv:
        if disagree:
            sys.exit("recomputed readings disagree with summary.json: " + ", ".join(disagree))
        print("\nevery recomputed reading agrees with summary.json")


if __name__ == "__main__":
    main()
