#!/bin/sh
# Cost of the two-way coupled puff (scenes/puff-fsi.toml, the whole
# timeline) against the air mesh and the linear solver, beside the
# one-way puff's two runs: the rigid-eye air on the same air mesh
# (scenes/puff-rigid-eye.toml) and the solid loaded by its table
# (scenes/puff-cfd.toml, at the coupled run's step).
# Usage: scripts/benchmark-fsi.sh [ranks] [jet:nozzle ...]
#   (default: 0.25:0.15 0.15:0.10; the air's jet core radius 1.5 mm, as in
#   the scene; SOLVERS="lu fieldsplit" by default: the coupled linear
#   solvers to run on every mesh)
# One row per run: DOFs per block (solid, air, mesh motion, all coupled),
# the puff's steps, Newton iterations and factorisations per step, and per
# step the wall time in the blocks' assembly (solid, air, the air's shape
# derivative, mesh motion, the interface with the Jacobian's
# communication), in the linear solves, and all of the step; the run's
# wall time. A failed run prints its reason.
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
np=${1:-2}
[ $# -gt 0 ] && shift
meshes=${*:-"0.25:0.15 0.15:0.10"}
out=$(mktemp -d)

report() { # summary.json, mesh, solver
  /usr/bin/python3 - "$@" <<'PY'
import json, sys
try:
    s = json.load(open(sys.argv[1]))
except OSError:
    print("%-10s %-14s no summary" % (sys.argv[2], sys.argv[3])); sys.exit()
solver = sys.argv[4]
if isinstance(s["steps"], int):  # the air alone: a count
    n, newton = max(s["steps"], 1), s["newton_iterations"]
else:
    puff = [x for x in s["steps"] if x["phase"] == "puff"]
    n, newton = max(len(puff), 1), sum(x["newton_iterations"] for x in puff)
main = s["timings_s"].get("solvers", {}).get(solver, {})
c = s.get("coupled_timings_s", {})
blocks = [c.get(k, 0.0) for k in ("solid", "air", "air_shape", "mesh_motion")]
interface = c.get("interface", 0.0) + c.get("matrix_communication", 0.0)
step = (main.get("assemble", 0.0) + main.get("linear_solve", 0.0)) / n
solid = s["dofs"] if "air_dofs" in s or solver == "solid" else 0
air = s.get("air_dofs", s["dofs"] if solver == "air" else 0)
line = "%-10s %-14s %7d %7d %7d %8d %5d %7.2f %6.2f " % (
    sys.argv[2], sys.argv[3], solid, air, s.get("mesh_motion_dofs", 0),
    s.get("coupled_dofs", 0), n, newton / n, main.get("jacobians", 0) / n)
line += " ".join("%6.2f" % (b / n) for b in blocks)
line += " %6.2f %7.2f %7.2f %8.1f" % (interface / n, main.get("linear_solve", 0.0) / n, step,
                                       s["wall_s"])
if s["status"] != "converged":
    line += "  FAILED: " + s.get("error", "")[:120]
print(line)
PY
}

printf "%-10s %-14s %7s %7s %7s %8s %5s %7s %6s %6s %6s %6s %6s %6s %7s %7s %8s\n" \
  air_mesh solver solid air motion coupled steps newton/ LU/ solid air shape motion \
  iface solve/ step/ wall_s
printf "%-10s %-14s %7s %7s %7s %8s %5s %7s %6s %6s %6s %6s %6s %6s %7s %7s %8s\n" \
  "" "" dofs dofs dofs dofs "" step step s/step s/step s/step s/step s/step step_s s ""
solvers=${SOLVERS:-"lu fieldsplit"}
for m in $meshes; do
  jet=${m%%:*}; nozzle=${m#*:}
  mesh="--set air.size_jet=$jet --set air.size_nozzle=$nozzle --set air.jet_radius=1.5"
  dir="$out/$jet-rigid"
  # shellcheck disable=SC2086
  mpirun -n "$np" build/nct run scenes/puff-rigid-eye.toml --out "$dir" $mesh \
    --set output.fields=false > "$dir.log" 2>&1 || true
  report "$dir/summary.json" "$jet/$nozzle" "rigid eye" air
  dir="$out/$jet-one-way"
  mpirun -n "$np" build/nct run scenes/puff-cfd.toml --out "$dir" --set dynamics.dt=0.25 \
    --set puff.table=\"$out/$jet-rigid/corneal_pressure.csv\" --set output.fields=false \
    > "$dir.log" 2>&1 || true
  report "$dir/summary.json" "$jet/$nozzle" "one-way" solid
  for solver in $solvers; do
    dir="$out/$jet-$solver"
    # shellcheck disable=SC2086
    mpirun -n "$np" build/nct run scenes/puff-fsi.toml --out "$dir" $mesh \
      --set fsi.linear_solver=\"$solver\" --set output.fields=false > "$dir.log" 2>&1 || true
    report "$dir/summary.json" "$jet/$nozzle" "fsi $solver" coupled
  done
done
echo "($np ranks; run folders in $out)"
