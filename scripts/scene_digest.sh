#!/usr/bin/env bash
# A digest of short runs of the scenes that exercise every boundary kind and fluid method: each scene
# runs a few dozen steps with a diagnostics row at every step, and the sha256 of its diagnostics.csv is
# printed. Two builds give the same results bit for bit when their digests agree:
#   bash scripts/scene_digest.sh [SPHIB] > before.txt; ...; bash scripts/scene_digest.sh > after.txt; diff before.txt after.txt
# SPHIB: the command to use (default build/sphib). The main job (membrane_oscillation to t = 0.5) is the
# first line.
set -euo pipefail
cd "$(dirname "$0")/.."
SPHIB=${1:-build/sphib}
SPHIB=$(readlink -f "$SPHIB")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# name | scene | settings
scenes=(
  "membrane_oscillation|cases/membrane_oscillation.toml|time.end=0.5"
  "poiseuille|cases/poiseuille.toml|time.end=5e-5 output.diagnostics_every=1"
  "couette|cases/couette.toml|time.end=3e-3 output.diagnostics_every=1"
  "cavity_re100|cases/cavity_re100.toml|time.end=0.12 output.diagnostics_every=1"
  "rbc_channel|cases/rbc_channel.toml|time.end=0.02 output.diagnostics_every=1"
  "membrane_oscillation_lagrangian|cases/membrane_oscillation_lagrangian.toml|time.end=3e-3 output.diagnostics_every=1"
  "dam_break_isph|cases/dam_break.toml|time.end=4.5e-3 output.diagnostics_every=1"
  "dam_break_wcsph|cases/dam_break_wcsph.toml|time.end=1.6e-3 output.diagnostics_every=1"
  "wcsph_poiseuille|cases/wcsph_poiseuille.toml|time.end=3e-3 output.diagnostics_every=1"
  "wcsph_couette|cases/wcsph_couette.toml|time.end=3e-3 output.diagnostics_every=1"
  "still_tank_isph|cases/still_tank_isph.toml|time.end=3e-3 output.diagnostics_every=1"
  "vesicle_shear_contrast|cases/vesicle_shear.toml|time.end=0.02 membrane.viscosity_ratio=5.0 output.diagnostics_every=1"
  "capsule_open_channel|cases/capsule_open_channel.toml|time.end=0.03 output.diagnostics_every=1"
)
for entry in "${scenes[@]}"; do
  IFS='|' read -r name scene settings <<< "$entry"
  args=()
  for s in $settings; do args+=(--set "$s"); done
  if "$SPHIB" run "$scene" "${args[@]}" --out "$work/$name" --quiet > "$work/$name.log" 2>&1; then
    echo "$name $(sha256sum < "$work/$name/diagnostics.csv" | cut -c1-16) $(($(wc -l < "$work/$name/diagnostics.csv") - 1)) rows"
  else
    echo "$name FAILED: $(tail -1 "$work/$name.log")"
  fi
done
