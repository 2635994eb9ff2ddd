#!/usr/bin/env bash
# Blender (headless) imports every example scene's .glb; each body's world position and
# rotation at every key frame must match the run within 1e-4 m and 0.1 degree
# (tests/export/blender_check.py). The fast tumble is also measured between keys, with
# CUBICSPLINE and LINEAR keys, and the figures printed. scripts/test.sh calls it; it installs
# Debian's Blender 3.4 and NumPy for its Python when they are missing (scripts/setup.sh: as
# root with apt-get, about 70 s on a fresh machine; the checks take about 40 s).
#   scripts/test_blender.sh [BUILD_DIRECTORY]     (default build; needs examples/export_scene)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh blender python3-numpy
build=${1:-build}
out="$build/blender-check"
mkdir -p "$out"
check() { # the check's lines, and its exit status (non-zero: a body out of tolerance)
    local log status=0
    log=$(blender -b --factory-startup --python tests/export/blender_check.py -- "$@" 2>&1) ||
        status=$?
    grep '^blender_check' <<<"$log" || { echo "$log" >&2; return 1; }
    return $status
}
export_and_check() { # scene, fps (0: the scene's), [extra export arguments]
    local scene=$1 fps=$2 name
    name=$(basename "$scene" .json)
    shift 2
    local line
    line=$("$build/examples/export_scene" "$scene" "$out/$name.csv" "$fps")
    "$build/examples/export_scene" "$scene" "$out/$name.glb" "$fps" "$@" >/dev/null
    check "$out/$name.glb" "$out/$name.csv" "$(echo "$line" | sed 's/.* at \([0-9.]*\) fps/\1/')"
}
for scene in examples/scenes/*.json tests/scenes/shapes/every_shape.json; do
    # the dice, dominoes and stack take 10-25 s a run; their boxes are checked in other scenes
    case "$scene" in */dice.json | */dominoes.json | */stack.json) continue ;; esac
    export_and_check "$scene" 0
done
# Between keys: keys at 24 fps, the reference at 16 x 24 fps.
fast=tests/scenes/fast_tumble.json
"$build/examples/export_scene" "$fast" "$out/fast_tumble.csv" 24 >/dev/null
"$build/examples/export_scene" "$fast" "$out/fast_tumble-reference.csv" 384 >/dev/null
for keys in cubic linear; do
    "$build/examples/export_scene" "$fast" "$out/fast_tumble-$keys.glb" 24 $keys >/dev/null
    check "$out/fast_tumble-$keys.glb" "$out/fast_tumble.csv" 24 "$out/fast_tumble-reference.csv"
done
