#!/bin/bash
# SPDX-License-Identifier: GPL-3.0-or-later
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
# The programs link libstdc++, GMP, MPFR and PPL statically by default (IMPACTCERT_STATIC_LIBS);
# every shared library they need must be declared.
needed=$(readelf -d "$build/impactcert" "$build/impactcert-verify" "$build/impactcert-check" | sed -n 's/.*NEEDED.*\[\(lib[a-z+]*\).*/\1/p' | sort -u)
for lib in $needed; do
    case "$lib" in libm) lib=libc6 ;; libc) lib=libc6 ;; libstdc) lib=libstdc++ ;; esac
    case "$depends" in *"$lib"*) ;; *) echo "Depends lacks $lib" >&2; exit 1 ;; esac
done
test -x "$dir/root/usr/bin/impactcert" && test -x "$dir/root/usr/bin/impactcert-verify" && test -x "$dir/root/usr/bin/impactcert-check"
test -f "$dir/root/usr/include/impactcert/float_law.hpp"
# Licences: the copyright file names GPL-3.0-or-later for the programs and MIT for the header,
# whose own SPDX line says MIT.
grep -q "^License: GPL-3.0-or-later" "$dir/root/usr/share/doc/impactcert/copyright"
grep -q "^License: MIT" "$dir/root/usr/share/doc/impactcert/copyright"
test -f "$dir/root/usr/share/doc/impactcert/MIT.txt"
head -1 "$dir/root/usr/include/impactcert/float_law.hpp" | grep -q "SPDX-License-Identifier: MIT"
test -n "$(find "$dir/root/usr/lib" -name impactcertConfig.cmake -path '*cmake/impactcert*')"
"$dir/root/usr/bin/impactcert" verify >/dev/null
"$dir/root/usr/bin/impactcert-verify" >/dev/null
"$dir/root/usr/bin/impactcert" certify -o "$dir/paper.cert.json" 2>/dev/null
"$dir/root/usr/bin/impactcert-check" "$dir/paper.cert.json"
