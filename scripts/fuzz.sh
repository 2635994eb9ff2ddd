#!/usr/bin/env bash
# Fuzzes tumble with libFuzzer under AddressSanitizer and UndefinedBehaviorSanitizer (clang).
#   scripts/fuzz.sh [--runs N] [--seed S] [--build DIR] [SECONDS] [TARGET...]
# TARGETs: scene_loader (scene files), api (random scenes through the C API), obj (OBJ meshes),
# contact (contact between bodies through the C API);
# default all four, one after another, each for SECONDS (default 600). --runs N stops each
# after N inputs instead (with --seed, a reproducible run: the test command's short runs).
# --build DIR uses an existing clang build configured with -DTUMBLE_FUZZ=ON -DTUMBLE_SANITIZE=ON
# (scripts/test.sh's build-clang) instead of configuring build-fuzz.
# Each target starts from its committed seed corpus (fuzz/corpus/TARGET) plus what earlier runs
# found (BUILD/corpus/TARGET, kept between runs). An input that breaks an invariant, crashes or
# takes over 30 s (wall clock) is written to BUILD/crashes/TARGET-*; minimise it with
#   BUILD/fuzz/fuzz_TARGET -minimize_crash=1 -runs=10000 FILE
# replay it as C calls with TUMBLE_FUZZ_TRACE=1 BUILD/fuzz/fuzz_api FILE, record it in the
# findings and, once fixed, commit it to fuzz/regressions/TARGET/ (ctest replays those).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=600
runs=""
seed=""
build=""
while [ $# -gt 0 ]; do
    case "$1" in
    --runs) runs=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    [0-9]*) seconds=$1; shift ;;
    *) break ;;
    esac
done
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(scene_loader api obj contact)

if [ -z "$build" ]; then
    build=build-fuzz
    scripts/setup.sh
    CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DTUMBLE_FUZZ=ON -DTUMBLE_SANITIZE=ON \
        -DTUMBLE_WARNINGS_AS_ERRORS=ON -DTUMBLE_BUILD_TESTS=OFF -DTUMBLE_BUILD_EXAMPLES=OFF \
        -DTUMBLE_BUILD_BENCHMARKS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
for target in "${targets[@]}"; do
    cmake --build "$build" --target "fuzz_$target"
done

# Longest input per target: scene files and OBJ meshes need room for long lines and many
# bodies; the API target reads a few bytes a call.
declare -A max_len=([scene_loader]=16384 [api]=4096 [obj]=65536)
status=0
for target in "${targets[@]}"; do
    corpus=$build/corpus/$target
    # A seeded run starts from the committed corpus alone, so it is the same run every time.
    [ -n "$seed" ] && corpus=$build/corpus/$target-seed-$seed && rm -rf "$corpus"
    mkdir -p "$corpus" "$build/crashes"
    # 30 s: an input's few seconds of CPU (a budgeted BDF run under the sanitizers) took 11 s of
    # wall clock on a 2-core machine at load 14, which is not a loop; a loop still shows.
    options=(-max_len="${max_len[$target]:-4096}" -timeout=30 -rss_limit_mb=2048
             -artifact_prefix="$build/crashes/$target-" -print_final_stats=1)
    [ -f "fuzz/$target.dict" ] && options+=(-dict="fuzz/$target.dict")
    if [ -n "$runs" ]; then
        options+=(-runs="$runs")
    else
        options+=(-max_total_time="$seconds")
    fi
    [ -n "$seed" ] && options+=(-seed="$seed")
    bound=${runs:+$runs inputs}
    echo "fuzz: $target (${bound:-$seconds s}), corpus $corpus" >&2
    seeds=("fuzz/corpus/$target")
    [ "$target" = scene_loader ] && seeds+=(examples/scenes tests/scenes)
    # Niced: the fuzzer must not starve the rest of the machine.
    if ! ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
        UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
        nice -n 10 "$build/fuzz/fuzz_$target" "${options[@]}" "$corpus" "${seeds[@]}"; then
        echo "fuzz: $target found an input that breaks it (in $build/crashes/)" >&2
        status=1
    fi
done
exit $status
