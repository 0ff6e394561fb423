#!/usr/bin/python3
"""A synthetic cohort: eyes with known truths, their Corvis readings and the
patients' table that nct fit takes (docs/manual.md, "Cohorts").

Usage: scripts/synthetic-cohort.py OUT [--nct build/nct] [--scene SCENE]
       [--set KEY=VALUE ...] [--eyes 10] [--seed 1] [--runs runs/synthetic-cohort]

Draws each eye's corneal C10 (0.04 to 0.10 MPa), IOP (11 to 22 mmHg),
central corneal thickness (0.49 to 0.61 mm) and age (20 to 75) across the
clinical ranges (a Latin hypercube: each range cut in `eyes` strata, one
eye per stratum, the strata paired at random), runs the scene at each
truth (`nct run`, with --set), and writes into OUT:
- RUNS/<patient>: the truth's run (--runs);
- OUT/<patient>/apex.csv and profiles.csv: its readings with the Corvis
  ST's noise (scripts/synthetic-readings.py, seed = the row);
- OUT/patients.csv: patient, folder, the thickness as the scene key
  geometry.cornea_central_thickness, age, the tonometer's IOP as the
  prior of the parameter labelled iop (truth + 1.5 N(0, 1) mmHg, SD 1.5),
  and the truths as truth.c10_cornea and truth.iop.
"""
import argparse
import csv
import pathlib
import subprocess
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
RANGES = {"c10": (0.04, 0.10), "iop": (11.0, 22.0), "cct": (0.49, 0.61), "age": (20, 75)}
IOP_SD = 1.5  # mmHg: the tonometer's


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--nct", type=pathlib.Path, default=ROOT / "build" / "nct")
    ap.add_argument("--scene", type=pathlib.Path,
                    default=ROOT / "scenes" / "puff-faithful-section.toml")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--eyes", type=int, default=10)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--runs", type=pathlib.Path, default=pathlib.Path("runs/synthetic-cohort"))
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    n = a.eyes
    draw = {}
    for name, (lo, hi) in RANGES.items():
        strata = (rng.permutation(n) + rng.uniform(size=n)) / n
        draw[name] = lo + (hi - lo) * strata
    a.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for i in range(n):
        patient = "P%02d" % (i + 1)
        c10, iop = round(draw["c10"][i], 4), round(draw["iop"][i], 1)
        cct, age = round(draw["cct"][i], 3), int(round(draw["age"][i]))
        run = a.runs / patient
        sets = a.set + ["output.fields=false", "material.cornea.c10=%g" % c10,
                        "material.limbus.c10=%g" % c10, "inflate.iop=%g" % iop,
                        "geometry.cornea_central_thickness=%g" % cct]
        if not (run / "summary.json").exists():
            p = subprocess.run([a.nct, "run", a.scene.resolve(), "--out", run]
                               + [w for s in sets for w in ("--set", s)],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            if p.returncode != 0:
                sys.exit("synthetic-cohort: the truth of %s failed:\n%s" % (patient,
                                                                           p.stdout[-2000:]))
        subprocess.run(["/usr/bin/python3", ROOT / "scripts" / "synthetic-readings.py", run,
                        a.out / patient, "--seed", str(i + 1)], check=True,
                       stdout=subprocess.DEVNULL)
        for extra in ("whole-eye.csv", "biomarkers.toml"):
            (a.out / patient / extra).unlink(missing_ok=True)
        tonometer = iop + IOP_SD * np.random.default_rng(1000 + i + 1).normal()
        rows.append({"patient": patient, "folder": patient,
                     "geometry.cornea_central_thickness": cct, "age": age,
                     "prior.iop.mean": round(tonometer, 1), "prior.iop.sd": IOP_SD,
                     "truth.c10_cornea": c10, "truth.iop": iop})
        print("%s: C10 %.4f MPa, IOP %.1f mmHg (tonometer %.1f), CCT %.3f mm, age %d"
              % (patient, c10, iop, tonometer, cct, age), flush=True)
    with open(a.out / "patients.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("synthetic cohort of %d eyes in %s" % (n, a.out))


if __name__ == "__main__":
    main()
