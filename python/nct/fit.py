"""Plots of an nct fit: the readings against the start and the fit, the
convergence, the correlations.

    figures(folder)       # [(name, matplotlib figure)], as the report shows them
    plot(folder, out)     # the same as PNGs into out (default: the fit's folder)

- fit-curves.png: per curve observation, the measured points with their
  SDs, the best run's whole curve (the fit) and run-0001's (the start,
  dashed);
- fit-profiles.png: per profile observation, the measured points per time
  with their SDs, the model's values at them (crosses) and the best run's
  profile at the nearest frame (a line; with reference "rest", the default,
  the displacement from frame 0 at the same x), one colour per time;
- fit-residuals.png: per observation, the residuals in SDs against time,
  x or reading, the +-1 and +-2 SD bands shaded;
- fit-convergence.png: the cost and each parameter per iteration, refused
  steps hollow, the parameters' 95 % intervals shaded;
- fit-correlation.png: the parameters' correlation matrix.
A figure whose inputs are absent is skipped with a note.
"""
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

from .figures import save_png  # noqa: E402
from .folders import Fit  # noqa: E402


def _start_run(fit):
    """runs/run-0001 (the start point), with a note if its sets differ from the starts."""
    run = fit.run("run-0001")
    if not run.has("frames.csv"):
        return print("no runs/run-0001/frames.csv: no start curve")
    sets = dict(s.split("=", 1) for s in run.sets)
    for p in fit.result["parameters"]:
        for k in p["keys"]:
            if k not in sets or not np.isclose(float(sets[k]), p["start"], rtol=1e-9):
                print("note: run-0001 sets %s=%s, not the start %g" % (k, sets.get(k), p["start"]))
    return run


def _curves(result, obs, best, start):
    todo = [o for o in result["observations"] if o["kind"] == "curve"]
    if not todo:
        return print("no curve observation: no fit-curves.png")
    fig, axes = plt.subplots(len(todo), 1, figsize=(8, 3.5 * len(todo)), squeeze=False)
    for ax, o in zip(axes[:, 0], todo):
        m = obs.get(o["label"])
        if m is not None:
            ax.errorbar(m["t_ms"], m["measured"], yerr=m["sd"], fmt="o", ms=3, color="k",
                        label="measured")
        for run, style, label in ((start, dict(ls="--", color="0.5"), "start"),
                                  (best, dict(color="C3"), "fit")):
            if run:
                ax.plot(run.frames["t_ms"], run.frames[o["quantity"]], label=label, **style)
        ax.set(xlabel="t [ms]", ylabel=o["quantity"],
               title="%s: weighted RMS residual %.3g" % (o["label"], o["rms_weighted_residual"]))
        ax.legend()
    fig.tight_layout()
    return fig


def _profiles(result, obs, best):
    todo = [o for o in result["observations"] if o["kind"] == "profile"]
    if not todo:
        return print("no profile observation: no fit-profiles.png")
    fig, axes = plt.subplots(len(todo), 1, figsize=(8, 4 * len(todo)), squeeze=False)
    for ax, o in zip(axes[:, 0], todo):
        mine = obs.get(o["label"])
        rest = o.get("reference", "rest") == "rest"
        model = best.profiles if best else None
        times = sorted(set(mine["t_ms"].tolist())) if mine is not None else []
        for i, t in enumerate(times):
            pts = mine.where(mine["t_ms"] == t)
            order = np.argsort(pts["x_mm"], kind="stable")
            x, c = pts["x_mm"][order], "C%d" % i
            ax.errorbar(x, pts["measured"][order], yerr=pts["sd"][order], fmt="o", ms=3,
                        color=c, label="t = %.2f ms" % t)
            ax.plot(x, pts["model"][order], "x", color=c)
            if model:  # as nct: y(x) at the frame minus y(x) at frame 0, both interpolated
                fx, fy = model.curve(model.nearest(t), o["quantity"])
                x0, y0 = model.curve(0, o["quantity"])
                xs = np.linspace(max(fx[0], x0[0]), min(fx[-1], x0[-1]), 200) if rest else fx
                ys = np.interp(xs, fx, fy) - np.interp(xs, x0, y0) if rest else fy
                ax.plot(xs, ys, color=c, lw=1)
        ax.set(xlabel="x [mm]",
               ylabel="axial displacement [mm]" if rest else "%s y [mm]" % o["quantity"],
               title="%s: weighted RMS residual %.3g\n(points measured, x the model, lines "
               "the fit's nearest frame)" % (o["label"], o["rms_weighted_residual"]))
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def _convergence(fit):
    rows = fit.iterations if fit.has("iterations.csv") else None
    if rows is None or not len(rows):
        return print("no iterations.csv (or no rows in it): no fit-convergence.png")
    result = fit.result
    pars = result["parameters"]
    it = rows["iteration"]
    ok = rows["accepted"] == 1
    fig, axes = plt.subplots(1 + len(pars), 1, figsize=(7, 1.2 + 2.2 * (1 + len(pars))),
                             sharex=True, squeeze=False)
    axes = axes[:, 0]
    series = [("cost", rows["cost"], None)] + [(p["label"], rows[p["label"]], p) for p in pars]
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
        result.get("status"), result.get("iterations", len(rows) - 1), result.get("forward_runs"),
        result.get("chi2", np.nan), result.get("dof")))
    fig.tight_layout()
    return fig


