#!/usr/bin/env bash
# Configures and builds tumble in build/ (after installing what is missing).
# Extra arguments go to cmake's configure step, e.g. -DTUMBLE_WARNINGS_AS_ERRORS=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake -S . -B build -G Ninja "$@" >/dev/null
cmake --build build
