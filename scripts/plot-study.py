#!/usr/bin/python3
"""Plots of a study's analysis (the tables `nct study` writes).

    /usr/bin/python3 scripts/plot-study.py STUDY_FOLDER

writes into STUDY_FOLDER/plots:
- correlation.png: the Pearson correlation matrix of factors and
  responses as circles (area ~ |r|, colour = r);
- main_effects.png: the mean response at each level of each factor, one
  row per response, on a shared axis per row;
- pareto.png: per response, the terms' |effect| largest first, with the
  cumulative share of the explained sum of squares (factorial) or of the
  |effects| (one factor at a time);
an ablation study (design = "ablation") instead:
- variants.png: one panel per response, a bar per variant (the baseline
  first, hatched, labelled with its value), each other labelled with its
  percent difference from the baseline (its difference where the baseline
  is 0).
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def rows(folder, name):
    with open(os.path.join(folder, name)) as f:
        return list(csv.DictReader(f))


def save(fig, out):
    fig.tight_layout()
    fig.savefig(out, dpi=150)
    plt.close(fig)


def correlation(folder, out):
    path = os.path.join(folder, "correlation.csv")
    if not os.path.exists(path):
        print("plot-study: no correlation.csv (fewer than 3 complete cases)")
        return
    with open(path) as f:
        table = list(csv.reader(f))
    names = table[0][1:]
    r = np.array([[float(x) for x in row[1:]] for row in table[1:]])
    m = len(names)
    fig, ax = plt.subplots(figsize=(1.0 + 0.8 * m, 0.6 + 0.8 * m))
    cmap = plt.get_cmap("RdBu_r")
    for i in range(m):
        for j in range(m):
            v = r[i, j]
            if np.isnan(v):
                ax.text(j, i, "-", ha="center", va="center", color="0.5")
                continue
            ax.add_patch(plt.Circle((j, i), 0.45 * np.sqrt(abs(v)), color=cmap((v + 1) / 2)))
            ax.text(j, i, f"{v:.2f}", ha="center", va="center", fontsize=7,
                    color="white" if abs(v) > 0.6 else "black")
    ax.set_xlim(-0.5, m - 0.5)
    ax.set_ylim(m - 0.5, -0.5)
    ax.set_aspect("equal")
    ax.set_xticks(range(m), names, rotation=60, ha="right", fontsize=8)
    ax.set_yticks(range(m), names, fontsize=8)
    ax.set_xticks(np.arange(-0.5, m), minor=True)
    ax.set_yticks(np.arange(-0.5, m), minor=True)
    ax.grid(which="minor", color="0.85")
    ax.tick_params(which="minor", length=0)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(-1, 1))
    fig.colorbar(sm, ax=ax, shrink=0.8, label="Pearson r")
    ax.set_title("Correlation of factors and responses")
    save(fig, out)


def main_effects(folder, out):
    data = rows(folder, "main_effects.csv")
    responses = list(dict.fromkeys(d["response"] for d in data))
    factors = list(dict.fromkeys(d["factor"] for d in data))
    if not data:
        print("plot-study: no main effects (no response analysed)")
        return
    fig, axes = plt.subplots(len(responses), len(factors), squeeze=False, sharey="row",
                             figsize=(2.2 * len(factors), 2.2 * len(responses)))
    for a, resp in enumerate(responses):
        for b, fac in enumerate(factors):
            pts = [d for d in data if d["response"] == resp and d["factor"] == fac]
            ax = axes[a][b]
            ax.plot(range(len(pts)), [float(p["mean"]) for p in pts], "o-", color="C0")
            ax.set_xticks(range(len(pts)), [p["level"] for p in pts], fontsize=8)
            ax.grid(alpha=0.3)
            if a == len(responses) - 1:
                ax.set_xlabel(fac)
            if b == 0:
                ax.set_ylabel(resp, fontsize=8)
    fig.suptitle("Main effects: mean response at each level")
    save(fig, out)


def pareto(folder, out):
    effects = rows(folder, "effects.csv")
    responses = list(dict.fromkeys(d["response"] for d in effects))
    if not effects:
        print("plot-study: no effects (no response analysed)")
        return
    factorial = os.path.exists(os.path.join(folder, "anova.csv"))
    fig, axes = plt.subplots(len(responses), 1, squeeze=False,
                             figsize=(8, 2.8 * len(responses)))
    for a, resp in enumerate(responses):
        terms = [d for d in effects if d["response"] == resp]
        size = np.array([abs(float(d["effect"])) for d in terms])
        share = size**2 if factorial else size  # SS ~ effect^2 in a 2^k design
        cum = 100 * np.cumsum(share) / share.sum() if share.sum() > 0 else 0 * share
        ax = axes[a][0]
        colours = ["C3" if float(d["effect"]) < 0 else "C0" for d in terms]
        ax.bar(range(len(terms)), size, color=colours)
        ax.set_xticks(range(len(terms)), [d["term"] for d in terms], rotation=60, ha="right",
                      fontsize=7)
        ax.set_ylabel(f"|effect|\n{resp}", fontsize=8)
        twin = ax.twinx()
        twin.plot(range(len(terms)), cum, "k.-", lw=1)
        twin.set_ylim(0, 105)
        twin.set_ylabel("cumulative %", fontsize=8)
    axes[0][0].set_title("Pareto of effects (blue: raises the response, red: lowers it)")
    save(fig, out)


def variants(folder, out):
    data = rows(folder, "ablation.csv")
    analysis = json.load(open(os.path.join(folder, "analysis.json")))
    names = [v["name"] for v in analysis["variants"]]
    described = [v for v in analysis["variants"] if v["description"]]
    responses = list(dict.fromkeys(d["response"] for d in data))
    cols = min(3, len(responses))
    nrows = -(-len(responses) // cols)
    fig, axes = plt.subplots(nrows, cols, squeeze=False,
                             figsize=(1.2 + (0.75 + 0.55 * len(names)) * cols, 3.2 * nrows))
    for a, resp in enumerate(responses):
        ax = axes[a // cols][a % cols]
        by_name = {d["variant"]: d for d in data if d["response"] == resp}
        values = [float(by_name[v]["value"]) if by_name[v]["value"] else np.nan for v in names]
        colours = ["0.45"] + [f"C{i % 10}" for i in range(len(names) - 1)]
        bars = ax.bar(range(len(names)), np.nan_to_num(values), color=colours,
                      edgecolor="black", linewidth=0.6)
        bars[0].set_hatch("//")
        if np.isfinite(values[0]):
            ax.axhline(values[0], color="0.3", lw=0.8, ls="--")
        for i, v in enumerate(names):
            percent = by_name[v]["percent"]
            if not np.isfinite(values[i]):
                label = "no value"
            elif i == 0:
                label = f"{values[0]:.4g}"
            elif percent:
                p = float(percent)
                label = f"{p:+.1f} %" if abs(p) >= 0.1 or p == 0 else f"{p:+.1g} %"
            else:  # a zero or missing baseline
                label = f"{float(by_name[v]['difference']):+.3g}" if by_name[v]["difference"] else ""
            y = values[i] if np.isfinite(values[i]) else 0.0
            ax.annotate(label, (i, y), xytext=(0, 3 if y >= 0 else -3), textcoords="offset points",
                        ha="center", va="bottom" if y >= 0 else "top", fontsize=7)
        ax.set_xticks(range(len(names)), names, rotation=30, ha="right", fontsize=8)
        unit = analysis["responses"].get(resp, {}).get("unit", "")
        ax.set_ylabel(resp + (f" [{unit}]" if unit else ""), fontsize=8)
        ax.margins(y=0.15)
        ax.grid(axis="y", alpha=0.3)
    for a in range(len(responses), nrows * cols):
        axes[a // cols][a % cols].set_visible(False)
    fig.suptitle(f"Variants against the baseline, {names[0]} (hatched): percent difference")
    if described:
        fig.text(0.01, 0.005, "\n".join(f"{v['name']}: {v['description']}" for v in described),
                 fontsize=7, va="bottom")
        fig.tight_layout(rect=(0, 0.04 * len(described) / nrows + 0.02, 1, 1))
        fig.savefig(out, dpi=150)
        plt.close(fig)
    else:
        save(fig, out)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    folder = sys.argv[1]
    if not os.path.exists(os.path.join(folder, "analysis.json")):
        sys.exit(f"plot-study: {folder} has no analysis.json: run `nct study` to the end first")
    plots = os.path.join(folder, "plots")
    os.makedirs(plots, exist_ok=True)
    analysis = json.load(open(os.path.join(folder, "analysis.json")))
    if analysis["design"] == "ablation":
        variants(folder, os.path.join(plots, "variants.png"))
    else:
        correlation(folder, os.path.join(plots, "correlation.png"))
        main_effects(folder, os.path.join(plots, "main_effects.png"))
        pareto(folder, os.path.join(plots, "pareto.png"))
    print(f"plot-study: {analysis['design']}, {analysis['cases']} cases -> {plots}")


if __name__ == "__main__":
    main()
