#!/usr/bin/env bash
# Builds the documentation site from docs/ (Sphinx with MyST Markdown, warnings as errors) into
# build/docs/html, then takes headless-Chromium screenshots of its front page and a gallery page
# into build/docs/screenshots/ and checks that they show a rendered page. Installs the Debian
# packages it misses (python3-sphinx, python3-myst-parser, chromium). Needs build/sphib and the
# Python module (the key reference is `sphib keys --json`, the API reference the module): builds
# them when missing. Exit status 0 only if the site built without a warning and both pictures are
# pages.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh python3-sphinx python3-myst-parser chromium
if [ ! -x build/sphib ] || ! ls build/python/sphib*.so > /dev/null 2>&1; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > build-docs.log 2>&1 || { cat build-docs.log; exit 1; }
  cmake --build build --parallel 2 --target sphib sphib_python >> build-docs.log 2>&1 || { tail -50 build-docs.log; exit 1; }
fi
out=build/docs
rm -rf $out/html $out/doctrees
SPHIB_BINARY=$PWD/build/sphib SPHIB_PYTHONPATH=$PWD/build/python \
  /usr/bin/python3 -m sphinx -W --keep-going -q -b html -d $out/doctrees docs $out/html
echo "docs: site built without warnings in $out/html"

# Screenshots: Debian's Chromium, headless, without the background services this closed network
# refuses, in a profile of its own.
mkdir -p $out/screenshots
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
shot() {  # shot PAGE PNG
  timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync --hide-scrollbars \
    --user-data-dir="$profile" --window-size=1280,1600 --screenshot="$2" "file://$PWD/$out/html/$1" \
    > $out/screenshots/chromium.log 2>&1 || { cat $out/screenshots/chromium.log; return 1; }
}
pages=(index.html validation/index.html)
passed=0 failed=0
for page in "${pages[@]}"; do
  png=$out/screenshots/$(echo "$page" | tr / _ | sed 's/.html$//').png
  rm -f "$png"
  shot "$page" "$png"
  # A rendered page: a PNG of the window's size with text and pictures (many distinct colours, not
  # a blank or error page).
  if /usr/bin/python3 - "$png" <<'PYEOF'
import sys
import matplotlib.image as mpimg
import numpy as np
img = mpimg.imread(sys.argv[1])[..., :3]
colours = len(np.unique((img.reshape(-1, 3) * 255).astype(np.uint8), axis=0))
dark = float((img.mean(axis=2) < 0.5).mean())
print(f"{sys.argv[1]}: {img.shape[1]} x {img.shape[0]}, {colours} colours, {dark:.1%} dark pixels")
sys.exit(0 if img.shape[:2] == (1600, 1280) and colours > 200 and 0.005 < dark < 0.9 else 1)
PYEOF
  then passed=$((passed + 1)); else failed=$((failed + 1)); echo "docs: $png is not a rendered page"; fi
done
echo "docs: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
