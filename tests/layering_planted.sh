#!/usr/bin/env bash
# The layering check must fail on a wrong include: plant one at a time in a copy of the tree
# and expect .ci/check-layering.sh to name the file (and to pass on the unplanted copy).
# Usage: layering_planted.sh REPO_ROOT
set -u
root=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fresh() {
  rm -rf "$work/tree"; mkdir -p "$work/tree"
  cp -r "$root"/{names,model,devices,db,acquisition,ui,python} "$work/tree/"
}
failures=0
fresh
if ! "$root/.ci/check-layering.sh" "$work/tree" >"$work/out" 2>&1; then
  echo "the unplanted copy should pass:"; cat "$work/out"; failures=1
fi
plant() {  # file, include line, what it breaks
  fresh
  printf '%s\n' "$2" >>"$work/tree/$1"
  if "$root/.ci/check-layering.sh" "$work/tree" >"$work/out" 2>&1; then
    echo "not caught: $3 ($2 in $1)"; failures=1
  elif ! grep -q "$1" "$work/out"; then
    echo "caught but not named: $3 ($1):"; cat "$work/out"; failures=1
  else
    echo "caught: $3"
  fi
}
plant devices/src/sim/faults.cpp '#include "leafdig/devices/links/links.hpp"' "sim using links"
plant devices/src/links/driver.cpp '#include "leafdig/devices/sim/sim.hpp"' "links using sim"
plant devices/src/codecs/fastrak.cpp '#include "transports/termios_speed.hpp"' "a codec using a transport's private header"
plant devices/include/leafdig/devices/transports/hid.hpp '#include "leafdig/devices/codecs/calipers.hpp"' "a transport using a codec"
plant devices/include/leafdig/devices/sample.hpp '#include "leafdig/devices/codecs/fastrak.hpp"' "the root using a room"
plant names/include/leafdig/names/name_table.hpp '#include "leafdig/model/errors.hpp"' "names using a module"
plant model/src/spline/banded.cpp '#include "leafdig/db/store.hpp"' "model using db"
plant devices/src/errors.cpp '#include "leafdig/acquisition/protocol/engine.hpp"' "devices using acquisition"
plant acquisition/src/protocol/engine.cpp '#include <QString>' "Qt outside ui/"
plant acquisition/src/protocol/plant_engine.cpp '#include "leafdig/acquisition/session/preview.hpp"' "the protocol using the session"
plant acquisition/src/review/review.cpp '#include "leafdig/acquisition/live/capture_loop.hpp"' "the review using the live loops"
plant acquisition/src/session/session.cpp '#include "review/review_checks.hpp"' "the session using the review's private header"
plant model/src/leaf/blade.cpp '#include <opencv2/core.hpp>' "OpenCV outside leaf_scan.cpp"
plant ui/cli/web/web_app.cpp '#include <httplib.h>' "cpp-httplib outside ui/cli/web/http.cpp"
plant model/src/leaf/leaf_model.cpp '#include "leafdig/model/mesh/mesh.hpp"' "the leaf model using meshes"
plant model/include/leafdig/model/synth/synthetic_leaf.hpp '#include "leafdig/model/plant/plant.hpp"' "synth using plant"
plant model/src/io/model_json.cpp '#include "leafdig/model/study/accuracy.hpp"' "io using study"
plant model/src/archive/mtg_archive.cpp '#include "leafdig/model/io/plant_export.hpp"' "archive using io"
plant model/src/metrics/metrics.cpp '#include "leaf2d/outline_check.hpp"' "metrics using leaf2d's private header"
plant model/include/leafdig/model/files.hpp '#include "leafdig/model/spline/bspline.hpp"' "model's root using a room"
# Sizes and cycles (part 8): a change the check must name by its words.
expect() {  # what it breaks, the words the check must print (after plantIn has changed the copy)
  if "$root/.ci/check-layering.sh" "$work/tree" >"$work/out" 2>&1; then
    echo "not caught: $1"; failures=1
  elif ! grep -qF "$2" "$work/out"; then
    echo "caught but not named: $1 (expected \"$2\"):"; cat "$work/out"; failures=1
  else
    echo "caught: $1"
  fi
}
fresh
printf '#include "model/mesh_cmd.hpp"\n' >>"$work/tree/ui/cli/model/model_build.cpp"
expect "an include cycle between two command files" "ui/cli/model/mesh_cmd, ui/cli/model/model_build include each other"
fresh
printf '#include "leafdig/acquisition/review/review.hpp"\n' >>"$work/tree/acquisition/src/review/plant_export.cpp"
printf '#include "leafdig/acquisition/review/plant_export.hpp"\n' >>"$work/tree/acquisition/src/review/review.cpp"
expect "an include cycle inside a room" "include cycle in acquisition/: acquisition/src/review/plant_export"
fresh
for i in $(seq 1 701); do echo "// line $i"; done >>"$work/tree/model/src/spline/banded.cpp"
expect "a source file over 700 lines" "model/src/spline/banded.cpp:"
fresh
for i in $(seq 1 15); do echo "// planted" >"$work/tree/ui/station/review/planted_$i.cpp"; done
expect "a folder over 14 sources" "ui/station/review/: "
exit $failures
