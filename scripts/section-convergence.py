#!/usr/bin/python3
"""Mesh and time-step convergence of the coupled puff on the eye's
axisymmetric section (docs/sections.md).

Runs a coupled scene (scenes/puff-fsi.toml unless --scene) with
mesh.dimension = "axisymmetric" over a ladder of air meshes, each level
halving air.size_jet and air.size_nozzle (with --solid the eye's
mesh.size_* too; with --uniform also the growth of the air's cells away
from the jet's core and their largest size, so that every cell halves), at the scene's time step and at half of it on the two
finest meshes. Prints a table of the biomarkers and the wall time, then
per biomarker the observed order over the three finest meshes and
Richardson's estimate of the converged value, with each run's distance
from it.

Usage: scripts/section-convergence.py [--scene S] [--levels N] [--ranks N]
       [--out DIR] [--solid | --uniform] [--set KEY=VALUE ...]
A finished case (its summary.json present) is not run again.
"""
import argparse
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESPONSES = [("deformation_amplitude_mm", "deformation [mm]"),
             ("deflection_amplitude_mm", "deflection [mm]"),
             ("apex_pressure_max_mmHg", "apex pressure [mmHg]"),
             ("a1_time_ms", "A1 [ms]"), ("hc_time_ms", "HC [ms]"), ("a2_time_ms", "A2 [ms]")]
BASE = {"air.size_jet": 0.2, "air.size_nozzle": 0.13,
        "mesh.size_cornea": 0.5, "mesh.size_limbus": 0.5, "mesh.size_sclera": 1.5,
        "air.size_gradation": 0.25, "air.size_far": 5.0}


def refined(key, a):
    """Is this size halved from level to level?"""
    if key.startswith("mesh."):
        return a.solid or a.uniform
    if key in ("air.size_gradation", "air.size_far"):
        return a.uniform
    return True


def run(args, name, sets):
    out = os.path.join(args.out, name)
    summary = os.path.join(out, "summary.json")
    if not os.path.exists(summary):
        cmd = ["mpirun", "-n", str(args.ranks), "--allow-run-as-root", "--oversubscribe",
               os.path.join(ROOT, "build", "nct"), "run", args.scene, "--out", out,
               "--set", 'mesh.dimension="axisymmetric"', "--set", "output.fields=false",
               "--set", "checkpoint.steps=0"]
        for s in sets + args.set:
            cmd += ["--set", s]
        print(f"running {name} ...", file=sys.stderr, flush=True)
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return json.load(open(summary))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scene", default=os.path.join(ROOT, "scenes", "puff-fsi.toml"))
    p.add_argument("--levels", type=int, default=4)
    p.add_argument("--ranks", type=int, default=2)
    p.add_argument("--out", default="runs/section-convergence")
    p.add_argument("--solid", action="store_true", help="refine the eye's mesh with the air's")
    p.add_argument("--uniform", action="store_true",
                   help="refine everywhere: the eye's mesh, and the air's sizes away from the "
                        "jet's core too (air.size_gradation, air.size_far)")
    p.add_argument("--set", action="append", default=[])
    a = p.parse_args()
    dt = 0.25
    for s in a.set:
        if s.startswith("dynamics.dt="):
            dt = float(s.split("=")[1])
    rows = []
    for level in range(a.levels):
        f = 0.5 ** level
        sets = [f"{k}={v * f}" for k, v in BASE.items() if refined(k, a)]
        rows.append((level, dt, run(a, f"level{level}-dt{dt}", sets)))
    for level in range(max(0, a.levels - 2), a.levels):
        f = 0.5 ** level
        sets = [f"{k}={v * f}" for k, v in BASE.items() if refined(k, a)]
        sets.append(f"dynamics.dt={dt / 2}")
        rows.append((level, dt / 2, run(a, f"level{level}-dt{dt / 2}", sets)))

    print("| air mesh (size_jet) | dt [ms] | air cells | coupled DOFs | "
          + " | ".join(label for _, label in RESPONSES) + " | Newton | wall [s] |")
    print("|---" * (len(RESPONSES) + 6) + "|")
    for level, step, s in rows:
        values = " | ".join(f"{s.get(k, float('nan')):.4f}" for k, _ in RESPONSES)
        print(f"| {BASE['air.size_jet'] * 0.5 ** level:.4f} | {step} | {s.get('air_cells')} | "
              f"{s.get('coupled_dofs', '')} | {values} | {s.get('newton_iterations')} | "
              f"{s.get('wall_s', 0):.1f} |")
    finest = [s for level, step, s in rows if step == dt][-3:]
    if len(finest) == 3:
        print("\n| biomarker | observed order | Richardson estimate | finest mesh | its error | "
              "half step on the finest | its change |")
        print("|---|---|---|---|---|---|---|")
        half = rows[-1][2]
        for key, label in RESPONSES:
            f1, f2, f3 = (s.get(key, float("nan")) for s in finest)
            d1, d2 = f2 - f1, f3 - f2
            order = math.log2(d1 / d2) if d1 * d2 > 0 and d2 != 0 else float("nan")
            limit = f3 + d2 / (2 ** order - 1) if order == order and order > 0 else float("nan")
            err = (f3 / limit - 1) * 100 if limit == limit else float("nan")
            h = half.get(key, float("nan"))
            if order == order:
                converged = f"{order:.2f} | {limit:.4f} | {f3:.4f} | {err:+.2f} %"
            else:  # not monotone: no order; the three finest meshes' spread instead
                spread = (max(f1, f2, f3) - min(f1, f2, f3)) / abs(f3) * 100
                converged = f"- (not monotone) | - | {f3:.4f} | spread {spread:.2f} %"
            print(f"| {label} | {converged} | {h:.4f} | {(h / f3 - 1) * 100:+.2f} % |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
