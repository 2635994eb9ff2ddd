#!/usr/bin/env bash
# Installs what is missing, builds with warnings as errors, and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh -DTUMBLE_WARNINGS_AS_ERRORS=ON
ctest --test-dir build --output-on-failure -j "$(nproc)"
# The exports read back by NumPy, pygltflib and the Khronos glTF validator (installs them).
scripts/test_export.sh build
# Blender imports every example's .glb (installs Debian's Blender when missing: ~70 s, then ~40 s
# of checks). TUMBLE_SKIP_BLENDER=1 leaves it out (say so when reporting a run).
if [ "${TUMBLE_SKIP_BLENDER:-0}" = 1 ]; then
    echo "test: TUMBLE_SKIP_BLENDER=1: scripts/test_blender.sh not run" >&2
else
    scripts/test_blender.sh build
fi

# A shared libtumble: the install consumers against it, tumble for Blender (blender_addon: the
# add-on's keys against `tumble run`, needs Blender), and the Python bindings' tests.
cmake -S . -B build-shared -G Ninja -DTUMBLE_WARNINGS_AS_ERRORS=ON -DBUILD_SHARED_LIBS=ON \
    >/dev/null
cmake --build build-shared
ctest --test-dir build-shared --output-on-failure -R "install_consumers|example_embed_loop|blender_addon"
# The Python package as a user gets it: a wheel that pip builds (scikit-build-core running this
# CMake project: bindings/python/pyproject.toml), installed into a fresh venv and tested from
# outside the source tree with no TUMBLE_LIBRARY (tests/test_install.py checks which copy runs).
rm -rf build-shared/venv build-shared/wheel
python3 -m venv build-shared/venv
build-shared/venv/bin/pip install --quiet --upgrade pip
# The wheel is built from the sdist (scripts/make_sdist.sh), as a package index's users would.
scripts/make_sdist.sh build-shared
build-shared/venv/bin/pip wheel --quiet --no-deps build-shared/sdist/tumble-*.tar.gz \
    -w build-shared/wheel
# That wheel made one to publish (scripts/repair_wheel.sh: auditwheel bundles its libraries and
# tags it manylinux), installed into a fresh venv and run with the system's copies of those
# libraries hidden (about 30 s).
scripts/test_wheel.sh build-shared
build-shared/venv/bin/pip install --quiet build-shared/wheel/tumble-*.whl pytest matplotlib \
    "dask[distributed]" jsonschema
# The scene format's JSON Schema against the loader (the scene_schema ctest, here with PyPI's
# jsonschema for certain: ctest skips it when python3 lacks the package).
build-shared/venv/bin/python tests/scene_schema.py --tumble build-shared/cli/tumble
(cd build-shared && env -u TUMBLE_LIBRARY venv/bin/python -c "import tumble; print(tumble.__version__)")
# And exactly what README.md and docs/python.md tell a user, in another fresh venv.
rm -rf build-shared/venv-user && python3 -m venv build-shared/venv-user
build-shared/venv-user/bin/pip install --quiet ./bindings/python
(cd build-shared && env -u TUMBLE_LIBRARY venv-user/bin/python -c "import tumble; print(tumble.__version__)")
(cd build-shared && env -u TUMBLE_LIBRARY TUMBLE_TEST_INSTALLED=1 \
    TUMBLE_LAYOUT_PROBE="$PWD/bindings/python/tumble_layout_probe" \
    venv/bin/python -m pytest -q ../bindings/python/tests)
# The Python-against-C speed benchmark, in a smoke form (docs/performance.md has the real run).
(cd build-shared && venv/bin/python ../bindings/python/bench/bench_frames.py \
    --c-bench bench/bench_frames_in_memory --bodies 100 --repeats 1)

# The whole suite again under AddressSanitizer and UndefinedBehaviorSanitizer.
cmake -S . -B build-sanitize -G Ninja -DTUMBLE_WARNINGS_AS_ERRORS=ON -DTUMBLE_SANITIZE=ON \
    -DCMAKE_BUILD_TYPE=Debug >/dev/null
cmake --build build-sanitize
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-sanitize --output-on-failure -j "$(nproc)"

# The whole suite again built by clang, whose UndefinedBehaviorSanitizer also checks
# float-to-integer conversions that overflow (float-cast-overflow; gcc's does not), with the
# fuzz targets as libFuzzer programs: ctest replays their seed corpora and regression inputs,
# then a short reproducible run of each (fixed seed, a fixed number of inputs) looks further.
CC=clang CXX=clang++ cmake -S . -B build-clang -G Ninja -DTUMBLE_WARNINGS_AS_ERRORS=ON -DTUMBLE_SANITIZE=ON \
    -DTUMBLE_FUZZ=ON >/dev/null
cmake --build build-clang
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-clang --output-on-failure -j "$(nproc)"
scripts/fuzz.sh --build build-clang --seed 1 --runs 30000 scene_loader api # ~10 s each
scripts/fuzz.sh --build build-clang --seed 1 --runs 4000 obj # a file write an input: ~15 s
scripts/fuzz.sh --build build-clang --seed 1 --runs 2000 contact # contact steps: ~30 s

# The one benchmark command, in its smoke-test form (every benchmark, the chart).
scripts/bench.sh --quick
