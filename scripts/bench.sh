#!/usr/bin/env bash
# Builds tumble (installing what is missing) and runs every benchmark: each one's CSV goes to
# build/bench-results/<name>.csv, and the work-precision chart (matplotlib, in a virtual
# environment under build/) to build/bench-results/work_precision.png. The committed figures in
# docs/ (accuracy.md, performance.md, integrators.md, effects.md, work_precision.*,
# contact_work_precision.*) come from
# these runs. A full run takes about 20 minutes on 2 cores; the machines are shared, so compare
# ratios from one run rather than absolute times across runs.
#   scripts/bench.sh [--quick]    (--quick: the smoke-test runs, a few seconds)
set -euo pipefail
cd "$(dirname "$0")/.."
quick=()
if [ "${1:-}" = "--quick" ]; then
    quick=(--quick)
fi
# The chart's matplotlib, and MuJoCo's C library for bench_peer (the mujoco-core wheel ships
# libmujoco and its headers; CMake finds them in this environment), before the build.
scripts/setup.sh
if [ ! -x build/bench-venv/bin/python ]; then
    python3 -m venv build/bench-venv
    build/bench-venv/bin/pip install --quiet --upgrade pip
fi
build/bench-venv/bin/python -c "import matplotlib" 2>/dev/null ||
    build/bench-venv/bin/pip install --quiet matplotlib
# PyBullet for bench_peer_pybullet.py (bench_peer_contact's worlds in the third engine).
build/bench-venv/bin/python -c "import pybullet, numpy" 2>/dev/null ||
    build/bench-venv/bin/pip install --quiet pybullet numpy ||
    echo "bench: pybullet could not be installed: bench_peer_pybullet is skipped" >&2
ls build/bench-venv/lib/python3*/site-packages/mujoco/libmujoco.so* >/dev/null 2>&1 ||
    build/bench-venv/bin/pip install --quiet mujoco-core ||
    echo "bench: mujoco-core could not be installed: bench_peer runs tumble alone" >&2
scripts/build.sh
out=build/bench-results
mkdir -p "$out"
for bench in bench_work_precision bench_torque_free_top bench_bdf_scaling bench_effects \
    bench_throughput bench_export bench_contact_geometry bench_contact bench_peer \
    bench_peer_contact bench_limit bench_dice_events bench_bdf_contact bench_contact_rate \
    bench_contact_work; do
    echo "bench: $bench" >&2
    "build/bench/$bench" "${quick[@]}" >"$out/$bench.csv"
done
echo "bench: bench_peer_pybullet" >&2
status=0
build/bench-venv/bin/python bench/bench_peer_pybullet.py "${quick[@]}" \
    --describe-with build/bench/bench_peer_contact >"$out/bench_peer_pybullet.csv" || status=$?
if [ "$status" != 0 ] && [ "$status" != 77 ]; then # 77: pybullet missing, said on stderr
    exit "$status"
fi
build/bench-venv/bin/python bench/plot_work_precision.py "$out/bench_work_precision.csv" \
    "$out/work_precision.png"
if [ "${1:-}" != "--quick" ]; then # tumble accuracy on four contact scenes: about 3 minutes
    echo "bench: contact_work_precision" >&2
    build/bench-venv/bin/python bench/contact_work_precision.py build/cli/tumble \
        "$out/contact_work_precision.csv" "$out/contact_work_precision.png"
fi
echo "bench: results in $out" >&2
