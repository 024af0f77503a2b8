#!/usr/bin/env bash
# clang-tidy over the project's own sources with the checks of .clang-tidy, every warning an
# error. Nightly, not in the test command: with clang-analyzer a translation unit takes
# ~55 s here (Eigen, nlohmann-json, Qt), ~70 minutes for the tree on 2 cores, past CI's
# 45-minute budget (docs/decisions.md, "clang-tidy is a nightly script").
# Usage: scripts/tidy.sh [FILE|FOLDER...]   (default: every .cpp of the modules and ui/)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
tidy=$(command -v clang-tidy-14 || command -v clang-tidy || true)
if [ -z "$tidy" ]; then
  echo "tidy: clang-tidy is not installed: apt-get install clang-tidy" >&2; exit 2
fi
if [ ! -f build/ci/compile_commands.json ]; then
  echo "tidy: no build/ci/compile_commands.json: run scripts/setup.sh ci first" >&2; exit 2
fi
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(model devices db acquisition ui)
mapfile -t files < <(find "${targets[@]}" -name '*.cpp' -not -path '*/tests/*' | sort)
echo "tidy: ${#files[@]} files on $(nproc) cores"
log=$(mktemp)
# GCC-only warning flags in the compile commands are not clang's concern.
printf '%s\n' "${files[@]}" |
  xargs -P "$(nproc)" -n 1 "$tidy" -p build/ci --quiet --warnings-as-errors='*' \
    --extra-arg=-Wno-unknown-warning-option >"$log" 2>&1 || true
if grep -qE '(warning|error): ' "$log"; then
  grep -E '(warning|error): ' "$log" | sort -u
  echo "tidy: $(grep -cE '(warning|error): ' "$log") findings (full output: $log)" >&2
  exit 1
fi
rm -f "$log"
echo "tidy: clean"
