"""A table design: each row of its CSV one case, run as `nct run` would.

study_table.py NCT STUDY OUT

Runs STUDY (design = "table") into OUT and checks: every case converged;
cases.csv holds the table's values, row for row; a case's summary equals
`nct run` of the base scene with the same overrides (every response to
1e-12); correlation.csv and analysis.json (design "table") are written.
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import read_json  # noqa: E402
from nct.tables import read_csv  # noqa: E402

nct, study, out = sys.argv[1:4]
r = subprocess.run([nct, "study", study, "--out", out, "--no-report"], capture_output=True, text=True)
print(r.stdout, r.stderr)
assert r.returncode == 0, f"nct study exited with {r.returncode}"

design = read_csv(os.path.join(os.path.dirname(study), "quick-table.csv"))
cases = read_csv(os.path.join(out, "cases.csv"))
assert len(cases) == len(design), (len(cases), len(design))
assert all(s == "converged" for s in cases["status"]), list(cases["status"])
for name in design.columns:
    assert list(cases[name]) == list(design[name]), (name, list(cases[name]), list(design[name]))

# The third case, run directly.
scene = os.path.join(os.path.dirname(os.path.abspath(study)), "..", "..", "scenes", "default.toml")
direct = os.path.join(out, "direct")
r = subprocess.run([nct, "run", scene, "--out", direct, "--no-report",
                    "--set", 'mesh.dimension="axisymmetric"',
                    "--set", "material.cornea.c10=0.0731", "--set", "material.limbus.c10=0.0731",
                    "--set", "inflate.iop=14.137"], capture_output=True, text=True)
assert r.returncode == 0, r.stderr
a = read_json(os.path.join(out, "cases", "case-003", "summary.json"))
b = read_json(os.path.join(direct, "summary.json"))
for k in ["deflection_amplitude_mm", "deformation_amplitude_mm", "a1_time_ms", "iop_max_mmHg"]:
    assert abs(a[k] - b[k]) <= 1e-12 * max(1.0, abs(b[k])), (k, a[k], b[k])

analysis = read_json(os.path.join(out, "analysis.json"))
assert analysis["design"] == "table" and analysis["cases"] == len(design), analysis
corr = read_csv(os.path.join(out, "correlation.csv"))
assert "IOP" in corr.columns and "iop_max_mmHg" in corr.columns, corr.columns
print(f"study_table: {len(design)} cases from the table, case-003 equal to nct run")
