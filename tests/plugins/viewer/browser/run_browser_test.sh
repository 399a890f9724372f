#!/usr/bin/env bash
# The browser viewer end to end, in headless Chromium. Skips (exit 77) when
# Chromium, Node.js or the viewer's packages are missing, saying which.
#   run_browser_test.sh recorded TREPHINE SOURCE_DIR OUT_DIR SCENE DURATION TIMES PARTS MIN_FPS
#     runs the scene, writes its viewer (trephine view), loads it (viewerBrowserTest.mjs);
#   run_browser_test.sh live TREPHINE SOURCE_DIR OUT_DIR SCENE DURATION TIMES PARTS
#     runs the scene in real time with --view and watches it (liveBrowserTest.mjs).
set -euo pipefail
mode=$1 trephine=$2 source=$3 out=$4 scene=$5 duration=$6 times=$7 parts=$8
web="$source/plugins/viewer/web"
here="$source/tests/plugins/viewer/browser"
chromium=${CHROMIUM:-/usr/bin/chromium}
[ -x "$chromium" ] || { echo "SKIP: no Chromium at $chromium (tools/setup installs Debian's chromium)"; exit 77; }
command -v node >/dev/null || { echo "SKIP: no Node.js (tools/setup installs it)"; exit 77; }
[ -d "$web/node_modules/playwright-core" ] || { echo "SKIP: the viewer's packages are not installed (tools/setup runs npm ci in $web)"; exit 77; }
rm -rf "$out"
mkdir -p "$out"
if [ "$mode" = live ]; then
  exec node "$here/liveBrowserTest.mjs" --web "$web" --trephine "$trephine" --scene "$source/$scene" \
    --duration "$duration" --times "$times" --parts "$parts" --out "$out"
fi
min_fps=$9
"$trephine" run "$source/$scene" --duration "$duration" --out "$out/run" --quiet
if ! "$trephine" view "$out/run" > "$out/view.txt" 2>&1; then
  cat "$out/view.txt"
  grep -q "was not built" "$out/view.txt" && { echo "SKIP: the viewer was not built"; exit 77; }
  exit 1
fi
cat "$out/view.txt"
exec node "$here/viewerBrowserTest.mjs" --web "$web" --view "$out/run/view" \
  --out "$out" --times "$times" --parts "$parts" --min-fps "$min_fps" --open-limit 3
