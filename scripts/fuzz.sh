#!/usr/bin/env bash
# Fuzzes the scene loader with libFuzzer under AddressSanitizer and UndefinedBehaviorSanitizer
# for a bounded time, seeded with the example and test scenes.
#   scripts/fuzz.sh [SECONDS]     (default 600)
# Crashes are written to build-fuzz/crashes/; turn each into a regression test
# (tests/test_scene_file.c) before fixing it.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
scripts/setup.sh
# clang, and its OpenMP (SUNDIALS' CMake package asks for OpenMP).
if ! command -v clang >/dev/null || ! dpkg-query -W libomp-dev >/dev/null 2>&1; then
    if [ "$(id -u)" -eq 0 ]; then
        apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq clang libomp-dev
    else
        echo "fuzz: needs clang and libomp-dev: sudo apt-get install clang libomp-dev" >&2
        exit 1
    fi
fi
CC=clang cmake -S . -B build-fuzz -G Ninja -DTUMBLE_FUZZ=ON -DTUMBLE_SANITIZE=ON \
    -DTUMBLE_BUILD_TESTS=OFF -DTUMBLE_BUILD_EXAMPLES=OFF -DTUMBLE_BUILD_BENCHMARKS=OFF \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build-fuzz --target fuzz_scene_loader
mkdir -p build-fuzz/corpus build-fuzz/crashes
cp examples/scenes/*.json tests/scenes/*.json build-fuzz/corpus/
ASAN_OPTIONS=detect_leaks=1 build-fuzz/fuzz/fuzz_scene_loader build-fuzz/corpus \
    -max_total_time="$seconds" -max_len=16384 -timeout=10 -rss_limit_mb=2048 \
    -dict=fuzz/scene.dict -artifact_prefix=build-fuzz/crashes/ -print_final_stats=1
