#!/usr/bin/env bash
# Flips random bits of a checkpoint and restarts from each damaged copy (CI runs 25; the full
# campaign is 100):   bash scripts/flip_bits.sh [FLIPS] [SEED]   (defaults 100 and 26; needs build/sphib)
# A run of the small oscillating membrane (24 x 24, 48 markers) writes a checkpoint at step 20; a
# restart from it to step 40 is the reference. Each round copies the checkpoint, flips one bit chosen
# at random over the whole file, and restarts from the copy alone (`sphib run --restart FILE`: its
# scene from the checkpoint too). Every flip must be refused (exit 2, nothing written) or give a
# diagnostics.csv bit-identical to the reference; anything else (another exit status, a crash,
# different numbers) fails the campaign. Prints one line per flip and the tally.
set -euo pipefail
cd "$(dirname "$0")/.."
flips=${1:-100}
seed=${2:-26}
SPHIB=build/sphib
PY=/usr/bin/python3
work=$(mktemp -d /tmp/sphib_flip_bits.XXXXXX)
trap 'rm -rf "$work"' EXIT

fail() { echo "flip_bits: FAILED: $*" >&2; exit 1; }

$SPHIB run cases/membrane_oscillation.toml --out "$work/a" --quiet --set grid.nx=24 --set grid.ny=24 \
  --set membrane.nb=48 --set time.dt=1e-3 --set time.end=0.02 || fail "the run that writes the checkpoint"
$SPHIB run --restart "$work/a/checkpoint.h5" --out "$work/ref" --quiet --set time.end=0.04 || fail "the reference restart"
size=$(stat -c %s "$work/a/checkpoint.h5")
echo "flip_bits: checkpoint of $size bytes (step 20), restarts to step 40; $flips flips, seed $seed"

refused=0
identical=0
for k in $(seq 1 "$flips"); do
  bit=$($PY -c "import random; r = random.Random($seed * 100003 + $k); print(r.randrange(8 * $size))")
  $PY - "$work/a/checkpoint.h5" "$work/flip.h5" "$bit" <<'PYEOF'
import sys
data = bytearray(open(sys.argv[1], "rb").read())
bit = int(sys.argv[3])
data[bit // 8] ^= 1 << (bit % 8)
open(sys.argv[2], "wb").write(data)
PYEOF
  out="$work/run_$k"
  status=0
  $SPHIB run --restart "$work/flip.h5" --out "$out" --quiet --set time.end=0.04 2> "$work/err" || status=$?
  if [ "$status" -eq 2 ]; then
    [ -e "$out" ] && fail "flip $k (byte $((bit / 8)), bit $((bit % 8))): refused but it wrote $out"
    refused=$((refused + 1))
    echo "flip $k: byte $((bit / 8)) bit $((bit % 8)): refused: $(head -c 150 "$work/err")"
  elif [ "$status" -eq 0 ]; then
    cmp -s "$out/diagnostics.csv" "$work/ref/diagnostics.csv" ||
      fail "flip $k (byte $((bit / 8)), bit $((bit % 8))): ran to a different result"
    identical=$((identical + 1))
    echo "flip $k: byte $((bit / 8)) bit $((bit % 8)): ran, bit-identical"
  else
    fail "flip $k (byte $((bit / 8)), bit $((bit % 8))): exit status $status: $(cat "$work/err")"
  fi
  rm -rf "$out"
done
echo "flip_bits: $flips flips: $refused refused, $identical bit-identical, 0 otherwise"
