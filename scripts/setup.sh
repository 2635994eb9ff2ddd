#!/usr/bin/env bash
# Installs the distribution packages tumble needs to build and test, if any are missing.
# As root it installs them (apt-get); anyone else is told the exact command to run.
#   scripts/setup.sh [EXTRA_PACKAGE...]   (extra ones for one script, e.g. blender)
set -euo pipefail

# clang with its sanitizer and libFuzzer runtimes (libclang-rt-dev: Debian 12 ships them apart
# from clang) and OpenMP (SUNDIALS' CMake package asks for it): the clang build of the test
# command and scripts/fuzz.sh.
packages=(cmake ninja-build gcc g++ pkg-config libgsl-dev libsundials-dev libsuitesparse-dev libcmocka-dev libjansson-dev libccd-dev libdeflate-dev valgrind clang-format
          python3 python3-venv python3-pip clang libclang-rt-dev libomp-dev "$@")

if ! command -v dpkg-query >/dev/null 2>&1; then
    echo "setup: not a Debian-like system; make sure these are installed: ${packages[*]}" >&2
    exit 0
fi

missing=()
for package in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$package")
    fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

command="apt-get update && apt-get install -y ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
    echo "setup: installing ${missing[*]}" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    echo "setup: installing ${missing[*]} with sudo" >&2
    sudo sh -c "DEBIAN_FRONTEND=noninteractive $command"
else
    echo "setup: tumble needs ${missing[*]}. Install them as root with:" >&2
    echo "    sudo sh -c '$command'" >&2
    exit 1
fi
