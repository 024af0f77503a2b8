#!/usr/bin/env bash
# The docs are written from the tree and must stay true (issue 48):
#  1. every source file of a module is named in its README (by its name without the
#     extension: `markers` names markers.hpp and markers.cpp); ui/cli and ui/station in
#     ui/README.md;
#  2. every C++ name docs/architecture.md cites — `A::b` anywhere on the page, a CamelCase
#     name in backquotes — exists: A is declared (class, struct, enum, namespace, using, concept) in a
#     source, and b is declared in a file that declares A (followed by ( , = ; { or }: not a
#     word in a comment);
#  3. every docs/FILE.md a source or script names exists, and every section it cites as
#     `docs/FILE.md, "Section"` is there: a heading of FILE, or the bold words that open one of
#     its paragraphs or list items, that holds the cited words (case aside).
# Usage: check-docs.sh [REPO_ROOT]
set -u
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root" || exit 2
fail=0
# The tracked files (a tree that is no git work tree, as the planted test's copy: every file).
tracked() {
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then git ls-files "$@"; else
    local args=() p; for p in "$@"; do case $p in *'*'*) args+=(-name "$p" -o) ;; esac; done
    if [ ${#args[@]} -gt 0 ]; then unset 'args[${#args[@]}-1]'; find . -type f \( "${args[@]}" \) | sed 's|^\./||'
    else find "$@" -type f; fi
  fi
}

readme_of() {
  case $1 in
    ui/*) echo ui/README.md ;;
    *) echo "$1/README.md" ;;
  esac
}
for module in names devices model db acquisition ui/cli ui/station python; do
  readme=$(readme_of "$module")
  [ -f "$readme" ] || { echo "$module has no $readme"; fail=1; continue; }
  for f in $(tracked "$module" | grep -E '\.(cpp|hpp|h)$' | grep -v '/tests/'); do
    stem=$(basename "$f"); stem=${stem%.*}
    grep -qE "(^|[^A-Za-z0-9_])${stem}([^A-Za-z0-9_]|$)" "$readme" ||
      { echo "$readme does not name $f"; fail=1; }
  done
done

doc=docs/architecture.md
mapfile -t sources < <(tracked '*.hpp' '*.cpp' '*.h' | grep -v -e '^tests/' -e '^build/')
declared_in() {  # files that declare the name $1
  grep -lE "(class|struct|enum class|enum|namespace|using|concept)[[:space:]]+([A-Za-z_:]*::)?$1([^A-Za-z0-9_]|$)" "${sources[@]}"
}
names=$( { grep -oE '[A-Za-z_][A-Za-z0-9_]*(::[A-Za-z_~][A-Za-z0-9_]*)+' "$doc";
           grep -oE '`[A-Z][a-z0-9]+[A-Z][A-Za-z0-9]*`' "$doc" | tr -d '`'; } | sort -u)
cmake_names=$(tracked '*CMakeLists.txt' | grep -v '^build/' | xargs cat)
for name in $names; do
  # A CMake target (leafdig::names, pybind11::embed) is checked by check-architecture.sh.
  grep -qF -- "$name" <<< "$cmake_names" && continue
  IFS=: read -ra parts <<< "${name//::/:}"
  owner=${parts[0]}
  [ "$owner" = leafdig ] && [ ${#parts[@]} -gt 1 ] && { owner=${parts[1]}; parts=("${parts[@]:1}"); }
  files=$(declared_in "$owner")
  if [ -z "$files" ]; then echo "$doc cites $name: nothing declares $owner"; fail=1; continue; fi
  for part in "${parts[@]:1}"; do
    # shellcheck disable=SC2086
    grep -qE -- "(^|[^A-Za-z0-9_~])${part}[[:space:]]*[(,=;{}]" $files || { echo "$doc cites $name: no $part where $owner is declared"; fail=1; }
  done
done

mapfile -t citing < <(tracked '*.cpp' '*.hpp' '*.h' '*.py' '*.sh' | grep -v -e '^build/' -e 'docs_planted.sh$' -e '^\.ci/check-docs.sh$')
while IFS= read -r file; do
  [ -f "$file" ] || { echo "a source names $file: there is no such file"; fail=1; }
done < <(grep -ohE '(^|[^A-Za-z0-9_./-])docs/[A-Za-z0-9_/-]+\.md' "${citing[@]}" | sed -E 's|^[^d]*||' | sort -u)
while IFS= read -r ref; do
  file=${ref%%, \"*}
  section=${ref#*, \"}; section=${section%\"}
  if [ ! -f "$file" ]; then echo "a source cites $ref: there is no $file"; fail=1; continue; fi
  grep -E '^#+ |^(- )?\*\*' "$file" | grep -qiF -- "$section" ||
    { echo "a source cites $ref: $file has no such section"; fail=1; }
done < <(grep -ohE 'docs/[a-z0-9_-]+\.md, "[^"]+"' "${citing[@]}" | sort -u)

if [ $fail -ne 0 ]; then
  echo "check-docs: the docs name what is not there (or leave out what is): write them from the tree"
  exit 1
fi
echo "docs ok: every module's files are in its README, every name docs/architecture.md cites exists, every docs section a source cites is there"
