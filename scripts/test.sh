#!/usr/bin/env bash
# The whole test suite: set up and build the `ci` preset (checks: layering, architecture,
# format), every test (unit, CLI, exports checked by the Khronos glTF validator and assimp,
# samples, the station under Xvfb) under AddressSanitizer + UndefinedBehaviorSanitizer, the
# kill -9 tests at full count on the plain build, a short soak, the threaded tests under
# ThreadSanitizer, every fuzz target for 10 s, and the benchmarks' smoke pass. Set
# LEAFDIG_SKIP_ASAN=1 / LEAFDIG_SKIP_TSAN=1 / LEAFDIG_SKIP_FUZZ=1 / LEAFDIG_SKIP_SOAK=1 to
# skip a pass locally (without ASan the plain build runs the whole suite).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
# Each pass says how long it took (CI's budget is 45 minutes on two cores).
started=$(date +%s); passStarted=$started
passDone() {
  local now; now=$(date +%s)
  echo "leafdig test: $1 took $((now - passStarted)) s ($((now - started)) s so far)"
  passStarted=$now
}
# ctest starts the longest tests first when it knows their times, which a clean clone does
# not: each preset's times, measured on the 2-core machine, seed it (tests/ctest-costs/;
# ctest keeps its own measurements afterwards).
seedCosts() {
  local f="$root/build/$1/Testing/Temporary/CTestCostData.txt"
  if [ ! -f "$f" ] && [ -f "$root/tests/ctest-costs/$1.txt" ]; then
    mkdir -p "$(dirname "$f")"
    cp "$root/tests/ctest-costs/$1.txt" "$f"
  fi
}
# With the suite under ASan (below), the plain build makes only what runs on it: the two programs
# and the Python module (the package, the soak, the benchmarks' smokes), the two CLI test binaries
# that hold the kill -9 tests, and the benchmarks; the other test binaries are compiled once, for
# ASan (a cold compiler cache spent a third of this pass on them).
if [ "${LEAFDIG_SKIP_ASAN:-0}" != "1" ]; then
  LEAFDIG_BUILD_TARGETS="leafdig leafdig-station _leafdig leafdig_cli_tests leafdig_lab_cli_tests leafdig_bench"
  LEAFDIG_BUILD_TARGETS+=" leafdig_plant_bench leafdig_mesh_bench leafdig_leaf2d_bench leafdig_codec_bench"
  LEAFDIG_BUILD_TARGETS+=" leafdig_capture_bench leafdig_lab_bench leafdig_station_bench"
  export LEAFDIG_BUILD_TARGETS
fi
"$root/scripts/setup.sh" ci
unset LEAFDIG_BUILD_TARGETS
passDone "set-up and the ci build"
"$root/.ci/check-layering.sh" "$root"
"$root/.ci/check-architecture.sh" "$root"
"$root/.ci/check-docs.sh" "$root"
"$root/.ci/check-format.sh" "$root"
# The whole suite runs once, under ASan+UBSan (every test: units, CLI, exports through their
# real readers, the station under Xvfb, the demo). The plain build then runs what is about
# numbers and durability rather than memory: the kill -9 tests at their full count (200
# capture kills, 50 push kills; under ASan 10 each), then the short soak, the benchmarks'
# smoke pass and the fuzzers' builds use it too. With LEAFDIG_SKIP_ASAN=1 the plain build runs
# the whole suite instead. (Both passes over everything took 24 of CI's 45 minutes.)
durability='KillNineAtRandomInstants|SyncPushKilledAtRandomInstants'
# Tests in flight: twice the cores. Most of the suite's time is simulated captures waiting on
# their devices' clock (a simulated FASTRAK at 960 Hz, a technician's dwell), which costs no CPU
# since the emulators wait to the nanosecond (devices/src/sim/pty.cpp); what waits overlaps with
# what computes. No test asserts on speed: a loaded machine only makes each one slower.
testJobs=$(( $(nproc) * 2 ))
if [ "${LEAFDIG_SKIP_ASAN:-0}" != "1" ]; then
  cmake --preset asan >/dev/null
  cmake --build --preset asan -j"$(nproc)"
  passDone "the ASan+UBSan build"
  # The kill -9 tests at full count run on the plain build beside the ASan tests: they are
  # processes killed at instants taken from what each run shows, waiting most of the time.
  seedCosts ci
  killLog="$root/build/ci/kill-nine.log"
  ctest --preset ci -j2 -R "$durability" >"$killLog" 2>&1 &
  killPid=$!
  seedCosts asan
  asanStatus=0
  ctest --preset asan -j"$testJobs" || asanStatus=$?
  killStatus=0
  wait "$killPid" || killStatus=$?
  cat "$killLog"
  [ "$asanStatus" = 0 ] || { echo "leafdig test: the ASan+UBSan tests failed" >&2; exit "$asanStatus"; }
  [ "$killStatus" = 0 ] || { echo "leafdig test: the kill -9 tests at full count failed" >&2; exit "$killStatus"; }
  passDone "the ASan+UBSan tests, and beside them the kill -9 tests at full count (plain build)"
  # The Debian package of the plain build, installed and checked as a user gets it (with
  # `import leafdig` from the system Python). The module's pytest suite ran above under ASan
  # (an interpreter with the module built in: tests/python/asan_python.cpp); the plain module
  # itself runs again in the benchmark smokes below.
  ctest --preset ci -R '^package\.debian$'
  passDone "the Debian package (plain build)"
