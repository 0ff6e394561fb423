#!/bin/sh
# One-way coupling: the rigid-eye air puff (scenes/puff-rigid-eye.toml)
# writes the corneal pressure table, which then drives the NCT puff on the
# elastic eye (scenes/puff-cfd.toml, the default scene's timeline, with
# this run's table instead of the shipped copy); the
# biomarkers are printed next to the default scene's assumed Gaussian.
# Usage: scripts/one-way.sh [ranks]. Run folders: runs/puff-rigid-eye,
# runs/puff-cfd, runs/default (reused when its summary exists).
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
np=${1:-2}
mpirun -n "$np" build/nct run scenes/puff-rigid-eye.toml --out runs/puff-rigid-eye
# The table just computed (a path relative to the scene file's folder).
mpirun -n "$np" build/nct run scenes/puff-cfd.toml --out runs/puff-cfd \
  --set 'puff.table="../runs/puff-rigid-eye/corneal_pressure.csv"'
[ -f runs/default/summary.json ] || mpirun -n "$np" build/nct run scenes/default.toml --out runs/default
/usr/bin/python3 - <<'PY'
import json
keys = ["deflection_amplitude_mm", "peak_distance_mm", "a1_time_ms", "hc_time_ms", "a2_time_ms",
        "a1_length_mm", "a2_length_mm", "iop_max_mmHg", "apex_pressure_hc_mmHg",
        "apex_pressure_max_mmHg", "wall_s"]
runs = {name: json.load(open("runs/%s/summary.json" % name)) for name in ("default", "puff-cfd")}
print("%-26s %14s %14s" % ("biomarker", "gaussian", "cfd table"))
for k in keys:
    print("%-26s %14s %14s" % (k, *("%.3f" % runs[n][k] if k in runs[n] else "-"
                                   for n in ("default", "puff-cfd"))))
PY
