#!/usr/bin/env bash
# Makes the documentation's figures (docs/*.png) from runs of the cases, each section one command
# the documentation quotes beside its figures:
#   bash scripts/docs_figures.sh [SECTION...]    (default: all; the runs go to out/docs_figures/)
# Sections: oscillation (the main job, about 20 s), dam_break_wcsph (about 1 min), dam_break_isph
# (about 1 min; its loads beside dam_break_wcsph's when that ran first), droplet (WCSPH and ISPH, a
# few seconds), inclined_plane (N = 2500 by WCSPH to t = 4, a few minutes), paraview (needs pvpython
# and xvfb-run: scripts/run_paraview_test.sh installs them). Needs build/sphib (scripts/run_main.sh).
# REUSE=1 keeps the runs that finished (a summary.json) and only draws them again.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=out/docs_figures
SPHIB=build/sphib
PY=/usr/bin/python3
mkdir -p "$OUT"

# snapshot DIR T: the snapshot PNG of DIR nearest time T (plot.py names them by snapshot group).
snapshot() {
  $PY - "$1" "$2" <<'PYEOF'
import sys, h5py
d, t = sys.argv[1], float(sys.argv[2])
with h5py.File(d + "/output.h5", "r") as f:
    names = sorted(f["snapshots"])
    best = min(names, key=lambda n: abs(float(f["snapshots"][n].attrs["time"]) - t))
print("%s/snapshot_%s.png" % (d, best))
PYEOF
}

run() {  # run CASE DIR [--set ...]: a run of the case into DIR (again, so the figures are of this build)
  local scene=$1 dir=$2; shift 2
  if [ -n "${REUSE:-}" ] && [ -f "$dir/summary.json" ]; then echo "docs_figures: reusing $dir"; return; fi
  echo "docs_figures: $SPHIB run $scene --out $dir --quiet $*"
  $SPHIB run "$scene" --out "$dir" --quiet "$@"
}

sections=("$@")
[ ${#sections[@]} -gt 0 ] || sections=(oscillation dam_break_wcsph dam_break_isph droplet inclined_plane paraview)
for s in "${sections[@]}"; do
  case $s in
    oscillation)
      d=$OUT/membrane_oscillation
      run cases/membrane_oscillation.toml $d
      $PY scripts/plot.py $d --snapshots 21 > /dev/null
      cp "$(snapshot $d 0.5)" docs/oscillation_t0.5.png
      cp $d/rx_ry.png docs/oscillation_rx_ry.png
      cp $d/pressure_sections.png docs/oscillation_sections_t10.png
      cp $d/area_error.png docs/oscillation_area_error.png
      cp $d/energy.png docs/oscillation_energy.png ;;
    dam_break_wcsph)
      d=$OUT/dam_break_wcsph
      run cases/dam_break_wcsph.toml $d
      $PY scripts/plot.py $d > /dev/null
      for t in 0.195 0.278 0.593; do cp "$(snapshot $d $t)" docs/dam_break_t$t.png; done
      cp $d/loads.png docs/dam_break_loads.png
      cp $d/dam_break_front.png docs/dam_break_front.png ;;
    dam_break_isph)
      d=$OUT/dam_break_isph
      run cases/dam_break.toml $d
      compare=()
      [ -f $OUT/dam_break_wcsph/diagnostics.csv ] && compare=(--compare $OUT/dam_break_wcsph)
      $PY scripts/plot.py $d "${compare[@]}" > /dev/null
      for t in 0.195 0.278 0.593; do cp "$(snapshot $d $t)" docs/isph_dam_break_t$t.png; done
      cp $d/loads.png docs/isph_dam_break_loads.png
      cp $d/dam_break_front.png docs/isph_dam_break_front.png ;;
    droplet)
      run cases/droplet_wcsph.toml $OUT/droplet_wcsph
      $PY scripts/plot.py $OUT/droplet_wcsph > /dev/null
      cp $OUT/droplet_wcsph/droplet_axis.png docs/droplet_axis.png
      run cases/droplet.toml $OUT/droplet_isph
      $PY scripts/plot.py $OUT/droplet_isph > /dev/null
      cp $OUT/droplet_isph/droplet_axis.png docs/isph_droplet_axis.png ;;
    inclined_plane)
      d=$OUT/inclined_plane_wcsph
      run cases/inclined_plane_wcsph.toml $d --set grid.nx=50 --set grid.ny=100 --set time.dt=1e-4 --set output.interval=0
      $PY scripts/plot.py $d > /dev/null
      cp $d/velocity_profile.png docs/inclined_plane_profile.png ;;
    paraview)
      if ! command -v pvpython > /dev/null || ! command -v xvfb-run > /dev/null; then
        echo "docs_figures: paraview skipped (no pvpython or xvfb-run; bash scripts/run_paraview_test.sh installs them)"
        continue
      fi
      d=$OUT/paraview
      run cases/membrane_oscillation.toml $d --set time.end=0.5 --set output.interval=0.25
      xvfb-run -a pvpython scripts/paraview_picture.py $d --time 0.5
      cp $d/paraview.png docs/paraview_oscillation_t0.5.png ;;
    *) echo "docs_figures: unknown section $s" >&2; exit 2 ;;
  esac
  echo "docs_figures: $s done"
done
