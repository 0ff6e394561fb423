"""A study's plots and its report (the tables `nct study` writes).

    plot(folder)          # FOLDER/plots/*.png; returns the paths written
    report(folder, 8)     # the rankings (or the ablation's table) as Markdown

plot writes, for a factorial or one-factor-at-a-time study:
- correlation.png: the Pearson correlation matrix of factors and
  responses as circles (area ~ |r|, colour = r);
- main_effects.png: the mean response at each level of each factor, one
  row per response, on a shared axis per row;
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
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .folders import Study  # noqa: E402
from .tables import read_csv  # noqa: E402


def _save(fig, out):
    fig.tight_layout()
    fig.savefig(out, dpi=150)
    plt.close(fig)


def _correlation(study, out):
    if study.correlation is None:
        print("plot-study: no correlation.csv (fewer than 3 complete cases)")
        return None
    names, r = study.correlation
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
    _save(fig, out)
    return out


def _main_effects(study, out):
    # The levels as printed (text), the means as numbers.
    data = read_csv(study.folder / "main_effects.csv", numeric=False)
    if not len(data):
        print("plot-study: no main effects (no response analysed)")
        return None
    responses = list(dict.fromkeys(data["response"]))
    factors = list(dict.fromkeys(data["factor"]))
    fig, axes = plt.subplots(len(responses), len(factors), squeeze=False, sharey="row",
                             figsize=(2.2 * len(factors), 2.2 * len(responses)))
    for a, resp in enumerate(responses):
        for b, fac in enumerate(factors):
            pts = data.where((data["response"] == resp) & (data["factor"] == fac))
            ax = axes[a][b]
            ax.plot(range(len(pts)), pts["mean"].astype(float), "o-", color="C0")
            ax.set_xticks(range(len(pts)), list(pts["level"]), fontsize=8)
            ax.grid(alpha=0.3)
            if a == len(responses) - 1:
                ax.set_xlabel(fac)
            if b == 0:
                ax.set_ylabel(resp, fontsize=8)
    fig.suptitle("Main effects: mean response at each level")
    _save(fig, out)
    return out


def _pareto(study, out):
    effects = study.table("effects.csv")
    if not len(effects):
        print("plot-study: no effects (no response analysed)")
        return None
    responses = list(dict.fromkeys(effects["response"]))
    factorial = study.has("anova.csv")
    fig, axes = plt.subplots(len(responses), 1, squeeze=False,
                             figsize=(8, 2.8 * len(responses)))
    for a, resp in enumerate(responses):
        terms = effects.where(effects["response"] == resp)
        size = np.abs(terms["effect"])
        share = size**2 if factorial else size  # SS ~ effect^2 in a 2^k design
        cum = 100 * np.cumsum(share) / share.sum() if share.sum() > 0 else 0 * share
        ax = axes[a][0]
        colours = ["C3" if e < 0 else "C0" for e in terms["effect"]]
        ax.bar(range(len(terms)), size, color=colours)
        ax.set_xticks(range(len(terms)), list(terms["term"]), rotation=60, ha="right",
                      fontsize=7)
        ax.set_ylabel(f"|effect|\n{resp}", fontsize=8)
        twin = ax.twinx()
        twin.plot(range(len(terms)), cum, "k.-", lw=1)
        twin.set_ylim(0, 105)
        twin.set_ylabel("cumulative %", fontsize=8)
    axes[0][0].set_title("Pareto of effects (blue: raises the response, red: lowers it)")
    _save(fig, out)
    return out


def _variants(study, out):
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
        fig.savefig(out, dpi=150)
        plt.close(fig)
    else:
        _save(fig, out)
    return out


def plot(folder):
    """The study's plots into FOLDER/plots; returns the paths written."""
    study = Study(folder)
    plots = study.folder / "plots"
    plots.mkdir(exist_ok=True)
    if study.analysis["design"] == "ablation":
        written = [_variants(study, plots / "variants.png")]
    elif study.analysis["design"] == "table":
        written = [_correlation(study, plots / "correlation.png")]
    else:
        written = [_correlation(study, plots / "correlation.png"),
                   _main_effects(study, plots / "main_effects.png"),
                   _pareto(study, plots / "pareto.png")]
    return [p for p in written if p]


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
