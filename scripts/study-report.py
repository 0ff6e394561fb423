#!/usr/bin/python3
"""A study's rankings as Markdown (for docs/studies.md).

    /usr/bin/python3 scripts/study-report.py STUDY_FOLDER [TERMS]

prints, per response, the TERMS (default 8) largest effects with their
share of the sum of squares and p (factorial), then the cases' wall time;
for an ablation, one table: per response, each variant's value and its
difference from the baseline (absolute and in percent).
"""
import csv
import json
import os
import sys

folder = sys.argv[1]
show = int(sys.argv[2]) if len(sys.argv) > 2 else 8
analysis = json.load(open(os.path.join(folder, "analysis.json")))
cases = list(csv.DictReader(open(os.path.join(folder, "cases.csv"))))
anova = {}
if os.path.exists(os.path.join(folder, "anova.csv")):
    for a in csv.DictReader(open(os.path.join(folder, "anova.csv"))):
        anova[a["response"], a["source"]] = a


def ablation_table():
    """Responses down, variants across: the baseline's value, then each
    other variant's value, difference and percent."""
    names = [v["name"] for v in analysis["variants"]]
    head = f"| response | {names[0]} |"
    rule = "|---|---|"
    for n in names[1:]:
        head += f" {n} | difference | % |"
        rule += "---|---|---|"
    print(head + "\n" + rule)
    fmt = lambda v, sign="": "-" if v is None else f"{v:{sign}.4g}"
    for name in [c for c in cases[0] if c in analysis["responses"]]:  # the study's order
        r = analysis["responses"][name]
        row = {v["variant"]: v for v in r["variants"]}
        unit = f" [{r['unit']}]" if r["unit"] else ""
        line = f"| {name}{unit} | {fmt(row[names[0]]['value'])} |"
        for n in names[1:]:
            v = row[n]
            pct = "-" if v["percent"] is None else f"{v['percent']:+.1f}"
            line += f" {fmt(v['value'])} | {fmt(v['difference'], '+')} | {pct} |"
        print(line)
    print()
    for v in analysis["variants"]:
        print(f"- `{v['name']}`: {v.get('description', '')}")
    print()


if analysis["design"] == "ablation":
    ablation_table()
    walls = [float(c["wall_s"]) for c in cases if c["wall_s"] != "nan"]
    print(f"{[c['status'] for c in cases].count('converged')} of {len(cases)} converged; "
          f"wall time per case {min(walls):.0f} to {max(walls):.0f} s")
    sys.exit(0)
print(f"{analysis['design']}, {analysis['cases']} cases; error term: {analysis['error_term']}\n")
for name in [c for c in cases[0] if c in analysis["responses"]]:  # the study's order
    r = analysis["responses"][name]
    values = [float(c[name]) for c in cases if c[name] != "nan"]
    print(f"**{name}** (range {min(values):.4g} to {max(values):.4g})\n")
    if "constant" in r:
        print(f"{r['constant']} in every case: no effects\n")
        continue
    if "skipped" in r:
        print(f"not analysed: {r['skipped']}\n")
        continue
    print("| rank | term | effect | % of SS | p |\n|---|---|---|---|---|")
    for i, term in enumerate(r["ranking"][:show]):
        t = r["terms"][term]
        a = anova.get((name, term))
        share = f"{float(a['percent']):.1f}" if a else ""
        p = a["p"] if a and a["p"] not in ("", "nan") else ""
        p = f"{float(p):.2g}" if p else ""
        print(f"| {i + 1} | {term} | {t['effect']:+.4g} | {share} | {p} |")
    print()
walls = [float(c["wall_s"]) for c in cases if c["wall_s"] != "nan"]
status = [c["status"] for c in cases]
print(f"{status.count('converged')} of {len(cases)} converged; wall time per case "
      f"{min(walls):.0f} to {max(walls):.0f} s (mean {sum(walls) / len(walls):.0f} s)")
