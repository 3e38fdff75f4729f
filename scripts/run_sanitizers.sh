#!/usr/bin/env bash
# Builds the library and tests with AddressSanitizer and UndefinedBehaviorSanitizer and runs the
# unit tests. Leaks inside libhdf5 (it keeps a few allocations when a file cannot be created)
# are suppressed by name; everything else fails the run. The Python module is left out (an
# AddressSanitizer build cannot be imported by an uninstrumented python3).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPHIB_BUILD_BENCH=OFF -DSPHIB_PYTHON=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  > build-asan.log 2>&1 || { cat build-asan.log; exit 1; }
cmake --build build-asan --parallel 2 >> build-asan.log 2>&1 || { tail -50 build-asan.log; exit 1; }
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp"
export UBSAN_OPTIONS="print_stacktrace=1"
cd build-asan && ctest --output-on-failure --parallel 2 -L unit
