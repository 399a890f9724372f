#!/bin/sh
# Fails when any binary given after the first defines a CGAL symbol. The
# first, the meshing plugin (or "-" without it), must define some: that
# shows nm reads the binaries and the pattern matches, so the check could fail.
set -eu
meshing=$1
shift
count() { nm -C --defined-only "$1" | grep -c 'CGAL::' || true; }
if [ "$meshing" != "-" ]; then
  found=$(count "$meshing")
  if [ "$found" -eq 0 ]; then
    echo "no CGAL symbol found in $meshing: the check cannot tell CGAL code apart" >&2
    exit 1
  fi
  echo "$meshing: $found CGAL symbols (the one binary allowed them)"
fi
status=0
for binary in "$@"; do
  found=$(count "$binary")
  if [ "$found" -ne 0 ]; then
    echo "$binary defines $found CGAL symbols: CGAL (GPL) must stay in the meshing plugin" >&2
    status=1
  else
    echo "$binary: none"
  fi
done
exit $status
