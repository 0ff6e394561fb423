#!/usr/bin/python3
"""Writes cases/real-eyes/narrow-jet.csv: the narrowest plausible radial
profile of the Corvis jet's pressure on the cornea, for the ablation's
bound on the load's width. A fully developed round jet impinging on a wall
at H = 11 mm from its nozzle gives a Gaussian wall pressure
p / p_max = exp(-114 (r / H)^2) (Beltaos and Rajaratnam, J. Hydraul. Div.
ASCE 100 (1974) 1313-1328), half at r = 0.078 H = 0.86 mm; the Corvis jet
(2.4 mm nozzle, H / D = 4.6) is still near its potential core, so its
profile is wider (nct's calibrated CFD: half at 1.4 mm,
scenes/tables/puff-profile-measured.csv)."""
import math
import pathlib

H = 11.0  # mm, nozzle exit to apex
out = pathlib.Path(__file__).resolve().parent / "narrow-jet.csv"
rows = ["r_mm,p_mmHg"] + [f"{r:.3f},{math.exp(-114 * (r / H) ** 2):.6f}"
                          for r in (0.05 * i for i in range(161))]
out.write_text("\n".join(rows) + "\n")
print(f"wrote {out}: half at r = {H * math.sqrt(math.log(2) / 114):.3f} mm")
