#!/usr/bin/python3
"""Plots of an nct fit: the readings against the start and the fit, the
convergence, the correlations.

Usage: /usr/bin/python3 scripts/plot-fit.py DIR [--out PNGDIR]

DIR is a fit folder (nct fit FIT --out DIR). Writes into PNGDIR (default
DIR):
- fit-curves.png: per curve observation, the measured points with their
  SDs, the best run's whole curve (the fit) and run-0001's (the start,
  dashed);
- fit-profiles.png: per profile observation, the measured points per time
  with their SDs, the model's values at them (crosses) and the best run's
  profile at the nearest frame (a line; with reference "rest", the default,
  the displacement from frame 0 at the same x), one colour per time;
- fit-convergence.png: the cost and each parameter per iteration, refused
  steps hollow, the parameters' 95 % intervals shaded;
- fit-correlation.png: the parameters' correlation matrix.
A figure whose inputs are absent is skipped with a note.
"""
import argparse
import csv
import json
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402


def table(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def frames(run, quantity):
    rows = table(run / "frames.csv")
    return column(rows, "t_ms"), column(rows, quantity)


def profiles(run, surface):
    """Per frame: [t, x, y] of the surface, sorted by x."""
    out = {}
    for r in table(run / "profiles.csv"):
        if r["surface"] == surface:
            f = out.setdefault(int(r["frame"]), [float(r["t_ms"]), [], []])
            f[1].append(float(r["x_mm"]))
            f[2].append(float(r["y_mm"]))
    for f in out.values():
        o = np.argsort(f[1])
        f[1], f[2] = np.array(f[1])[o], np.array(f[2])[o]
    return out


def column(rows, key):
    return np.array([float(r[key]) for r in rows])


def start_run(fit, folder):
    """runs/run-0001 (the start point), with a note if its sets differ from the starts."""
    run = folder / "runs" / "run-0001"
    if not (run / "frames.csv").is_file():
        return print("no runs/run-0001/frames.csv: no start curve")
    sets = json.load(open(run / "run.json")).get("sets", []) if (run / "run.json").is_file() else []
    sets = dict(s.split("=", 1) for s in sets)
    for p in fit["parameters"]:
        for k in p["keys"]:
            if k not in sets or not np.isclose(float(sets[k]), p["start"], rtol=1e-9):
                print("note: run-0001 sets %s=%s, not the start %g" % (k, sets.get(k), p["start"]))
    return run


def curves(fit, obs, best, start, out):
    todo = [o for o in fit["observations"] if o["kind"] == "curve"]
    if not todo:
        return print("no curve observation: no fit-curves.png")
    fig, axes = plt.subplots(len(todo), 1, figsize=(8, 3.5 * len(todo)), squeeze=False)
    for ax, o in zip(axes[:, 0], todo):
        m = obs.get(o["label"], [])
        ax.errorbar(column(m, "t_ms"), column(m, "measured"), yerr=column(m, "sd"), fmt="o",
                    ms=3, color="k", label="measured")
        if start:
            ax.plot(*frames(start, o["quantity"]), "--", color="0.5", label="start")
        if best:
            ax.plot(*frames(best, o["quantity"]), color="C3", label="fit")
        ax.set(xlabel="t [ms]", ylabel=o["quantity"],
               title="%s: weighted RMS residual %.3g" % (o["label"], o["rms_weighted_residual"]))
        ax.legend()
    save(fig, out / "fit-curves.png")


def profile_plots(fit, obs, best, out):
    todo = [o for o in fit["observations"] if o["kind"] == "profile"]
    if not todo:
        return print("no profile observation: no fit-profiles.png")
    fig, axes = plt.subplots(len(todo), 1, figsize=(8, 4 * len(todo)), squeeze=False)
    for ax, o in zip(axes[:, 0], todo):
        mine = obs.get(o["label"], [])
        rest = o.get("reference", "rest") == "rest"
        model = profiles(best, o["quantity"]) if best else {}
        keys = sorted(model)
        for i, t in enumerate(sorted({float(r["t_ms"]) for r in mine})):
            pts = sorted((r for r in mine if float(r["t_ms"]) == t), key=lambda r: float(r["x_mm"]))
            x, c = column(pts, "x_mm"), "C%d" % i
            ax.errorbar(x, column(pts, "measured"), yerr=column(pts, "sd"), fmt="o", ms=3,
                        color=c, label="t = %.2f ms" % t)
            ax.plot(x, column(pts, "model"), "x", color=c)
            if model:  # as nct: y(x) at the frame minus y(x) at frame 0, both interpolated
                k = keys[int(np.argmin([abs(model[k][0] - t) for k in keys]))]
                _, fx, fy = model[k]
                _, x0, y0 = model[keys[0]]
                xs = np.linspace(max(fx[0], x0[0]), min(fx[-1], x0[-1]), 200) if rest else fx
                ys = np.interp(xs, fx, fy) - np.interp(xs, x0, y0) if rest else fy
                ax.plot(xs, ys, color=c, lw=1)
        ax.set(xlabel="x [mm]",
               ylabel="axial displacement [mm]" if rest else "%s y [mm]" % o["quantity"],
               title="%s: weighted RMS residual %.3g\n(points measured, x the model, lines "
               "the fit's nearest frame)" % (o["label"], o["rms_weighted_residual"]))
        ax.legend(fontsize=8)
    save(fig, out / "fit-profiles.png")


def convergence(fit, folder, out):
    path = folder / "iterations.csv"
    rows = table(path) if path.is_file() else []
    if not rows:
        return print("no iterations.csv (or no rows in it): no fit-convergence.png")
    pars = fit["parameters"]
    it = column(rows, "iteration")
    ok = np.array([r["accepted"] == "1" for r in rows])
    fig, axes = plt.subplots(1 + len(pars), 1, figsize=(7, 1.2 + 2.2 * (1 + len(pars))),
                             sharex=True, squeeze=False)
    axes = axes[:, 0]
    series = [("cost", column(rows, "cost"), None)] + [(p["label"], column(rows, p["label"]), p)
                                                        for p in pars]
    for ax, (name, v, p) in zip(axes, series):
        ax.plot(it[ok], v[ok], "-o", color="C0", label="taken")
        ax.plot(it[~ok], v[~ok], "o", mfc="none", color="C3", label="refused")
        ax.set_ylabel(name)
        if p is None or p.get("log"):
            ax.set_yscale("log")
            # over more than a decade, only 1, 2 and 5 times a power of 10 labelled
            one25 = lambda y: np.isclose(y / 10 ** np.floor(np.log10(y)), [1, 2, 5]).any()  # noqa
            f = matplotlib.ticker.FuncFormatter(lambda y, _, wide=v.max() > 10 * v.min():
                                                "%g" % y if not wide or one25(y) else "")
            ax.yaxis.set_major_formatter(f)
            ax.yaxis.set_minor_formatter(f)
        ci = p and p.get("ci95") and None not in p["ci95"]
        if ci:
            ax.axhspan(*p["ci95"], color="C1", alpha=0.2)
        ax.set_title("%s = %.4g" % (name, v[-1]) + ("" if p is None or p.get("se") is None
                     else " (SE %.2g" % p["se"] + ("; shaded: 95 % interval)" if ci else ")")),
                     fontsize=9, loc="left")
        if p and p.get("at_bound"):
            ax.set_title("at a bound", fontsize=8, loc="right", color="C3")
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel("iteration")
    axes[-1].xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
    fig.suptitle("%s after %s iterations, %s forward runs; chi2 %.4g for %s dof" % (
        fit.get("status"), fit.get("iterations", len(rows) - 1), fit.get("forward_runs"),
        fit.get("chi2", np.nan), fit.get("dof")))
    save(fig, out / "fit-convergence.png")


def correlation(fit, out):
    labels = [p["label"] for p in fit["parameters"]]
    c = np.array([[np.nan if v is None else v for v in row]
                  for row in fit.get("correlation") or []], dtype=float).reshape(-1, len(labels))
    n = len(labels)
    fig, ax = plt.subplots(figsize=(2.4 + 1.1 * n, 1.6 + 1.1 * n))
    if np.isnan(c).all():
        ax.text(0.5, 0.5, "not identifiable:\nno covariance", ha="center", va="center",
                fontsize=14)
        ax.axis("off")
    else:
        im = ax.imshow(c, vmin=-1, vmax=1, cmap="RdBu_r")
        for i in range(n):
            for j in range(n):
                ax.text(j, i, "-" if np.isnan(c[i, j]) else "%.3f" % c[i, j], ha="center",
                        va="center", color="w" if abs(c[i, j]) > 0.6 else "k")
        ax.set_xticks(range(n), labels, rotation=30, ha="right")
        ax.set_yticks(range(n), labels)
        fig.colorbar(im, ax=ax, shrink=0.8)
    ax.set_title("correlation of the fitted parameters")
    save(fig, out / "fit-correlation.png")


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print("wrote", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir", type=pathlib.Path)
    ap.add_argument("--out", type=pathlib.Path, help="folder of the PNGs (default DIR)")
    a = ap.parse_args()
    if not (a.dir / "fit.json").is_file():
        print("plot-fit: %s has no fit.json (not an nct fit folder)" % a.dir, file=sys.stderr)
        sys.exit(2)
    fit = json.load(open(a.dir / "fit.json"))
    out = a.out or a.dir
    out.mkdir(parents=True, exist_ok=True)
    obs = {}
    if (a.dir / "observations.csv").is_file():
        for r in table(a.dir / "observations.csv"):
            obs.setdefault(r["observation"], []).append(r)
    else:
        print("no observations.csv: no measured points")
    best = pathlib.Path(fit.get("best_run") or "-")
    if not (best / "frames.csv").is_file() or not (best / "profiles.csv").is_file():
        print("no best run's frames.csv and profiles.csv (%s): no fitted curves" % best)
        best = None
    curves(fit, obs, best, start_run(fit, a.dir), out)
    profile_plots(fit, obs, best, out)
    convergence(fit, a.dir, out)
    correlation(fit, out)


if __name__ == "__main__":
    main()