else
  seedCosts ci
  ctest --preset ci -j"$testJobs"
  passDone "the ci tests"
fi
# A short soak (about two minutes; scripts/soak.sh has the long one): capture with faults,
# kill -9, a full disk and lab pushes, then every acknowledged event checked.
if [ "${LEAFDIG_SKIP_SOAK:-0}" != "1" ]; then
  "$root/scripts/soak.sh" --short
  passDone "the short soak"
fi
# The device drivers and emulators are threaded: their tests again under ThreadSanitizer.
if [ "${LEAFDIG_SKIP_TSAN:-0}" != "1" ]; then
  cmake --preset tsan >/dev/null
  cmake --build --preset tsan -j"$(nproc)"
  passDone "the TSan build"
  seedCosts tsan
  ctest --preset tsan -j"$testJobs"
  passDone "the TSan tests"
fi
# Every codec's libFuzzer target, for a bounded time from the seed corpus.
if [ "${LEAFDIG_SKIP_FUZZ:-0}" != "1" ]; then
  "$root/scripts/fuzz.sh" "${LEAFDIG_FUZZ_SECONDS:-10}"
  passDone "the fuzzers"
fi
# The benchmarks must still run (a quick smoke pass; numbers live in docs/benchmarks.md).
# A benchmark that reports an error (SkipWithError), or a binary that runs none, fails here.
bench_smoke() {
  local report
  report=$(mktemp)
  if ! "$@" --benchmark_min_time=0.01 --benchmark_format=json >"$report"; then
    echo "benchmark smoke: $* exited non-zero" >&2; rm -f "$report"; return 1
  fi
  if grep -q '"error_occurred": true' "$report"; then
    echo "benchmark smoke: $* reported an error:" >&2
    grep -E '"(name|error_message)"' "$report" | grep -B1 '"error_message"' >&2
    rm -f "$report"; return 1
  fi
  if ! grep -q '"run_name"' "$report"; then
    echo "benchmark smoke: $* ran no benchmark" >&2; rm -f "$report"; return 1
  fi
  rm -f "$report"
}
bench_smoke build/ci/tests/leafdig_bench --benchmark_filter='Rebuild(Preview|Paper)/1|SyntheticLeafAndTruth/0|AreaInterval/1|BuildLeafAsModelBuild'
# Python's build_leaf against the same in C++ (three leaves, one round: that it runs).
LEAFDIG_BENCH_ROUNDS=1 PYTHONPATH=build/ci/python /usr/bin/python3 tests/bench/python_bench.py build/ci/tests/leafdig_bench 3 >/dev/null
bench_smoke build/ci/tests/leafdig_codec_bench
bench_smoke build/ci/tests/leafdig_leaf2d_bench
bench_smoke build/ci/tests/leafdig_plant_bench --benchmark_filter='PlantAssemble|PlantSilhouette/0|PlantEncode/(5|6)|SurveyedPlantExport/0|ArchiveWalnutImport'
bench_smoke build/ci/tests/leafdig_mesh_bench --benchmark_filter='AdaptiveLeaf/30|SeedLeaf|SeedAxisOrgan/170'
bench_smoke env LEAFDIG_BENCH_LEAVES=200 LEAFDIG_BENCH_PLANT_NODES=4 build/ci/tests/leafdig_capture_bench
# The lab server's push, incremental push and listing, on a PostgreSQL cluster of its own.
bench_smoke env LEAFDIG_BENCH_LEAVES=20 build/ci/tests/leafdig_lab_bench
# The station's preview frame, snapshot → screen and start-up, on a real window under Xvfb
# (Mesa llvmpipe); it fails if the preview draws nothing or the station does not start.
bench_smoke xvfb-run -a -s "-screen 0 1920x1080x24" build/ci/tests/leafdig_station_bench
passDone "the benchmark smokes"
echo "leafdig: all tests passed"
