#!/usr/bin/env bash
# sphib check's memory estimate against the peak resident memory of the run it describes
# (/usr/bin/time -v, two steps with their output), and what check itself took.
#   bash bench/memory_estimate.sh [main|cavity|others|all]
# main (default): the main case, cases/membrane_oscillation.toml (EPSPH, FFT solvers, exact
#   projection), at 64^2, 128^2, 256^2, 512^2 and 1024^2 (the last run needs about 0.9 GB and a minute);
# cavity: the closed cavity with the lattice solvers (the default), 64^2-256^2 (part of others);
# others: the closed cavity with the lattice solvers (the default) and with sparse Cholesky factors
#   forced (dt = dx/4), LPSPH and WCSPH at 64^2-256^2 (the cavity's 256^2 factorisations take
#   minutes); all: both.
# Prints one row per size: the estimate, the measured peak, their ratio, check's own peak and time.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build --target sphib > /dev/null
SPHIB=build/sphib
tmp=$(mktemp -d /tmp/sphib_memory.XXXXXX)
trap 'rm -rf "$tmp"' EXIT

to_bytes() {  # "7.06 GB" -> bytes
  /usr/bin/python3 -c "import sys; v, u = sys.argv[1], sys.argv[2]; print(float(v) * {'B': 1, 'kB': 1e3, 'MB': 1e6, 'GB': 1e9, 'TB': 1e12}[u])" "$1" "$2"
}

row() {  # scene n [--set ...]
  local scene=$1 n=$2
  shift 2
  local sets=(--set grid.nx="$n" --set grid.ny="$n" --set time.max_steps=2 "$@")
  /usr/bin/time -v $SPHIB check "cases/$scene.toml" "${sets[@]}" > "$tmp/check.txt" 2> "$tmp/check_time.txt"
  local est
  est=$(grep -o "memory estimate: [0-9.]* [kMGT]*B" "$tmp/check.txt" | awk '{print $3, $4}')
  local est_b
  est_b=$(to_bytes $est)
  local check_kb check_s
  check_kb=$(grep "Maximum resident" "$tmp/check_time.txt" | awk '{print $6}')
  check_s=$(grep "Elapsed" "$tmp/check_time.txt" | awk '{print $8}')
  rm -rf "$tmp/out"
  /usr/bin/time -v $SPHIB run "cases/$scene.toml" --out "$tmp/out" --quiet "${sets[@]}" 2> "$tmp/run_time.txt" > /dev/null ||
    { echo "$scene $n: the run failed:"; grep "sphib: error" "$tmp/run_time.txt"; }
  local run_kb
  run_kb=$(grep "Maximum resident" "$tmp/run_time.txt" | awk '{print $6}')
  /usr/bin/python3 -c "
import sys
scene, n, est, run_kb, check_kb, check_s = sys.argv[1:]
run = float(run_kb) * 1024
print(f'| {scene} | {n}^2 | {float(est)/1e6:9.1f} MB | {run/1e6:9.1f} MB | {float(est)/run:5.2f} | {float(check_kb)*1024/1e6:7.1f} MB | {check_s} |')
" "$scene" "$n" "$est_b" "$run_kb" "$check_kb" "$check_s"
}

echo "| scene | N | check's estimate | run's peak (time -v) | estimate / peak | check's own peak | check's time |"
echo "|---|---|---|---|---|---|---|"
what=${1:-main}
if [ "$what" = main ] || [ "$what" = all ]; then
  for n in 64 128 256 512 1024; do row membrane_oscillation $n --set membrane.nb=$((2 * n)); done
fi
if [ "$what" != main ]; then
  for n in 64 128 256; do row cavity_re100 $n --set time.dt="$(/usr/bin/python3 -c "print(0.25 / $n)")"; done
fi
if [ "$what" = others ] || [ "$what" = all ]; then
  for n in 64 128 256; do
    row cavity_re100 $n --set time.dt="$(/usr/bin/python3 -c "print(0.25 / $n)")" \
      --set solver.poisson=cholmod_supernodal --set solver.crank_nicolson=cholmod_supernodal
  done
  for n in 64 128 256; do row membrane_oscillation_lagrangian $n --set membrane.nb=$((2 * n)); done
  for n in 64 128 256; do row wcsph_couette $n --set time.dt=1e-7; done
fi
