# scripts/lib.sh -- shared by the set-up scripts (sourced, not run).
# Installs the Debian packages impactcert needs (only the missing ones) and configures/builds.
set -euo pipefail

IMPACTCERT_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
IMPACTCERT_PACKAGES=(build-essential cmake libcgal-dev libgmp-dev catch2 nlohmann-json3-dev
                     libcli11-dev libbenchmark-dev libssl-dev z3)

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

# build_tree DIR [cmake options...]: configure (once) and build with both cores.
build_tree() {
    local dir="$1"
    shift
    cmake -S "$IMPACTCERT_ROOT" -B "$dir" "$@" >/dev/null
    cmake --build "$dir" -j2
}
