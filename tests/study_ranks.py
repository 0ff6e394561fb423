"""A study whose cases run on 2 ranks each agrees with the same study on 1.

study_ranks.py NCT STUDY ONE_RANK_FOLDER OUT

Runs STUDY again with study.ranks = 2 (through mpiexec) into OUT and
compares every physical response of the case summaries with ONE_RANK_FOLDER's
(the study_resume test's): 1e-8 relative or 1e-9 absolute (mm, ms, mmHg),
as the scene tests' rank comparisons.
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import read_json  # noqa: E402
from nct.tables import read_csv  # noqa: E402

nct, study, one, out = sys.argv[1:5]
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
text = open(study).read()
text = re.sub(r"ranks = 1", "ranks = 2", text)
text = re.sub(r"jobs = 2", 'jobs = 1\nmpiexec = "mpiexec --bind-to none --oversubscribe --allow-run-as-root"', text)
text = text.replace('"../../scenes/', '"' + os.path.dirname(os.path.abspath(study)) + "/../../scenes/")
two_ranks = os.path.join(out, "study.toml.in")
open(two_ranks, "w").write(text)
r = subprocess.run([nct, "study", two_ranks, "--out", out, "--no-report"], capture_output=True,
                   text=True)
print(r.stdout, r.stderr)
assert r.returncode == 0, f"nct study exited with {r.returncode}"
ranks = [open(os.path.join(out, "cases", c, "summary.json")).read() for c in sorted(os.listdir(os.path.join(out, "cases")))]
assert all('"ranks": 2' in s for s in ranks), "the cases did not run on 2 ranks"

# Full precision: the summaries, for the responses of cases.csv.
names = [k for k in read_csv(os.path.join(one, "cases.csv")).columns
         if k not in {"case", "status", "wall_s", "newton_iterations", "step_cuts"}]
worst = 0.0
for case in sorted(os.listdir(os.path.join(out, "cases"))):
    x = read_json(os.path.join(one, "cases", case, "summary.json"))
    y = read_json(os.path.join(out, "cases", case, "summary.json"))
    for k in names:
        if k not in x and k not in y:  # e.g. no applanation in either
            continue
        u, v = float(x[k]), float(y[k])
        diff = abs(u - v)
        assert diff <= max(1e-8 * abs(u), 1e-9), f"{case} {k}: 1 rank {u}, 2 ranks {v}"
        worst = max(worst, diff / max(abs(u), 1e-300))
print(f"study_ranks: 1 and 2 ranks per case agree (largest relative difference {worst:.1e})")
