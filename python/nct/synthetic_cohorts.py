"""Synthetic cohorts for fits on an emulator, and how often their
intervals hold the truth.

    rows = from_runs(study_folder, out, fitted=["c10_cornea", "c10_sclera", "iop"])
    rows = from_emulator("emulator.json", points, out, fitted=[...])
    write_fit(out / "cohort.toml", scene, emulator, parameters, confirm=False)
    table = coverage(out / "fits" / "cohort.csv", ["c10_cornea", "iop"])

Each eye: Corvis readings with the device's noise (the apex and the whole
eye's motion every 4th frame, the anterior profile at 5, 10 and 15 ms;
nct.readings.synthetic), its measured geometry as scene-key columns (the
emulator's inputs that are not fitted), a tonometer's IOP drawn about the
truth (SD 1.5 mmHg) as the IOP's prior, and the truths. `from_runs` takes
the eyes from a table study's converged runs (the true model);
`from_emulator` makes them from the emulator's mean at given points (the
emulator is then exact: for the pipeline's speed and self-consistency).
"""
import json
import math
import pathlib

import numpy as np
from scipy import stats

from . import design, readings
from .emulator import Exported
from .folders import Study
from .tables import read_csv, write_csv
from .training import PROFILE_TIMES, PROFILE_X

EVERY = 4  # the readings' frames: every 4th of the clock, as readings.synthetic


def _row(name, box, x, fitted, rng):
    """A patient's row: geometry columns, the tonometer's prior, truths."""
    row = {"patient": name, "folder": name}
    for b, v in zip(box, x):
        if b["input"] not in fitted:
            for key in b["keys"]:
                row[key] = float(f"{v:.6g}")
    iop = dict(zip([b["input"] for b in box], x))["iop"]
    row["prior.iop.mean"] = round(iop + readings.IOP_SD * rng.normal(), 3)
    row["prior.iop.sd"] = readings.IOP_SD
    for b, v in zip(box, x):
        if b["input"] in fitted:
            row["truth." + b["input"]] = float(f"{v:.6g}")
    return row


def from_runs(study_folder, out, fitted, seed=1):
    """The converged runs of a table study as eyes in out (readings per
    eye, patients.csv); returns the rows."""
    study = Study(study_folder)
    cases = study.cases
    factors = design.read_factors(study.folder / "study.toml")
    box = [{"input": f.label, "keys": f.keys} for f in factors]
    out = pathlib.Path(out)
    rng = np.random.default_rng(seed)
    rows = []
    for i in range(len(cases)):
        if cases["status"][i] != "converged":
            continue
        name = cases["case"][i]
        x = [float(cases[f.label][i]) for f in factors]
        readings.synthetic(study.folder / "cases" / name, out / name, seed=seed + i)
        (out / name / "biomarkers.toml").unlink(missing_ok=True)
        rows.append(_row(name, box, x, fitted, rng))
    write_csv(out / "patients.csv", rows)
    return rows


def from_emulator(emulator_file, points, out, fitted, seed=1, sd=0.02):
    """Eyes made by the emulator's mean at the points (natural units, the
    emulator's inputs in order) plus the device's noise, in out."""
    em = Exported(emulator_file)
    with open(emulator_file) as f:
        meta = json.load(f)
    t = np.array(meta["t_ms"])
    n = len(t)
    frames = range(0, n, EVERY)
    out = pathlib.Path(out)
    rng = np.random.default_rng(seed)
    rows = []
    for i, x in enumerate(points):
        name = f"eye-{i + 1:03d}"
        folder = out / name
        folder.mkdir(parents=True, exist_ok=True)
        curves = em.predict(x)["curves_mm"]
        for offset, file in ((0, "apex.csv"), (n, "whole-eye.csv")):
            with open(folder / file, "w") as f:
                f.write("t_ms,value_mm,sd_mm\n")
                for k in frames:
                    f.write(f"{t[k]:.9g},{curves[offset + k] + rng.normal(0, sd):.6g},{sd:g}\n")
        with open(folder / "profiles.csv", "w") as f:
            f.write("t_ms,x_mm,y_mm,sd_mm\n")
            for a, tm in enumerate(meta["profile_t_ms"]):
                for b, xm in enumerate(meta["profile_x_mm"]):
                    y = curves[2 * n + a * len(meta["profile_x_mm"]) + b]
                    f.write(f"{tm:.9g},{xm:g},{y + rng.normal(0, sd):.6g},{sd:g}\n")
        rows.append(_row(name, meta["box"], x, fitted, rng))
    write_csv(out / "patients.csv", rows)
    return rows


