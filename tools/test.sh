#!/usr/bin/env bash
# Builds tsubu and runs the test suite (every CTest test, in parallel on all cores).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
source "$root/tools/setup.sh"
ctest --test-dir "$root/build" --output-on-failure -j "$(nproc)"
