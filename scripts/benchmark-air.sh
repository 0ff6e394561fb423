#!/bin/sh
# Cost of the air (the rigid-eye puff) against the mesh and the linear
# solver. Usage: scripts/benchmark-air.sh [ranks] [extra nct run arguments...]
# Runs 4 ms of scenes/puff-rigid-eye.toml around a puff peak (16 steps of
# 0.25 ms) on three meshes with three linear solvers, and prints one row
# per run: cells, DOFs, Newton iterations, Jacobian assemblies (and
# factorisations or preconditioner set-ups), linear solves, time in
# assembly and in linear solves, total wall time. A failed run prints its
# reason.
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
np=${1:-2}
[ $# -gt 0 ] && shift
out=$(mktemp -d)

# Meshes: air.size_jet air.size_nozzle
meshes="coarse:0.4:0.25 medium:0.25:0.15 fine:0.15:0.1"
# Linear solvers (PETSc options)
mumps="-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps"
asm="-ksp_type gmres -ksp_gmres_restart 200 -ksp_max_it 1000 -ksp_rtol 1e-10 -pc_type asm -pc_asm_overlap 1 -sub_pc_type ilu -sub_pc_factor_levels 1"
schur="-ksp_type fgmres -ksp_gmres_restart 200 -ksp_max_it 1000 -ksp_rtol 1e-10 -pc_type fieldsplit -pc_fieldsplit_type schur -pc_fieldsplit_schur_fact_type lower -pc_fieldsplit_schur_precondition selfp -fieldsplit_u_ksp_type preonly -fieldsplit_u_pc_type hypre -fieldsplit_p_ksp_type preonly -fieldsplit_p_pc_type hypre"

printf "%-7s %-9s %8s %8s %7s %9s %7s %10s %9s %9s\n" mesh solver cells dofs newton jacobians solves assemble_s solve_s total_s
for m in $meshes; do
  name=${m%%:*}; rest=${m#*:}; jet=${rest%%:*}; nozzle=${rest#*:}
  for solver in mumps asm schur; do
    eval "options=\$$solver"
    dir="$out/$name-$solver"
    mpirun -n "$np" build/nct run scenes/puff-rigid-eye.toml --out "$dir" \
      --set air.size_jet=$jet --set air.size_nozzle=$nozzle \
      --set puff.duration=4.0 --set puff.peak_time=2.0 --set puff.width_t=1.0 \
      --set air.dt=0.25 --set output.fields=false --petsc "$options" "$@" \
      > "$dir.log" 2>&1 || true
    /usr/bin/python3 - "$dir/summary.json" "$name" "$solver" <<'PY'
import json, sys
try:
    s = json.load(open(sys.argv[1]))
except OSError:
    print("%-7s %-9s no summary" % (sys.argv[2], sys.argv[3])); sys.exit()
t = s["timings_s"]
line = "%-7s %-9s %8d %8d %7d %9d %7d %10.2f %9.2f %9.2f" % (sys.argv[2], sys.argv[3],
       s["cells"], s["dofs"], s["newton_iterations"], s["jacobians"], s["linear_solves"],
       t["assemble"], t["linear_solve"], s["wall_s"])
if s["status"] != "converged":
    line += "  FAILED: " + s.get("error", "")[:120]
print(line)
PY
  done
done
echo "($np ranks; run folders in $out)"
