"""A puff run's plots, and the air's pressure on the cornea of any puff
run (prescribed, from a table or computed).

    plot(run)                           # RUN/puff.png and RUN/profiles.png
    corneal_pressure(run, t_ms)         # [(r, p)] on the anterior cornea at a time
    axial_force(profile)                # its axial force [N]
"""
import math
import os
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .folders import Run  # noqa: E402
from .tables import read_csv  # noqa: E402

MMHG = 1.333224e-4  # MPa
EVENTS = ("a1", "hc", "a2")


def events(summary):
    """[(name, time)] of A1, HC and A2 where the run has them."""
    return [(k, summary[k + "_time_ms"]) for k in EVENTS if k + "_time_ms" in summary]


def plot(run):
    """Apex displacement, cavity and apex air pressures against time
    (puff.png), the corneal profiles at the start, A1, HC and A2
    (profiles.png). Returns the two paths."""
    run = run if isinstance(run, Run) else Run(run)
    s = run.summary
    if "hc_time_ms" not in s:
        raise ValueError(f"{run.folder}: no puff biomarkers in summary.json "
                         f"(status {s.get('status')})")
    fr = run.frames
    t = fr["t_ms"]
    marks = events(s)

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    ax[0].plot(t, fr["apex_displacement_mm"], label="apex")
    ax[0].plot(t, fr["whole_eye_motion_mm"], label="whole eye (x = 4 mm)")
    ax[0].set_ylabel("axial displacement [mm] (+ outwards)")
    iops = [k for k in fr.columns
            if k.endswith("_pressure_mmHg") and k != "apex_air_pressure_mmHg"]
    for k in iops:
        ax[1].plot(t, fr[k], label=k.replace("_pressure_mmHg", ""))
    ax[1].set_ylabel("cavity pressure [mmHg]")
    ax[2].plot(t, fr["apex_air_pressure_mmHg"])
    ax[2].set_ylabel("air pressure at the apex [mmHg]")
    for a in ax:
        for name, te in marks:
            a.axvline(te, color="grey", lw=0.8, ls="--")
            a.text(te, a.get_ylim()[1], " " + name.upper(), va="top", fontsize=8)
        a.set_xlabel("time from the start of the puff [ms]")
        a.grid(alpha=0.3)
    ax[0].legend()
    if len(iops) > 1:
        ax[1].legend()
    fig.suptitle("%s: deformation %.3f mm, deflection %.3f mm, peak distance %.2f mm, "
                 "HC %.2f ms" % (os.path.basename(os.path.normpath(run.folder)),
                                 s["deformation_amplitude_mm"],
                                 s["deflection_amplitude_mm"], s["peak_distance_mm"],
                                 s["hc_time_ms"]))
    fig.tight_layout()
    puff_png = run.folder / "puff.png"
    fig.savefig(puff_png, dpi=120)
    plt.close(fig)

    # Profiles: the frames nearest t = 0, A1, HC and A2.
    profiles = run.profiles
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for (name, te), colour in zip([("start", 0.0)] + marks, ["k", "C0", "C3", "C2"]):
        k = profiles.nearest(te)
        for surface, style in (("anterior", "-"), ("posterior", "--")):
            x, y = profiles.curve(k, surface)
            label = "%s (%.2f ms)" % (name.upper() if name != "start" else name,
                                      profiles.t_ms[k])
            ax.plot(x, y, style, color=colour, label=label if surface == "anterior" else None)
    ax.set_xlabel("x [mm] (horizontal section)")
    ax.set_ylabel("y [mm] (along the axis)")
    ax.set_title("corneal profiles, anterior (solid) and posterior (dashed)")
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    profiles_png = run.folder / "profiles.png"
    fig.savefig(profiles_png, dpi=120)
    plt.close(fig)
    return puff_png, profiles_png


def pressure_table(path):
    """A t_ms,r_mm,p_mmHg table as {t: [(r, p)...]}, each sorted by r."""
    table = read_csv(path)
    out = {}
    for t, r, p in zip(table["t_ms"], table["r_mm"], table["p_mmHg"]):
        out.setdefault(float(t), []).append((float(r), float(p)))
    return {t: sorted(v) for t, v in out.items()}


def corneal_pressure(run, t_ms):
    """The air pressure on the anterior cornea as [(r, p)] at a time: the
    computed one (corneal_pressure.csv, r the current radius), the table's
    (r the reference radius) or the Gaussian's."""
    run = run if isinstance(run, Run) else Run(run)
    puff = run.scene["puff"]
    if run.has("corneal_pressure.csv"):
        table = pressure_table(run.folder / "corneal_pressure.csv")
    elif puff["load"] == "table":
        scene_folder = pathlib.Path(run.summary["scene"]).parent
        table = pressure_table(scene_folder / puff["table"])
    else:  # the Gaussian: peak exp(-(t - t0)^2 / 2 wt^2) exp(-r^2 / 2 wr^2)
        g = puff["peak"] * math.exp(-(t_ms - puff["peak_time"]) ** 2 / (2 * puff["width_t"] ** 2))
        return [(r, g * math.exp(-r * r / (2 * puff["width_r"] ** 2)))
                for r in (0.1 * k for k in range(59))]
    return table[min(table, key=lambda x: abs(x - t_ms))]


def axial_force(profile):
    """The axial force [N] of a pressure profile [(r [mm], p [mmHg])] on the
    whole eye: the integral of p 2 pi r dr, trapezoidal in p over rings."""
    f = sum(0.5 * (p0 + p1) * math.pi * (r1 * r1 - r0 * r0)
            for (r0, p0), (r1, p1) in zip(profile, profile[1:]))
    return f * MMHG


def pressure_at(profile, r):
    """p at r of a profile, linear between its radii; None beyond its last."""
    rs, ps = zip(*profile)
    return float(np.interp(r, rs, ps)) if rs[-1] >= r else None
