#!/usr/bin/env bash
# The main job on embedded defaults: set up and build; with a display, open the Qt station
# with simulated devices (a virtual technician captures a leaf while you watch); then
# `leafdig demo`: a simulated
# FASTRAK and Sylvac caliper on pseudo-terminals, a virtual technician capturing the three
# sample leaves and two synthetic leaves of known area into out/demo/demo.sqlite, each leaf
# exported to out/demo/, a summary with each leaf's area against the known one; then the sample
# plant digitized where it stands, node by node, exported as an MTG, a CSV and its survey.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# Only what the main job needs is installed and built (preset `main`: leafdig and
# leafdig-station; the tests, benchmarks and the Python module are the test command's).
"$root/scripts/setup.sh" main
leafdig="$root/build/main/ui/cli/leafdig"
out="$root/out"
mkdir -p "$out/demo"
# A fresh demo database each run (the previous one is kept as demo.sqlite.previous).
if [ -e "$out/demo/demo.sqlite" ]; then
  mv -f "$out/demo/demo.sqlite" "$out/demo/demo.sqlite.previous"
  rm -f "$out/demo/demo.sqlite-wal" "$out/demo/demo.sqlite-shm"
fi
# With a display, the Qt station with simulated devices (close the window to go on);
# without one, the same capture headless.
if [ -n "${DISPLAY:-}" ] && [ -x "$root/build/main/ui/station/leafdig-station" ]; then
  "$root/build/main/ui/station/leafdig-station" --simulate --speed 2 --db "$out/demo/station.sqlite" || true
fi
"$leafdig" demo --out "$out/demo" --samples "$root/data/samples"
echo
"$leafdig" sessions list --db "$out/demo/demo.sqlite"

# The geometry core on its own: the sample leaves' marker files straight to exports.
for markers in "$root"/data/samples/*.markers.json; do
  name=$(basename "$markers" .markers.json)
  "$leafdig" model build "$markers" --resolution export -o "$out/$name.glb" -o "$out/$name.obj" \
    --model-json "$out/$name.model.json" >/dev/null
done
echo "Model exports of the sample marker files are in $out/; the demo's captures in $out/demo/"
