#!/usr/bin/env bash
# Installs the Debian packages sphib needs, if any is missing. Idempotent and quick when all are present.
#   bash scripts/setup.sh                      the build's packages
#   bash scripts/setup.sh --recommends P...    those and the packages P, with their recommended ones
#                                              (ParaView: scripts/run_paraview_test.sh)
set -euo pipefail
pkgs=(cmake g++ ninja-build libeigen3-dev libsuitesparse-dev libhdf5-dev libtomlplusplus-dev
      libcli11-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev libfftw3-dev liblapack-dev
      libopenblas0-serial libssl-dev ccache python3-matplotlib python3-h5py python3-numpy python3-mpmath pybind11-dev python3-dev)
recommends=(--no-install-recommends)
if [ "${1:-}" = --recommends ]; then recommends=(); shift; fi
pkgs+=("$@")
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${recommends[@]}" "${missing[@]}"
fi
