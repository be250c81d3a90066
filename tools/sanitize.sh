#!/usr/bin/env bash
# The test suite built with AddressSanitizer + UndefinedBehaviorSanitizer (no recovery:
# any report fails its test), in build-asan/. Run by CI after tools/test.sh.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
source "$root/tools/setup.sh" >/dev/null
cmake -S "$root" -B "$root/build-asan" -G Ninja -DTSUBU_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
ninja -C "$root/build-asan"
# Without the long validations and the "matrix" tests: the split runs' process x thread
# configurations beyond the two that reach every exchange (2 processes x 2 threads, 3 x 1),
# each 5-10 minutes under the sanitizers; tools/test.sh runs them all.
ctest --test-dir "$root/build-asan" --output-on-failure -j "$(nproc)" -LE 'validation|matrix'
