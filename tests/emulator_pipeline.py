"""The emulator's whole path on the prescribed-load section (about a second
a run): a maximin design over corneal C10, IOP and central corneal
thickness run as a table study, its training set collected, the emulator
trained and exported; held-out eyes (another design's points) run, their
Corvis readings made with the device's noise and a tonometer's IOP drawn
about each truth; then the cohort fitted on the emulator.

emulator_pipeline.py NCT SCENE OUT

Checks: the held-out truths inside their 95 % intervals (C10 and IOP of 20
eyes: at least 35 of 40; 38 expected, and 34 or fewer has a chance of 1.4
% when the intervals hold); a rebuild from the same design and seed gives
the same file; the confirming forward run of one patient at its answer,
with its verdict (the share of its values within 2 of the emulator's SDs,
the answer's shift in standard errors) and, where it disagrees, the
corrected fit with forward runs converged; an eye outside the box (a thickness of 0.70 mm, an IOP
prior of 40 mmHg, bounds beyond the box, a reading the training never
gave) refused before any work, naming the input, its value and the box.
"""
import json
import os
import shutil
import subprocess
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from nct import design, emulator, readings, training  # noqa: E402
from nct.tables import read_csv  # noqa: E402

nct, scene, out = sys.argv[1:4]
os.makedirs(out, exist_ok=True)
for folder in os.listdir(out):  # the fits again; the studies resume
    if folder in ("cohort", "confirm") or folder.startswith("refused-"):
        shutil.rmtree(os.path.join(out, folder))
SECTION = 'mesh.dimension="axisymmetric"'
FACTORS = """
[[factor]]
label = "c10_cornea"
key = ["material.cornea.c10", "material.limbus.c10"]
range = [0.04, 0.10]
scale = "log"

[[factor]]
label = "iop"
key = "inflate.iop"
range = [10.0, 25.0]

[[factor]]
label = "cct"
key = "geometry.cornea_central_thickness"
range = [0.48, 0.62]
"""
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def study(name, n, seed):
    """A table study of n maximin points (seed) in OUT/name."""
    toml = os.path.join(out, name + ".toml")
    with open(toml, "w") as f:
        f.write(f'[study]\nscene = "{scene}"\ndesign = "table"\ncases = "{name}-design.csv"\n'
                f"set = ['{SECTION}', \"output.fields=false\"]\n"
                'responses = ["deflection_amplitude_mm", "hc_time_ms", "iop_max_mmHg"]\n'
                "jobs = 2\n" + FACTORS)
    factors = design.read_factors(toml)
    rows = design.to_box(design.maximin_hypercube(len(factors), n, seed=seed, candidates=200),
                         factors)
    design.write_design(os.path.join(out, name + "-design.csv"), rows, factors)
    folder = os.path.join(out, name)
    subprocess.run([nct, "study", toml, "--out", folder, "--no-report"], check=True, stdout=subprocess.DEVNULL)
    return folder, rows