def _correlation(result):
    labels = [p["label"] for p in result["parameters"]]
    c = np.array([[np.nan if v is None else v for v in row]
                  for row in result.get("correlation") or []], dtype=float).reshape(-1, len(labels))
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
    fig.tight_layout()
    return fig


def _residuals(obs):
    """Each observation's residuals in SDs ((measured - model) / SD, as
    observations.csv gives them) against time, x or index, with the
    +-1 and +-2 SD bands."""
    if not obs:
        return None
    fig, axes = plt.subplots(1, len(obs), figsize=(0.6 + 4.2 * len(obs), 3.2), squeeze=False)
    for ax, (label, pts) in zip(axes[0], obs.items()):
        kind = pts["kind"][0] if len(pts) else ""
        if kind == "curve":
            x, xlabel = pts["t_ms"], "t [ms]"
        elif kind == "profile":
            x, xlabel = pts["x_mm"], "x [mm] (all its times)"
        else:
            x, xlabel = np.arange(len(pts)), "reading"
        r = pts["residual"]
        ax.axhspan(-2, 2, color="C2", alpha=0.08)
        ax.axhspan(-1, 1, color="C2", alpha=0.12)
        ax.plot(x, r, "o", ms=3, color="C0")
        ax.axhline(0, color="k", lw=0.6)
        ax.set(xlabel=xlabel, ylabel="residual [SD]",
               title="%s: %d points, RMS %.2f SD" % (label, len(r), np.sqrt(np.mean(r**2))))
        ax.title.set_fontsize(9)
        if kind not in ("curve", "profile"):
            ax.set_xticks(range(len(pts)), [str(k) for k in pts["observation"]], rotation=30,
                          fontsize=7)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def observed(fit):
    """observations.csv split per observation label ({} without it)."""
    if not fit.has("observations.csv"):
        return {}
    table = fit.observations
    return {label: table.where(table["observation"] == label)
            for label in dict.fromkeys(table["observation"])}


def figures(folder):
    """The fit's figures as [(name, matplotlib figure)]: fit-curves,
    fit-profiles, fit-residuals, fit-convergence, fit-correlation, each
    where its inputs exist."""
    fit = Fit(folder)
    obs = observed(fit)
    if not obs:
        print("no observations.csv: no measured points")
    best = fit.best_run
    if not best or not best.has("frames.csv") or not best.has("profiles.csv"):
        print("no best run's frames.csv and profiles.csv (%s): no fitted curves"
              % (best.folder if best else "-"))
        best = None
    made = [("fit-curves", _curves(fit.result, obs, best, _start_run(fit))),
            ("fit-profiles", _profiles(fit.result, obs, best)),
            ("fit-residuals", _residuals(obs)),
            ("fit-convergence", _convergence(fit)),
            ("fit-correlation", _correlation(fit.result))]
    return [(name, fig) for name, fig in made if fig is not None]


def plot(folder, out=None):
    """The fit's figures as PNGs into out (default: the folder); returns the paths."""
    return save_png(figures(folder), pathlib.Path(out or folder), dpi=110)


RESULTS_HEAD = ["fit", "parameter", "truth", "fit", "SE", "95 % interval", "correlations",
                "forward runs, wall; chi2 / dof"]


def results_rows(name, result, truths=None):
    """A fit's answer as rows under RESULTS_HEAD: per parameter its truth
    (where given), value, SE, 95 % interval; the correlations, forward
    runs, wall time and status, chi2 / dof."""
    truths = truths or {}
    labels = [p["label"] for p in result["parameters"]]
    correlation = result.get("correlation") or []
    pairs = ["%s-%s %+.3f" % (labels[i], labels[j], correlation[i][j])
             for i in range(len(labels)) for j in range(i + 1, len(labels))
             if correlation and correlation[i][j] is not None]
    rows = []
    for k, p in enumerate(result["parameters"]):
        lo, hi = p.get("ci95") or (None, None)
        rows.append([name if k == 0 else "", p["label"], "%g" % truths[p["label"]]
                     if p["label"] in truths else "-", "%.4g" % p["value"],
                     "%.2g" % p["se"] if p.get("se") is not None else "-",
                     "%.4g - %.4g" % (lo, hi) if lo is not None else "-",
                     ", ".join(pairs) if k == 0 else "",
                     "%s runs, %.0f s, %s; chi2 %.1f / %s dof" % (
                         result.get("forward_runs"), result.get("wall_s", 0), result.get("status"),
                         result.get("chi2", float("nan")), result.get("dof")) if k == 0 else ""])
    return rows
