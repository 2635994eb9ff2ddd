#!/usr/bin/env bash
# The Python package's source distribution, BUILD/sdist/tumble-VERSION.tar.gz, one that builds
# alone: bindings/python/pyproject.toml builds the library from the repository two levels up,
# which an sdist of bindings/python would not hold, so this stages what the wheel's CMake build
# reads (CMakeLists.txt, cmake/, include/, src/, the licence and bindings/python's package and
# CMake files) with that pyproject.toml pointed at the staged root, and runs `python -m build
# --sdist` on it. scripts/test.sh builds the wheel it tests from this sdist.
# Installs build (PyPI) into BUILD/wheel-tools.
#   scripts/make_sdist.sh BUILD
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-shared}
tools=$PWD/$build/wheel-tools
if [ ! -x "$tools/bin/pyproject-build" ]; then
    [ -x "$tools/bin/pip" ] || python3 -m venv "$tools"
    "$tools/bin/pip" install --quiet --upgrade pip
    "$tools/bin/pip" install --quiet build
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
stage=$work/tumble
mkdir -p "$stage/bindings/python"
cp -r CMakeLists.txt LICENSE cmake include src "$stage/"
cp -r bindings/python/CMakeLists.txt bindings/python/layout_probe.c bindings/python/README.md \
    bindings/python/tumble "$stage/bindings/python/"
find "$stage" -name __pycache__ -prune -exec rm -rf {} +
# The same pyproject.toml, its paths taken from the staged root instead of bindings/python.
sed -e 's|^cmake.source-dir = "../.."$|cmake.source-dir = "."|' \
    -e 's|^metadata.version.input = "../../CMakeLists.txt"$|metadata.version.input = "CMakeLists.txt"|' \
    -e 's|^wheel.packages = \["tumble"\]$|wheel.packages = ["bindings/python/tumble"]|' \
    -e 's|^readme = "README.md"$|readme = "bindings/python/README.md"|' \
    bindings/python/pyproject.toml >"$stage/pyproject.toml"
for line in 'cmake.source-dir = "."' 'metadata.version.input = "CMakeLists.txt"' \
    'wheel.packages = ["bindings/python/tumble"]' 'readme = "bindings/python/README.md"'; do
    grep -qxF "$line" "$stage/pyproject.toml" ||
        { echo "make_sdist: pyproject.toml changed: no '$line' after the rewrite" >&2; exit 1; }
done
rm -rf "$build/sdist"
"$tools/bin/pyproject-build" --sdist --outdir "$build/sdist" "$stage" >"$work/log" 2>&1 ||
    { cat "$work/log" >&2; exit 1; }
echo "make_sdist: $(ls "$build"/sdist/tumble-*.tar.gz)"
