#!/usr/bin/env bash
# docs/architecture.md is written from the tree and must stay true: every CMake target we
# define (add_library / add_executable; a foreach template `fuzz_${x}` counts as `fuzz_<…>`)
# and every top-level folder of the repository must be named on that page, in backquotes.
# Usage: check-architecture.sh [REPO_ROOT]
set -u
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root" || exit 2
doc=docs/architecture.md
[ -f "$doc" ] || { echo "check-architecture: $doc is missing"; exit 1; }
fail=0
targets=$(git ls-files '*CMakeLists.txt' | xargs grep -hoE 'add_(library|executable)\(\s*[A-Za-z0-9_.${}-]+' |
          sed -E 's/add_(library|executable)\(\s*//' | grep -v '::' | sort -u)
for t in $targets; do
  case $t in
    *'${'*) grep -qF "\`${t%%\$\{*}<" "$doc" || { echo "$doc does not name the targets $t"; fail=1; } ;;
    *) grep -qF "\`$t\`" "$doc" || { echo "$doc does not name the CMake target \`$t\`"; fail=1; } ;;
  esac
done
for d in $(git ls-files | cut -d/ -f1 | sort -u); do
  [ -d "$d" ] || continue
  case $d in .*) continue ;; esac
  grep -qF "\`$d/\`" "$doc" || { echo "$doc does not name the top-level folder \`$d/\`"; fail=1; }
done
if [ $fail -ne 0 ]; then
  echo "check-architecture: say in $doc what each of these is (it is written from the tree)"
  exit 1
fi
echo "architecture ok: every CMake target and top-level folder is in $doc"
