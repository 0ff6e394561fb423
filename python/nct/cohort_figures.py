"""Plots and the recovery table of an nct cohort (a fit file with a
[cohort] table, fitted with nct fit).

    figures(folder)       # [(name, matplotlib figure)], as the report shows them
    plot(folder, out)     # the same as PNGs into out (default: the cohort's folder)
    recovery(folder)      # per parameter with truths, the Markdown recovery table

- cohort-iop.png: each patient's first parameter (the stiffness) with its
  95 % interval against the IOP: the fitted one (with its interval) when
  the IOP is a parameter labelled iop, else the table's inflate.iop column;
- cohort-age.png: the same against age, when the table has an age column;
- cohort-recovery.png: per parameter with truths (truth.<label> columns),
  the fitted value and its interval against the truth, with the identity.
Patients whose fit failed are left out, with a note.
"""
import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .figures import save_png  # noqa: E402
from .folders import Cohort  # noqa: E402


def _number(x):
    """A finite number, or None (an empty or text cell)."""
    return x if isinstance(x, float) and math.isfinite(x) else None


def labels(columns):
    """The fitted parameters' labels: the columns with an _se twin."""
    return [c[:-3] for c in columns if c.endswith("_se") and c[:-3] in columns]


def fitted(folder):
    """(rows of the patients whose fit gave values, the names of the others)."""
    table = Cohort(folder).table
    params = labels(table.columns)
    rows = table.rows()
    failed = [r["patient"] for r in rows if not params or _number(r[params[0]]) is None]
    return [r for r in rows if r["patient"] not in failed], failed


def figures(folder):
    """The cohort's figures as [(name, matplotlib figure)]: cohort-iop,
    cohort-age, cohort-recovery, each where its columns exist; none
    without a fitted patient."""
    folder = pathlib.Path(folder)
    rows, _ = fitted(folder)
    if not rows:
        return []
    params = labels(list(rows[0]))
    stiff = params[0]
    made = []

    def bars(label):
        """The 95 % interval of a fitted label as error bars about its values."""
        v = [_number(r[label]) for r in rows]
        # A sampled posterior's interval need not hold the fitted value: then
        # the bar stops at the value on that side.
        lo = [max(0.0, vi - _number(r[label + "_lo"])) if _number(r[label + "_lo"]) is not None
              else 0 for vi, r in zip(v, rows)]
        hi = [max(0.0, _number(r[label + "_hi"]) - vi) if _number(r[label + "_hi"]) is not None
              else 0 for vi, r in zip(v, rows)]
        return [lo, hi]

    def errorbar(ax, x, label, xlabel=None):
        y = [_number(r[label]) for r in rows]
        ax.errorbar(x, y, yerr=bars(label), xerr=bars(xlabel) if xlabel in params else None,
                    fmt="o", capsize=3)
        for xi, yi, r in zip(x, y, rows):
            ax.annotate(r["patient"], (xi, yi), textcoords="offset points", xytext=(4, 4),
                        fontsize=7)

    against = []
    if "iop" in params:
        against.append(("iop", "IOP, fitted [mmHg]", "cohort-iop"))
    elif "inflate.iop" in rows[0]:
        against.append(("inflate.iop", "IOP, measured [mmHg]", "cohort-iop"))
    if "age" in rows[0]:
        against.append(("age", "age [years]", "cohort-age"))
    for column, xlabel, name in against:
        fig, ax = plt.subplots(figsize=(6, 4.5))
        errorbar(ax, [_number(r[column]) for r in rows], stiff, column)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("%s (95 %% interval)" % stiff)
        ax.set_title("%s: %d patients" % (folder.name, len(rows)))
        ax.grid(alpha=0.3)
        fig.tight_layout()
        made.append((name, fig))

    truths = [p for p in params if "truth_" + p in rows[0]]
    if truths:
        fig, axes = plt.subplots(1, len(truths), figsize=(5 * len(truths), 4.5), squeeze=False)
        for ax, p in zip(axes[0], truths):
            t = [_number(r["truth_" + p]) for r in rows]
            errorbar(ax, t, p)
            lim = [min(t + [_number(r[p + "_lo"]) or t[0] for r in rows]),
                   max(t + [_number(r[p + "_hi"]) or t[0] for r in rows])]
            ax.plot(lim, lim, "k--", lw=0.8, label="fit = truth")
            ax.set_xlabel("truth: %s" % p)
            ax.set_ylabel("fit (95 % interval)")
            ax.legend()
            ax.grid(alpha=0.3)
        fig.tight_layout()
        made.append(("cohort-recovery", fig))
    return made


def plot(folder, out=None):
    """The cohort's figures as PNGs into out (default: the folder); returns the paths."""
    return save_png(figures(folder), pathlib.Path(out or folder))


def recovery(folder):
    """Per parameter with truths: a Markdown table (patient, truth, fit, SE,
    interval, error, inside) and the share of truths inside their intervals."""
    rows, _ = fitted(folder)
    params = labels(list(rows[0]))
    parts = []
    for p in [p for p in params if "truth_" + p in rows[0]]:
        lines = ["| patient | truth %s | fit | SE | 95 %% interval | error | inside |" % p,
                 "|---|---|---|---|---|---|---|"]
        inside = 0
        for r in rows:
            ok = r.get(p + "_inside") in (1, "1", "true")
            inside += ok
            lines.append("| %s | %.4g | %.4g | %.2g | %.4g - %.4g | %+.1f %% | %s |"
                         % (r["patient"], r["truth_" + p], r[p], r[p + "_se"], r[p + "_lo"],
                            r[p + "_hi"], 100 * (r[p] / r["truth_" + p] - 1),
                            "yes" if ok else "no"))
        lines.append("%s: %d of %d truths inside their 95 %% intervals" % (p, inside, len(rows)))
        parts.append("\n".join(lines))
    return parts
