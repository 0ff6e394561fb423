#!/usr/bin/python3
"""What the 202 real eyes' own readings say about the device's definitions,
without any model (cases/real-eyes/README.md):

- bIOP against the device's IOP, CCT and age: the linear least-squares fit,
  its residuals, after dropping the rows beyond 3 RMS (three passes);
- the HC profile implied if the DA ratio's maximum came at HC: the height
  of the anterior profile 2 mm out above the apex, DA - DA/ratio - 4/(2 R)
  (R = 7.8 mm, the cornea at rest), and the radius of the parabola over
  +-2 mm through it, against the eye's HC radius.

Usage: cases/real-eyes/consistency.py [all_eyes.csv]
"""
import csv
import pathlib
import sys

import numpy as np

here = pathlib.Path(__file__).resolve().parent
rows = list(csv.DictReader(open(sys.argv[1] if len(sys.argv) > 1 else here / "all_eyes.csv")))


def column(name):
    return np.array([float(r[name]) for r in rows])


biop, iop, cct, age = column("bIOP"), column("IOPnc"), column("CCT"), column("age")
X = np.c_[np.ones_like(biop), iop, cct, age]
keep = np.ones(len(biop), bool)
for _ in range(3):
    coef = np.linalg.lstsq(X[keep], biop[keep], rcond=None)[0]
    e = biop - X @ coef
    rms = float(np.sqrt(np.mean(e[keep] ** 2)))
    keep = np.abs(e) < 3 * rms
print("## bIOP from the device's IOP, CCT and age\n")
print(f"bIOP = {coef[0]:.2f} + {coef[1]:.3f} IOPnc {coef[2]:+.4f} CCT[um] {coef[3]:+.4f} age")
print(f"{keep.sum()} of {len(biop)} eyes within {rms:.3f} mmHg RMS; the others off by "
      + ", ".join(f"{v:.2f}" for v in sorted(np.abs(e[~keep]))) + " mmHg")

da, ratio, hcr = column("HCDA"), column("DA_Ratio"), column("HCR")
rise = da - da / ratio - 4 / (2 * 7.8)
radius = np.where(rise > 0, 4 / (2 * np.maximum(rise, 1e-9)), np.inf)
print("\n## The HC profile if the DA ratio's maximum came at HC\n")
print(f"height 2 mm out above the apex: mean {rise.mean():.3f} mm; its parabola's radius over "
      f"+-2 mm: median {np.median(radius):.2f} mm, against the HC radius's median "
      f"{np.median(hcr):.2f} mm; in {np.mean(radius < hcr) * 100:.0f} % of the eyes the "
      "parabola is the more curved")
