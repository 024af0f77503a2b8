#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan+UBSan) and runs each codec's fuzzer for a bounded
# time, starting from the seed corpus in tests/fuzz/corpus (new inputs go to a temporary
# directory, so the repository corpus only changes when someone adds seeds on purpose).
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 10)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-10}
cd "$root"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j"$(nproc)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for corpus in tests/fuzz/corpus/*/; do
  codec=$(basename "$corpus")
  mkdir -p "$work/$codec"
  echo "fuzz: $codec for ${seconds}s"
  (cd "$work" && "$root/build/fuzz/tests/fuzz/fuzz_$codec" -max_total_time="$seconds" -print_final_stats=1 \
     "$work/$codec" "$root/$corpus" 2>"$work/$codec.log") || { tail -40 "$work/$codec.log"; exit 1; }
  grep -E "stat::number_of_executed_units" "$work/$codec.log" | sed "s/^/  /"
done
echo "fuzz: all codecs clean"
