#!/usr/bin/env bash
# Regenerates the golden numbers of tests/golden/*.csv (the diagnostics of short runs of every method,
# which tests/test_regression.cpp compares to 1e-9) from the current build, then shows what changed.
# Run it only when the numerics change on purpose, and say why in the commit:
#   bash scripts/regenerate_goldens.sh            every golden file
#   bash scripts/regenerate_goldens.sh Isph       those whose test name matches (Golden.Isph*)
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build --target sphib_tests > /dev/null
SPHIB_REGENERATE_GOLDENS=1 build/sphib_tests --gtest_filter="Golden.${1:-}*" | grep -E "regenerated|FAILED" || true
git --no-pager diff --stat -- tests/golden
