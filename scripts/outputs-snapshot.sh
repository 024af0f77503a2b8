#!/usr/bin/env bash
# Every output the main jobs write, for a before/after comparison of a change that must not
# change behaviour (issue 27): `model build` of each sample leaf to every format and its
# --json, `mesh study --json` with its meshes, `plant build` of the sample plan to every
# format and its --json, and `synth leaf`. Timings (keys "milliseconds", "ms" and "*_ms")
# are taken out of the JSON; everything else is compared byte for byte.
# With DEMO_DB (a `leafdig demo --out` database), every session in it is exported too: the
# demo's own capture depends on timing, so both binaries export the same recorded sessions.
# Usage: scripts/outputs-snapshot.sh LEAFDIG_BINARY OUT_DIR [DEMO_DB]; then diff -r two OUT_DIRs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=$1 out=$2 demo=${3:-}
rm -rf "$out"; mkdir -p "$out"
untimed() {  # JSON on stdin without timing keys, sorted, to stdout
  python3 -c '
import json, sys
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items()
                if not (k in ("milliseconds", "ms", "seconds") or k.endswith("_ms"))}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v
print(json.dumps(strip(json.load(sys.stdin)), indent=1, sort_keys=True))'
}
for m in "$root"/data/samples/*.markers.json; do
  n=$(basename "$m" .markers.json)
  "$bin" model build "$m" -o "$out/$n.glb" -o "$out/$n.obj" -o "$out/$n.ply" -o "$out/$n.stl" \
    --model-json "$out/$n.model.json" --json | untimed >"$out/$n.build.json"
  "$bin" model build "$m" --frame leaf --blade nurbs --mesh adaptive --max-error 0.1 \
    -o "$out/$n.leaf-frame.glb" --json | untimed >"$out/$n.leaf-frame.json"
done
"$bin" mesh study "$root/data/samples/upper-small-leaf-n17.markers.json" --max-error 0.1 \
  --out "$out/study" --json | untimed >"$out/study.json"
plan="$root/data/plants/tobacco-p07.plant.json"
"$bin" plant build "$plan" -o "$out/plant.glb" -o "$out/plant.obj" -o "$out/plant.can" \
  -o "$out/plant.mtg" -o "$out/plant.csv" -o "$out/plant.json" --json | untimed >"$out/plant.build.json"
"$bin" synth leaf --shape obovate --serration straight --noise 0.3 --seed 4 \
  --markers "$out/synth.markers.json" --truth "$out/synth.truth.json" --json | untimed >"$out/synth.json"
if [ -n "$demo" ]; then
  cp "$demo" "$out/demo.sqlite.tmp"
  for id in $(python3 -c 'import sqlite3, sys
for (i,) in sqlite3.connect(sys.argv[1]).execute("SELECT id FROM sessions ORDER BY id"): print(i)' "$demo"); do
    "$bin" sessions export "$id" --db "$out/demo.sqlite.tmp" --out "$out/demo-$id" --json | untimed >"$out/demo-$id.json"
  done
  rm -f "$out"/demo.sqlite.tmp*
fi
# Paths of this run's folder and of the checkout appear in some JSON ("outputs", "plan"):
# make them relative, so two checkouts compare equal.
sed -i -e "s#$out/##g" -e "s#$root/##g" "$out"/*.json
echo "outputs-snapshot: $(find "$out" -type f | wc -l) files in $out"
