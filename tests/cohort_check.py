"""nct fit over a cohort: a table of 3 synthetic patients (the package's
readings.draw_cohort on the default scene's axisymmetric section: each
eye its own corneal C10, IOP, central thickness and age, its readings
with the Corvis ST's noise, its tonometer's IOP as a prior), each fitted
for its corneal C10 and IOP, 2 patients at once.

cohort_check.py NCT OUT

- interrupted (SIGINT) once forward runs have finished, it exits 130; the
  same command then completes it (exit 0), every fit converged;
- cohort.csv holds a row per patient equal to its fit.json (values, SEs,
  intervals, chi2), its covariate and scene-key columns and truths; the
  table's prior (the tonometer's IOP) is the one the patient's fit used,
  and its thickness reached every one of its forward runs;
- each fitted C10 lies within 4 standard errors of its truth;
- run again, nothing is fitted again and cohort.csv is unchanged; a
  patient whose row changed (its age) is fitted again from its finished
  forward runs (no new run), the others kept;
- its page (report.html, written at the end) draws the recovery and the
  stiffness against IOP and age; the patients' fits write none.
"""
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct import cohort_figures, readings  # noqa: E402
from nct.folders import read_json  # noqa: E402
from nct.tables import read_csv  # noqa: E402

nct, out = sys.argv[1:3]
out = pathlib.Path(out)
root = pathlib.Path(__file__).resolve().parent.parent
shutil.rmtree(out, ignore_errors=True)
out.mkdir(parents=True)
SETS = ['mesh.dimension="axisymmetric"']
scene = root / "scenes" / "default.toml"

readings.draw_cohort(out / "data", nct, scene, SETS, eyes=3, runs=out / "truths")
fit_file = out / "cohort.toml"
fit_file.write_text(
    '[fit]\nscene = %s\nset = %s\njobs = 2\n\n[cohort]\ntable = "data/patients.csv"\n'
    'covariates = ["age"]\npatients = 2\n\n'
    '[[parameter]]\nlabel = "c10_cornea"\nkey = ["material.cornea.c10", "material.limbus.c10"]\n'
    'start = 0.05\nbounds = [0.01, 0.5]\n\n'
    '[[parameter]]\nlabel = "iop"\nkey = "inflate.iop"\nstart = 15.0\nbounds = [5.0, 40.0]\n\n'
    '[[observation]]\ncurve = "apex.csv"\n\n[[observation]]\nprofile = "profiles.csv"\n'
    % (json.dumps(str(scene)), json.dumps(SETS)))
folder = out / "fit"
command = [nct, "fit", fit_file, "--out", folder]


def runs():
    return sorted(p for p in folder.glob("patients/*/runs/run-*") if (p / "summary.json").exists())


def nct_fit(expect):
    p = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(p.stdout)
    assert p.returncode == expect, f"nct fit exited {p.returncode}, expected {expect}"
    return p.stdout


# Interrupted once a few forward runs have finished, then resumed.
p = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
deadline = time.time() + 600
while len(runs()) < 4 and p.poll() is None and time.time() < deadline:
    time.sleep(0.2)
p.send_signal(signal.SIGINT)
text = p.communicate()[0]
print(text)
assert p.returncode == 130, f"the interrupted cohort exited {p.returncode}"
assert "the same command resumes it" in text
before = len(runs())
print(f"interrupted after {before} forward runs")
text = nct_fit(0)

rows = read_csv(folder / "cohort.csv", numeric=False).rows()
table = {r["patient"]: r for r in read_csv(out / "data" / "patients.csv", numeric=False).rows()}
assert [r["patient"] for r in rows] == ["P01", "P02", "P03"], rows
summary = read_json(folder / "cohort.json")
assert summary["converged"] == 3 and summary["patients_at_once"] == 2
for r in rows:
    t = table[r["patient"]]
    fit = read_json(folder / "patients" / r["patient"] / "fit.json")
    assert fit["patient"] == r["patient"] and fit["status"] == r["status"] == "converged"
    for q in fit["parameters"]:
        label = q["label"]
        assert float(r[label]) == q["value"] and float(r[label + "_se"]) == q["se"]
        assert [float(r[label + "_lo"]), float(r[label + "_hi"])] == q["ci95"]
        assert float(r["truth_" + label]) == float(t["truth." + label])
    assert float(r["chi2"]) == fit["chi2"] and r["age"] == t["age"]
    iop = next(q for q in fit["parameters"] if q["label"] == "iop")
    assert iop["prior"] == {"mean": float(t["prior.iop.mean"]), "sd": float(t["prior.iop.sd"])}
    cct = "geometry.cornea_central_thickness=" + t["geometry.cornea_central_thickness"]
    for run in (folder / "patients" / r["patient"] / "runs").glob("run-*"):
        assert cct in read_json(run / "run.json")["sets"], run
    c10, se, truth = float(r["c10_cornea"]), float(r["c10_cornea_se"]), float(r["truth_c10_cornea"])
    print("%s: C10 truth %.4f, fit %.4f +- %.4f (%.1f SE); IOP truth %s, fit %.2f"
          % (r["patient"], truth, c10, se, (c10 - truth) / se, r["truth_iop"], float(r["iop"])))
    assert abs(c10 - truth) < 4 * se

# Nothing to do again; a changed row is fitted again from its runs.
csv_before, n_runs = (folder / "cohort.csv").read_text(), len(runs())
text = nct_fit(0)
assert "(3 fitted before)" in text and len(runs()) == n_runs
assert (folder / "cohort.csv").read_text() == csv_before
lines = (out / "data" / "patients.csv").read_text().splitlines()
header = lines[0].split(",")
cells = lines[2].split(",")
cells[header.index("age")] = str(int(cells[header.index("age")]) + 1)
lines[2] = ",".join(cells)
(out / "data" / "patients.csv").write_text("\n".join(lines) + "\n")
text = nct_fit(0)
assert "(2 fitted before)" in text and "patient P02" in text and len(runs()) == n_runs, text
fit = read_json(folder / "patients" / "P02" / "fit.json")
assert fit["forward_runs_reused"] == fit["forward_runs"], fit["forward_runs"]

# The cohort's page, written at its end (tests/report_pages.py opens it in
# a browser); the patients' pages only on request.
page = (folder / "report.html").read_text()
for name in ("cohort-iop", "cohort-age", "cohort-recovery"):
    assert f'data-name="{name}"' in page, name
assert not list(folder.glob("patients/*/report.html"))
assert "truths inside their 95 % intervals" in cohort_figures.recovery(folder)[0]
print("cohort: OK")
