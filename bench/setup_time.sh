#!/bin/bash
# The set-up of the main scene on large lattices: for each size N (N x N particles, 2N markers), one
# run of each build given (alternately, in one sitting), one step without output, and a table of the
# run log's set-up line (set-up, assembly, factorisation wall seconds), the lattice solvers' analysis
# of G^T G, the peak resident memory and the process's CPU seconds (/usr/bin/time), with the load
# average before and after.
#   bash bench/setup_time.sh [-s "512 1024 2048"] [SPHIB ...]     (default: build/sphib)
set -euo pipefail
cd "$(dirname "$0")/.."
sizes="512 1024 2048"
if [ "${1:-}" = "-s" ]; then
  sizes=$2
  shift 2
fi
builds=("$@")
[ ${#builds[@]} -gt 0 ] || builds=(build/sphib)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "| N | build | set-up (s) | assembly (s) | factorisation (s) | G^T G analysis (s) | peak | CPU (s) |"
echo "|---:|---|---:|---:|---:|---:|---:|---:|"
for n in $sizes; do
  for b in "${builds[@]}"; do
    log=$work/log
    /usr/bin/time -f "TIME %M %U %S" -o "$work/time" "$b" run cases/membrane_oscillation.toml \
      --set time.max_steps=1 --set output.interval=0 --set grid.nx="$n" --set grid.ny="$n" \
      --set membrane.nb=$((2 * n)) --out "$work/out" > "$log" 2>&1
    /usr/bin/python3 - "$n" "$b" "$log" "$work/time" <<'PY'
import re, sys
n, b, log, tm = sys.argv[1:]
text = open(log).read()
m = re.search(r"set-up ([0-9.e+-]+) s \(neighbours [0-9.e+-]+ s, assembly ([0-9.e+-]+) s, factorisation ([0-9.e+-]+) s\)", text)
g = re.search(r"G\^T G, odd images\).*analysis ([0-9.e+-]+) s", text)
t = open(tm).read().split("TIME")[-1].split()
kb = int(t[0])
peak = f"{kb / 1e6:.2f} GB" if kb >= 1e6 else f"{kb / 1e3:.0f} MB"
f = lambda x: f"{float(x):.2f}"
print(f"| {n}² | {b} | {f(m[1])} | {f(m[2])} | {f(m[3])} | {f(g[1]) if g else '-'} | {peak} | {float(t[1]) + float(t[2]):.1f} |")
PY
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
