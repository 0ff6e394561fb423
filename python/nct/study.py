"""A study's plots and its report (the tables `nct study` writes).

    figures(folder)       # [(name, matplotlib figure)], as the report shows them
    plot(folder)          # the same as FOLDER/plots/*.png; returns the paths written
    report(folder, 8)     # the rankings (or the ablation's table) as Markdown

The figures, for a factorial or one-factor-at-a-time study:
- correlation.png: the Pearson correlation matrix of factors and
  responses as circles (area ~ |r|, colour = r; the values printed up to
  14 names);
- main_effects.png: per response, the mean response at each factor's
  levels (low to high), a line per factor;
- pareto.png: per response, the terms' |effect| largest first, with the
  cumulative share of the explained sum of squares (factorial) or of the
  |effects| (one factor at a time);
for a table design (design = "table": the cases of a CSV file), its
correlation.png alone; for an ablation (design = "ablation"):
- variants.png: one panel per response, a bar per variant (the baseline
  first, hatched, labelled with its value), each other labelled with its
  percent difference from the baseline (its difference where the baseline
  is 0).
"""
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .figures import save_png  # noqa: E402
from .folders import Study  # noqa: E402
from .tables import read_csv  # noqa: E402


def _correlation(study):
    if study.correlation is None:
        print("study figures: no correlation.csv (fewer than 3 complete cases)")
        return None
    names, r = study.correlation
    m = len(names)
    fig, ax = plt.subplots(figsize=(1.0 + 0.8 * m, 0.6 + 0.8 * m))
    cmap = plt.get_cmap("RdBu_r")
    j, i = np.meshgrid(range(m), range(m))
    ok = np.isfinite(r)
    # One collection of circles, area ~ |r|: sized once the layout is done.
    dots = ax.scatter(j[ok], i[ok], c=r[ok], cmap=cmap, vmin=-1, vmax=1, linewidths=0)
    for a, b in zip(*np.nonzero(~ok)):
        ax.text(b, a, "-", ha="center", va="center", color="0.5")
    if m <= 14:  # the values too, where they fit
        for a, b in zip(*np.nonzero(ok)):
            ax.text(b, a, f"{r[a, b]:.2f}", ha="center", va="center", fontsize=7,
                    color="white" if abs(r[a, b]) > 0.6 else "black")
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
    fig.tight_layout()
    cell = ax.get_window_extent().width / m * 72 / fig.dpi  # a cell's width in points
    dots.set_sizes((0.9 * cell) ** 2 * np.abs(r[ok]))  # a circle of 0.9 cell at |r| = 1
    return fig


