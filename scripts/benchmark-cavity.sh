#!/bin/sh
# Cost of the closed cavities and of the zero-pressure geometry, on the
# cavity-press scene (5 layers, P2).
# Usage: scripts/benchmark-cavity.sh [ranks]
# Table 1: the press phase with the cavity closed (bordered Newton) against
#   the open cavity (plain displacement solve), with Jacobian reuse and with
#   full Newton: Newton iterations, factorisations, time in assembly, in
#   linear solves, of it the border's share (its assembly, back-solves and
#   Schur complement), time per Newton iteration, total.
# Table 2: the zero-pressure fixed point with and without Aitken
#   acceleration, at two tolerances: iterations, final residual, Newton
#   iterations, wall time.
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
np=${1:-2}
out=$(mktemp -d)
run() { # name, then --set arguments
  name=$1; shift
  mpirun -n "$np" build/nct run scenes/cavity-press.toml --out "$out/$name" \
    --set output.fields=false "$@" > "$out/$name.log" 2>&1 \
    || { echo "$name failed:"; tail -5 "$out/$name.log"; exit 1; }
}
for jac in reuse every_iteration; do
  for model in closed constant_pressure; do
    run "press-$model-$jac" --set zero_pressure.enabled=false \
      --set "cavity.model=\"$model\"" --set "solver.jacobian=\"$jac\""
  done
done
for tol in 1e-4 1e-6; do
  for acc in aitken none; do
    run "zero-pressure-$acc-$tol" --set press.pressure=0.0 \
      --set "zero_pressure.acceleration=\"$acc\"" --set zero_pressure.tolerance=$tol
  done
done
/usr/bin/python3 - "$out" "$np" <<'PY'
import json, sys
out, np = sys.argv[1], sys.argv[2]
print("Press phase (cavity-press scene without zero-pressure), %s ranks" % np)
print("%-18s %-16s %6s %6s %10s %9s %9s %7s %10s %8s" % ("cavity", "jacobian", "newton", "jacs",
      "assemble_s", "solve_s", "border_s", "border%", "ms/newton", "total_s"))
for jac in ("reuse", "every_iteration"):
    for model in ("closed", "constant_pressure"):
        s = json.load(open("%s/press-%s-%s/summary.json" % (out, model, jac)))
        t = s["timings_s"]; work = t["assemble"] + t["linear_solve"]
        print("%-18s %-16s %6d %6d %10.2f %9.2f %9.2f %7.1f %10.1f %8.2f" % (model, jac,
              s["newton_iterations"], s["jacobians"], t["assemble"], t["linear_solve"],
              t["border"], 100 * t["border"] / work, 1000 * work / s["newton_iterations"],
              s["wall_s"]))
print()
print("Zero-pressure geometry (15 mmHg), %s ranks" % np)
print("%-12s %-12s %10s %14s %14s %8s %8s" % ("tolerance_mm", "acceleration", "iterations",
      "residual_max_mm", "residual_rms_mm", "newton", "wall_s"))
for tol in ("1e-4", "1e-6"):
  for acc in ("aitken", "none"):
    s = json.load(open("%s/zero-pressure-%s-%s/summary.json" % (out, acc, tol)))
    print("%-12s %-12s %10d %14.2e %14.2e %8d %8.2f" % (tol, acc, s["zero_pressure_iterations"],
          s["zero_pressure_residual_max_mm"], s["zero_pressure_residual_rms_mm"],
          s["zero_pressure_newton_iterations"], s["zero_pressure_wall_s"]))
print("(run folders in %s)" % out)
PY
