"""A study whose cases run on 2 ranks each agrees with the same study on 1.

study_ranks.py NCT STUDY ONE_RANK_FOLDER OUT

Runs STUDY again with study.ranks = 2 (through mpiexec) into OUT and
compares every physical response of cases.csv with ONE_RANK_FOLDER's
(the study_resume test's): 1e-8 relative or 1e-9 absolute (mm, ms, mmHg),
as the scene tests' rank comparisons.
"""
import csv
import math
import os
import re
import shutil
import subprocess
import sys

nct, study, one, out = sys.argv[1:5]
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
text = open(study).read()
text = re.sub(r"ranks = 1", "ranks = 2", text)
text = re.sub(r"jobs = 2", 'jobs = 1\nmpiexec = "mpiexec --bind-to none --oversubscribe --allow-run-as-root"', text)
text = text.replace('"../../scenes/', '"' + os.path.dirname(os.path.abspath(study)) + "/../../scenes/")
two_ranks = os.path.join(out, "study.toml.in")
open(two_ranks, "w").write(text)
r = subprocess.run([nct, "study", two_ranks, "--out", out], capture_output=True, text=True)
print(r.stdout, r.stderr)
assert r.returncode == 0, f"nct study exited with {r.returncode}"
ranks = [open(os.path.join(out, "cases", c, "summary.json")).read() for c in sorted(os.listdir(os.path.join(out, "cases")))]
assert all('"ranks": 2' in s for s in ranks), "the cases did not run on 2 ranks"

a = list(csv.DictReader(open(os.path.join(one, "cases.csv"))))
b = list(csv.DictReader(open(os.path.join(out, "cases.csv"))))
skip = {"case", "status", "wall_s", "newton_iterations", "step_cuts"}
worst = 0.0
for x, y in zip(a, b, strict=True):
    for k in x:
        if k in skip:
            continue
        u, v = float(x[k]), float(y[k])
        if math.isnan(u) and math.isnan(v):
            continue
        diff = abs(u - v)
        assert diff <= max(1e-8 * abs(u), 1e-9), f"{x['case']} {k}: 1 rank {u}, 2 ranks {v}"
        worst = max(worst, diff / max(abs(u), 1e-300))
print(f"study_ranks: 1 and 2 ranks per case agree (largest relative difference {worst:.1e})")