def _main_effects(study):
    # The levels as printed (text), the means as numbers.
    data = read_csv(study.folder / "main_effects.csv", numeric=False)
    if not len(data):
        print("study figures: no main effects (no response analysed)")
        return None
    responses = list(dict.fromkeys(data["response"]))
    factors = list(dict.fromkeys(data["factor"]))
    cols = min(5, len(responses))
    rows = -(-len(responses) // cols)
    fig, axes = plt.subplots(rows, cols, squeeze=False, figsize=(0.4 + 2.7 * cols, 0.9 + 2.3 * rows))
    for a, resp in enumerate(responses):
        ax = axes[a // cols][a % cols]
        width = 1
        for b, fac in enumerate(factors):
            pts = data.where((data["response"] == resp) & (data["factor"] == fac))
            width = max(width, len(pts))
            ax.plot(range(len(pts)), pts["mean"].astype(float), "o-", color=f"C{b % 10}",
                    label=fac)
        ax.set_xticks(range(width), ["low", "high"] if width == 2 else
                      [f"level {i + 1}" for i in range(width)], fontsize=7)
        ax.tick_params(axis="y", labelsize=7)
        ax.set_title(resp, fontsize=8)
        ax.grid(alpha=0.3)
    for a in range(len(responses), rows * cols):
        axes[a // cols][a % cols].set_visible(False)
    fig.legend(*axes[0][0].get_legend_handles_labels(), loc="upper right", fontsize=8,
               ncol=min(len(factors), 5))
    fig.suptitle("Main effects: the mean response at each factor's levels (the levels: "
                 "the design table)", fontsize=10, x=0.02, ha="left")
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.5 / (0.9 + 2.3 * rows)))
    return fig


def _pareto(study):
    effects = study.table("effects.csv")
    if not len(effects):
        print("study figures: no effects (no response analysed)")
        return None
    responses = list(dict.fromkeys(effects["response"]))
    factorial = study.has("anova.csv")
    cols = min(4, len(responses))
    rows = -(-len(responses) // cols)
    height = 0.8 + 2.9 * rows
    fig, axes = plt.subplots(rows, cols, squeeze=False, figsize=(0.4 + 3.6 * cols, height))
    for a, resp in enumerate(responses):
        terms = effects.where(effects["response"] == resp)
        size = np.abs(terms["effect"])
        share = size**2 if factorial else size  # SS ~ effect^2 in a 2^k design
        cum = 100 * np.cumsum(share) / share.sum() if share.sum() > 0 else 0 * share
        ax = axes[a // cols][a % cols]
        colours = ["C3" if e < 0 else "C0" for e in terms["effect"]]
        ax.bar(range(len(terms)), size, color=colours)
        ax.set_xticks(range(len(terms)), list(terms["term"]), rotation=60, ha="right",
                      fontsize=7)
        ax.tick_params(axis="y", labelsize=7)
        ax.set_title(resp, fontsize=8)
        twin = ax.twinx()
        twin.plot(range(len(terms)), cum, "k.-", lw=1)
        twin.set_ylim(0, 105)
        twin.tick_params(axis="y", labelsize=7)
        if a % cols == cols - 1:
            twin.set_ylabel("cumulative %", fontsize=7)
    for a in range(len(responses), rows * cols):
        axes[a // cols][a % cols].set_visible(False)
    fig.suptitle("Pareto of effects: |effect| per term (blue: raises the response, red: "
                 "lowers it), the cumulative share (line)", fontsize=10, x=0.02, ha="left")
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.4 / height))
    return fig


def _variants(study):
    data = study.table("ablation.csv")
    analysis = study.analysis
    names = [v["name"] for v in analysis["variants"]]
    described = [v for v in analysis["variants"] if v["description"]]
    responses = list(dict.fromkeys(data["response"]))
    cols = min(3, len(responses))
    nrows = -(-len(responses) // cols)
    fig, axes = plt.subplots(nrows, cols, squeeze=False,
                             figsize=(1.2 + (0.75 + 0.55 * len(names)) * cols, 3.2 * nrows))
    for a, resp in enumerate(responses):
        ax = axes[a // cols][a % cols]
        by_name = {d["variant"]: d for d in data.where(data["response"] == resp).rows()}
        values = [by_name[v]["value"] for v in names]
        colours = ["0.45"] + [f"C{i % 10}" for i in range(len(names) - 1)]
        bars = ax.bar(range(len(names)), np.nan_to_num(values), color=colours,
                      edgecolor="black", linewidth=0.6)
        bars[0].set_hatch("//")
        if np.isfinite(values[0]):
            ax.axhline(values[0], color="0.3", lw=0.8, ls="--")
        for i, v in enumerate(names):
            percent, difference = by_name[v]["percent"], by_name[v]["difference"]
            if not np.isfinite(values[i]):
                label = "no value"
            elif i == 0:
                label = f"{values[0]:.4g}"
            elif np.isfinite(percent):
                label = f"{percent:+.1f} %" if abs(percent) >= 0.1 or percent == 0 \
                    else f"{percent:+.1g} %"
            else:  # a zero or missing baseline
                label = f"{difference:+.3g}" if np.isfinite(difference) else ""
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
    else:
        fig.tight_layout()
    return fig


def _interactions(study, response):
    """Per pair of factors (A, B): the mean response at each level of A,
    a line per level of B (parallel lines: no interaction)."""
    cases = study.cases
    factors = [f for f in study.factors if f in cases.columns]
    pairs = [(a, b) for i, a in enumerate(factors) for b in factors[i + 1:]]
    if not pairs or response not in cases.columns:
        return None
    ok = np.isfinite(cases[response])
    cols = min(4, len(pairs))
    rows = -(-len(pairs) // cols)
    fig, axes = plt.subplots(rows, cols, squeeze=False, sharey=True,
                             figsize=(0.6 + 2.9 * cols, 0.6 + 2.5 * rows))
    for k, (a, b) in enumerate(pairs):
        ax = axes[k // cols][k % cols]
        levels_a = sorted(set(cases[a][ok].tolist()))
        for j, lb in enumerate(sorted(set(cases[b][ok].tolist()))):
            means = [np.mean(cases[response][ok & (cases[a] == la) & (cases[b] == lb)])
                     if np.any(ok & (cases[a] == la) & (cases[b] == lb)) else np.nan
                     for la in levels_a]
            ax.plot(range(len(levels_a)), means, "o-", color=f"C{j}", label=f"{b} = {lb:g}")
        ax.set_xticks(range(len(levels_a)), [f"{v:g}" for v in levels_a], fontsize=8)
        ax.set_xlabel(a, fontsize=8)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        if k % cols == 0:
            ax.set_ylabel(response, fontsize=8)
    for k in range(len(pairs), rows * cols):
        axes[k // cols][k % cols].set_visible(False)
    fig.suptitle(f"Interactions: {response} (parallel lines: none)", fontsize=10)
    fig.tight_layout()
    return fig


def interaction_figures(folder, responses=3):
    """[(name, figure)]: the interaction plots of the study's first
    responses (a factorial or one-factor-at-a-time study with 2+ factors)."""
    study = folder if isinstance(folder, Study) else Study(folder)
    if study.analysis["design"] in ("ablation", "table"):
        return []
    made = [(f"interactions_{r}", _interactions(study, r)) for r in study.responses[:responses]]
    return [(name, fig) for name, fig in made if fig is not None]


def figures(folder):
    """The study's figures as [(name, matplotlib figure)]: an ablation's
    variants; a table design's correlation; else the correlation, the main
    effects and the Pareto of effects (each where its table exists)."""
    study = folder if isinstance(folder, Study) else Study(folder)
    if study.analysis["design"] == "ablation":
        made = [("variants", _variants(study))]
    elif study.analysis["design"] == "table":
        made = [("correlation", _correlation(study))]
    else:
        made = [("correlation", _correlation(study)), ("main_effects", _main_effects(study)),
                ("pareto", _pareto(study))]
    return [(name, fig) for name, fig in made if fig is not None]


def plot(folder):
    """The study's figures as PNGs into FOLDER/plots; returns the paths."""
    plots = pathlib.Path(folder) / "plots"
    plots.mkdir(exist_ok=True)
    return save_png(figures(folder), plots, dpi=150)


def _number(v, sign=""):
    return "-" if v is None else f"{v:{sign}.4g}"


def ablation_table(study):
    """Responses down, variants across: the baseline's value, then each
    other variant's value, difference and percent; then the variants'
    descriptions."""
    analysis = study.analysis
    names = [v["name"] for v in analysis["variants"]]
    head = f"| response | {names[0]} |"
    rule = "|---|---|"
    for n in names[1:]:
        head += f" {n} | difference | % |"
        rule += "---|---|---|"
    lines = [head, rule]
    for name in study.responses:
        r = analysis["responses"][name]
        row = {v["variant"]: v for v in r["variants"]}
        unit = f" [{r['unit']}]" if r["unit"] else ""
        line = f"| {name}{unit} | {_number(row[names[0]]['value'])} |"
        for n in names[1:]:
            v = row[n]
            pct = "-" if v["percent"] is None else f"{v['percent']:+.1f}"
            line += f" {_number(v['value'])} | {_number(v['difference'], '+')} | {pct} |"
        lines.append(line)
    lines.append("")
    lines += [f"- `{v['name']}`: {v.get('description', '')}" for v in analysis["variants"]]
    return "\n".join(lines)


def rankings(study, terms=8):
    """Per response, the largest effects with their share of the sum of
    squares and p (factorial)."""
    analysis, cases = study.analysis, study.cases
    anova = {}
    table = study.table("anova.csv")
    if table is not None:
        anova = {(a["response"], a["source"]): a for a in table.rows()}
    lines = [f"{analysis['design']}, {analysis['cases']} cases; "
             f"error term: {analysis.get('error_term', 'none')}\n"]
    for name in study.responses:
        r = analysis["responses"][name]
        values = cases[name][np.isfinite(cases[name])]
        lines.append(f"**{name}** (range {min(values):.4g} to {max(values):.4g})\n")
        if "constant" in r:
            lines.append(f"{r['constant']} in every case: no effects\n")
            continue
        if "skipped" in r:
            lines.append(f"not analysed: {r['skipped']}\n")
            continue
        lines.append("| rank | term | effect | % of SS | p |\n|---|---|---|---|---|")
        for i, term in enumerate(r["ranking"][:terms]):
            a = anova.get((name, term))
            share = f"{a['percent']:.1f}" if a else ""
            p = f"{a['p']:.2g}" if a and np.isfinite(a["p"]) else ""
            effect = r["terms"][term]["effect"]
            lines.append(f"| {i + 1} | {term} | {effect:+.4g} | {share} | {p} |")
        lines.append("")
    return "\n".join(lines)


def report(folder, terms=8):
    """The study as Markdown: an ablation's table, or the factorial's (or
    one-factor-at-a-time's) rankings; then the cases' status and wall time."""
    study = Study(folder)
    cases = study.cases
    walls = cases["wall_s"][np.isfinite(cases["wall_s"])]
    status = f"{list(cases['status']).count('converged')} of {len(cases)} converged"
    if len(walls):
        status += f"; wall time per case {min(walls):.0f} to {max(walls):.0f} s"
    if study.analysis["design"] == "ablation":
        return ablation_table(study) + "\n\n" + status
    if study.analysis["design"] == "table":
        return f"{len(cases)} cases from a table (cases.csv: their values and responses); " + status
    if len(walls):
        status += f" (mean {sum(walls) / len(walls):.0f} s)"
    return rankings(study, terms) + "\n" + status
