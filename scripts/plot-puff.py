#!/usr/bin/python3
"""Plots of a puff run: apex displacement, IOP and apex air pressure against
time, and the corneal profiles at A1, HC and A2.

Usage: scripts/plot-puff.py RUN_DIR   (writes RUN_DIR/puff.png and
RUN_DIR/profiles.png from frames.csv, profiles.csv and summary.json)
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def columns(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def nearest_frame(times, t):
    return min(range(len(times)), key=lambda i: abs(times[i] - t))


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    run = sys.argv[1]
    with open(os.path.join(run, "summary.json")) as f:
        s = json.load(f)
    if "hc_time_ms" not in s:
        sys.exit(f"{run}: no puff biomarkers in summary.json (status {s.get('status')})")
    fr = columns(os.path.join(run, "frames.csv"))
    t = fr["t_ms"]
    events = [(k, s[k + "_time_ms"]) for k in ("a1", "hc", "a2") if k + "_time_ms" in s]

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    ax[0].plot(t, fr["apex_displacement_mm"], label="apex")
    ax[0].plot(t, fr["whole_eye_motion_mm"], label="whole eye (x = 4 mm)")
    ax[0].set_ylabel("axial displacement [mm] (+ outwards)")
    iops = [k for k in fr if k.endswith("_pressure_mmHg") and k != "apex_air_pressure_mmHg"]
    for k in iops:
        ax[1].plot(t, fr[k], label=k.replace("_pressure_mmHg", ""))
    ax[1].set_ylabel("cavity pressure [mmHg]")
    ax[2].plot(t, fr["apex_air_pressure_mmHg"])
    ax[2].set_ylabel("air pressure at the apex [mmHg]")
    for a in ax:
        for name, te in events:
            a.axvline(te, color="grey", lw=0.8, ls="--")
            a.text(te, a.get_ylim()[1], " " + name.upper(), va="top", fontsize=8)
        a.set_xlabel("time from the start of the puff [ms]")
        a.grid(alpha=0.3)
    ax[0].legend()
    if len(iops) > 1:
        ax[1].legend()
    fig.suptitle("%s: deformation %.3f mm, deflection %.3f mm, peak distance %.2f mm, "
                 "HC %.2f ms" % (os.path.basename(os.path.normpath(run)),
                                 s["deformation_amplitude_mm"], s["deflection_amplitude_mm"],
                                 s["peak_distance_mm"], s["hc_time_ms"]))
    fig.tight_layout()
    fig.savefig(os.path.join(run, "puff.png"), dpi=120)

    # Profiles: the frames nearest t = 0, A1, HC and A2.
    with open(os.path.join(run, "profiles.csv")) as f:
        prof = list(csv.DictReader(f))
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for (name, te), colour in zip([("start", 0.0)] + events, ["k", "C0", "C3", "C2"]):
        k = nearest_frame(t, te)
        for surface, style in (("anterior", "-"), ("posterior", "--")):
            pts = [(float(r["x_mm"]), float(r["y_mm"])) for r in prof
                   if int(r["frame"]) == k and r["surface"] == surface]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style, color=colour,
                    label="%s (%.2f ms)" % (name.upper() if name != "start" else name, t[k])
                    if surface == "anterior" else None)
    ax.set_xlabel("x [mm] (horizontal section)")
    ax.set_ylabel("y [mm] (along the axis)")
    ax.set_title("corneal profiles, anterior (solid) and posterior (dashed)")
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "profiles.png"), dpi=120)
    print(f"wrote {run}/puff.png and {run}/profiles.png")


if __name__ == "__main__":
    main()
