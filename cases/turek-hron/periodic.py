#!/usr/bin/python3
"""The periodic state of a Turek-Hron FSI2 or FSI3 run against the
published values (Turek & Hron 2006, tables 12 and 13; for FSI3 also the
later Featflow table, "fsi3-featflow": level 4, dt 0.00025 s).

Usage: cases/turek-hron/periodic.py RUN_DIR [--case fsi3] [--from T_MS]
       [--depth MM] [--plot OUT.png] [--check]

--depth: the run's thickness [mm] its forces are for (10 for the 3D slab
of meshes/turek-hron.geo, 1 for a plane section). --check: exit 1 unless
every amplitude and every mean is within 5 % and every frequency within
2 % of the reference; a mean near zero against the amplitude (u_y and
lift, whose published means are 1-2 % of their amplitudes and uncertain
by as much), the others against the mean itself.

From the tip's displacement (summary.json's steps, probe 0) and the force
on the cylinder plus the flag (forces.csv) after --from (default: the
last 40 % of the run), as the benchmark defines them: mean = (max + min) / 2,
amplitude = (max - min) / 2 over the window, the frequency from the mean
upward crossings (linearly interpolated) averaged over the window.
"""
import argparse
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "python"))
from nct.folders import Run  # noqa: E402

PUBLISHED = {  # mean, amplitude, frequency [Hz]; mm and N/m
    "fsi2": {"u_x": (-14.58, 12.44, 3.8), "u_y": (1.23, 80.6, 2.0),
             "drag": (208.83, 73.75, 3.8), "lift": (0.88, 234.2, 2.0)},
    "fsi3": {"u_x": (-2.69, 2.53, 10.9), "u_y": (1.48, 34.38, 5.3),
             "drag": (457.3, 22.66, 10.9), "lift": (2.22, 149.78, 5.3)},
    "fsi3-featflow": {"u_x": (-2.88, 2.72, 10.93), "u_y": (1.47, 34.99, 5.46),
                      "drag": (460.5, 27.74, 10.93), "lift": (2.50, 153.91, 5.46)},
}
# Whose mean is checked against the amplitude (near zero).
CENTRED = {"u_y", "lift"}


def periodic(t, y):
    mean = 0.5 * (y.max() + y.min())
    amplitude = 0.5 * (y.max() - y.min())
    s = y - mean
    up = [t[i] - s[i] * (t[i + 1] - t[i]) / (s[i + 1] - s[i])
          for i in range(len(s) - 1) if s[i] < 0 <= s[i + 1]]
    frequency = (len(up) - 1) / (up[-1] - up[0]) * 1e3 if len(up) > 1 else float("nan")
    return mean, amplitude, frequency, len(up) - 1


def signals(run, depth):
    """The tip's displacement (summary.json's steps, probe 0) and the
    force per unit depth [N/m] on cylinder and flag (forces.csv)."""
    steps = run.summary["steps"]
    t = np.array([s["time"] for s in steps])
    tip = np.array([s["probe_0_displacement_mm"] for s in steps])
    f = run.forces
    return {"u_x": (t, tip[:, 0]), "u_y": (t, tip[:, 1]),
            "drag": (f["t_ms"], f["fx_N"] / depth * 1e3),
            "lift": (f["t_ms"], f["fy_N"] / depth * 1e3)}


def analyse(run, case="fsi3", start=None, depth=10.0):
    """(the window's start, a Markdown table against the published values,
    the quantities outside the tolerances)."""
    data = signals(run if isinstance(run, Run) else Run(run), depth)
    t = data["u_x"][0]
    start = start if start is not None else t[0] + 0.6 * (t[-1] - t[0])
    lines = ["| quantity | mean | amplitude | frequency [Hz] | periods | published mean +- "
             "amplitude [Hz] | error of mean | error of amplitude | error of frequency |",
             "|---|---|---|---|---|---|---|---|---|"]
    failed = []
    for name, (ts, y) in data.items():
        w = ts >= start
        m, amp, f, n = periodic(ts[w], y[w])
        pm, pa, pf = PUBLISHED[case][name]
        em = (m - pm) / (pa if name in CENTRED else abs(pm))
        ea, ef = (amp - pa) / pa, (f - pf) / pf
        lines.append(f"| {name} | {m:.3f} | {amp:.3f} | {f:.2f} | {n} | {pm} +- {pa} [{pf}] | "
                     f"{100 * em:+.1f} %{' of the amplitude' if name in CENTRED else ''} | "
                     f"{100 * ea:+.1f} % | {100 * ef:+.1f} % |")
        failed += [f"{name} {what}" for what, e, tol in
                   (("mean", em, 0.05), ("amplitude", ea, 0.05), ("frequency", ef, 0.02))
                   if not abs(e) <= tol]
    return start, "\n".join(lines), failed


def plot(run, case, start, depth, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 2, figsize=(10, 6), sharex=True)
    for k, (name, (ts, y)) in enumerate(signals(Run(run), depth).items()):
        axk = ax[k // 2][k % 2]
        axk.plot(ts / 1e3, y, lw=0.8)
        axk.axvline(start / 1e3, color="gray", ls=":")
        axk.set_ylabel(name + (" [mm]" if name.startswith("u") else " [N/m]"))
        axk.grid(alpha=0.3)
    for axk in ax[1]:
        axk.set_xlabel("t [s]")
    fig.suptitle(f"Turek-Hron {case.upper()}: the tip A and the force on cylinder + flag")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("run")
    p.add_argument("--case", default="fsi3", choices=sorted(PUBLISHED))
    p.add_argument("--from", dest="start", type=float, default=None)
    p.add_argument("--depth", type=float, default=10.0)
    p.add_argument("--plot", default=None)
    p.add_argument("--check", action="store_true")
    a = p.parse_args()
    start, table, failed = analyse(a.run, a.case, a.start, a.depth)
    t = Run(a.run).summary["steps"][-1]["time"]
    print(f"{a.run}: {a.case.upper()} over t >= {start:.0f} ms (to {t:.0f} ms)")
    print(table)
    if a.plot:
        plot(a.run, a.case, start, a.depth, a.plot)
    if a.check and failed:
        print("outside the tolerances: " + ", ".join(failed))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
