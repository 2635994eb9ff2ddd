#!/usr/bin/env bash
# Renders the pictures in README.md and docs/export.md: every example scene is exported to
# .glb (examples/export_scene) and drawn by Blender headless (scripts/render_scene.py, Cycles
# on the CPU, 16 samples, no denoising) twice: docs/images/<scene>.png, a 480 x 270 multiple
# exposure of the motion (the Dzhanibekov handle as a film strip, as it stays in place), and
# docs/images/<scene>.gif, the motion at 480 x 270, 12 pictures a simulated second played at
# 12 a second (real time; runs over 6 s faster, 72 pictures; the Dzhanibekov handle once a
# turn of its spin), made from the pictures by ffmpeg.
# Installs blender, NumPy for its Python and ffmpeg when missing (scripts/setup.sh).
# About 10 minutes on 2 cores.
#   scripts/render_examples.sh [BUILD_DIRECTORY] [--movie]   (--movie: also <scene>.mp4)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh blender python3-numpy ffmpeg
build=${1:-build}
movie=()
[ "${2:-}" = "--movie" ] && movie=(--movie)
mkdir -p "$build/renders" docs/images
blender_render() { # render_scene.py's arguments
    blender -b --factory-startup --python scripts/render_scene.py -- "$@" 2>&1 |
        grep -E "^Error|Traceback" || true
}
render() { # scene, "render_scene.py options for the still", [options for the GIF's pictures]
    local name
    name=$(basename "$1" .json)
    "$build/examples/export_scene" "$1" "$build/renders/$name.glb" >/dev/null
    # shellcheck disable=SC2086 # the options are words
    blender_render "$build/renders/$name.glb" "docs/images/$name" "${movie[@]}" $2
    rm -f "$build/renders/$name"-[0-9]*.png
    # shellcheck disable=SC2086
    blender_render "$build/renders/$name.glb" "$build/renders/$name" --width 480 ${3:---frames 72}
    # one palette for the whole animation (64 colours, ordered dither: small and steady)
    ffmpeg -loglevel error -y -framerate 12 -pattern_type glob \
        -i "$build/renders/$name-[0-9]*.png" \
        -vf "split[a][b];[a]palettegen=max_colors=64[p];[b][p]paletteuse=dither=bayer:bayer_scale=3" \
        "docs/images/$name.gif"
    echo "render: docs/images/$name.png ($(stat -c %s "docs/images/$name.png") bytes)," \
        "docs/images/$name.gif ($(stat -c %s "docs/images/$name.gif") bytes)"
}
render examples/scenes/tumbling_box.json "--strobe 9"
# the handle spins at 20 rad/s: a picture a turn (2 pi / 20 s) holds the spin still, so the
# flips of the spin axis show
render examples/scenes/dzhanibekov.json "--strobe 13 --spread 0.1" "--every 0.3141593"
render examples/scenes/spring_chain.json "--strobe 5"
render examples/scenes/sliding_block.json "--strobe 6"
render examples/scenes/box_on_slope.json "--still-time 5"
render examples/scenes/spinning_top.json "--strobe 5"
render tests/scenes/shapes/every_shape.json "--still-time 0.25"
# contact between bodies: the dice in the air at 0.2 s, and their throw at a quarter speed (a
# picture every 1/48 s); the dominoes at 0.6 s, half of them down
render examples/scenes/dice.json "--still-time 0.2" "--every 0.0208333"
render examples/scenes/dominoes.json "--still-time 0.6" "--every 0.0416667"
# a keyframed collider: the bat sweeping the boxes off the static table at half speed (a picture
# every 1/24 s, 8 samples: the GIF stays small)
render examples/scenes/bat_sweep.json "--still-time 0.9" "--every 0.0416667 --samples 8"
# joints (docs/joints.md): the chain of ten links on ball joints falling and whipping, half speed,
# each joint a dark marker between the links
render examples/scenes/chain.json "--still-time 0.6" "--every 0.0416667"
