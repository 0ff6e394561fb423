#!/usr/bin/python3
"""What the coupling changes: the same eye under the assumed Gaussian
pressure, the one-way table (the rigid-eye air's pressure) and the
two-way coupled air.

Usage: scripts/compare-puffs.py GAUSSIAN_RUN ONE_WAY_RUN TWO_WAY_RUN OUT_DIR

Prints a markdown table of the biomarkers (deflection and deformation
amplitude, peak distance, A1/HC/A2 times and lengths, IOP maximum, apex
air pressure at HC and its maximum, the air's axial force on the eye at
HC where the run has it) and of the air pressure on the anterior cornea
at A1, HC and A2 of each run (the one-way's from its table at the
reference radius, the two-way's at the current radius). Writes
OUT_DIR/apex_pressure.png (the apex air pressure over time, the three
runs) and OUT_DIR/corneal_pressure.png (the profiles at A1, HC, A2).
"""
import csv
import json
import math
import os
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MMHG = 1.333224e-4  # MPa

BIOMARKERS = [
    ("deflection_amplitude_mm", "deflection amplitude [mm]", "%.3f"),
    ("deformation_amplitude_mm", "deformation amplitude [mm]", "%.3f"),
    ("peak_distance_mm", "peak distance [mm]", "%.2f"),
    ("a1_time_ms", "A1 time [ms]", "%.2f"),
    ("hc_time_ms", "HC time [ms]", "%.2f"),
    ("a2_time_ms", "A2 time [ms]", "%.2f"),
    ("a1_length_mm", "A1 length [mm]", "%.2f"),
    ("a2_length_mm", "A2 length [mm]", "%.2f"),
    ("iop_max_mmHg", "IOP max [mmHg]", "%.1f"),
    ("apex_pressure_hc_mmHg", "apex air pressure at HC [mmHg]", "%.1f"),
    ("apex_pressure_max_mmHg", "apex air pressure max [mmHg]", "%.1f"),
]


def columns(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def table(path):
    """A t_ms,r_mm,p_mmHg file as {t: [(r, p)...]}, sorted by r."""
    out = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            out.setdefault(float(row["t_ms"]), []).append((float(row["r_mm"]),
                                                          float(row["p_mmHg"])))
    return {t: sorted(v) for t, v in out.items()}


def at(times, values, t):
    """Linear in time."""
    for i in range(1, len(times)):
        if times[i] >= t:
            s = (t - times[i - 1]) / (times[i] - times[i - 1])
            return (1 - s) * values[i - 1] + s * values[i]
    return values[-1]


def profile(run, summary, t):
    """The air pressure on the cornea as [(r, p)] at time t of a run."""
    with open(os.path.join(run, "scene.toml"), "rb") as f:
        puff = tomllib.load(f)["puff"]
    if os.path.exists(os.path.join(run, "corneal_pressure.csv")):
        p = table(os.path.join(run, "corneal_pressure.csv"))
    elif puff["load"] == "table":
        p = table(os.path.join(os.path.dirname(summary["scene"]), puff["table"]))
    else:  # the gaussian: peak exp(-(t - t0)^2 / 2 wt^2) exp(-r^2 / 2 wr^2)
        g = puff["peak"] * math.exp(-(t - puff["peak_time"]) ** 2 / (2 * puff["width_t"] ** 2))
        return [(r, g * math.exp(-r * r / (2 * puff["width_r"] ** 2)))
                for r in (0.1 * k for k in range(59))]
    return p[min(p, key=lambda x: abs(x - t))]


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    runs = sys.argv[1:4]
    out = sys.argv[4]
    os.makedirs(out, exist_ok=True)
    names = ["Gaussian (assumed)", "one-way (rigid-eye table)", "two-way (coupled)"]
    summaries = [json.load(open(os.path.join(r, "summary.json"))) for r in runs]
    frames = [columns(os.path.join(r, "frames.csv")) for r in runs]

    print("| biomarker | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    for key, label, fmt in BIOMARKERS:
        print("| %s | " % label + " | ".join(
            fmt % s[key] if key in s else "-" for s in summaries) + " |")
    # The pressure's axial force at HC, whole eye: integral of p 2 pi r dr
    # over the profile (the projected area; the one-way's r is the
    # reference radius, the two-way's the current one).
    forces = []
    for run, s in zip(runs, summaries):
        pr = profile(run, s, s["hc_time_ms"])
        f = sum(0.5 * (p0 + p1) * math.pi * (r1 * r1 - r0 * r0)
                for (r0, p0), (r1, p1) in zip(pr, pr[1:]))
        forces.append("%.4f N" % (f * MMHG))
    print("| air pressure's axial force on the cornea at HC (whole eye) | " + " | ".join(forces)
          + " |")
    print("| the air's force on the eye at HC (the coupled reaction) | " + " | ".join(
        "%.4f N" % at(f["t_ms"], f["air_force_N"], s["hc_time_ms"]) if "air_force_N" in f
        else "-" for s, f in zip(summaries, frames)) + " |")

    print("\nAir pressure on the anterior cornea [mmHg] at r [mm] (two-way: the current radius)")
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2), sharey=True)
    for k, event in enumerate(("a1", "hc", "a2")):
        print("\nAt %s (%s ms):\n" % (event.upper(), " / ".join(
            "%.2f" % s.get(event + "_time_ms", float("nan")) for s in summaries)))
        print("| r [mm] | " + " | ".join(names) + " |")
        print("|---|" + "---|" * len(names))
        profiles = []
        for run, s in zip(runs, summaries):
            profiles.append(profile(run, s, s.get(event + "_time_ms", s["hc_time_ms"])))
        for r in (0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0):
            row = []
            for pr in profiles:
                rs = [x[0] for x in pr]
                ps = [x[1] for x in pr]
                row.append("%.1f" % at(rs, ps, r) if rs[-1] >= r else "-")
            print("| %.1f | " % r + " | ".join(row) + " |")
        for name, pr, s in zip(names, profiles, summaries):
            ax[k].plot([x[0] for x in pr], [x[1] for x in pr],
                       label="%s, t = %.2f ms" % (name, s.get(event + "_time_ms", s["hc_time_ms"])))
        ax[k].set_title(event.upper())
        ax[k].set_xlabel("distance from the axis r [mm]")
        ax[k].axhline(0, color="grey", lw=0.5)
        ax[k].legend(fontsize=7)
    ax[0].set_ylabel("air pressure on the cornea [mmHg]")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "corneal_pressure.png"), dpi=120)

    fig, ax = plt.subplots(figsize=(7, 4.2))
    for name, f in zip(names, frames):
        ax.plot(f["t_ms"], f["apex_air_pressure_mmHg"], label=name)
    ax.set_xlabel("time from the start of the puff [ms]")
    ax.set_ylabel("air pressure at the corneal apex [mmHg]")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "apex_pressure.png"), dpi=120)
    print("\nwrote %s/apex_pressure.png, %s/corneal_pressure.png" % (out, out))


main()
