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
# The section's converged mesh (scenes/puff-fsi-section.toml, docs/sections.md):
# the air's models also run on it, as a third column.
CONVERGED = ["air.size_jet=0.05", "air.size_nozzle=0.0325", "air.size_gradation=0.0625",
             "air.size_far=1.25", "air.jet_radius=1.5", "mesh.size_cornea=0.125",
             "mesh.size_limbus=0.125", "mesh.size_sclera=0.375"]
MODELS = {  # scene, its keys, whether the air is computed
    "prescribed": ("default.toml", [], False),
    "prescribed-iso": ("default.toml", ISO, False),
    "rigid-eye": ("puff-rigid-eye.toml", [], True),
    "one-way": ("puff-cfd.toml", [], False),
    "two-way": ("puff-fsi.toml", [], True),
    "two-way-iso": ("puff-fsi.toml", ISO, True),
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
    ("cells", "air cells"),
    ("newton_iterations", "Newton iterations"),
    ("coupled_dofs", "coupled DOFs"),
    ("dofs", "DOFs (the solid's; the rigid eye: the air's)"),
    ("wall_s", "wall time [s]"),
]


def run(args, model, dimension, converged=False):
    scene, sets, _ = MODELS[model]
    sets = sets + (CONVERGED if converged else [])
    out = os.path.join(args.out, f"{model}-{dimension}" + ("-converged" if converged else ""))
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
    if s is None:
        return None
    if key == "cells":
        return s.get("air_cells", s.get("cells") if "stagnation_pressure_mmHg" in s else None)
    return s.get(key)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--models", nargs="+", default=list(MODELS), choices=list(MODELS))
    p.add_argument("--ranks", type=int, default=2)
    p.add_argument("--out", default="runs/section-accuracy")
    a = p.parse_args()
    results = {m: (run(a, m, "3d"), run(a, m, "axisymmetric"),
                   run(a, m, "axisymmetric", True) if MODELS[m][2] else None)
               for m in a.models}
    number = lambda v: isinstance(v, (int, float))
    for m, (three, *sections) in results.items():
        print(f"\n### {m} ({MODELS[m][0]} {' '.join(MODELS[m][1])})\n")
        columns = ["section"] + (["section, converged mesh"] if sections[1] else [])
        print("| | 3D | " + " | ".join(f"{c} | {c} - 3D" for c in columns) + " |")
        print("|---|---|" + "---|---|" * len(columns))
        for key, label in BIOMARKERS:
            x = value(three, key)
            ys = [value(sec, key) for sec in sections if sec]
            if not number(x) and not any(number(y) for y in ys):
                continue
            fmt = (lambda v: f"{v:,}") if key.endswith("dofs") or key in ("newton_iterations", "cells") \
                else (lambda v: f"{v:.4g}")
            cells = [fmt(x) if number(x) else "-"]
            for y in ys:
                diff = ""
                if number(x) and number(y) and x != 0:
                    diff = f"{y / x:.3g}x" if key in ("wall_s", "dofs", "coupled_dofs", "cells") \
                        else f"{100 * (y - x) / abs(x):+.1f} %"
                cells += [fmt(y) if number(y) else "-", diff]
            print(f"| {label} | " + " | ".join(cells) + " |")


main()
