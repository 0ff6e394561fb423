#!/bin/sh
# The README's second command: build if needed, then run every test (ctest).
# Extra arguments go to ctest, e.g. scripts/test.sh -L scene or -R bad_input.
set -eu
cd "$(dirname "$0")/.."
scripts/build.sh
. scripts/env.sh
cd build
ctest --output-on-failure --timeout 1500 "$@"