def write_fit(path, scene, emulator_file, parameters, confirm=False, extra="", sets=()):
    """A cohort's fit file on the emulator: the scene with `sets`,
    `parameters` as (label, keys, start, bounds) with the IOP's prior from
    each patient's row; the apex, whole-eye and profile readings of each
    eye's folder."""
    text = (f'[fit]\nscene = "{pathlib.Path(scene).resolve()}"\n'
            + (f"set = {json.dumps(list(sets))}\n" if sets else "")
            + f'emulator = "{pathlib.Path(emulator_file).resolve()}"\n'
            f"confirm = {'true' if confirm else 'false'}\n{extra}\n")
    for label, keys, start, bounds in parameters:
        text += (f'[[parameter]]\nlabel = "{label}"\nkey = {json.dumps(keys)}\n'
                 f"start = {start}\nbounds = [{bounds[0]}, {bounds[1]}]\n")
        if label == "iop":
            text += "prior = {mean = 15.0, sd = 1.5}   # each patient's tonometer replaces it\n"
        text += "\n"
    text += ('[[observation]]\ncurve = "apex.csv"\n\n'
             '[[observation]]\ncurve = "whole-eye.csv"\nquantity = "whole_eye_motion_mm"\n\n'
             '[[observation]]\nprofile = "profiles.csv"\nsurface = "anterior"\n\n'
             '[cohort]\ntable = "patients.csv"\n')
    pathlib.Path(path).write_text(text)


def clopper_pearson(k, n, level=0.95):
    """The exact binomial interval of a share k / n."""
    a = (1 - level) / 2
    lo = stats.beta.ppf(a, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(1 - a, k + 1, n - k) if k < n else 1.0
    return float(lo), float(hi)


def coverage(cohort_csv, labels):
    """Per label (and all together): truths inside their 95 % intervals,
    out of how many, the share and its Clopper-Pearson 95 % interval; the
    intervals' median width and the errors' RMS."""
    t = read_csv(cohort_csv, numeric=False)
    out = {}
    total_k = total_n = 0
    for label in labels:
        ok = [i for i in range(len(t["patient"])) if t[f"{label}_inside"][i] not in ("", "nan")]
        k = sum(t[f"{label}_inside"][i] in ("1", "true", "True") for i in ok)
        width = [float(t[f"{label}_hi"][i]) - float(t[f"{label}_lo"][i]) for i in ok]
        error = [float(t[f"{label}_error"][i]) for i in ok]
        out[label] = {"inside": k, "of": len(ok), "share": k / len(ok),
                      "interval": clopper_pearson(k, len(ok)),
                      "median_width": float(np.median(width)),
                      "rms_error": math.sqrt(float(np.mean(np.square(error))))}
        total_k += k
        total_n += len(ok)
    out["all"] = {"inside": total_k, "of": total_n, "share": total_k / total_n,
                  "interval": clopper_pearson(total_k, total_n)}
    return out


def markdown(table, title):
    """A coverage table as Markdown."""
    lines = [f"**{title}**", "", "| parameter | inside | share | 95 % binomial interval | "
             "median interval width | RMS error |", "|---|---|---|---|---|---|"]
    for label, c in table.items():
        lines.append(f"| {label} | {c['inside']} of {c['of']} | {c['share']:.1%} | "
                     f"[{c['interval'][0]:.1%}, {c['interval'][1]:.1%}] | "
                     + (f"{c['median_width']:.4g} | {c['rms_error']:.3g} |"
                        if "median_width" in c else " | |"))
    return "\n".join(lines) + "\n"
