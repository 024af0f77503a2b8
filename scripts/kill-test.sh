#!/usr/bin/env bash
# The kill -9 test on its own: `leafdig capture --simulate` killed at seeded random instants,
# each time checking that every acknowledged item is stored and that a resume starts at the
# exact step. 200 runs (as in CI), or 1000 with --long. Needs the `ci` build
# (./scripts/setup.sh ci). Usage: scripts/kill-test.sh [--long]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
runs=200
[ "${1:-}" = "--long" ] && runs=1000
start=$(date +%s)
LEAFDIG_KILL_RUNS=$runs "$root/build/ci/tests/leafdig_cli_tests" \
  --gtest_filter='CaptureCli.KillNineAtRandomInstants*'
echo "kill-test: $runs runs in $(( $(date +%s) - start )) s"
