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
- HC radius: 1 / (2 b) of the same fit over |x| <= `window` at HC.
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
            ("A1 length [mm]", flat_length(at(t, profiles, a1), 0.02) if a1 else None,
             summary.get("a1_length_mm")),
            ("A2 length [mm]", flat_length(at(t, profiles, a2), 0.02) if a2 else None,
             summary.get("a2_length_mm"))]
    b_hc = curvature(at(t, profiles, hc), 1.5)
    rows.append(("HC radius [mm]", 1 / (2 * b_hc) if b_hc > 0 else None,
                 summary.get("hc_radius_mm")))
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
        for tol in (0.005, 0.01, 0.02, 0.03, 0.05):
            print(f"| {tol} | {flat_length(at(t, profiles, a1), tol):.3f} | "
                  f"{flat_length(at(t, profiles, a2), tol):.3f} |")

    print("\nHC radius against the fit's half-width:\n")
    print("| half-width [mm] | HC radius [mm] |")
    print("|---|---|")
    for w in (1.0, 1.5, 2.0, 2.5, 3.0):
        b = curvature(at(t, profiles, hc), w)
        print(f"| {w} | {'-' if b <= 0 else f'{1 / (2 * b):.3f}'} |")

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
