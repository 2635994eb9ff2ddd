#!/usr/bin/env bash
# Builds the installable zip of tumble for Blender (Blender: Edit > Preferences > Add-ons >
# Install..., then enable "tumble for Blender"; docs/blender.md).
#   scripts/make_blender_addon.sh [BUILD_DIRECTORY]    (default build) -> BUILD/tumble_blender.zip
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
mkdir -p "$build"
python3 - "$build/tumble_blender.zip" <<'PY'
import pathlib, sys, zipfile
source = pathlib.Path("bindings/blender/tumble_blender")
with zipfile.ZipFile(sys.argv[1], "w", zipfile.ZIP_DEFLATED) as archive:
    for path in sorted(source.glob("*.py")):  # the modules only: no __pycache__
        archive.write(path, f"tumble_blender/{path.name}")
PY
echo "$build/tumble_blender.zip"
