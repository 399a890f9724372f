#!/usr/bin/env bash
# The live view end to end (liveBrowserTest.mjs): a real-time run with
# --view, watched by headless Chromium. Skips (exit 77) when Chromium,
# Node.js or the viewer's packages are missing, saying which.
#   run_live_test.sh TREPHINE SOURCE_DIR OUT_DIR SCENE DURATION TIMES PARTS
set -euo pipefail
trephine=$1 source=$2 out=$3 scene=$4 duration=$5 times=$6 parts=$7
web="$source/plugins/viewer/web"
chromium=${CHROMIUM:-/usr/bin/chromium}
[ -x "$chromium" ] || { echo "SKIP: no Chromium at $chromium (tools/setup installs Debian's chromium)"; exit 77; }
command -v node >/dev/null || { echo "SKIP: no Node.js (tools/setup installs it)"; exit 77; }
[ -d "$web/node_modules/playwright-core" ] || { echo "SKIP: the viewer's packages are not installed (tools/setup runs npm ci in $web)"; exit 77; }
rm -rf "$out"
mkdir -p "$out"
node "$source/tests/plugins/viewer/browser/liveBrowserTest.mjs" --web "$web" --trephine "$trephine" \
  --scene "$source/$scene" --duration "$duration" --times "$times" --parts "$parts" --out "$out"
