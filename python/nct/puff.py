"""A puff run's figures, and the air's pressure on the cornea of any puff
run (prescribed, from a table or computed).

    figures(run)                        # [(name, figure)]: deformation, pressures, profiles
    plot(run)                           # the same as PNGs in the run's folder
    corneal_pressure(run, t_ms)         # [(r, p)] on the anterior cornea at a time
    axial_force(profile)                # its axial force [N]
"""
import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .figures import save_png  # noqa: E402
from .folders import Run  # noqa: E402
from .tables import read_csv  # noqa: E402

MMHG = 1.333224e-4  # MPa
EVENTS = ("a1", "hc", "a2")


def events(summary):
    """[(name, time)] of A1, HC and A2 where the run has them."""
    return [(k, summary[k + "_time_ms"]) for k in EVENTS if k + "_time_ms" in summary]


def _marked(ax, marks):
    for name, te in marks:
        ax.axvline(te, color="grey", lw=0.8, ls="--")
        ax.text(te, 1.0, " " + name.upper(), va="bottom", fontsize=8,
                transform=ax.get_xaxis_transform())
    ax.set_xlabel("time from the onset of the puff [ms]")
    ax.grid(alpha=0.3)


def deformation_figure(run):
    """The apex's axial displacement (deformation), its deflection (less
    the whole eye's) and the whole eye's movement against time, A1, HC and
    A2 marked."""
    fr, marks = run.frames, events(run.summary)
    t = fr["t_ms"]
    fig, ax = plt.subplots(1, 2, figsize=(12, 3.8))
    ax[0].plot(t, fr["apex_displacement_mm"], label="deformation (apex)")
    ax[0].plot(t, fr["apex_displacement_mm"] - fr["whole_eye_motion_mm"],
               label="deflection (apex less the whole eye)")
    ax[0].set_ylabel("axial displacement [mm] (+ outwards)")
    ax[0].legend(fontsize=8)
    ax[1].plot(t, 1e3 * fr["whole_eye_motion_mm"], color="C2")
    ax[1].set_ylabel("whole-eye movement [um] (+ outwards):\nthe cornea at x = 4 mm")
    for a in ax:
        _marked(a, marks)
    fig.tight_layout()
    return fig


def pressure_figure(run):
    """The air's pressure at the apex and the IOP (each cavity's pressure)
    against time, A1, HC and A2 marked."""
    fr, marks = run.frames, events(run.summary)
    t = fr["t_ms"]
    fig, ax = plt.subplots(1, 2, figsize=(12, 3.8))
    ax[0].plot(t, fr["apex_air_pressure_mmHg"], color="C3")
    ax[0].set_ylabel("air pressure at the apex [mmHg]")
    iops = [k for k in fr.columns
            if k.endswith("_pressure_mmHg") and k != "apex_air_pressure_mmHg"]
    for k in iops:
        ax[1].plot(t, fr[k], label=k.replace("_pressure_mmHg", ""))
    ax[1].set_ylabel("IOP: cavity pressure [mmHg]")
    if len(iops) > 1:
        ax[1].legend(fontsize=8)
    for a in ax:
        _marked(a, marks)
    fig.tight_layout()
    return fig


def profiles_figure(run):
    """The corneal profiles (anterior solid, posterior dashed) at the frames
    nearest the onset, A1, HC and A2."""
    profiles = run.profiles
    fig, ax = plt.subplots(figsize=(9, 4.2))
    for (name, te), colour in zip([("start", 0.0)] + events(run.summary), ["k", "C0", "C3", "C2"]):
        k = profiles.nearest(te)
        for surface, style in (("anterior", "-"), ("posterior", "--")):
            if surface not in profiles.surfaces:
                continue
            x, y = profiles.curve(k, surface)
            label = "%s (%.2f ms)" % (name.upper() if name != "start" else name,
                                      profiles.t_ms[k])
            ax.plot(x, y, style, color=colour, label=label if surface == "anterior" else None)
    ax.set_xlabel("x [mm] (horizontal section)")
    ax.set_ylabel("y [mm] (along the axis)")
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def figures(run):
    """A puff run's figures as [(name, matplotlib figure)]: deformation,
    pressures, profiles. A run without the puff's biomarkers has none."""
    run = run if isinstance(run, Run) else Run(run)
    if "hc_time_ms" not in run.summary or not run.has("frames.csv"):
        return []
    made = [("deformation", deformation_figure(run)), ("pressures", pressure_figure(run))]
    if run.has("profiles.csv"):
        made.append(("profiles", profiles_figure(run)))
    return made


def plot(run):
    """The figures as PNGs into the run's folder; returns the paths."""
    run = run if isinstance(run, Run) else Run(run)
    return save_png(figures(run), run.folder)


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
