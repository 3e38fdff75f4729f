#!/usr/bin/env bash
# Kills sphib runs at random moments and checks what they leave (CI runs it; about 30 s):
#   bash scripts/kill_loop.sh [ROUNDS]    (default 12; needs build/sphib: scripts/run_tests.sh builds it)
# Each round starts the small oscillating membrane (24 x 24, snapshots every 0.01, checkpoints every
# 0.005, a diagnostics row every step) into a fresh directory, sends SIGKILL or SIGTERM (alternately)
# after a random 0.05-1 s, then checks with scripts/check_outputs.py that every file under a final
# name opens and is whole (HDF5 with h5py, JSON, CSV, XDMF); after SIGTERM the run must have finished
# its files (exit 143, stop_reason terminated), unless the signal came during its set-up (nothing
# written). Then a run into a fresh directory and a restart from the killed run's checkpoint into its
# own directory must both finish with complete files. Exits 1 at the first failure.
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-12}
SPHIB=build/sphib
PY=/usr/bin/python3
SCENE=cases/membrane_oscillation.toml
SMALL=(--set grid.nx=24 --set grid.ny=24 --set membrane.nb=48 --set time.dt=1e-3)
work=$(mktemp -d /tmp/sphib_kill_loop.XXXXXX)
trap 'rm -rf "$work"' EXIT
RANDOM=17  # the same waits on every machine

fail() { echo "kill_loop: FAILED: $*" >&2; exit 1; }
# The files of DIR open and are whole (its report printed only when one is not).
check() { local out; out=$($PY scripts/check_outputs.py "$@") || { echo "$out"; return 1; }; }

for round in $(seq 1 "$rounds"); do
  dir=$work/run_$round
  signal=$([ $((round % 2)) -eq 0 ] && echo TERM || echo KILL)
  wait_ms=$((50 + RANDOM % 950))
  $SPHIB run $SCENE --out "$dir" --quiet "${SMALL[@]}" --set time.end=1000 --set output.interval=0.01 \
    --set output.checkpoint_interval=0.005 --set output.diagnostics_every=1 &
  pid=$!
  sleep "$(printf '0.%03d' "$wait_ms")"
  kill -s "$signal" "$pid"
  status=0
  wait "$pid" 2> /dev/null || status=$?
  echo "round $round: SIG$signal after $wait_ms ms: exit $status"
  [ -d "$dir" ] || { echo "  (stopped during its set-up: nothing written)"; continue; }
  check "$dir" || fail "round $round: a file under a final name is broken"
  if [ "$signal" = TERM ]; then
    [ "$status" -eq 143 ] || fail "round $round: SIGTERM gave exit $status (143 expected)"
    check "$dir" --complete || fail "round $round: SIGTERM left an unfinished run"
  fi
  # A run into a fresh directory works.
  $SPHIB run $SCENE --out "$dir.fresh" --quiet "${SMALL[@]}" --set time.max_steps=20 || fail "round $round: a fresh run failed"
  check "$dir.fresh" --complete || fail "round $round: the fresh run's files"
  # A restart from the killed run's checkpoint into its own directory works and continues its files.
  [ -f "$dir/checkpoint.h5" ] || { echo "  (no checkpoint yet)"; continue; }
  step=$($PY -c "import h5py; print(int(h5py.File('$dir/checkpoint.h5')['fluid/clock'][0, 1]))")
  $SPHIB run $SCENE --out "$dir" --quiet "${SMALL[@]}" --set time.end=1000 --set time.max_steps=$((step + 20)) \
    --set output.interval=0.01 --restart "$dir/checkpoint.h5" || fail "round $round: the restart from step $step failed"
  check "$dir" --complete || fail "round $round: the restart's files"
  echo "  restart from step $step: ok"
done
echo "kill_loop: $rounds rounds: every final file opened; fresh runs and restarts finished"
