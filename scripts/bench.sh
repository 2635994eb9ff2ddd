#!/usr/bin/env bash
# Builds tumble (installing what is missing) and runs every benchmark: each one's CSV goes to
# build/bench-results/<name>.csv, and the work-precision chart (matplotlib, in a virtual
# environment under build/) to build/bench-results/work_precision.png. The committed figures in
# docs/ (accuracy.md, performance.md, integrators.md, effects.md, work_precision.*) come from
# these runs. A full run takes about 20 minutes on 2 cores; the machines are shared, so compare
# ratios from one run rather than absolute times across runs.
#   scripts/bench.sh [--quick]    (--quick: the smoke-test runs, a few seconds)
set -euo pipefail
cd "$(dirname "$0")/.."
quick=()
if [ "${1:-}" = "--quick" ]; then
    quick=(--quick)
fi
scripts/build.sh
out=build/bench-results
mkdir -p "$out"
for bench in bench_work_precision bench_torque_free_top bench_bdf_scaling bench_effects \
    bench_throughput bench_export bench_contact_geometry; do
    echo "bench: $bench" >&2
    "build/bench/$bench" "${quick[@]}" >"$out/$bench.csv"
done
if [ ! -x build/bench-venv/bin/python ]; then
    python3 -m venv build/bench-venv
    build/bench-venv/bin/pip install --quiet --upgrade pip
    build/bench-venv/bin/pip install --quiet matplotlib
fi
build/bench-venv/bin/python bench/plot_work_precision.py "$out/bench_work_precision.csv" \
    "$out/work_precision.png"
echo "bench: results in $out" >&2
