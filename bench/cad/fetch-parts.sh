#!/usr/bin/env bash
# Fetches CAD-like parts (flat faces, sharp creases, holes, gear teeth) for measuring how edge
# collapse keeps such shapes: the meshes of Debian's libcgal-demo package (CGAL's demo data,
# data/meshes/ inside usr/share/doc/libcgal-dev/data.tar.gz), unpacked with dpkg, not installed.
# They are not copied into the repository: CGAL's data carry CGAL's terms (see the package's
# copyright file, which libcgal-dev holds and this script keeps beside them).
#
# Usage: bench/cad/fetch-parts.sh [DIR]      (default: bench/data/cad, git-ignored)
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out="${1:-$here/../data/cad}"
readonly parts=(anchor couplingdown dragknob fandisk pinion rotor spool part mech-holes-shark
    turbine blade ALSTOM_TEST4)

mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && apt-get download libcgal-demo libcgal-dev >/dev/null 2>&1)
dpkg -x "$work"/libcgal-demo_*.deb "$work/pkg"
dpkg -x "$work"/libcgal-dev_*.deb "$work/pkg"
tar -xzf "$work/pkg/usr/share/doc/libcgal-dev/data.tar.gz" -C "$work" data/meshes
for part in "${parts[@]}"; do
    cp "$work/data/meshes/$part.off" "$out/"
done
cp "$work/pkg/usr/share/doc/libcgal-dev/copyright" "$out/COPYRIGHT.libcgal"
dpkg-deb -f "$work"/libcgal-demo_*.deb Version >"$out/VERSION.libcgal-demo"
echo "${#parts[@]} parts in $out"
