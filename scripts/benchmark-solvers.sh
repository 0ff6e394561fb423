#!/bin/sh
# The default puff under each Newton / linear-solver strategy, back to back.
# Usage: scripts/benchmark-solvers.sh [ranks] [extra nct run arguments...]
# Prints one row per strategy: wall time, Newton iterations,
# factorisations, Krylov iterations, time in assembly and in linear solves,
# and the largest relative change of the biomarkers against the first row.
# Each run's profile: scripts/profile.py <run folder>.
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
np=${1:-2}
[ $# -gt 0 ] && shift
out=$(mktemp -d)
run() { # name, then nct run arguments
  name=$1
  shift
  mpirun -n "$np" build/nct run scenes/default.toml --out "$out/$name" \
    --set output.fields=false "$@" > "$out/$name.log" 2>&1 \
    || { echo "$name failed:"; tail -5 "$out/$name.log"; exit 1; }
}
# Every row spells out its strategy, so the table does not depend on the
# defaults or the scene's [solver]: all but the last two at 1e-9 N with LU.
# The first row is 581e1cc's strategy, default_scene the scene's own.
tight='--set solver.atol=1e-9 --set solver.factorisation="lu"'
old="$tight --set solver.anderson=0 --set solver.reuse_contraction=0.25 --set solver.predictor=\"previous\""
new="--set solver.anderson=5 --set solver.reuse_contraction=0.7 --set solver.predictor=\"extrapolate\""
run modified_newton $old
run every_iteration $old --set 'solver.jacobian="every_iteration"'
run krylov $old --set 'solver.jacobian="krylov"'
run ldlt $old --set 'solver.factorisation="ldlt"'
run anderson $tight --set solver.anderson=5 --set solver.reuse_contraction=0.7 --set 'solver.predictor="previous"'
run anderson_predictor $tight $new
run anderson_predictor_ldlt $tight $new --set 'solver.factorisation="ldlt"'
run default_scene $new --set 'solver.factorisation="ldlt"' --set solver.atol=1e-7
run blr_1e-8 $old --petsc "-mat_mumps_icntl_35 1 -mat_mumps_cntl_7 1e-8"
/usr/bin/python3 - "$out" <<'PY'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
names = ["modified_newton", "every_iteration", "krylov", "ldlt", "anderson",
         "anderson_predictor", "anderson_predictor_ldlt", "default_scene", "blr_1e-8"]
keys = ["deformation_amplitude_mm", "deflection_amplitude_mm", "peak_distance_mm", "hc_time_ms",
        "a1_time_ms", "a2_time_ms", "whole_eye_movement_max_mm"]
ref = json.loads((out / names[0] / "summary.json").read_text())
print("%-24s %8s %7s %7s %7s %10s %9s %12s" % ("strategy", "wall_s", "newton", "factor",
      "krylov", "assemble_s", "linear_s", "max_rel_change"))
for n in names:
    s = json.loads((out / n / "summary.json").read_text())
    t = s["timings_s"]
    change = max(abs(s[k] - ref[k]) / abs(ref[k]) for k in keys)
    print("%-24s %8.1f %7d %7d %7d %10.1f %9.1f %12.2e" % (n, s["wall_s"], s["newton_iterations"],
          s["factorisations"], s["krylov_iterations"], t["assemble"], t["linear_solve"], change))
print("(%s DOFs; run folders in %s)" % (ref["dofs"], out))
PY
echo "($np ranks)"
