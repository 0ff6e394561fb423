#!/bin/sh
# The README's first command: install, build, and run the default scene on
# 2 ranks into runs/default.
set -eu
cd "$(dirname "$0")/.."
scripts/build.sh
. scripts/env.sh
mpirun -n 2 build/nct run scenes/default.toml --out runs/default
