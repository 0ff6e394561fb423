#!/usr/bin/python3
"""One case of the hard-case matrix (tests/CMakeLists.txt, label "hard").

    hard_case.py NAME OUT TIMEOUT [EXPECT] -- COMMAND...

runs COMMAND (an `nct run ... --out OUT`) and passes when the run either
converged with physically sensible results or stopped with a diagnosis;
never a crash, a hang, NaN in an output or an unreadable output file:

- exit 0: summary.json says "converged" and the biomarkers are sensible
  (see `sensible`);
- exit 3 (nct's "diverged"): summary.json says "failed" and its error
  names the phase, the time or load, the Newton residual history and
  where in the mesh (or why) it failed;
- anything else (a crash, exit 1, a signal, the timeout) fails the case.

Either way every file written must be complete: summary.json parses with
no null (nlohmann writes NaN as null), every CSV has rows of finite
numbers, every XDMF is well-formed XML whose HDF5 datasets exist and hold
finite values; without --no-report, the run's page (report.html) exists
and, for a run that stopped, says so. EXPECT (converged, failed; default
either) demands one outcome. The outcome goes to OUT/outcome.json for cases/hard-cases/run.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ElementTree

import h5py
import numpy

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import read_summary  # noqa: E402
from nct.tables import read_csv  # noqa: E402


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def finite_json(value, path="summary"):
    """Every number in a JSON value is finite, and no value is null."""
    if value is None:
        fail(f"{path} is null (NaN written?)")
    if isinstance(value, float) and not math.isfinite(value):
        fail(f"{path} = {value}")
    if isinstance(value, dict):
        for k, v in value.items():
            finite_json(v, f"{path}.{k}")
    if isinstance(value, list):
        for i, v in enumerate(value):
            finite_json(v, f"{path}[{i}]")


def check_csv(path):
    """Every row as long as the header, every number finite."""
    try:
        table = read_csv(path, numeric=False)
    except ValueError as e:
        fail(str(e))
    for name in table.columns:
        for n, cell in enumerate(table[name], start=2):
            try:
                v = float(cell)
            except ValueError:
                continue  # a text column (e.g. a phase name)
            if not math.isfinite(v):
                fail(f"{path}:{n}: {name} = {cell}")
    return len(table)


def check_xdmf(path):
    try:
        root = ElementTree.parse(path).getroot()
    except ElementTree.ParseError as e:
        fail(f"{path} is not well-formed XML: {e}")
    folder = os.path.dirname(path)
    items = 0
    for item in root.iter("DataItem"):
        if item.get("Format") != "HDF":
            continue
        file, dataset = item.text.strip().split(":")
        with h5py.File(os.path.join(folder, file), "r") as h5:
            if dataset not in h5:
                fail(f"{path}: {file}:{dataset} does not exist")
            data = numpy.asarray(h5[dataset])
            if data.dtype.kind == "f" and not numpy.isfinite(data).all():
                fail(f"{path}: {file}:{dataset} holds NaN or Inf")
        items += 1
    return items


def sensible(s):
    """What a converged run must show; returns the problems found."""
    problems = []

    def within(key, lo, hi):
        v = s.get(key)
        if v is None or not lo <= v <= hi:
            problems.append(f"{key} = {v}, expected in [{lo}, {hi}]")

    if "stagnation_pressure_mmHg" in s:  # the air (puff.load = "air" or "fsi")
        stagnation = s["stagnation_pressure_mmHg"]
        within("apex_pressure_max_mmHg", 0.3 * stagnation, 3 * stagnation)
    if "air_mesh_jacobian_min" in s:  # the moving air mesh: no cell folded
        within("air_mesh_jacobian_min", 0.05, 1.5)
    if "deflection_amplitude_mm" in s:  # the puff on the eye
        # The cornea moves inwards (a few tenths of a mm to a few mm at the
        # Corvis' 65 mmHg), the deflection peaks while the puff acts and
        # the closed eye's pressure rises but stays finite.
        within("deflection_amplitude_mm", 0.05, 5.0)
        within("peak_distance_mm", 0.0, 12.0)
        within("hc_time_ms", 2.0, 20.0)
        if "a1_time_ms" in s:
            if not s["a1_time_ms"] < s["hc_time_ms"] < s["a2_time_ms"]:
                problems.append("the applanations are not A1 < HC < A2: "
                                f"{s['a1_time_ms']}, {s['hc_time_ms']}, {s['a2_time_ms']}")
        if "iop_max_mmHg" in s:
            within("iop_max_mmHg", s.get("iop_mmHg", 0), 500)
    return problems


def main():
    if "--" not in sys.argv[4:6]:
        fail(__doc__)
    split = sys.argv.index("--")
    name, out, timeout = sys.argv[1], sys.argv[2], float(sys.argv[3])
    expect = sys.argv[4] if split == 5 else "either"
    command = sys.argv[split + 1:]
    shutil.rmtree(out, ignore_errors=True)
    start = time.time()
    try:
        run = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        fail(f"{name}: no answer in {timeout} s (a hang?)")
    wall = time.time() - start
    print(run.stdout[-4000:])
    print(run.stderr[-4000:])
    if run.returncode not in (0, 3):
        fail(f"{name}: exit code {run.returncode} (0 = converged, 3 = diverged with a diagnosis)")
    if expect != "either" and run.returncode != {"converged": 0, "failed": 3}[expect]:
        fail(f"{name}: expected to have {expect}, exit code {run.returncode}")

    summary_path = os.path.join(out, "summary.json")
    if not os.path.exists(summary_path):
        fail(f"{name}: no summary.json")
    summary = read_summary(summary_path)
    finite_json(summary)
    tables = {f: check_csv(os.path.join(out, f)) for f in sorted(os.listdir(out))
              if f.endswith(".csv")}
    xdmf = {f: check_xdmf(os.path.join(out, f)) for f in sorted(os.listdir(out))
            if f.endswith(".xdmf")}

    outcome = {"case": name, "exit_code": run.returncode, "wall_s": wall,
               "status": summary.get("status"), "tables": tables, "xdmf": xdmf}
    for key in ("newton_iterations", "step_cuts", "dofs", "deflection_amplitude_mm",
                "peak_distance_mm", "a1_time_ms", "hc_time_ms", "a2_time_ms", "iop_max_mmHg",
                "apex_pressure_max_mmHg", "stagnation_pressure_mmHg", "air_mesh_jacobian_min",
                "error"):
        if key in summary:
            outcome[key] = summary[key]
    if run.returncode == 0:
        if summary.get("status") != "converged":
            fail(f"{name}: exit 0 but status {summary.get('status')}")
        problems = sensible(summary)
        if problems:
            fail(f"{name}: converged, but " + "; ".join(problems))
    else:
        error = summary.get("error", "")
        if summary.get("status") != "failed":
            fail(f"{name}: exit 3 but status {summary.get('status')}")
        for needle in ("diverged", "residuals:"):
            if needle not in error:
                fail(f"{name}: the diagnosis lacks '{needle}': {error}")
        if "error:" not in run.stderr:
            fail(f"{name}: no 'error:' line on stderr")
    if "--no-report" not in command:  # its page, for a run that stopped too
        page = os.path.join(out, "report.html")
        if not os.path.exists(page):
            fail(f"{name}: no report.html")
        with open(page) as f:
            text = f.read()
        if run.returncode == 3 and "The run stopped: status failed" not in text:
            fail(f"{name}: its page does not say it stopped")
    with open(os.path.join(out, "outcome.json"), "w") as f:
        json.dump(outcome, f, indent=1)
    print(f"{name}: {'converged' if run.returncode == 0 else 'failed with a diagnosis'}"
          f" in {wall:.1f} s; tables {tables}; xdmf {xdmf}")


main()
