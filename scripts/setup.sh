#!/bin/sh
# The README's first command: install, build, run the default scene (the
# puff) on 2 ranks into runs/default; the run writes its page,
# runs/default/report.html.
set -eu
cd "$(dirname "$0")/.."
scripts/build.sh
. scripts/env.sh
mpirun -n 2 build/nct run scenes/default.toml --out runs/default
