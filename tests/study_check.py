"""A study's tables against an independent computation.

study_check.py NCT SCENE OUT

Writes a 2^5 study whose 32 cases are already "run" (case folders with
synthetic summaries from a model with known effects and noise), lets
`nct study` analyse them (finished cases are kept, so nothing runs), and
compares its ANOVA, effects, main effects and correlations with a least
squares fit by numpy and F tests by scipy: effects are twice the
regression coefficients of the coded factors, each term's sum of squares
is the rise of the residual when it is dropped from the model (main
effects and two-way interactions), the error is the full model's
residual. Then one case is made to fail: the study must say so (exit 3)
and analyse nothing it cannot.
"""
import itertools
import json
import os
import shutil
import subprocess
import sys

import numpy as np
from scipy import stats

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import Study, read_json  # noqa: E402
from nct.tables import read_csv  # noqa: E402

nct, scene, out = sys.argv[1], os.path.abspath(sys.argv[2]), sys.argv[3]
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)

factors = [  # label, key, levels
    ("C10", "material.cornea.c10", [0.25, 0.75]),
    ("k1", "material.cornea.k1", [0.005, 0.015]),
    ("k2", "material.cornea.k2", [50.0, 150.0]),
    ("C10s", "material.sclera.c10", [0.4, 1.2]),
    ("IOP", "inflate.iop", [8.0, 22.0]),
]
responses = ["deflection_amplitude_mm", "peak_distance_mm"]
study = os.path.join(out, "study.toml.in")
with open(study, "w") as f:
    f.write(f'[study]\nscene = "{scene}"\nresponses = {json.dumps(responses)}\n')
    f.write('set = ["fem.degree=1"]\n')
    for label, key, levels in factors:
        f.write(f'[[factor]]\nlabel = "{label}"\nkey = "{key}"\nlevels = {levels}\n')

# Yates order: factor i at its second level in case c when bit i is set.
n, k = 32, 5
coded = np.array([[1 if (c >> i) & 1 else -1 for i in range(k)] for c in range(n)])
rng = np.random.default_rng(7)
y = {
    # IOP dominant, then C10, an interaction C10:IOP, noise
    "deflection_amplitude_mm": 1.0 - 0.2 * coded[:, 0] - 0.05 * coded[:, 1]
    - 0.4 * coded[:, 4] + 0.03 * coded[:, 0] * coded[:, 4] + 0.01 * rng.standard_normal(n),
    "peak_distance_mm": 4.0 + 0.5 * coded[:, 3] - 1.0 * coded[:, 4]
    + 0.2 * coded[:, 1] * coded[:, 2] + 0.05 * rng.standard_normal(n),
}


def write_cases(failed=None):
    for c in range(n):
        d = os.path.join(out, "cases", f"case-{c + 1:03d}")
        os.makedirs(d, exist_ok=True)
        sets = ["fem.degree=1"] + [
            f"{key}={repr(levels[(c >> i) & 1])}" for i, (_, key, levels) in enumerate(factors)]
        json.dump({"case": f"case-{c + 1:03d}", "sets": sets}, open(os.path.join(d, "case.json"), "w"))
        summary = {"status": "converged", "wall_s": 1.0}
        if c == failed:
            summary["status"] = "failed"
        else:
            summary.update({r: float(y[r][c]) for r in responses})
        json.dump(summary, open(os.path.join(d, "summary.json"), "w"))


def nct_study():
    r = subprocess.run([nct, "study", study, "--out", out, "--no-report"], capture_output=True, text=True)
    print(r.stdout, r.stderr)
    return r.returncode


def rows(name):
    return read_csv(os.path.join(out, name), numeric=False).rows()


write_cases()
code = nct_study()
assert code == 0, f"nct study exited with {code}"

# The independent fit: main effects and two-way interactions.
terms = [(i,) for i in range(k)] + list(itertools.combinations(range(k), 2))
labels = [f[0] for f in factors]
names = [":".join(labels[i] for i in t) for t in terms]


def columns(ts):
    return np.column_stack([np.ones(n)] + [np.prod(coded[:, list(t)], axis=1) for t in ts])


def rss(ts, v):
    X = columns(ts)
    beta, *_ = np.linalg.lstsq(X, v, rcond=None)
    return float(np.sum((v - X @ beta) ** 2)), beta


worst = 0.0


def close(got, want, what, tol=1e-9):
    global worst
    err = abs(got - want) / max(abs(want), 1e-12)
    worst = max(worst, err)
    assert err < tol, f"{what}: nct {got}, independent {want}"


