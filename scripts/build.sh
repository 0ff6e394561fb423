#!/bin/sh
# Install what is missing (Debian packages), configure and build into build/.
set -eu
cd "$(dirname "$0")/.."
. scripts/env.sh
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build -j "$(nproc)" >> build.log 2>&1 || { tail -50 build.log; exit 1; }
echo "built build/nct (log: build.log)"
