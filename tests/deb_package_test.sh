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
# The manual pages and the bash completion are installed (compressed pages, as Debian does).
for page in impactcert impactcert-check impactcert-verify; do
    gzip -t "$dir/root/usr/share/man/man1/$page.1.gz"
done
test -f "$dir/root/usr/share/bash-completion/completions/impactcert"
test -L "$dir/root/usr/share/bash-completion/completions/impactcert-check"
test -L "$dir/root/usr/share/bash-completion/completions/impactcert-verify"
# What the manual cites is installed (issue 40, item 4).
for f in docs/formats.md docs/commands.md docs/exit-status.md docs/fuzzing.md docs/derive.md docs/ci.md \
         docs/schemas/law.schema.json proofs/README.md; do
    test -f "$dir/root/usr/share/doc/impactcert/$f" || { echo "FAIL: $f not installed"; exit 1; }
done
test -f "$dir/root/usr/share/doc/impactcert/changelog.gz"
# lintian (one of scripts/test's packages): no error or warning but these, each by design --
#   embedded-library gmp: the programs link GMP, MPFR and PPL statically (IMPACTCERT_STATIC_LIBS:
#     start-up time and one binary that runs without the -dev packages);
#   hardening-no-pie: impactcert and impactcert-verify are linked -no-pie (start-up time of a CI
#     gate, CMakeLists.txt); impactcert-check with the same flags;
#   bogus-mail-host: the project has no mail address yet (the Maintainer field says localhost).
if ! command -v lintian >/dev/null; then
    echo "lintian is missing (scripts/test installs it)" >&2
    exit 1
fi
report=$(lintian --tag-display-limit 0 "$deb" 2>/dev/null || true)
unexpected=$(grep -E '^(E|W): ' <<<"$report" | grep -vE 'embedded-library gmp|hardening-no-pie|bogus-mail-host' || true)
if [ -n "$unexpected" ]; then
    echo "lintian: $unexpected" >&2
    exit 1
fi
echo "lintian: $(grep -cE '^(E|W): ' <<<"$report") tags, all of them explained (embedded-library gmp, hardening-no-pie, bogus-mail-host)"
