#!/usr/bin/env bash
# Every C++ file is formatted by .clang-format (clang-format 14, 120 columns, the limit the
# code base is written to). Prints the files that are not, and how to fix them.
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' | grep -v '^tests/fuzz/corpus/')
bad=()
for f in "${files[@]}"; do
  clang-format-14 --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]})); then
  echo "check-format: ${#bad[@]} file(s) not formatted by .clang-format:"
  printf '  %s\n' "${bad[@]}"
  echo "fix with: clang-format-14 -i ${bad[*]}"
  exit 1
fi
echo "check-format: ${#files[@]} files formatted"
