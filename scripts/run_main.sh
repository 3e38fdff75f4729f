#!/usr/bin/env bash
# Sets up a fresh Debian machine (missing packages only), builds sphib (the command and the Python
# module), runs the main job (the oscillating membrane of Section 5.2.2, 64 x 64, Nb = 128,
# dt = 1e-4, t in [0, 10]) and draws its pictures into out/membrane_oscillation/. Extra arguments go
# to `sphib run`.
#
# The Python module is built into build/python and registered for this user's Python (a file
# sphib-build.pth in `python3 -m site --user-site` naming build/python), so that afterwards
# `/usr/bin/python3 -c "import sphib"` works from anywhere and sees every rebuild. Delete that file to
# undo it; `pip install` or `cmake --install` install a copy instead (README, "Python"; docs/guide/python.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > build.log 2>&1 || { cat build.log; exit 1; }
targets=(sphib)
cmake --build build --target help 2>/dev/null | grep -q "^sphib_python:" && targets+=(sphib_python)
cmake --build build --parallel 2 --target "${targets[@]}" >> build.log 2>&1 || { tail -50 build.log; exit 1; }
if [ -d build/python ] && ls build/python/sphib*.so > /dev/null 2>&1; then
  site=$(/usr/bin/python3 -m site --user-site)
  mkdir -p "$site"
  echo "$PWD/build/python" > "$site/sphib-build.pth"
  echo "run_main: the Python module is build/python/$(cd build/python && ls sphib*.so); $site/sphib-build.pth makes it importable"
fi
build/sphib run cases/membrane_oscillation.toml --out out/membrane_oscillation "$@"
/usr/bin/python3 scripts/plot.py out/membrane_oscillation --snapshots 21
