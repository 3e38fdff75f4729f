#!/usr/bin/env bash
# One core against two (OpenMP over the products' rows, fluid/products.hpp): time per step of the
# oscillating membrane (h = 1.2 dx, Nb = 2 Nx, dt = 1e-4) and the start-up Poiseuille flow
# (h = 1.525 dx), Nx = Ny = 64 .. 512, OMP_NUM_THREADS = 1 and 2, each a fresh `sphib run` of a
# fixed number of steps. Prints a Markdown table; the runs go to bench_out/two_cores/.
#   bench/two_cores.sh [STEPS]      (default 200; needs a quiet machine: a busy second core makes
#                                   the two-thread runs slower, not faster)
set -euo pipefail
cd "$(dirname "$0")/.."
steps=${1:-200}
out=bench_out/two_cores
mkdir -p "$out"
cmake --build build --target sphib > /dev/null
echo "| case | Nx | 1 thread ms/step | 2 threads ms/step | speed-up | products share (1 thread) |"
echo "|---|---:|---:|---:|---:|---:|"
for c in membrane_oscillation poiseuille; do
  for nx in 64 128 256 512; do
    sets=(--set grid.nx=$nx --set grid.ny=$nx --set output.interval=0 --set time.max_steps=$steps)
    [ "$c" = membrane_oscillation ] && sets+=(--set membrane.nb=$((2 * nx)))
    t=()
    for th in 1 2; do
      OMP_NUM_THREADS=$th build/sphib run cases/$c.toml --out "$out/${c}_${nx}_$th" --quiet "${sets[@]}"
      t+=("$(/usr/bin/python3 -c "import json; print(json.load(open('$out/${c}_${nx}_$th/summary.json'))['seconds_per_step'] * 1e3)")")
    done
    /usr/bin/python3 - "$out/${c}_${nx}_1/summary.json" "$c" "$nx" "${t[0]}" "${t[1]}" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
p = d["profile_seconds"]
prod = sum(v for k, v in p.items() if k.startswith(("convection", "viscous", "divergence", "projection")))
t1, t2 = float(sys.argv[4]), float(sys.argv[5])
print("| %s | %s | %.3f | %.3f | %.2f | %.0f%% |" % (sys.argv[2], sys.argv[3], t1, t2, t1 / t2, 100 * prod / d["loop_seconds"]))
PY
  done
done
