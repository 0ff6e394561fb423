#!/bin/sh
# Cost of the default scene against elements through the thickness.
# Usage: scripts/benchmark.sh [ranks] [extra nct run arguments...]
# Prints one row per mesh: cells, DOFs, time to mesh, assemble and solve
# (factorisations and back-solves), Newton iterations, Jacobian
# factorisations and the total wall time.
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
np=${1:-2}
[ $# -gt 0 ] && shift
out=$(mktemp -d)
printf "%-7s %8s %9s %8s %10s %10s %7s %9s %9s\n" layers cells dofs mesh_s assemble_s solve_s newton jacobians total_s
for layers in 3 4 5 6; do
  mpirun -n "$np" build/nct run scenes/default.toml --out "$out/l$layers" \
    --set mesh.layers=$layers --set output.fields=false "$@" > "$out/l$layers.log" 2>&1 \
    || { echo "layers $layers failed:"; tail -5 "$out/l$layers.log"; exit 1; }
  /usr/bin/python3 - "$out/l$layers/summary.json" $layers <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); t = s["timings_s"]
print("%-7s %8d %9d %8.2f %10.2f %10.2f %7d %9d %9.2f" % (sys.argv[2], s["cells"], s["dofs"],
      t["mesh"], t["assemble"], t["linear_solve"], s["newton_iterations"], s["jacobians"], s["wall_s"]))
PY
done
echo "($np ranks; run folders in $out)"
