"""An ablation study interrupted, resumed, and its table recomputed.

study_ablation.py NCT STUDY OUT

Starts `nct study` on an ablation of the default scene's section (three variants),
interrupts it (SIGINT) once a case has finished, and checks that it
stopped (exit 130) with the finished cases on disk. Run again, it must
run only the rest (the finished summaries untouched); then cases.csv
names each case's variant and ablation.csv holds, per variant and
response, the value of the case's own summary.json, its difference from
the baseline's and the percent of |baseline| (empty where either value is
missing or the baseline is 0), recomputed here; analysis.json the same.
"""
import glob
import math
import os
import shutil
import subprocess
import sys
import time

from study_interrupt import interrupt_after_first_case
import tomllib

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import read_json  # noqa: E402
from nct.tables import read_csv  # noqa: E402

nct, study, out = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(out, ignore_errors=True)
spec = tomllib.load(open(study, "rb"))
variants = [v["name"] for v in spec["variant"]]
responses = spec["study"]["responses"]
n = len(variants)

# 1. Interrupt once a case has finished.
interrupt_after_first_case(nct, study, out)
done = {f: os.stat(f).st_mtime_ns for f in glob.glob(os.path.join(out, "cases", "*", "summary.json"))}
assert 1 <= len(done) < n, f"{len(done)} cases finished before the interruption"
assert not os.path.exists(os.path.join(out, "ablation.csv"))

# 2. Resume: only the rest runs.
r = subprocess.run([nct, "study", study, "--out", out], capture_output=True, text=True)
print(r.stdout, r.stderr)
assert r.returncode == 0, f"resumed: exit {r.returncode}, expected 0"
assert f"ablation, {n} variants, {n} cases ({len(done)} already done)" in r.stdout
for f, mtime in done.items():
    assert os.stat(f).st_mtime_ns == mtime, f"{f} was redone"
for name in variants[1:]:
    assert f"\n  {name} " in r.stdout, f"no console row for {name}"
for stale in ("effects.csv", "anova.csv", "main_effects.csv", "correlation.csv"):
    assert not os.path.exists(os.path.join(out, stale)), f"an ablation wrote {stale}"

# 3. cases.csv: a case per variant, in order.
rows = read_csv(os.path.join(out, "cases.csv"), numeric=False).rows()
assert [row["variant"] for row in rows] == variants, rows
assert [row["status"] for row in rows] == ["converged"] * n
cases = sorted(os.listdir(os.path.join(out, "cases")))
assert cases == [f"case-{i + 1:03d}" for i in range(n)], cases
summary = [read_json(os.path.join(out, "cases", c, "summary.json")) for c in cases]
for c, name in zip(cases, variants):
    sets = read_json(os.path.join(out, "cases", c, "case.json"))["sets"]
    own = next(v for v in spec["variant"] if v["name"] == name).get("set", [])
    assert sets == spec["study"].get("set", []) + own, f"{c}: {sets}"

# 4. ablation.csv against the summaries: value, value - baseline and
# 100 (value - baseline) / |baseline|.
table = read_csv(os.path.join(out, "ablation.csv"), numeric=False).rows()
assert [(t["variant"], t["response"]) for t in table] == [(v, q) for v in variants for q in responses]
analysis = read_json(os.path.join(out, "analysis.json"))
assert analysis["design"] == "ablation" and analysis["baseline"] == variants[0]
assert [v["name"] for v in analysis["variants"]] == variants
assert [v["description"] for v in analysis["variants"]] == [v.get("description", "") for v in spec["variant"]]


def close(a, b):
    return abs(a - b) <= 1e-8 * max(abs(a), abs(b)) + 1e-12


def value(s, q):
    v = s.get(q)
    return float(v) if isinstance(v, (int, float)) and math.isfinite(v) else None


checked = missing = 0
for t in table:
    i, q = variants.index(t["variant"]), t["response"]
    y, base = value(summary[i], q), value(summary[0], q)
    js = next(e for e in analysis["responses"][q]["variants"] if e["variant"] == t["variant"])
    if y is None:
        assert t["value"] == t["difference"] == t["percent"] == "", t
        assert js["value"] is None and js["difference"] is None
        missing += 1
        continue
    assert close(float(t["value"]), y) and close(js["value"], y), (t, y)
    if base is None:
        assert t["difference"] == t["percent"] == "", t
        continue
    assert close(float(t["difference"]), y - base) and close(js["difference"], y - base), (t, y, base)
    if base == 0:
        assert t["percent"] == "" and js["percent"] is None, t
    else:
        want = 100 * (y - base) / abs(base)
        assert close(float(t["percent"]), want) and close(js["percent"], want), (t, want)
    if i == 0:
        assert float(t["difference"]) == 0
    checked += 1
# The variants do differ: the stiffer cornea deflects less.
d = {(t["variant"], t["response"]): t for t in table}
assert float(d[("stiff_cornea", "deflection_amplitude_mm")]["difference"]) < 0

# 5. Nothing left to run: the analysis alone, the same table.
start = time.time()
r = subprocess.run([nct, "study", study, "--out", out], capture_output=True, text=True)
assert r.returncode == 0 and f"{n} cases ({n} already done)" in r.stdout, r.stdout + r.stderr
assert time.time() - start < 10
assert read_csv(os.path.join(out, "ablation.csv"), numeric=False).rows() == table
print(f"study_ablation: resumed without redoing {len(done)} case(s); {checked} comparisons "
      f"recomputed, {missing} missing values left empty")
