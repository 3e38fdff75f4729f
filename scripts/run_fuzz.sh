#!/usr/bin/env bash
# Fuzzes the scene parser with libFuzzer for a bounded time (default 60 s), starting from the
# corpus in fuzz/corpus (the case files and a few broken ones) and the adversarial scenes of
# tests/bad_scenes. New interesting inputs are kept in build-fuzz/corpus; a crash leaves crash-*
# files and a non-zero exit.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
bash scripts/setup.sh
# clang with its OpenMP runtime (sphib's products use OpenMP)
if ! command -v clang++ > /dev/null || ! dpkg-query -W -f='${Status}' libomp-dev 2>/dev/null | grep -q "install ok installed"; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq clang libomp-dev > /dev/null
fi
CXX=clang++ CC=clang cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPHIB_FUZZ=ON \
  -DSPHIB_BUILD_TESTS=OFF -DSPHIB_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer" > build-fuzz.log 2>&1 \
  || { cat build-fuzz.log; exit 1; }
cmake --build build-fuzz --target fuzz_scene >> build-fuzz.log 2>&1 || { tail -30 build-fuzz.log; exit 1; }
mkdir -p build-fuzz/corpus
cp fuzz/corpus/* build-fuzz/corpus/
cp tests/bad_scenes/*.toml build-fuzz/corpus/
cd build-fuzz && ASAN_OPTIONS=detect_leaks=0 ./fuzz_scene -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -print_final_stats=1 corpus 2>&1 | tail -15
