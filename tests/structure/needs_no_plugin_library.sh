#!/bin/sh
# Fails when the program (the second argument) needs a shared library of
# this project that is not one of the framework's (or the program's own study
# library). The first argument, a plugin module, must need some plugin
# library: that shows readelf reads the binaries and the pattern matches, so
# the check could fail.
set -eu
plugin=$1
program=$2
needed() { readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(libtrephine_[a-z_]*\)\.so\]/\1/p'; }
allowed="libtrephine_math libtrephine_channels libtrephine_logs libtrephine_core libtrephine_geometry
libtrephine_devices libtrephine_scene libtrephine_runtime libtrephine_data libtrephine_formats
libtrephine_meshing_interface libtrephine_study"
outside() { for library in $(needed "$1"); do echo "$allowed" | grep -qw "$library" || echo "$library"; done; }
if [ -z "$(outside "$plugin")" ]; then
  echo "$plugin needs no plugin library: the check cannot tell plugin libraries apart" >&2
  exit 1
fi
echo "$plugin needs $(outside "$plugin" | tr '\n' ' ')(a plugin may)"
found=$(outside "$program")
if [ -n "$found" ]; then
  echo "$program needs $(echo "$found" | tr '\n' ' '): the program loads plugins, it links only the framework" >&2
  exit 1
fi
echo "$program needs: $(needed "$program" | tr '\n' ' ')"
