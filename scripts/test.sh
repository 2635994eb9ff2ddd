#!/usr/bin/env bash
# Installs what is missing, builds with warnings as errors, and runs every test.
#
# What runs, and what each part proves (each builds in its own directory):
#   static    build/: every ctest (physics, contracts, CLI, examples, smoke benchmarks), the
#             memcheck ctests (valgrind: no leak, no invalid access in the suites that reach CVODE,
#             GSL and every allocation path) and helgrind on the npz writer's thread.
#   exports   build/: the exports read back by independent readers, Blender among them; then the
#             benchmarks' smoke runs and the chart.
#   python    build-shared/: a shared libtumble, its install consumers, the sdist, the wheel pip
#             builds from it, repaired and run with the system's libraries hidden, the Python
#             tests against the installed wheel, the README's own install.
#   sanitize  build-sanitize/ (gcc, Debug: the suites valgrind did not check) and build-clang/
#             (clang, with float-cast-overflow and the fuzz targets: every suite): the ctests
#             again under AddressSanitizer and UndefinedBehaviorSanitizer, and a short
#             reproducible run of each fuzz target.
# The exports and python parts wait on the network, on pip's and CMake's single-threaded steps
# and on Blender's one core most of their time, so they run in the background (python from the
# end of the static build, exports from the end of its ctests) beside the CPU-bound builds and
# ctests, and 2 cores stay busy; so does the fuzzing (one core) beside the clang ctests. Each
# background part writes its log to build*/test-<part>.log, printed when it ends. Nothing is
# shared between the parts running at once: the exports reconfigure build/ only after the static
# ctests are done, the python part uses build-shared/ alone, the fuzzing build-clang/'s built
# fuzz targets and its own corpus folders.
set -euo pipefail
set -m # each part in its own process group, so that a failure can stop the others
cd "$(dirname "$0")/.."

parts=() part_pids=() part_logs=()
stop_parts() { # after a failure: the parts still running are stopped
    local i
    for i in "${!part_pids[@]}"; do
        if kill -- "-${part_pids[$i]}" 2>/dev/null; then
            echo "test: ${parts[$i]} stopped (log so far: ${part_logs[$i]})" >&2
        fi
    done
}
trap stop_parts EXIT
start_part() { # name log command...: runs a part in the background
    local name=$1 log=$2
    shift 2
    mkdir -p "$(dirname "$log")"
    "$@" >"$log" 2>&1 &
    parts+=("$name") part_pids+=($!) part_logs+=("$log")
    echo "test: $name started (log: $log)" >&2
}
finish_parts() { # waits for every part, prints its log, fails if one failed
    local status=0 i
    for i in "${!parts[@]}"; do
        if wait "${part_pids[$i]}"; then
            cat "${part_logs[$i]}"
            echo "test: ${parts[$i]} passed" >&2
        else
            cat "${part_logs[$i]}"
            echo "test: ${parts[$i]} FAILED (log: ${part_logs[$i]})" >&2
            status=1
        fi
    done
    part_pids=()
    return $status
}

# The exports read back by NumPy, pygltflib, usd-core and the Khronos glTF validator (installs
# them); Blender imports every example's .glb (installs Debian's Blender when missing: ~70 s,
# then ~40 s of checks; TUMBLE_SKIP_BLENDER=1 leaves it out: say so when reporting a run). Then
# the one benchmark command in its smoke-test form (every benchmark, the chart). All three
# reconfigure or read build/, so they run one after the other.
exports_part() {
    set -euo pipefail
    scripts/test_export.sh build
    if [ "${TUMBLE_SKIP_BLENDER:-0}" = 1 ]; then
        echo "test: TUMBLE_SKIP_BLENDER=1: scripts/test_blender.sh not run" >&2
    else
        scripts/test_blender.sh build
    fi
    scripts/bench.sh --quick
}

# A shared libtumble: the install consumers against it (CMake package, pkg-config, C++17), tumble
# for Blender (blender_addon: the add-on's keys against `tumble run`, registered when CMake finds
# Blender) and the Python package as a user gets it.
python_part() {
    set -euo pipefail
    cmake -S . -B build-shared -G Ninja -DTUMBLE_WARNINGS_AS_ERRORS=ON -DBUILD_SHARED_LIBS=ON \
        >/dev/null
    cmake --build build-shared
    ctest --test-dir build-shared --output-on-failure \
        -R "install_consumers|example_embed_loop|blender_addon"
    # A wheel that pip builds (scikit-build-core running this CMake project:
    # bindings/python/pyproject.toml), installed into a fresh venv and tested from outside the
    # source tree with no TUMBLE_LIBRARY (tests/test_install.py checks which copy runs).
    rm -rf build-shared/venv build-shared/wheel
    python3 -m venv build-shared/venv
    build-shared/venv/bin/pip install --quiet --upgrade pip
    # The wheel is built from the sdist (scripts/make_sdist.sh), as a package index's users would.
    scripts/make_sdist.sh build-shared
    build-shared/venv/bin/pip wheel --quiet --no-deps build-shared/sdist/tumble-*.tar.gz \
        -w build-shared/wheel
    # That wheel made one to publish (scripts/repair_wheel.sh: auditwheel bundles its libraries
    # and tags it manylinux), installed into a fresh venv and run with the system's copies of
    # those libraries hidden (about 30 s).
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
}

