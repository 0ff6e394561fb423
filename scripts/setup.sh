#!/bin/sh
# The README's first command: install, build, run the default scene (the
# puff) on 2 ranks into runs/default and plot it (puff.png, profiles.png).
set -eu
cd "$(dirname "$0")/.."
scripts/build.sh
. scripts/env.sh
mpirun -n 2 build/nct run scenes/default.toml --out runs/default
scripts/plot-puff.py runs/default
