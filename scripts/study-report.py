#!/usr/bin/python3
"""A study's rankings as Markdown (for docs/studies.md).

    /usr/bin/python3 scripts/study-report.py STUDY_FOLDER [TERMS]

prints, per response, the TERMS (default 8) largest effects with their
share of the sum of squares and p (factorial), then the cases' wall time.
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
