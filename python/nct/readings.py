"""Synthetic Corvis readings from nct runs, with measurement noise, and a
synthetic cohort of eyes drawn across the clinical ranges.

    synthetic(run, out, seed=1)     # apex.csv, whole-eye.csv, profiles.csv, biomarkers.toml
    draw_cohort(out, nct, scene, sets, eyes=10, seed=1, runs="runs/synthetic-cohort")

The noise defaults are the Corvis ST's precision as we read it: 0.02 mm
per frame (about one pixel of its camera) for the curves and profiles;
the deflection amplitude's SD 0.08 mm (docs/physics.md section 9), A1
time's 0.2 ms; a tonometer's SD 1.5 mmHg.
"""
import pathlib
import subprocess

import numpy as np

from .folders import Run
from .tables import write_csv

IOP_SD = 1.5  # mmHg: the tonometer's
# The cohort's clinical ranges: corneal C10 [MPa], IOP [mmHg], central
# corneal thickness [mm], age [years].
COHORT_RANGES = {"c10": (0.04, 0.10), "iop": (11.0, 22.0), "cct": (0.49, 0.61), "age": (20, 75)}


def synthetic(run, out, seed=1, sd_curve=0.02, sd_profile=0.02, every=4,
              profile_times=(5.0, 10.0, 15.0), profile_x=(-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0)):
    """Write into out:
    - apex.csv: t_ms,value_mm,sd_mm, the apex displacement (frames.csv) at
      every `every`-th Corvis frame, plus Gaussian noise of SD sd_curve;
    - whole-eye.csv: the same for the whole-eye motion;
    - profiles.csv: t_ms,x_mm,y_mm,sd_mm, the anterior surface's axial
      displacement from its t = 0 profile at the frames nearest the given
      times, at the given x, plus noise of SD sd_profile;
    - biomarkers.toml: [[observation]] tables of the run's deflection
      amplitude (SD 0.08 mm) and A1 time (SD 0.2 ms), each with noise of its SD."""
    run = run if isinstance(run, Run) else Run(run)
    out = pathlib.Path(out)
    rng = np.random.default_rng(seed)
    out.mkdir(parents=True, exist_ok=True)

    t = run.frames["t_ms"]
    for column, name in (("apex_displacement_mm", "apex.csv"),
                         ("whole_eye_motion_mm", "whole-eye.csv")):
        v = run.frames[column]
        with open(out / name, "w") as f:
            f.write("t_ms,value_mm,sd_mm\n")
            for i in range(0, len(t), every):
                f.write("%.9g,%.6g,%.6g\n" % (t[i], v[i] + rng.normal(0, sd_curve), sd_curve))

    profiles = run.profiles
    with open(out / "profiles.csv", "w") as f:
        f.write("t_ms,x_mm,y_mm,sd_mm\n")
        for tm in profile_times:
            k = profiles.nearest(tm)
            for x in profile_x:
                y = profiles.height(k, x) - profiles.height(0, x)
                f.write("%.9g,%.6g,%.6g,%.6g\n" % (profiles.t_ms[k], x,
                                                   y + rng.normal(0, sd_profile), sd_profile))

    with open(out / "biomarkers.toml", "w") as f:
        for key, sd in (("deflection_amplitude_mm", 0.08), ("a1_time_ms", 0.2)):
            f.write("[[observation]]\nbiomarker = \"%s\"\nvalue = %.6g\nsd = %g\n\n"
                    % (key, run.summary[key] + rng.normal(0, sd), sd))


def draw_cohort(out, nct, scene, sets=(), eyes=10, seed=1, runs="runs/synthetic-cohort",
                log=print):
    """A synthetic cohort: each eye's corneal C10, IOP, central corneal
    thickness and age drawn across COHORT_RANGES (a Latin hypercube: each
    range cut in `eyes` strata, one eye per stratum, the strata paired at
    random); the scene run at each truth (`nct run` with sets) into
    RUNS/<patient> (kept if it has its summary); into out:
    - <patient>/apex.csv and profiles.csv: its readings with the Corvis ST's
      noise (seed = the row);
    - patients.csv: patient, folder, the thickness as the scene key
      geometry.cornea_central_thickness, age, the tonometer's IOP as the
      prior of the parameter labelled iop (truth + 1.5 N(0, 1) mmHg, SD
      1.5), and the truths as truth.c10_cornea and truth.iop.
    Raises RuntimeError when a truth's run fails."""
    rng = np.random.default_rng(seed)
    draw = {}
    for name, (lo, hi) in COHORT_RANGES.items():
        strata = (rng.permutation(eyes) + rng.uniform(size=eyes)) / eyes
        draw[name] = lo + (hi - lo) * strata
    out, runs = pathlib.Path(out), pathlib.Path(runs)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for i in range(eyes):
        patient = "P%02d" % (i + 1)
        c10, iop = round(draw["c10"][i], 4), round(draw["iop"][i], 1)
        cct, age = round(draw["cct"][i], 3), int(round(draw["age"][i]))
        run = runs / patient
        truth = list(sets) + ["output.fields=false", "material.cornea.c10=%g" % c10,
                              "material.limbus.c10=%g" % c10, "inflate.iop=%g" % iop,
                              "geometry.cornea_central_thickness=%g" % cct]
        if not (run / "summary.json").exists():
            p = subprocess.run([str(nct), "run", str(pathlib.Path(scene).resolve()), "--out",
                                str(run)] + [w for s in truth for w in ("--set", s)],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            if p.returncode != 0:
                raise RuntimeError("the truth of %s failed:\n%s" % (patient, p.stdout[-2000:]))
        synthetic(run, out / patient, seed=i + 1)
        for extra in ("whole-eye.csv", "biomarkers.toml"):
            (out / patient / extra).unlink(missing_ok=True)
        tonometer = iop + IOP_SD * np.random.default_rng(1000 + i + 1).normal()
        rows.append({"patient": patient, "folder": patient,
                     "geometry.cornea_central_thickness": cct, "age": age,
                     "prior.iop.mean": round(tonometer, 1), "prior.iop.sd": IOP_SD,
                     "truth.c10_cornea": c10, "truth.iop": iop})
        log("%s: C10 %.4f MPa, IOP %.1f mmHg (tonometer %.1f), CCT %.3f mm, age %d"
            % (patient, c10, iop, tonometer, cct, age))
    write_csv(out / "patients.csv", rows)
    return rows
