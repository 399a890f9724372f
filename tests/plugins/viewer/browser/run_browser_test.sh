#!/usr/bin/env bash
# The browser viewer end to end: runs a scene with a VtkExporter, writes its
# viewer (trephine view) and loads it in headless Chromium
# (viewerBrowserTest.mjs). Skips (exit 77) when Chromium, Node.js or the
# built viewer is missing, saying which.
#   run_browser_test.sh TREPHINE SOURCE_DIR OUT_DIR SCENE DURATION TIMES PARTS MIN_FPS [--set ...]
set -euo pipefail
trephine=$1 source=$2 out=$3 scene=$4 duration=$5 times=$6 parts=$7 min_fps=$8
shift 8
web="$source/plugins/viewer/web"
chromium=${CHROMIUM:-/usr/bin/chromium}
[ -x "$chromium" ] || { echo "SKIP: no Chromium at $chromium (tools/setup installs Debian's chromium)"; exit 77; }
command -v node >/dev/null || { echo "SKIP: no Node.js (tools/setup installs it)"; exit 77; }
[ -d "$web/node_modules/playwright-core" ] || { echo "SKIP: the viewer's packages are not installed (tools/setup runs npm ci in $web)"; exit 77; }
rm -rf "$out"
mkdir -p "$out"
"$trephine" run "$source/$scene" --duration "$duration" --out "$out/run" --quiet "$@"
if ! "$trephine" view "$out/run" > "$out/view.txt" 2>&1; then
  cat "$out/view.txt"
  grep -q "was not built" "$out/view.txt" && { echo "SKIP: the viewer was not built"; exit 77; }
  exit 1
fi
cat "$out/view.txt"
node "$source/tests/plugins/viewer/browser/viewerBrowserTest.mjs" --web "$web" --view "$out/run/view" \
  --out "$out" --times "$times" --parts "$parts" --min-fps "$min_fps" --open-limit 3
