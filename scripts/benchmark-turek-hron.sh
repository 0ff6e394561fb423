#!/bin/sh
# Turek-Hron FSI1 (scenes/turek-hron-fsi1.toml) over meshes and the
# coupled linear solvers: cost and error against the published values.
# Usage: scripts/benchmark-turek-hron.sh [ranks] [h ...]
#   h: the element size at the flag and the cylinder [mm] (default: 4 2);
#   SOLVERS="lu fieldsplit" by default: the coupled linear solvers.
# One row per run: DOFs per block (solid, air, mesh motion, all coupled),
# steps, Newton iterations and factorisations, the wall time in assembly
# and in linear solves, the whole run; the tip's displacement and the drag
# and lift per unit depth with their errors from Turek & Hron (2006):
# u_x 0.0227 mm, u_y 0.8209 mm, drag 14.295 N/m, lift 0.7638 N/m.
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
np=${1:-2}
[ $# -gt 0 ] && shift
sizes=${*:-"4 2"}
out=$(mktemp -d)

report() { # summary.json, h, solver
  /usr/bin/python3 - "$@" <<'PY'
import json, sys
try:
    s = json.load(open(sys.argv[1]))
except OSError:
    print("%-5s %-10s no summary" % (sys.argv[2], sys.argv[3])); sys.exit()
t = s["timings_s"].get("solvers", {}).get("coupled", {})
tip = s["steps"][-1]["probe_0_displacement_mm"] if s["steps"] else [0, 0, 0]
f = s.get("air", {}).get("force_N", [0, 0, 0])
depth = 10.0  # mm, the slab's (meshes/turek-hron.geo)
values = [tip[0], tip[1], f[0] / depth * 1e3, f[1] / depth * 1e3]
published = [0.0227, 0.8209, 14.295, 0.7638]
line = "%-5s %-10s %7d %7d %7d %8d %5d %6d %4d %8.1f %8.1f %8.1f" % (
    sys.argv[2], sys.argv[3], s["dofs"], s.get("air_dofs", 0), s.get("mesh_motion_dofs", 0),
    s.get("coupled_dofs", 0), len(s["steps"]), s["newton_iterations"], s["jacobians"],
    t.get("assemble", 0.0), t.get("linear_solve", 0.0), s["wall_s"])
for v, p in zip(values, published):
    line += " %9.5f %+6.2f%%" % (v, 100 * (v - p) / p)
if s["status"] != "converged":
    line += "  FAILED: " + s.get("error", "")[:120]
print(line)
PY
}

printf "%-5s %-10s %7s %7s %7s %8s %5s %6s %4s %8s %8s %8s %9s %7s %9s %7s %9s %7s %9s %7s\n" \
  h solver solid air motion coupled steps newton LU assem_s solve_s wall_s \
  ux_mm err uy_mm err drag_N/m err lift_N/m err
solvers=${SOLVERS:-"lu fieldsplit"}
for h in $sizes; do
  for solver in $solvers; do
    dir="$out/h$h-$solver"
    mpirun -n "$np" build/nct run scenes/turek-hron-fsi1.toml --out "$dir" \
      --set mesh.parameters.h="$h" --set fsi.linear_solver=\""$solver"\" \
      --set output.fields=false > "$dir.log" 2>&1 || true
    report "$dir/summary.json" "$h" "$solver"
  done
done
echo "($np ranks; run folders in $out)"
