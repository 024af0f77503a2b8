#!/usr/bin/env bash
# The docs check must fail when the docs and the tree part: in a copy of the tree (no git, so
# the check reads every file), plant a source file no README names and a name on
# docs/architecture.md that nothing declares, a section of the docs a source cites that is not
# there, one at a time, and expect .ci/check-docs.sh to
# name each (and to pass on the unplanted copy).
# Usage: docs_planted.sh REPO_ROOT
set -u
root=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fresh() {
  rm -rf "$work/tree"; mkdir -p "$work/tree"
  cp -r "$root"/{names,model,devices,db,acquisition,ui,python,docs,CMakeLists.txt} "$work/tree/"
}
check() { (cd "$work/tree" && "$root/.ci/check-docs.sh" .) >"$work/out" 2>&1; }
failures=0
fresh
check || { echo "the unplanted copy should pass:"; cat "$work/out"; failures=1; }
expect() {  # what must be named, what it breaks
  if check; then echo "not caught: $2"; failures=1
  elif ! grep -qF "$1" "$work/out"; then echo "caught but not named: $2:"; cat "$work/out"; failures=1
  else echo "caught: $2"; fi
}
fresh; printf '// new\n' >"$work/tree/acquisition/src/protocol/jig_protocol.cpp"
expect "acquisition/src/protocol/jig_protocol.cpp" "a source file its README does not name"
fresh; printf '// new\n' >"$work/tree/ui/station/jig_view.hpp"
expect "ui/station/jig_view.hpp" "a station file ui/README.md does not name"
fresh; printf '\nThe engine decides in `Engine::decide`.\n' >>"$work/tree/docs/architecture.md"
expect "Engine::decide" "a member that does not exist"
fresh; printf '\nThe loop is `PlantCaptureLoopz`.\n' >>"$work/tree/docs/architecture.md"
expect "PlantCaptureLoopz" "a class that does not exist"
fresh; printf '// The jig (docs/devices.md, "The jig"); its check (docs/devices.md, "Checking the feld").\n' \
  >>"$work/tree/acquisition/src/field/field_check.cpp"
expect 'docs/devices.md, "Checking the feld"' "a section of the docs that is not there"
fresh; printf '// Its words (docs/fields.md).\n' >>"$work/tree/acquisition/src/field/field_check.cpp"
expect "docs/fields.md: there is no such file" "a docs file that is not there"
exit $failures
