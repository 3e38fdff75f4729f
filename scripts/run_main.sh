#!/usr/bin/env bash
# Sets up a fresh Debian machine (missing packages only), builds sphib, runs the main job (the
# oscillating membrane of Section 5.2.2, 64 x 64, Nb = 128, dt = 1e-4, t in [0, 10]) and draws
# its pictures into out/membrane_oscillation/. Extra arguments go to `sphib run`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build --parallel 2 --target sphib >> build.log 2>&1 || { tail -50 build.log; exit 1; }
build/sphib run cases/membrane_oscillation.toml --out out/membrane_oscillation "$@"
/usr/bin/python3 scripts/plot.py out/membrane_oscillation --snapshots 21
