#!/usr/bin/env bash
# The whole test suite: set up and build the `ci` preset, run every test (unit, CLI,
# exports checked by the Khronos glTF validator and assimp, samples, layering), then the
# same suite under AddressSanitizer + UndefinedBehaviorSanitizer.
# Set LEAFDIG_SKIP_ASAN=1 to skip the sanitizer pass when iterating locally.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
"$root/scripts/setup.sh" ci
"$root/.ci/check-layering.sh" "$root"
ctest --preset ci -j"$(nproc)"
if [ "${LEAFDIG_SKIP_ASAN:-0}" != "1" ]; then
  cmake --preset asan >/dev/null
  cmake --build --preset asan -j"$(nproc)"
  ctest --preset asan -j"$(nproc)"
fi
# The benchmarks must still run (a quick smoke pass; numbers live in docs/benchmarks.md).
build/ci/tests/leafdig_bench --benchmark_min_time=0.01 --benchmark_filter='Rebuild(Preview|Paper)/1' >/dev/null
echo "leafdig: all tests passed"
