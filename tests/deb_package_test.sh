#!/bin/bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the Debian packages with cpack (impactcert; with the library libimpactcert0,
# libimpactcert-dev and python3-impactcert), unpacks them into a scratch root (dpkg-deb -x, no
# root needed), and runs what they install from there: the paper's law proved, a certificate
# written and checked, the header and CMake package present, the dependencies declared, and
# `import impactcert` deciding a law.
set -euo pipefail
build=${1:?build directory}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
(cd "$build" && cpack -G DEB -B "$dir/out" >/dev/null)
deb=$(ls "$dir"/out/impactcert_*.deb)
for package in "$dir"/out/*.deb; do
    dpkg-deb -x "$package" "$dir/root"
done
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
# The library's packages, when the build has the library (and the module).
if [ -f "$build/libimpactcert.so" ]; then
    lib=$(ls "$dir"/out/libimpactcert0_*.deb)
    dev=$(ls "$dir"/out/libimpactcert-dev_*.deb)
    test -f "$dir/root/usr/lib/libimpactcert.so.0" && test -L "$dir/root/usr/lib/libimpactcert.so"
    test -f "$dir/root/usr/include/impactcert/impactcert.hpp"
    test -f "$dir/root/usr/lib/cmake/impactcert/impactcertLibraryTargets.cmake"
    dpkg-deb -I "$lib" shlibs | grep -q "^libimpactcert 0 libimpactcert0 (>= "
    dpkg-deb -I "$lib" triggers | grep -q "activate-noawait ldconfig"
    dpkg-deb -f "$dev" Depends | grep -q "libimpactcert0 (= "
    # Only the API's names are exported: nothing of the core (impactcert's other namespaces, CGAL,
    # PPL, nlohmann-json, the checker); the standard library's templates it instantiates over the
    # API's types keep their default visibility.
    exported=$(nm -D --defined-only "$dir/root/usr/lib/libimpactcert.so.0" | awk '{print $3}' | c++filt)
    leaked=$(sed 's/impactcert::api::[A-Za-z_:]*//g' <<<"$exported" |
             grep -E 'impactcert::|CGAL|Parma_Polyhedra|nlohmann|impactcert_check' || true)
    if [ -n "$leaked" ] || ! grep -q '^impactcert::api::verify(' <<<"$exported"; then
        echo "libimpactcert exports more than the API (or not the API):" >&2
        head -5 <<<"$leaked" >&2
        exit 1
    fi
    # Each file in its own package: the library in libimpactcert0, the header, link and targets in
    # -dev, the module in python3-impactcert, none of them in impactcert.
    contents() { dpkg-deb -c "$1" | awk '{print $6}'; }
    # (`! cmd` never stops a `set -e` script: absent says it and exits.)
    absent() {
        if contents "$1" | grep -qE "$2"; then
            echo "$(basename "$1") holds a file it should not: $(contents "$1" | grep -E "$2" | head -1)" >&2
            exit 1
        fi
    }
    contents "$lib" | grep -q '/usr/lib/libimpactcert.so.0.1.0$'
    absent "$lib" 'include/|cmake/|python3/|libimpactcert.so$'
    contents "$dev" | grep -q '/usr/include/impactcert/impactcert.hpp$'
    contents "$dev" | grep -q '/usr/lib/libimpactcert.so$'
    absent "$dev" 'libimpactcert.so.0|float_law.hpp'
    absent "$deb" 'libimpactcert|impactcert.hpp|python3/'
    if ls "$dir"/out/python3-impactcert_*.deb >/dev/null 2>&1; then
        python=$(ls "$dir"/out/python3-impactcert_*.deb)
        dpkg-deb -f "$python" Depends | grep -q "python3-numpy"
        contents "$python" | grep -q 'python3/dist-packages/impactcert/__init__.py$'
        absent "$python" 'libimpactcert.so|include/'
        PYTHONPATH="$dir/root/usr/lib/python3/dist-packages" LD_LIBRARY_PATH="$dir/root/usr/lib" /usr/bin/python3 -c '
import impactcert as ic
law = ic.derive(ic.System.chain([1, 1, 1])).law
assert ic.verify(law).verdict == "proved", "the elastic 3-ball chain"
assert ic.check_certificate(ic.certify(law)).verified
print("python3-impactcert:", law, "proved, certificate verified")'
    fi
fi
# lintian (one of scripts/test's packages): no error or warning but these, each by design --
#   embedded-library gmp: the programs link GMP, MPFR and PPL statically (IMPACTCERT_STATIC_LIBS:
#     start-up time and one binary that runs without the -dev packages);
#   hardening-no-pie: impactcert and impactcert-verify are linked -no-pie (start-up time of a CI
#     gate, CMakeLists.txt); impactcert-check with the same flags;
#   bogus-mail-host(-in-debian-changelog): the project has no mail address yet (the Maintainer
#     field and the changelog say localhost);
#   maintainer-script-empty (libimpactcert0): cpack writes maintainer scripts that call ldconfig
#     unless a package brings its own; ours do nothing, ldconfig runs by dpkg's trigger.
if ! command -v lintian >/dev/null; then
    echo "lintian is missing (scripts/test installs it)" >&2
    exit 1
fi
report=$(lintian --tag-display-limit 0 "$dir"/out/*.deb 2>/dev/null || true)
unexpected=$(grep -E '^(E|W): ' <<<"$report" | grep -vE 'embedded-library gmp|hardening-no-pie|bogus-mail-host|libimpactcert0: maintainer-script-empty' || true)
if [ -n "$unexpected" ]; then
    echo "lintian: $unexpected" >&2
    exit 1
fi
echo "lintian: $(grep -cE '^(E|W): ' <<<"$report") tags on $(ls "$dir"/out/*.deb | wc -l) packages, all of them explained (embedded-library gmp, hardening-no-pie, bogus-mail-host, maintainer-script-empty)"
