# SPDX-License-Identifier: GPL-3.0-or-later
# scripts/lib.sh -- shared by the set-up scripts (sourced, not run).
# Installs the Debian packages impactcert needs (only the missing ones) and configures/builds.
set -euo pipefail

IMPACTCERT_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
IMPACTCERT_PACKAGES=(build-essential cmake ninja-build libcgal-dev libgmp-dev catch2 nlohmann-json3-dev
                     libcli11-dev libmimalloc-dev libbenchmark-dev libssl-dev z3 libppl-dev python3 python3-jsonschema libbox2d-dev help2man groff-base lintian
                     librsvg2-bin)

ensure_packages() {
    local missing=() p
    for p in "${IMPACTCERT_PACKAGES[@]}" "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    if ((${#missing[@]} == 0)); then
        return 0
    fi
    echo "impactcert: installing ${missing[*]}" >&2
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
}

# build_jobs: one build job per core of this machine.
build_jobs() {
    nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2
}

# configure_tree DIR [cmake options...]: configure (cmake redoes only what changed). A new tree
# uses Ninja, which starts a target's compilations before the targets it links are linked (the
# builds of scripts/test keep both cores busy to the end); a tree configured earlier keeps
# its generator.
configure_tree() {
    local dir="$1"
    shift
    local generator=()
    if [ ! -f "$dir/CMakeCache.txt" ]; then generator=(-G Ninja); fi
    cmake -S "$IMPACTCERT_ROOT" -B "$dir" "${generator[@]}" "$@" >/dev/null
}

# build_tree DIR [cmake options...]: configure and build everything, one job per core.
build_tree() {
    configure_tree "$@"
    cmake --build "$1" -j "$(build_jobs)"
}

# build_target DIR TARGET [cmake options...]: configure the same way, build only TARGET.
build_target() {
    local dir="$1" target="$2"
    shift 2
    configure_tree "$dir" "$@"
    cmake --build "$dir" --target "$target" -j "$(build_jobs)"
}
