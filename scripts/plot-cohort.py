#!/usr/bin/python3
"""Plots and the recovery table of an nct cohort (a fit file with a
[cohort] table, fitted with nct fit).

Usage: /usr/bin/python3 scripts/plot-cohort.py DIR [--out PNGDIR]

DIR is the cohort's folder (its cohort.csv). Writes into PNGDIR (default
DIR):
- cohort-iop.png: each patient's first parameter (the stiffness) with its
  95 % interval against the IOP: the fitted one (with its interval) when
  the IOP is a parameter labelled iop, else the table's inflate.iop column;
- cohort-age.png: the same against age, when the table has an age column;
- cohort-recovery.png: per parameter with truths (truth.<label> columns),
  the fitted value and its interval against the truth, with the identity;
and prints per parameter with truths a Markdown recovery table (patient,
truth, fit, SE, interval, error, inside) and the share of truths inside
their intervals. Patients whose fit failed are left out, with a note.
"""
import argparse
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir", type=pathlib.Path)
    ap.add_argument("--out", type=pathlib.Path)
    a = ap.parse_args()
    out = a.out or a.dir
    out.mkdir(parents=True, exist_ok=True)
    path = a.dir / "cohort.csv"
    if not path.exists():
        sys.exit("plot-cohort: %s not found: run nct fit on the cohort first" % path)
    rows = list(csv.DictReader(open(path)))
    failed = [r["patient"] for r in rows if not number(r.get(next(iter(labels(rows)), "")))]
    if failed:
        print("plot-cohort: no fit for %s (left out)" % ", ".join(failed))
    rows = [r for r in rows if r["patient"] not in failed]
    if not rows:
        sys.exit("plot-cohort: no patient was fitted")
    params = labels(rows)
    stiff = params[0]

    def bars(label):
        """The 95 % interval of a fitted label as error bars about its values."""
        v = [number(r[label]) for r in rows]
        lo = [vi - number(r[label + "_lo"]) if number(r[label + "_lo"]) is not None else 0
              for vi, r in zip(v, rows)]
        hi = [number(r[label + "_hi"]) - vi if number(r[label + "_hi"]) is not None else 0
              for vi, r in zip(v, rows)]
        return [lo, hi]

    def errorbar(ax, x, label, xlabel=None):
        y = [number(r[label]) for r in rows]
        ax.errorbar(x, y, yerr=bars(label), xerr=bars(xlabel) if xlabel in params else None,
                    fmt="o", capsize=3)
        for xi, yi, r in zip(x, y, rows):
            ax.annotate(r["patient"], (xi, yi), textcoords="offset points", xytext=(4, 4),
                        fontsize=7)

    against = []
    if "iop" in params:
        against.append(("iop", "IOP, fitted [mmHg]", "cohort-iop.png"))
    elif "inflate.iop" in rows[0]:
        against.append(("inflate.iop", "IOP, measured [mmHg]", "cohort-iop.png"))
    if "age" in rows[0]:
        against.append(("age", "age [years]", "cohort-age.png"))
    for column, xlabel, name in against:
        fig, ax = plt.subplots(figsize=(6, 4.5))
        errorbar(ax, [number(r[column]) for r in rows], stiff, column)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("%s (95 %% interval)" % stiff)
        ax.set_title("%s: %d patients" % (a.dir.name, len(rows)))
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(out / name, dpi=120)
        plt.close(fig)
        print("wrote %s" % (out / name))

    truths = [p for p in params if "truth_" + p in rows[0]]
    if truths:
        fig, axes = plt.subplots(1, len(truths), figsize=(5 * len(truths), 4.5), squeeze=False)
        for ax, p in zip(axes[0], truths):
            t = [number(r["truth_" + p]) for r in rows]
            errorbar(ax, t, p)
            lim = [min(t + [number(r[p + "_lo"]) or t[0] for r in rows]),
                   max(t + [number(r[p + "_hi"]) or t[0] for r in rows])]
            ax.plot(lim, lim, "k--", lw=0.8, label="fit = truth")
            ax.set_xlabel("truth: %s" % p)
            ax.set_ylabel("fit (95 % interval)")
            ax.legend()
            ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(out / "cohort-recovery.png", dpi=120)
        plt.close(fig)
        print("wrote %s" % (out / "cohort-recovery.png"))
        for p in truths:
            print("\n| patient | truth %s | fit | SE | 95 %% interval | error | inside |" % p)
            print("|---|---|---|---|---|---|---|")
            inside = 0
            for r in rows:
                ok = r.get(p + "_inside") in ("1", "true")
                inside += ok
                print("| %s | %.4g | %.4g | %.2g | %.4g - %.4g | %+.1f %% | %s |"
                      % (r["patient"], number(r["truth_" + p]), number(r[p]), number(r[p + "_se"]),
                         number(r[p + "_lo"]), number(r[p + "_hi"]),
                         100 * (number(r[p]) / number(r["truth_" + p]) - 1),
                         "yes" if ok else "no"))
            print("%s: %d of %d truths inside their 95 %% intervals" % (p, inside, len(rows)))


def labels(rows):
    """The fitted parameters' labels: the columns with an _se twin."""
    return [c[:-3] for c in rows[0] if c.endswith("_se") and c[:-3] in rows[0]]


if __name__ == "__main__":
    main()
