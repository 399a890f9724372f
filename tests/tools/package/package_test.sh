#!/usr/bin/env bash
# Installs a Trephine build tree into a temporary prefix, builds the
# out-of-tree example plugin against the installed package, runs the
# installed program on the example scene with the plugin found through
# TREPHINE_PLUGIN_PATH, then installed into the same prefix.
#
# usage: package_test.sh CMAKE BINARY_DIR EXAMPLE_DIR GENERATOR MAKE_PROGRAM
#                        CXX_COMPILER BUILD_TYPE CXX_FLAGS LINKER_FLAGS
# CXX_FLAGS and LINKER_FLAGS are the parent build's, so a sanitizer build
# produces a plugin instrumented the same way as the program that loads it.
set -euo pipefail

cmake_command=$1 binary_dir=$2 example_dir=$3 generator=$4 make_program=$5
cxx_compiler=$6 build_type=${7:-Release} cxx_flags=$8 linker_flags=$9

work=$(mktemp -d "${TMPDIR:-/tmp}/trephine-package-XXXXXX")
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix build=$work/build out=$work/run log=$work/log

fail() {
  echo "FAIL: $*" >&2
  [[ -f $log ]] && sed 's/^/  | /' "$log" >&2
  exit 1
}
step() {  # step DESCRIPTION COMMAND...: runs COMMAND with its output in $log
  local what=$1
  shift
  echo "-- $what"
  "$@" >"$log" 2>&1 || fail "$what (exit $?)"
}

step "install $binary_dir into $prefix" "$cmake_command" --install "$binary_dir" --prefix "$prefix"
for file in bin/trephine lib/cmake/Trephine/TrephineConfig.cmake lib/trephine/plugins/trephine_haptics.so \
            lib/trephine/plugins/trephine_analytic.so lib/trephine/plugins/trephine_voxel_skull.so \
            include/trephine/framework/devices/HapticDevice.h include/trephine/framework/geometry/ShellTool.h; do
  [[ -e $prefix/$file ]] || fail "the installation lacks $file"
done

step "configure the example against the installed package" \
  "$cmake_command" -S "$example_dir" -B "$build" -G "$generator" \
  -DCMAKE_MAKE_PROGRAM="$make_program" -DCMAKE_CXX_COMPILER="$cxx_compiler" -DCMAKE_BUILD_TYPE="$build_type" \
  -DCMAKE_CXX_FLAGS="$cxx_flags" -DCMAKE_EXE_LINKER_FLAGS="$linker_flags" \
  -DCMAKE_SHARED_LINKER_FLAGS="$linker_flags" -DCMAKE_MODULE_LINKER_FLAGS="$linker_flags" \
  -DCMAKE_PREFIX_PATH="$prefix"
step "build the example plugin" "$cmake_command" --build "$build"
plugin_dir=$build/plugins
[[ -f $plugin_dir/trephine_lissajous.so ]] || fail "no trephine_lissajous.so in $plugin_dir"

scene=$example_dir/lissajous.xml
step "validate with TREPHINE_PLUGIN_PATH" env TREPHINE_PLUGIN_PATH="$plugin_dir" "$prefix/bin/trephine" validate "$scene"
step "run 0.2 s" env TREPHINE_PLUGIN_PATH="$plugin_dir" \
  "$prefix/bin/trephine" run "$scene" --duration 0.2 --out "$out" --quiet
[[ -f $out/summary.json ]] || fail "the run wrote no summary.json"
grep -q '"type": *"LissajousDevice"' "$out/summary.json" || { cp "$out/summary.json" "$log"; fail "summary.json does not name LissajousDevice"; }

# A tool of the plugin's own (EllipsoidTool) against a VoxelSkull, through
# GodObjectProxy: it touches, and its proxy never shows it inside the bone.
tool_scene=$example_dir/ellipsoid.xml
step "run the plugin's own tool 2 s" env TREPHINE_PLUGIN_PATH="$plugin_dir" \
  "$prefix/bin/trephine" run "$tool_scene" --duration 2 --out "$out/tool" --quiet
grep -q '"type": *"EllipsoidTool"' "$out/tool/summary.json" || { cp "$out/tool/summary.json" "$log"; fail "summary.json does not name EllipsoidTool"; }
grep -q '"proxy_inside_frames": *0,' "$out/tool/summary.json" || { cp "$out/tool/summary.json" "$log"; fail "the ellipsoid's proxy was inside the bone"; }
contacts=$(sed -n 's/.*"contact_frames": *\([0-9]*\).*/\1/p' "$out/tool/summary.json" | head -n 1)
[[ ${contacts:-0} -gt 300 ]] || { cp "$out/tool/summary.json" "$log"; fail "the ellipsoid touched the bone in ${contacts:-0} frames (expected over 300)"; }
# Drawn in its own shape: the surface it declares, in every frame's file.
shape=$out/tool/vtk/toolshape_00000.vtp
[[ -f $shape ]] || fail "the ellipsoid's surface was not written (vtk/toolshape_00000.vtp)"
grep -q 'NumberOfPolys="[1-9][0-9]*"' "$shape" || { cp "$shape" "$log"; fail "the ellipsoid's surface has no triangles"; }

echo "-- validate without TREPHINE_PLUGIN_PATH must fail"
status=0
env -u TREPHINE_PLUGIN_PATH "$prefix/bin/trephine" validate "$scene" >"$log" 2>&1 || status=$?
[[ $status -eq 1 ]] || fail "validate without the plugin path exited with $status, expected 1"
grep -q "lissajous" "$log" || fail "the error does not name the missing plugin 'lissajous'"

step "install the plugin next to Trephine's own" "$cmake_command" --install "$build" --prefix "$prefix"
step "validate with the installed plugin and no TREPHINE_PLUGIN_PATH" \
  env -u TREPHINE_PLUGIN_PATH "$prefix/bin/trephine" validate "$scene"

echo "package test passed"
