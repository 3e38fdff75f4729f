#!/usr/bin/env bash
# One thread against two (limits.threads: the fused passes by row blocks, the lattice solvers by
# columns, row blocks and wavenumbers, fluid/common/threads.hpp): time per step of the oscillating
# membrane (h = 1.2 dx, Nb = 2 Nx, dt = 1e-4) and the start-up Poiseuille flow (h = 1.525 dx),
# Nx = Ny = 64 .. 1024, each a fresh `sphib run` of a fixed number of steps, the one- and two-thread
# runs of a size one after the other. Prints the load before and after and a Markdown table with the
# speed-up and the share of the one-thread steps' time that the passes and solves take; the runs
# go to bench_out/two_cores/.
#   bench/two_cores.sh [STEPS [SIZES]]   (default 200 and "64 128 256 512 1024"; needs a quiet
#                                         machine: a busy second core makes the two-thread runs
#                                         slower, not faster)
set -euo pipefail
cd "$(dirname "$0")/.."
steps=${1:-200}
sizes=${2:-"64 128 256 512 1024"}
out=bench_out/two_cores
mkdir -p "$out"
cmake --build build --target sphib > /dev/null
echo "load before: $(uptime)"
echo "| case | Nx | 1 thread ms/step | 2 threads ms/step | speed-up | passes and solves (1 thread) |"
echo "|---|---:|---:|---:|---:|---:|"
for c in membrane_oscillation poiseuille; do
  for nx in $sizes; do
    sets=(--set grid.nx=$nx --set grid.ny=$nx --set output.interval=0 --set time.max_steps=$steps)
    [ "$c" = membrane_oscillation ] && sets+=(--set membrane.nb=$((2 * nx)))
    for th in 1 2; do
      build/sphib run cases/$c.toml --threads $th --out "$out/${c}_${nx}_$th" --quiet "${sets[@]}"
    done
    /usr/bin/python3 - "$out/${c}_${nx}_1/summary.json" "$out/${c}_${nx}_2/summary.json" "$c" "$nx" <<'PY'
import json, sys
d1, d2 = (json.load(open(f)) for f in sys.argv[1:3])
assert d1["threads"] == 1 and d2["threads"] == 2
p = d1["profile_seconds"]
fluid = ("convection", "viscous", "divergence", "projection", "solve", "pressure", "stream function")
share = sum(v for k, v in p.items() if k.startswith(fluid)) / (d1["seconds_per_step"] * d1["steps"])
t1, t2 = 1e3 * d1["seconds_per_step"], 1e3 * d2["seconds_per_step"]
print("| %s | %s | %.3f | %.3f | %.2f | %.0f%% |" % (sys.argv[3], sys.argv[4], t1, t2, t1 / t2, 100 * share))
PY
  done
done
echo "load after: $(uptime)"