def quiet(f, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # hyperparameters at their bounds
        return f(*args, **kwargs)


# Training: 30 runs (10 per input), the emulator and its rebuild.
training_folder, _ = study("training", 30, seed=1)
data = training.collect(training_folder)
check(len(data["runs"]) == 30, f"{len(data['runs'])} of 30 training runs converged")
path = os.path.join(out, "emulator.json")
em = quiet(emulator.train, data, seed=1, restarts=2)
emulator.export(em, path)
emulator.export(quiet(emulator.train, data, seed=1, restarts=2), path + ".again")
with open(path) as a, open(path + ".again") as b:
    check(a.read() == b.read(), "a rebuild from the same data and seed is the same file")
print(f"emulator: {em.components} components ({em.share:.5f} of the variance), "
      f"{len(em.readings)} readings")

# Held-out eyes: their readings and the cohort's table.
holdout_folder, truths = study("holdout", 20, seed=2)
cases = read_csv(os.path.join(holdout_folder, "cases.csv"), numeric=False)
rng = np.random.default_rng(3)
rows = []
for i, (c10, iop, cct) in enumerate(truths):
    name = cases["case"][i]
    if cases["status"][i] != "converged":
        check(False, f"held-out {name} converged")
        continue
    readings.synthetic(os.path.join(holdout_folder, "cases", name), os.path.join(out, "eyes", name),
                       seed=10 + i)
    rows.append(f"{name},{name},{cct:.6g},{iop + readings.IOP_SD * rng.normal():.4f},"
                f"{readings.IOP_SD},{c10:.6g},{iop:.6g}")
with open(os.path.join(out, "eyes", "patients.csv"), "w") as f:
    f.write("patient,folder,geometry.cornea_central_thickness,prior.iop.mean,prior.iop.sd,"
            "truth.c10_cornea,truth.iop\n" + "\n".join(rows) + "\n")

FIT = """[fit]
scene = "{scene}"
set = ['{section}']
emulator = "{emulator}"
confirm = {confirm}
{extra}
[[parameter]]
label = "c10_cornea"
key = ["material.cornea.c10", "material.limbus.c10"]
start = 0.06
bounds = {c10_bounds}

[[parameter]]
label = "iop"
key = "inflate.iop"
start = 15.0
bounds = [10.0, 25.0]
prior = {{mean = 15.0, sd = 1.5}}

[[observation]]
curve = "apex.csv"

[[observation]]
profile = "profiles.csv"
surface = "anterior"
{observation}"""


def fit_file(name, confirm="false", extra="", c10_bounds="[0.04, 0.10]", observation=""):
    text = FIT.format(scene=scene, section=SECTION, emulator=path, confirm=confirm, extra=extra,
                      c10_bounds=c10_bounds, observation=observation)
    file = os.path.join(out, "eyes", name)
    with open(file, "w") as f:
        f.write(text)
    return file


cohort = fit_file("cohort.toml", extra='[cohort]\ntable = "patients.csv"\n')
# The [cohort] table must come after [fit]'s keys: move it to the end.
with open(cohort) as f:
    text = f.read().replace('[cohort]\ntable = "patients.csv"\n', "")
with open(cohort, "w") as f:
    f.write(text + '\n[cohort]\ntable = "patients.csv"\n')
subprocess.run([nct, "fit", cohort, "--out", os.path.join(out, "cohort"), "--no-report"], check=True,
               stdout=subprocess.DEVNULL)
result = read_csv(os.path.join(out, "cohort", "cohort.csv"), numeric=False)
inside = sum(result[f"{p}_inside"][i] in ("1", "true", "True")
             for p in ("c10_cornea", "iop") for i in range(len(result["patient"])))
total = 2 * len(result["patient"])
for i in range(len(result["patient"])):
    print(f"  {result['patient'][i]}: c10 {result['c10_cornea'][i]} "
          f"[{result['c10_cornea_lo'][i]}, {result['c10_cornea_hi'][i]}] truth "
          f"{result['truth_c10_cornea'][i]}; iop {result['iop'][i]} [{result['iop_lo'][i]}, "
          f"{result['iop_hi'][i]}] truth {result['truth_iop'][i]}")
check(total == 40 and inside >= 35, f"{inside} of {total} held-out truths inside their 95 % "
                                    "intervals (at least 35 of 40)")

# One patient confirmed by a forward run at its answer.
first = cases["case"][0]
single = fit_file("confirm.toml", confirm="true")
with open(single) as f:
    text = f.read()
with open(single, "w") as f:
    f.write(text.replace(f"set = ['{SECTION}']", f"set = ['{SECTION}', "
                         f"\"geometry.cornea_central_thickness={truths[0][2]:.6g}\"]")
            .replace('curve = "apex.csv"', f'curve = "{first}/apex.csv"')
            .replace('profile = "profiles.csv"', f'profile = "{first}/profiles.csv"'))
subprocess.run([nct, "fit", single, "--out", os.path.join(out, "confirm"), "--no-report"], check=True,
               stdout=subprocess.DEVNULL)
with open(os.path.join(out, "confirm", "fit.json")) as f:
    confirmation = json.load(f)["confirmation"]
print(f"  confirmation: {confirmation}")
shifts = {k: v["in_se"] for k, v in confirmation["shift"].items()}
agrees = all(abs(v) <= 0.5 for v in shifts.values()) and confirmation["share_within_2sd"] >= 0.9
check(os.path.exists(os.path.join(confirmation["run"], "summary.json"))
      and confirmation["verdict"] == ("agrees" if agrees else "disagrees"),
      f"the confirming run's verdict: {confirmation['verdict']} (the answer's shift in SEs "
      f"{shifts}; {confirmation['share_within_2sd']:.0%} of its values within 2 emulator SDs)")
with open(os.path.join(out, "confirm", "fit.json")) as f:
    corrected = json.load(f).get("corrected")
check(agrees or (corrected and corrected["status"] == "converged"),
      "where it disagrees, the corrected fit with forward runs converged"
      + (f" ({corrected['forward_runs']} runs: "
         + ", ".join(f"{p['label']} {p['value']:.4g}" for p in corrected["parameters"]) + ")"
         if corrected else ""))

# What lies outside the box is refused before any work.
refusals = {
    "thickness": (fit_file("thick.toml").replace("thick.toml", "thick.toml"),
                  "geometry.cornea_central_thickness=0.7",
                  "cct = 0.7 (geometry.cornea_central_thickness, the scene's with the fit's and "
                  "the patient's settings) is outside the emulator's box [0.48, 0.62]"),
    "prior": (fit_file("prior.toml"), None,
              "the measured iop = 40 (the prior's mean) is outside the emulator's box [10, 25] "
              "by more than 3 sd"),
    "bounds": (fit_file("bounds.toml", c10_bounds="[0.02, 0.10]"), None,
               "parameter 'c10_cornea': its bounds [0.02, 0.1] reach outside the emulator's box "
               "for c10_cornea [0.04, 0.1]"),
    "reading": (fit_file("reading.toml", observation='\n[[observation]]\nbiomarker = '
                         '"hc_time_ms"\nvalue = 40.0\nsd = 0.2\n'), None,
                "hc_time_ms = 40 is outside what the emulator's training runs gave"),
}
for what, (file, setting, message) in refusals.items():
    with open(file) as f:
        text = f.read()
    text = text.replace('curve = "apex.csv"', f'curve = "{first}/apex.csv"').replace(
        'profile = "profiles.csv"', f'profile = "{first}/profiles.csv"')
    if setting:
        text = text.replace(f"set = ['{SECTION}']", f"set = ['{SECTION}', \"{setting}\"]")
    if what == "prior":
        text = text.replace("prior = {mean = 15.0, sd = 1.5}", "prior = {mean = 40.0, sd = 1.5}")
    with open(file, "w") as f:
        f.write(text)
    run = subprocess.run([nct, "fit", file, "--out", os.path.join(out, "refused-" + what)],
                         capture_output=True, text=True)
    check(run.returncode != 0 and message in run.stderr
          and not os.path.exists(os.path.join(out, "refused-" + what, "fit.json")),
          f"refused: {what} ({run.stderr.strip().splitlines()[-1] if run.stderr else 'no error'})")

if failures:
    sys.exit("emulator_pipeline: failed: " + "; ".join(failures))
print("emulator_pipeline: passed")
