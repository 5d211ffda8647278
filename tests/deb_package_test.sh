#!/bin/bash
# Builds the Debian package with cpack, unpacks it into a scratch root (dpkg-deb -x, no root
# needed), and runs the installed programs from there: the paper's law proved, a certificate
# written and checked, the header and CMake package present, the package's dependencies declared.
set -euo pipefail
build=${1:?build directory}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
(cd "$build" && cpack -G DEB -B "$dir/out" >/dev/null)
deb=$(ls "$dir"/out/impactcert_*.deb)
dpkg-deb -x "$deb" "$dir/root"
depends=$(dpkg-deb -f "$deb" Depends)
echo "package: $(basename "$deb"); Depends: $depends"
for lib in libgmp libppl libstdc++; do
    case "$depends" in *"$lib"*) ;; *) echo "Depends lacks $lib" >&2; exit 1 ;; esac
done
test -x "$dir/root/usr/bin/impactcert" && test -x "$dir/root/usr/bin/impactcert-check"
test -f "$dir/root/usr/include/impactcert/float_law.hpp"
test -n "$(find "$dir/root/usr/lib" -name impactcertConfig.cmake -path '*cmake/impactcert*')"
"$dir/root/usr/bin/impactcert" verify >/dev/null
"$dir/root/usr/bin/impactcert" certify -o "$dir/paper.cert.json" 2>/dev/null
"$dir/root/usr/bin/impactcert-check" "$dir/paper.cert.json"
