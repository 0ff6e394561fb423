"""An emulator's training set: from the runs of a table-design study, what
a fit compares, per run, in one JSON file.

    data = collect("runs/emulator-training")        # a dict, below
    write(data, "cases/emulator-faithful-section/training-data.json")
    data = read("cases/emulator-faithful-section/training-data.json")

Per run (a converged case of the study): its inputs (the factors'
values), the apex displacement and the whole eye's motion on the
device's frame clock (every frame of frames.csv), the anterior profile's
axial displacement from its t = 0 shape at the fit's frames and places
(the frames nearest `PROFILE_TIMES`, at `PROFILE_X`, as
nct.readings.synthetic reads them), and every reading of the biomarker
registry the run gave (the DCR parameters, the IOP's peak); the readings
a run lacks (A1 when the cornea never flattens) are null.
"""
import json
import math

import numpy as np

from . import biomarkers, design
from .folders import Run, Study

PROFILE_TIMES = (5.0, 10.0, 15.0)                      # ms
PROFILE_X = (-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0)     # mm
READINGS = [e["key"] for e in biomarkers.REGISTRY if e.get("reading") and "<" not in e["key"]]


def _run_outputs(run):
    """One run's outputs: curves on the frame clock, profiles, readings."""
    t = run.frames["t_ms"]
    profiles = run.profiles
    rows = []
    for tm in PROFILE_TIMES:
        k = profiles.nearest(tm)
        rows.append([profiles.height(k, x) - profiles.height(0, x) for x in PROFILE_X])
    readings = {}
    for key in READINGS + ["iop_max_mmHg"]:
        v = run.summary.get(key)
        readings[key] = v if isinstance(v, (int, float)) and math.isfinite(v) else None
    return {"t_ms": list(map(float, t)),
            "apex_mm": list(map(float, run.frames["apex_displacement_mm"])),
            "whole_eye_mm": list(map(float, run.frames["whole_eye_motion_mm"])),
            "profile_t_ms": [float(profiles.t_ms[profiles.nearest(tm)]) for tm in PROFILE_TIMES],
            "profiles_mm": rows,
            "readings": readings}


def collect(study_folder):
    """The training set of a table-design study's finished cases (its
    cases.csv): its inputs' names and box, every converged case's inputs
    and outputs."""
    study = Study(study_folder)
    cases = study.cases
    factors = design.read_factors(study.folder / "study.toml")
    inputs = [f.label for f in factors]
    runs = []
    for i in range(len(cases)):
        if cases["status"][i] != "converged":
            continue
        name = cases["case"][i]
        run = Run(study.folder / "cases" / name)
        runs.append({"case": name, "inputs": [float(cases[c][i]) for c in inputs],
                     "wall_s": float(cases["wall_s"][i]), **_run_outputs(run)})
    box = [{"input": f.label, "keys": f.keys, "range": [f.low, f.high], "scale": f.scale}
           for f in factors]
    return {"inputs": inputs, "box": box, "profile_x_mm": list(PROFILE_X), "runs": runs}


def write(data, path):
    """The training set as JSON (numbers to 10 significant digits)."""
    def rounded(v):
        if isinstance(v, float):
            return float(f"{v:.10g}")
        if isinstance(v, list):
            return [rounded(x) for x in v]
        if isinstance(v, dict):
            return {k: rounded(x) for k, x in v.items()}
        return v
    with open(path, "w") as f:
        json.dump(rounded(data), f, separators=(",", ":"))
        f.write("\n")


def read(path):
    """A training set written by `write`."""
    with open(path) as f:
        return json.load(f)


def arrays(data, block):
    """A block of every run's outputs as a (runs, values) array: "apex_mm",
    "whole_eye_mm", "profiles_mm" (flattened) or a reading's key."""
    if block in ("apex_mm", "whole_eye_mm"):
        return np.array([r[block] for r in data["runs"]])
    if block == "profiles_mm":
        return np.array([np.ravel(r[block]) for r in data["runs"]])
    return np.array([[np.nan if r["readings"][block] is None else r["readings"][block]]
                     for r in data["runs"]])
