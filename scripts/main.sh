#!/usr/bin/env bash
# The main job on embedded defaults: set up and build, then build the three sample
# leaves of data/samples/ and write their exports (GLB, OBJ, PLY, STL, model JSON) to
# out/, printing what was written and each leaf's metrics.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh" release
leafdig="$root/build/release/ui/cli/leafdig"
out="$root/out"
mkdir -p "$out"
for markers in "$root"/data/samples/*.markers.json; do
  name=$(basename "$markers" .markers.json)
  echo
  "$leafdig" model build "$markers" --resolution export \
    -o "$out/$name.glb" -o "$out/$name.obj" -o "$out/$name.ply" -o "$out/$name.stl" \
    --model-json "$out/$name.model.json"
done
echo
echo "Exports of the three sample leaves are in $out/"
