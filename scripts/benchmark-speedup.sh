#!/bin/sh
# The same scene with two builds, alternating, back to back: how much faster
# this build is than another (e.g. an older commit's), and what moved.
# Usage: [OTHER_SCENE=file] scripts/benchmark-speedup.sh OTHER_NCT [pairs] [scene] [ranks]
#   e.g. git worktree add ../nct-581e1cc 581e1cc && (cd ../nct-581e1cc && scripts/build.sh)
#        OTHER_SCENE=../nct-581e1cc/scenes/default.toml \
#          scripts/benchmark-speedup.sh ../nct-581e1cc/build/nct 4
# OTHER_SCENE (default: the same scene) is the scene the other build runs,
# e.g. the scene file as it stood at that commit.
# Prints each pair's wall times and ratio, the median ratio, and the largest
# relative change of the Corvis biomarkers between the two builds.
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
other=$(realpath "$1")
pairs=${2:-3}
scene=${3:-scenes/default.toml}
np=${4:-2}
other_scene=${OTHER_SCENE:-$scene}
out=$(mktemp -d)
i=1
while [ "$i" -le "$pairs" ]; do
  for build in other this; do
    exe=build/nct
    run_scene=$scene
    [ "$build" = other ] && { exe=$other; run_scene=$other_scene; }
    mpirun -n "$np" "$exe" run "$run_scene" --out "$out/$build-$i" > "$out/$build-$i.log" 2>&1 \
      || { echo "$build run $i failed:"; tail -5 "$out/$build-$i.log"; exit 1; }
  done
  i=$((i + 1))
done
/usr/bin/python3 - "$out" "$pairs" <<'PY'
import json, pathlib, statistics, sys
out, pairs = pathlib.Path(sys.argv[1]), int(sys.argv[2])
load = lambda name: json.loads((out / name / "summary.json").read_text())
ratios = []
print("%4s %10s %10s %7s" % ("pair", "other [s]", "this [s]", "ratio"))
for i in range(1, pairs + 1):
    a, b = load("other-%d" % i), load("this-%d" % i)
    ratios.append(a["wall_s"] / b["wall_s"])
    print("%4d %10.1f %10.1f %7.2f" % (i, a["wall_s"], b["wall_s"], ratios[-1]))
print("median ratio %.2f (min %.2f, max %.2f)" % (statistics.median(ratios), min(ratios),
                                                   max(ratios)))
a, b = load("other-1"), load("this-1")
keys = sorted(k for k in a if k in b and isinstance(a[k], float) and
              k.endswith(("_mm", "_ms", "_mmHg", "_m_s", "_per_mm", "_ms_per_mm"))
              and not k.startswith(("zero_pressure", "rest_")) and abs(a[k]) > 1e-12)
worst = max(keys, key=lambda k: abs(b[k] - a[k]) / abs(a[k]))
for k in keys:
    print("  %-40s %14.8g %14.8g %9.1e" % (k, a[k], b[k], abs(b[k] - a[k]) / abs(a[k])))
print("largest relative change: %s %.1e; %d DOFs, run folders in %s" % (
    worst, abs(b[worst] - a[worst]) / abs(a[worst]), b["dofs"], out))
PY
echo "($np ranks)"
