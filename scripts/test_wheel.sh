#!/usr/bin/env bash
# The wheel as it would be published (scripts/repair_wheel.sh: auditwheel bundles libtumble's
# libraries into it, with their licences, and tags it manylinux), installed into a fresh venv
# and imported and run (scripts/check_wheel.py) with LD_LIBRARY_PATH unset and, in a private
# mount namespace (unshare, as root), the system's copies of those libraries covered by
# /dev/null, so that only the wheel's own can load. About 30 s.
#   scripts/test_wheel.sh BUILD   (BUILD/wheel holds the wheel pip built: scripts/test.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-shared}
scripts/repair_wheel.sh "$build"
wheel=$(ls "$build"/wheelhouse/tumble-*-manylinux_*.whl)
names=() hidden=()
while read -r name path package; do
    names+=("$name=$package")
    hidden+=("$path")
done <"$build/wheelhouse/bundled.txt"

rm -rf "$build/venv-wheel"
python3 -m venv "$build/venv-wheel"
"$build/venv-wheel/bin/pip" install --quiet "$wheel"
python=$PWD/$build/venv-wheel/bin/python
check=$PWD/scripts/check_wheel.py
cd "$build" # not the source tree: the installed package is imported
if [ "$(id -u)" -eq 0 ] && unshare --mount true 2>/dev/null; then
    echo "test_wheel: hiding ${hidden[*]}"
    # shellcheck disable=SC2016 # expanded by the inner shell
    NAMES="${names[*]}" unshare --mount --propagation private sh -c \
        'python=$1 check=$2; shift 2
         for file in "$@"; do mount --bind /dev/null "$file" || exit 1; done
         for file in "$@"; do [ ! -s "$file" ] || { echo "still readable: $file" >&2; exit 1; }; done
         exec env -u LD_LIBRARY_PATH -u TUMBLE_LIBRARY -u NAMES "$python" "$check" $NAMES' \
        sh "$python" "$check" "${hidden[@]}"
else
    echo "test_wheel: not root (or no unshare): the system's copies stay reachable; the check" \
        "still requires every library to be loaded from the wheel" >&2
    env -u LD_LIBRARY_PATH -u TUMBLE_LIBRARY "$python" "$check" "${names[@]}"
fi
