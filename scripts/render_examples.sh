#!/usr/bin/env bash
# Renders the pictures in README.md and docs/export.md: every example scene is exported to
# .glb (examples/export_scene) and drawn by Blender headless (scripts/render_scene.py, Cycles
# on the CPU, 16 samples, no denoising, 480 x 270) into docs/images/<scene>.png: a multiple
# exposure of the motion (the Dzhanibekov handle as a film strip, as it stays in place).
# Needs blender (Debian: apt-get install blender python3-numpy). About a minute on 2 cores.
#   scripts/render_examples.sh [BUILD_DIRECTORY] [--movie]   (--movie: also <scene>.mp4)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
movie=()
[ "${2:-}" = "--movie" ] && movie=(--movie)
mkdir -p "$build/renders" docs/images
render() { # scene, then render_scene.py options
    local name
    name=$(basename "$1" .json)
    "$build/examples/export_scene" "$1" "$build/renders/$name.glb" >/dev/null
    shift
    blender -b --factory-startup --python scripts/render_scene.py -- \
        "$build/renders/$name.glb" "docs/images/$name" "${movie[@]}" "$@" 2>&1 |
        grep -E "^Saved|Error" || true
}
render examples/scenes/tumbling_box.json --strobe 9
render examples/scenes/dzhanibekov.json --strobe 13 --spread 0.1
render examples/scenes/spring_chain.json --strobe 5
render examples/scenes/sliding_block.json --strobe 6
render examples/scenes/box_on_slope.json --still-time 5
render examples/scenes/spinning_top.json --strobe 5
render tests/scenes/shapes/every_shape.json --still-time 0.25
