#!/usr/bin/env bash
# Installs Debian's ParaView (pvpython) and Xvfb when missing, builds sphib and runs the test that
# opens a run's output in ParaView with its default reader (ctest label paraview, about 15 s).
# The screenshot it saves is build/paraview_test/paraview_oscillation.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --recommends paraview python3-paraview xvfb xauth
# Configure again: the test is registered only when pvpython and xvfb-run are found.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build --parallel 2 --target sphib >> build.log 2>&1 || { tail -50 build.log; exit 1; }
cd build && ctest --output-on-failure --no-tests=error -L paraview "$@"