anova = rows("anova.csv")
effects = rows("effects.csv")
for r in responses:
    v = y[r]
    rss_full, beta = rss(terms, v)
    df_error = n - 1 - len(terms)
    total = float(np.sum((v - v.mean()) ** 2))
    by_source = {a["source"]: a for a in anova if a["response"] == r}
    for j, (t, name) in enumerate(zip(terms, names)):
        ss = rss([u for u in terms if u != t], v)[0] - rss_full
        F = ss / (rss_full / df_error)
        p = stats.f.sf(F, 1, df_error)
        a = by_source[name]
        close(float(a["sum_sq"]), ss, f"{r} {name} SS")
        close(float(a["F"]), F, f"{r} {name} F", 1e-7)
        close(float(a["p"]), p, f"{r} {name} p", 1e-6)
        close(float(a["percent"]), 100 * ss / total, f"{r} {name} %")
        e = [x for x in effects if x["response"] == r and x["term"] == name][0]
        close(float(e["effect"]), 2 * beta[j + 1], f"{r} {name} effect")
    close(float(by_source["error"]["sum_sq"]), rss_full, f"{r} error SS")
    assert int(by_source["error"]["df"]) == df_error == 16
    close(float(by_source["total"]["sum_sq"]), total, f"{r} total SS")
    # The ranking is by size of effect.
    ranked = [x["term"] for x in effects if x["response"] == r]
    size = {x["term"]: abs(float(x["effect"])) for x in effects if x["response"] == r}
    assert ranked == sorted(ranked, key=lambda t: -size[t])
assert [x["term"] for x in effects if x["response"] == responses[0]][:2] == ["IOP", "C10"]

# Main effects: the mean response at each level.
for m in rows("main_effects.csv"):
    i = labels.index(m["factor"])
    level = factors[i][2].index(float(m["value"]))
    want = y[m["response"]][coded[:, i] == 2 * level - 1].mean()
    close(float(m["mean"]), want, f"main effect {m['response']} {m['factor']}")

# Pearson: numpy over factor values and responses.
values = np.column_stack([np.where(coded[:, i] > 0, f[2][1], f[2][0]) for i, f in enumerate(factors)]
                         + [y[r] for r in responses])
want = np.corrcoef(values.T)
names, corr = Study(out).correlation
assert names == labels + responses
for a, row in enumerate(corr):
    for b, x in enumerate(row):
        close(x, want[a, b], f"r({names[a]}, {names[b]})", 1e-9) if abs(
            want[a, b]) > 1e-12 else None
        assert abs(want[a, b]) > 1e-12 or abs(x) < 1e-12
print(f"study_check: ANOVA, effects, main effects and correlations agree (largest relative "
      f"difference {worst:.1e})")

# A failed case: the study says so and leaves the responses unanalysed.
write_cases(failed=6)
code = nct_study()
assert code == 3, f"a failed case: nct study exited with {code}, expected 3"
analysis = read_json(os.path.join(out, "analysis.json"))
for r in responses:
    assert "case-007" in analysis["responses"][r]["skipped"], analysis["responses"][r]
status = {row["case"]: row["status"] for row in rows("cases.csv")}
assert status["case-007"] == "failed" and list(status.values()).count("converged") == 31
print("study_check: a failed case is reported and its responses left unanalysed")

# One factor at a time: the base scene (IOP 15 mmHg, k2 100), then each
# level that differs from it. Each effect is y at the factor's highest
# value minus y at its lowest; the main effects are the single runs.
ofat_out = out + "_ofat"
shutil.rmtree(ofat_out, ignore_errors=True)
study = os.path.join(out, "ofat.toml.in")
with open(study, "w") as f:
    f.write(f'[study]\nscene = "{scene}"\ndesign = "ofat"\nresponses = ["hc_time_ms"]\n'
            '[[factor]]\nlabel = "IOP"\nkey = "inflate.iop"\nlevels = [10.0, 15.0, 20.0]\n'
            '[[factor]]\nlabel = "k2"\nkey = "material.cornea.k2"\nlevels = [50.0, 200.0]\n')
cases = [([], 9.0), (["inflate.iop=10.0"], 9.5), (["inflate.iop=20.0"], 8.8),
         (["material.cornea.k2=50.0"], 9.1), (["material.cornea.k2=200.0"], 8.7)]
for c, (sets, hc) in enumerate(cases):
    d = os.path.join(ofat_out, "cases", f"case-{c + 1:03d}")
    os.makedirs(d)
    json.dump({"case": f"case-{c + 1:03d}", "sets": sets}, open(os.path.join(d, "case.json"), "w"))
    json.dump({"status": "converged", "hc_time_ms": hc}, open(os.path.join(d, "summary.json"), "w"))
r = subprocess.run([nct, "study", study, "--out", ofat_out, "--no-report"], capture_output=True, text=True)
print(r.stdout, r.stderr)
assert r.returncode == 0, f"ofat: nct study exited with {r.returncode}"
out = ofat_out
effects = {e["term"]: float(e["effect"]) for e in rows("effects.csv")}
close(effects["IOP"], 8.8 - 9.5, "ofat IOP effect")
close(effects["k2"], 8.7 - 9.1, "ofat k2 effect")
mains = [(m["factor"], float(m["value"]), float(m["mean"])) for m in rows("main_effects.csv")]
assert mains == [("IOP", 10, 9.5), ("IOP", 15, 9.0), ("IOP", 20, 8.8),
                 ("k2", 50, 9.1), ("k2", 100, 9.0), ("k2", 200, 8.7)], mains
assert not os.path.exists(os.path.join(out, "anova.csv"))
print("study_check: one factor at a time gives the single-run differences")
