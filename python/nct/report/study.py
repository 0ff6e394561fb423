"""A study's page: its design, each case's status and cost, the main
effects and interactions, the ANOVA table or the ablation's differences."""
import numpy as np

from .. import study as figures
from ..folders import Study
from .page import Page, links, number


def _design(section, s):
    analysis = s.analysis
    spec = s.spec
    head = spec.get("study", {})
    rows = [["design", analysis["design"]], ["base scene", head.get("scene", "-")],
            ["cases", str(analysis["cases"])],
            ["every case sets", ", ".join(head.get("set", [])) or "-"],
            ["ranks per case, cases at once", f"{head.get('ranks', '-')}, {head.get('jobs', '-')}"],
            ["responses", ", ".join(s.responses)]]
    if "error_term" in analysis:
        rows.append(["error term", analysis["error_term"]])
    section.table(["", "study"], rows, "design")
    factors = spec.get("factor", [])
    if factors:
        section.table(["factor", "scene keys", "levels"],
                      [[f["label"], ", ".join(f["key"]) if isinstance(f["key"], list) else f["key"],
                        ", ".join(f"{v:g}" if isinstance(v, (int, float)) else str(v)
                                  for v in f.get("levels", []))] for f in factors],
                      "factors")
    if analysis["design"] == "ablation":
        section.table(["variant", "what it changes", "sets"],
                      [[v["name"], v.get("description", ""), ", ".join(v.get("set", [])) or "-"]
                       for v in analysis["variants"]], "variants")


def _cases(section, s):
    cases = s.cases
    factors = [f for f in s.factors if f in cases.columns]
    head = ["case", "status"] + factors + ["Newton iterations", "step cuts", "wall [s]"]
    rows, flags = [], set()
    for i, r in enumerate(cases.rows()):
        if r["status"] != "converged":
            flags.add(i)
        rows.append([r["case"], r["status"]] + [number(r[f]) for f in factors]
                    + [number(r.get("newton_iterations"), 6), number(r.get("step_cuts"), 3),
                       number(r.get("wall_s"), 3)])
    section.table(head, rows, "cases", flags)
    walls = cases["wall_s"][np.isfinite(cases["wall_s"])] if "wall_s" in cases.columns else []
    done = list(cases["status"]).count("converged")
    text = f"{done} of {len(cases)} cases converged"
    if len(walls):
        text += (f"; wall time per case {min(walls):.1f} to {max(walls):.1f} s, "
                 f"{sum(walls):.0f} s in all")
    section.paragraph(text + ". Each case's run folder: cases/<case>; failed rows are marked.",
                      "note")


def _anova(section, s):
    table = s.table("anova.csv")
    if table is None:
        return section.paragraph("No ANOVA table (anova.csv): a factorial design gives one.",
                                 "note")
    by = {}
    for r in table.rows():
        by.setdefault(r["response"], {})[r["source"]] = r
    sources = [k for k in next(iter(by.values())) if k not in ("error", "total")] if by else []
    head = ["response"] + [f"{k}: % of SS (p)" for k in sources] + ["error df", "total SS"]
    rows = []
    for response, terms in by.items():
        cells = [response]
        for k in sources:
            t = terms.get(k, {})
            p = t.get("p")
            cells.append(number(t.get("percent"), 3) + (f" ({p:.2g})" if isinstance(p, float)
                                                         and p == p else ""))
        cells += [number(terms.get("error", {}).get("df"), 3),
                  number(terms.get("total", {}).get("sum_sq"))]
        rows.append(cells)
    section.table(head, rows, "anova")
    section.paragraph("Each term's share of the total sum of squares, with the F test's p where "
                      "the error term has degrees of freedom (anova.csv: df, sums of squares, "
                      "mean squares, F).", "note")
    if s.analysis.get("error_term"):
        section.paragraph("Error term: " + s.analysis["error_term"], "note")


def _ablation(section, s):
    analysis = s.analysis
    names = [v["name"] for v in analysis["variants"]]
    head = ["response", "baseline" if names[0] == "baseline" else f"{names[0]} (baseline)"]
    for n in names[1:]:
        head += [n, "difference", "%"]
    rows = []
    for name in s.responses:
        r = analysis["responses"][name]
        by = {v["variant"]: v for v in r["variants"]}
        row = [name + (f" [{r['unit']}]" if r.get("unit") else ""), number(by[names[0]]["value"])]
        for n in names[1:]:
            v = by[n]
            row += [number(v["value"]), number(v["difference"], 4, "+"),
                    number(v["percent"], 3, "+")]
        rows.append(row)
    section.table(head, rows, "ablation")


def page(folder):
    s = Study(folder)
    analysis = s.analysis
    page = Page("study", f"Study {s.folder.resolve().name}",
                f"{s.folder.resolve()}: {analysis['design']}, {analysis['cases']} cases")
    _design(page.section("design", "Design"), s)
    _cases(page.section("cases", "Cases: status and cost"), s)
    made = dict(figures.figures(s))
    if analysis["design"] == "ablation":
        sec = page.section("ablation", "The ablation's differences")
        _ablation(sec, s)
        if "variants" in made:
            sec.figure(made["variants"], "Each variant against the baseline (hatched), with "
                       "its percent difference", "variants")
    else:
        sec = page.section("effects", "Main effects and interactions")
        for name, caption in (("main_effects", "The mean response at each level of each "
                               "factor"), ("pareto", "The terms' effects, largest first, with "
                               "the cumulative share")):
            if name in made:
                sec.figure(made[name], caption, name)
        for name, fig in figures.interaction_figures(s):
            sec.figure(fig, "Interaction plots of " + name[len("interactions_"):], name)
        if not sec.parts:
            sec.paragraph("No effects: the study analysed no response.", "note")
        if analysis["design"] == "factorial":
            _anova(page.section("anova", "ANOVA"), s)
    if "correlation" in made:
        page.section("correlation", "Correlations").figure(
            made["correlation"], "Pearson correlations of the factors and responses over the "
            "cases", "correlation")
    tables = links(s.folder, ("study.toml", "cases.csv", "analysis.json", "effects.csv",
                              "anova.csv", "main_effects.csv", "correlation.csv", "ablation.csv"))
    page.section("files", "Files").raw(f"<p>Tables: {tables}</p>")
    return page
