#!/usr/bin/python3
"""What the axisymmetric section costs in accuracy and saves in time
(docs/sections.md, "What accuracy costs").

Runs each model of the puff as the 3D quarter eye and as the eye's
axisymmetric section (mesh.dimension = "axisymmetric"), on --ranks ranks
(2 by default), and prints one table per model: every biomarker in 3D and
on the section, their difference, and the wall time. The models:

  prescribed     scenes/default.toml: the measured pulse on the orbit
  prescribed-iso the same with the fibres off (k1 = 0 in cornea and limbus):
                 the section's difference from 3D without the azimuthal
                 average of the fibres, against "prescribed" with it
  rigid-eye      scenes/puff-rigid-eye.toml: the air alone, the eye rigid
  one-way        scenes/puff-cfd.toml: the 3D rigid eye's pressure table
  two-way        scenes/puff-fsi.toml: the coupled puff
  two-way-iso    the coupled puff with the fibres off

Usage: scripts/section-accuracy.py [--models M ...] [--ranks N] [--out DIR]
A finished case (its summary.json present) is not run again; cases run one
at a time, so that the wall times are comparable.
"""
import argparse
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ISO = ["material.cornea.k1=0", "material.limbus.k1=0"]
MODELS = {
    "prescribed": ("default.toml", []),
    "prescribed-iso": ("default.toml", ISO),
    "rigid-eye": ("puff-rigid-eye.toml", []),
    "one-way": ("puff-cfd.toml", []),
    "two-way": ("puff-fsi.toml", []),
    "two-way-iso": ("puff-fsi.toml", ISO),
}
BIOMARKERS = [
    ("deformation_amplitude_mm", "deformation amplitude [mm]"),
    ("deflection_amplitude_mm", "deflection amplitude [mm]"),
    ("peak_distance_mm", "peak distance [mm]"),
    ("hc_time_ms", "HC time [ms]"),
    ("hc_radius_mm", "HC radius [mm]"),
    ("a1_time_ms", "A1 time [ms]"),
    ("a1_length_mm", "A1 length [mm]"),
    ("a1_velocity_m_s", "A1 velocity [m/s]"),
    ("a1_deflection_mm", "A1 deflection [mm]"),
    ("a2_time_ms", "A2 time [ms]"),
    ("a2_length_mm", "A2 length [mm]"),
    ("a2_velocity_m_s", "A2 velocity [m/s]"),
    ("a1_a2_interval_ms", "A1 to A2 [ms]"),
    ("whole_eye_movement_max_mm", "whole-eye movement [mm]"),
    ("da_ratio_2mm", "DA ratio 2 mm"),
    ("da_ratio_1mm", "DA ratio 1 mm"),
    ("integrated_inverse_radius_ms_per_mm", "integrated inverse radius [ms/mm]"),
    ("max_inverse_radius_per_mm", "max inverse radius [1/mm]"),
    ("sp_a1_mmHg_per_mm", "SP-A1 [mmHg/mm]"),
    ("iop_max_mmHg", "IOP max [mmHg]"),
    ("apex_pressure_max_mmHg", "apex air pressure max [mmHg]"),
    ("apex_pressure_hc_mmHg", "apex air pressure at HC [mmHg]"),
    ("cells", "air cells (else the solid's)"),
    ("newton_iterations", "Newton iterations"),
    ("coupled_dofs", "coupled DOFs"),
    ("dofs", "solid DOFs"),
    ("wall_s", "wall time [s]"),
]


def run(args, model, dimension):
    scene, sets = MODELS[model]
    out = os.path.join(args.out, f"{model}-{dimension}")
    summary = os.path.join(out, "summary.json")
    if not os.path.exists(summary):
        cmd = ["mpirun", "-n", str(args.ranks), "--allow-run-as-root", "--oversubscribe",
               os.path.join(ROOT, "build", "nct"), "run", os.path.join(ROOT, "scenes", scene),
               "--out", out, "--set", f'mesh.dimension="{dimension}"',
               "--set", "output.fields=false", "--set", "checkpoint.steps=0"]
        for s in sets:
            cmd += ["--set", s]
        print(f"running {model} ({dimension}) ...", file=sys.stderr, flush=True)
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(summary) as f:
        return json.load(f)


def value(s, key):
    if key == "cells":
        return s.get("air_cells", s.get("cells"))
    return s.get(key)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--models", nargs="+", default=list(MODELS), choices=list(MODELS))
    p.add_argument("--ranks", type=int, default=2)
    p.add_argument("--out", default="runs/section-accuracy")
    a = p.parse_args()
    results = {m: (run(a, m, "3d"), run(a, m, "axisymmetric")) for m in a.models}
    for m, (three, section) in results.items():
        print(f"\n### {m} ({MODELS[m][0]} {' '.join(MODELS[m][1])})\n")
        print("| | 3D | section | section - 3D |")
        print("|---|---|---|---|")
        for key, label in BIOMARKERS:
            x, y = value(three, key), value(section, key)
            if not isinstance(x, (int, float)) and not isinstance(y, (int, float)):
                continue
            fmt = (lambda v: f"{v:,}") if key.endswith("dofs") or key == "newton_iterations" \
                else (lambda v: f"{v:.4g}")
            show = lambda v: fmt(v) if isinstance(v, (int, float)) else "-"
            diff = ""
            if isinstance(x, (int, float)) and isinstance(y, (int, float)) and x != 0:
                diff = f"{y / x:.3g}x" if key in ("wall_s", "dofs", "coupled_dofs") \
                    else f"{100 * (y - x) / abs(x):+.1f} %"
            print(f"| {label} | {show(x)} | {show(y)} | {diff} |")


main()
