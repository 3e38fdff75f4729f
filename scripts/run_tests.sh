#!/usr/bin/env bash
# Sets up a fresh Debian machine (missing packages only), builds sphib and runs the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build --parallel 2 >> build.log 2>&1 || { tail -50 build.log; exit 1; }
cd build && ctest --output-on-failure --parallel 2 -L unit "$@"
