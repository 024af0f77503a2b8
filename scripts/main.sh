#!/usr/bin/env bash
# The main job on embedded defaults: set up and build, then build the three sample
# leaves of data/samples/ and write their exports (GLB, OBJ, PLY, STL, model JSON) to
# out/, printing what was written and each leaf's metrics; then a simulated FASTRAK on a
# pseudo-terminal and the driver listening to it.
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

# The devices on embedded defaults: a simulated FASTRAK walks the first sample leaf; the
# driver connects over a pseudo-terminal and prints what the stylus reports.
echo
echo "A simulated FASTRAK (pseudo-terminal) and the driver listening to it:"
link="$out/fastrak-sim-port"
"$leafdig" sim fastrak --markers "$root/data/samples/lower-leaf-n10.markers.json" --link "$link" --seconds 4 \
  >/dev/null 2>"$out/fastrak-sim.log" &
for _ in $(seq 100); do [ -e "$link" ] && break; sleep 0.05; done
"$leafdig" devices listen --digitizer fastrak --port "$link" --seconds 2 | awk 'NR % 24 == 1'
wait