# The sanitizer builds run every suite with TUMBLE_TEST_SHORT=1, as the memcheck ctests do: the
# suites with long spans (tests/support/span.h) run the same physics, every code path of it,
# over a shorter span (a step costs about 10 times the CPU there); the contact scenes and
# suites have their own cuts under TUMBLE_SANITIZE (tests/CMakeLists.txt). The style checks
# (label style: clang-format, the sizes) read the sources, the same in every build: the static
# build runs them.
#
# LeakSanitizer's own stop-the-world tracer sometimes crashes at a test's exit after every check
# passed ("Tracer caught signal 11 ... LeakSanitizer has encountered a fatal error": a known
# intermittent fault of the sanitizer runtime, google/sanitizers#1353, not a leak report; CI met
# it once in visual_mesh). When every failed test of a run failed that way and no other, those
# tests run once more and must pass then; any other failure fails at once.
# intercept_tls_get_addr=0: with it on, the tracer crashed at every exit of one clang build's
# visual_mesh (in __lsan::ScanRangeForPointers, address 0x3f0) while scanning the thread's dynamic
# TLS, which holds glibc's dlerror buffer; off, that build passes 5 runs of 5, and a leak is still
# reported (a malloc dropped in a 3-line program, under gcc's and clang's ASan).
sanitized_ctest_once() { # build directory, [more ctest arguments]
    local build=$1
    shift
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 LSAN_OPTIONS=intercept_tls_get_addr=0 \
        UBSAN_OPTIONS=print_stacktrace=1 TUMBLE_TEST_SHORT=1 ctest --test-dir "$build" --output-on-failure -j "$(nproc)" -LE style "$@"
}
sanitized_ctest() { # build directory, [more ctest arguments]
    local build=$1 log failed crashes
    log="$build/sanitized-ctest.log"
    if sanitized_ctest_once "$@" 2>&1 | tee "$log"; then
        return 0
    fi
    failed=$(grep -c . "$build/Testing/Temporary/LastTestsFailed.log" || true)
    crashes=$(grep -c "LeakSanitizer has encountered a fatal error" "$log" || true)
    if [ "$failed" -gt 0 ] && [ "$failed" = "$crashes" ]; then
        echo "test.sh: LeakSanitizer's tracer crashed in $failed test(s) after their checks;" \
            "running them once more" >&2
        sanitized_ctest_once "$build" --rerun-failed
        return
    fi
    return 1
}

# Blender first, when it is to be tested (~70 s on a fresh machine): the exports part imports
# into it and the python part's build-shared registers the add-on's test only where CMake finds
# it; installed here, before the parts run at once, so that two apt-gets never meet.
if [ "${TUMBLE_SKIP_BLENDER:-0}" != 1 ]; then
    scripts/setup.sh blender python3-numpy
fi
# The static build and its ctests first: the quickest answer, and the exports need build/.
scripts/build.sh -DTUMBLE_WARNINGS_AS_ERRORS=ON
start_part python build-shared/test-python.log python_part
ctest --test-dir build --output-on-failure -j "$(nproc)"
# the suites memcheck ran (read before the exports reconfigure build/)
memchecked=$(ctest --test-dir build -N -L memcheck | sed -n 's/^ *Test *#[0-9]*: memcheck_//p' |
    paste -sd '|')
start_part exports build/test-exports.log exports_part

# The suite again under AddressSanitizer and UndefinedBehaviorSanitizer (gcc, Debug), but for
# the suites valgrind memcheck already ran in the static build (the memcheck_<suite> ctests: no
# leak, no invalid heap access there) and the few that cost the most here (over 30 s each at -O0:
# the friction and contact-law sweeps, sleeping, the accuracy sweeps and the benchmarks' smoke
# runs, about 5 of the run's 20 minutes): those run under both sanitizers in the clang build
# below, so every suite still runs under ASan and UBSan once, and the memcheck suites under
# valgrind too.
cmake -S . -B build-sanitize -G Ninja -DTUMBLE_WARNINGS_AS_ERRORS=ON -DTUMBLE_SANITIZE=ON \
    -DCMAKE_BUILD_TYPE=Debug >/dev/null
cmake --build build-sanitize
clang_only="contact_friction|contact_law|sleep|smoke_bench_.*|cli_accuracy_.*"
sanitized_ctest build-sanitize -E "^(${memchecked:+$memchecked|}$clang_only)\$"

# Every suite again, built by clang, whose UndefinedBehaviorSanitizer also checks
# float-to-integer conversions that overflow (float-cast-overflow; gcc's does not), with the
# fuzz targets as libFuzzer programs: ctest replays their seed corpora and regression inputs,
# and beside it a short reproducible run of each (fixed seed, a fixed number of inputs, one
# core) looks further.
CC=clang CXX=clang++ cmake -S . -B build-clang -G Ninja -DTUMBLE_WARNINGS_AS_ERRORS=ON -DTUMBLE_SANITIZE=ON \
    -DTUMBLE_FUZZ=ON >/dev/null
cmake --build build-clang
fuzz_part() {
    set -euo pipefail
    scripts/fuzz.sh --build build-clang --seed 1 --runs 30000 scene_loader api # ~10 s each
    scripts/fuzz.sh --build build-clang --seed 1 --runs 4000 obj # a file write an input: ~15 s
    scripts/fuzz.sh --build build-clang --seed 1 --runs 2000 contact # contact steps: ~30 s
}
start_part fuzz build-clang/test-fuzz.log fuzz_part
sanitized_ctest build-clang

finish_parts
