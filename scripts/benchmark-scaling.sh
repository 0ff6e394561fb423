#!/bin/sh
# Cost and memory of the default puff against the mesh: layers through the
# wall and in-plane element size refined together, fields off.
# Usage: scripts/benchmark-scaling.sh [ranks] [extra nct run arguments...]
# Prints one row per mesh (DOFs, wall time, Newton iterations,
# factorisations, the mean factorisation and back-solve, peak memory) and
# the exponents of a power law fitted to time and memory against DOFs.
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
np=${1:-2}
[ $# -gt 0 ] && shift
out=$(mktemp -d)
# layers, cornea and limbus size [mm], sclera size [mm]
for level in "3 0.5 1.5" "4 0.35 1.05" "5 0.3 0.9" "6 0.25 0.75"; do
  set -- $level "$@"
  name="l$1-h$2"
  mpirun -n "$np" build/nct run scenes/default.toml --out "$out/$name" \
    --set mesh.layers="$1" --set mesh.size_cornea="$2" --set mesh.size_limbus="$2" \
    --set mesh.size_sclera="$3" --set output.fields=false > "$out/$name.log" 2>&1 \
    || { echo "$name failed:"; tail -5 "$out/$name.log"; exit 1; }
  shift 3
  echo "$out/$name" >> "$out/runs"
done
/usr/bin/python3 - "$out" <<'PY'
import json, math, pathlib, sys
out = pathlib.Path(sys.argv[1])
rows = []
print("%-12s %9s %9s %7s %6s %10s %9s %12s %11s" % ("mesh", "dofs", "wall_s", "newton",
      "facts", "factor_s", "solve_ms", "peak_rank_mb", "peak_all_mb"))
for run in (out / "runs").read_text().split():
    s = json.loads((pathlib.Path(run) / "summary.json").read_text())
    p = {k: sum(ph.get(k, 0) for ph in s["profile"])
         for k in ("factorisations", "factorise_s", "linear_solves", "solve_s")}
    factor = p["factorise_s"] / max(p["factorisations"], 1)
    solve = 1e3 * p["solve_s"] / max(p["linear_solves"], 1)
    rows.append((s["dofs"], s["wall_s"], s["memory_peak_total_mb"]))
    print("%-12s %9d %9.1f %7d %6d %10.2f %9.1f %12.0f %11.0f" % (pathlib.Path(run).name,
          s["dofs"], s["wall_s"], s["newton_iterations"], p["factorisations"], factor, solve,
          s["memory_peak_rank_mb"], s["memory_peak_total_mb"]))
def slope(i):
    x = [math.log(r[0]) for r in rows]; y = [math.log(r[i]) for r in rows]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
print("power law against DOFs: time ~ N^%.2f, peak memory ~ N^%.2f" % (slope(1), slope(2)))
PY
echo "($np ranks; run folders in $out)"
