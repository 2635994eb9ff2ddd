#!/usr/bin/env bash
# The export checks with their independent readers: installs NumPy, pygltflib and usd-core
# (PyPI; usd-core before 26, whose UsdUtils still has the ComplianceChecker) into
# build/export-venv and the Khronos glTF validator (npm: gltf-validator) into
# build/export-node, points the build at them and runs the ctests labelled "export".
# Needs python3 (with venv), node and npm; scripts/test.sh calls it after the main build.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
if [ ! -x "$build/export-venv/bin/python" ]; then
    python3 -m venv "$build/export-venv"
    "$build/export-venv/bin/pip" install --quiet --upgrade pip
fi
"$build/export-venv/bin/pip" install --quiet numpy pygltflib "usd-core>=24.3,<26"
if ! command -v npm >/dev/null 2>&1 || ! command -v node >/dev/null 2>&1; then
    echo "test_export: node and npm are needed for the glTF validator" >&2
    exit 1
fi
if [ ! -f "$build/export-node/node_modules/gltf-validator/package.json" ]; then
    mkdir -p "$build/export-node"
    npm install --silent --prefix "$build/export-node" gltf-validator >/dev/null
fi
cmake -S . -B "$build" -DTUMBLE_EXPORT_PYTHON="$PWD/$build/export-venv/bin/python" \
    -DTUMBLE_EXPORT_NODE_MODULES="$PWD/$build/export-node/node_modules" >/dev/null
cmake --build "$build"
ctest --test-dir "$build" --output-on-failure -L export -j "$(nproc)"
