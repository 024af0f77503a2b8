#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan+UBSan) and runs each one: every codec, and the
# readers of the files a user hands us (markers, plant plans, outlines in JSON and CSV, scans'
# headers). Each starts from its seed corpus in tests/fuzz/corpus/<target>.
#
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 10; new inputs go to a temporary
#                                                directory: the repository corpus only
#                                                changes when someone adds seeds on purpose)
#        scripts/fuzz.sh --long [RUNS [TARGET ...]]
#                                               (every target, or the TARGETs named, to RUNS
#                                                executions, default 10^7, with its corpus kept
#                                                in build/fuzz-corpus/ between runs; prints
#                                                executions, time and corpus size per target for
#                                                docs/benchmarks.md. Two runs on different
#                                                targets may run side by side, one per core)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
long=0
runs=10000000
seconds=10
only=()
if [ "${1:-}" = "--long" ]; then
  long=1
  runs=${2:-$runs}
  only=("${@:3}")
  for target in "${only[@]}"; do
    [ -d "$root/tests/fuzz/corpus/$target" ] || {
      echo "fuzz.sh: no fuzz target \"$target\" (the targets are the directories of tests/fuzz/corpus/)" >&2
      exit 2
    }
  done
else
  seconds=${1:-10}
fi
cd "$root"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j"$(nproc)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# One short run: the target for `seconds` on one core, then its executions (or the log's tail).
runShort() {
  local target=$1 corpus=$2
  mkdir -p "$work/$target"
  if ! (cd "$work" && "$root/build/fuzz/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -print_final_stats=1 \
        "$work/$target" "$root/$corpus" 2>"$work/$target.log"); then
    echo "fuzz: $target FAILED:"; tail -40 "$work/$target.log"
    return 1
  fi
  echo "fuzz: $target for ${seconds}s, $(grep -E "stat::number_of_executed_units" "$work/$target.log" | awk '{print $2}') executions"
}
# The short runs go one per core at a time (each target still has its seconds of one core).
cores=$(nproc)
running=0
for corpus in tests/fuzz/corpus/*/; do
  target=$(basename "$corpus")
  if [ "${#only[@]}" -gt 0 ] && [[ " ${only[*]} " != *" $target "* ]]; then
    continue
  fi
  if [ "$long" = 1 ]; then
    kept="$root/build/fuzz-corpus/$target"
    mkdir -p "$kept"
    echo "fuzz --long: $target to $runs executions"
    start=$(date +%s)
    (cd "$work" && "$root/build/fuzz/tests/fuzz/fuzz_$target" -runs="$runs" -print_final_stats=1 \
       "$kept" "$root/$corpus" 2>"$work/$target.log") || { tail -40 "$work/$target.log"; exit 1; }
    end=$(date +%s)
    executed=$(grep -E "stat::number_of_executed_units" "$work/$target.log" | awk '{print $2}')
    echo "  $target: $executed executions in $((end - start)) s, corpus $(ls "$kept" | wc -l) inputs, clean"
  else
    if [ "$running" -ge "$cores" ]; then
      wait -n || { kill $(jobs -p) 2>/dev/null; wait; exit 1; }
      running=$((running - 1))
    fi
    runShort "$target" "$corpus" &
    running=$((running + 1))
  fi
done
while [ "$running" -gt 0 ]; do
  wait -n || { kill $(jobs -p) 2>/dev/null; wait; exit 1; }
  running=$((running - 1))
done
echo "fuzz: every target clean"
