#!/usr/bin/env bash
# The browser viewer end to end, in headless Chromium. Where it cannot run
# (no Chromium, Node.js, viewer or packages) it says why and skips (exit 77),
# or fails (exit 1) when the browser tests are required:
# TREPHINE_REQUIRE_BROWSER_TESTS=ON in the environment, or else as configured
# (TREPHINE_REQUIRE_BROWSER_TESTS_CONFIGURED, set by CMake).
#   run_browser_test.sh recorded TREPHINE SOURCE_DIR OUT_DIR SCENE DURATION TIMES PARTS MIN_FPS
#     runs the scene, writes its viewer (trephine view), loads it (viewerBrowserTest.mjs);
#   run_browser_test.sh controls TREPHINE SOURCE_DIR OUT_DIR SCENE DURATION PRESS
#     the same, then checks the colour maps, the view's controls and the
#     events (viewerControlsTest.mjs; PRESS: a time the tool presses the brain);
#   run_browser_test.sh compare TREPHINE SOURCE_DIR OUT_DIR SCENE DURATION PRESS SETTING
#     runs the scene as it is and with --set SETTING, writes their viewer side
#     by side (trephine view A B --out) and checks it (viewerCompareTest.mjs);
#   run_browser_test.sh live TREPHINE SOURCE_DIR OUT_DIR SCENE DURATION TIMES PARTS
#     runs the scene in real time with --view and watches it (liveBrowserTest.mjs);
#   run_browser_test.sh unavailable REASON
#     stands for a test that the configure could not set up, saying why.
set -euo pipefail
cannot_run() {
  local required=${TREPHINE_REQUIRE_BROWSER_TESTS:-${TREPHINE_REQUIRE_BROWSER_TESTS_CONFIGURED:-OFF}}
  case ${required^^} in
    ON | 1 | TRUE | YES)
      echo "FAIL: $* (the browser tests are required: TREPHINE_REQUIRE_BROWSER_TESTS=$required)"
      exit 1 ;;
  esac
  echo "SKIP: $*"
  exit 77
}
mode=$1
[ "$mode" = unavailable ] && cannot_run "$2"
trephine=$2 source=$3 out=$4 scene=$5 duration=$6 times=$7 parts=$8
web="$source/plugins/viewer/web"
here="$source/tests/plugins/viewer/browser"
chromium=${CHROMIUM:-/usr/bin/chromium}
[ -x "$chromium" ] || cannot_run "no Chromium at $chromium (tools/setup installs Debian's chromium)"
command -v node >/dev/null || cannot_run "no Node.js (tools/setup installs it)"
node_major=$(node -p 'process.versions.node.split(".")[0]')
[ "$node_major" -ge 18 ] || cannot_run "Node.js $(node --version) is too old: the tests need 18 or newer"
[ -d "$web/node_modules/playwright-core" ] ||
  cannot_run "the viewer's packages are not installed (tools/setup runs npm ci in $web)"
echo "Node.js $(node --version), $("$chromium" --version 2>/dev/null || echo "Chromium of unknown version")"
rm -rf "$out"
mkdir -p "$out"
if [ "$mode" = live ]; then
  exec node "$here/liveBrowserTest.mjs" --web "$web" --trephine "$trephine" --scene "$source/$scene" \
    --duration "$duration" --times "$times" --parts "$parts" --out "$out"
fi
if [ "$mode" = compare ]; then
  "$trephine" run "$source/$scene" --duration "$duration" --out "$out/run_a" --quiet
  "$trephine" run "$source/$scene" --duration "$duration" --out "$out/run_b" --quiet --set "$8"
  if ! "$trephine" view "$out/run_a" "$out/run_b" --out "$out/view" > "$out/view.txt" 2>&1; then
    cat "$out/view.txt"
    grep -q "was not built" "$out/view.txt" && cannot_run "the viewer was not built"
    exit 1
  fi
  cat "$out/view.txt"
  exec node "$here/viewerCompareTest.mjs" --web "$web" --view "$out/view" --out "$out" --press "$times"
fi
min_fps=${9:-0}
"$trephine" run "$source/$scene" --duration "$duration" --out "$out/run" --quiet
if ! "$trephine" view "$out/run" > "$out/view.txt" 2>&1; then
  cat "$out/view.txt"
  grep -q "was not built" "$out/view.txt" && cannot_run "the viewer was not built"
  exit 1
fi
cat "$out/view.txt"
if [ "$mode" = controls ]; then
  exec node "$here/viewerControlsTest.mjs" --web "$web" --view "$out/run/view" --out "$out" --press "$times"
fi
exec node "$here/viewerBrowserTest.mjs" --web "$web" --view "$out/run/view" \
  --out "$out" --times "$times" --parts "$parts" --min-fps "$min_fps" --open-limit 3
