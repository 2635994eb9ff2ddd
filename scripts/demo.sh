#!/usr/bin/env bash
# Builds tumble and runs the main demo.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
exec build/examples/tumble_demo
