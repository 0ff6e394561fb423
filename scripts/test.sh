#!/bin/sh
# The README's second command: build if needed, then run every test (ctest).
# Extra arguments go to ctest, e.g. scripts/test.sh -L scene or -R bad_input;
# without any, the tests labelled "slow" (the 3D hard-case matrix,
# cases/hard-cases) are left out: scripts/test.sh -L hard runs them.
set -eu
cd "$(dirname "$0")/.."
scripts/build.sh
. scripts/env.sh
# One machine: Open MPI's shared-memory transport without probing UCX
# first (which Debian's Open MPI cannot select here: 0.2 s an mpirun).
export OMPI_MCA_pml="${OMPI_MCA_pml:-ob1}"
cd build
[ $# -gt 0 ] || set -- -LE slow
# As many tests at once as there are cores (a 2-rank test takes two).
ctest --output-on-failure --timeout 1500 -j "$(nproc)" "$@"
