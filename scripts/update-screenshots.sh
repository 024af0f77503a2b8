#!/usr/bin/env bash
# Regenerates the README's screenshots (docs/station-capture.png, docs/station-review.png,
# docs/station-plant.png) with the station itself under Xvfb at 1366 × 768, the smallest
# screen the station is laid out for: the end-to-end test's simulated capture and review,
# then the Plant view on the sample plan with that capture approved in its library, and on
# the sample plant captured where it stands (docs/station-plant-captured.png); a plant digitized
# in the station's plant capture view (docs/station-plant-capture.png). Needs
# the `ci` build (./scripts/setup.sh ci).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
station="$root/build/ci/ui/station/leafdig-station"
leafdig="$root/build/ci/ui/cli/leafdig"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
LEAFDIG_E2E_SCREEN=1366x768 "$root/tests/station/e2e.sh" "$station" "$out"
cp "$out/capture.png" "$root/docs/station-capture.png"
cp "$out/review.png" "$root/docs/station-review.png"
"$leafdig" sessions approve 1 --db "$out/station.sqlite" --who curator >/dev/null
(cd "$root" && timeout 120 xvfb-run -a -s "-screen 0 1366x768x24" "$station" --no-audio \
  --db "$out/station.sqlite" --settings "$out/station.ini" --plant data/plants/tobacco-p07.plant.json \
  --plant-screenshot "$out/plant.png")
[ -s "$out/plant.png" ] || { echo "update-screenshots: no Plant view screenshot"; exit 1; }
cp "$out/plant.png" "$root/docs/station-plant.png"
# A plant captured where it stands (the sample plant by the virtual technician), its quick
# leaves shaped from the approved capture, opened in the Plant view with its divergences.
"$leafdig" plant capture --simulate --db "$out/station.sqlite" --speed 40 --json >"$out/plant-capture.jsonl"
session=$(head -1 "$out/plant-capture.jsonl" | python3 -c 'import json, sys; print(json.load(sys.stdin)["session"])')
(cd "$root" && timeout 120 xvfb-run -a -s "-screen 0 1366x768x24" "$station" --no-audio \
  --db "$out/station.sqlite" --settings "$out/station.ini" --plant-session "$session" \
  --plant-screenshot "$out/plant-captured.png")
[ -s "$out/plant-captured.png" ] || { echo "update-screenshots: no captured plant screenshot"; exit 1; }
cp "$out/plant-captured.png" "$root/docs/station-plant-captured.png"
# The plant capture view: a synthetic plant of 8 nodes digitized by the virtual technician in
# the station, saved while node 6's full leaf is taken.
"$leafdig" synth plant --markers "$out/p8.plant-markers.json" --truth "$out/p8.truth.json" --nodes 8 --seed 4 >/dev/null
(cd "$root" && timeout 300 xvfb-run -a -s "-screen 0 1366x768x24" "$station" --simulate --speed 40 --no-audio \
  --db "$out/plant-capture.sqlite" --settings "$out/station.ini" --plant-markers "$out/p8.plant-markers.json" \
  --screenshot "$out/plant-capture.png" --screenshot-when "Node 6 · leaf · Row 7" --quit-when-complete)
[ -s "$out/plant-capture.png" ] || { echo "update-screenshots: no plant capture screenshot"; exit 1; }
cp "$out/plant-capture.png" "$root/docs/station-plant-capture.png"
echo "update-screenshots: docs/station-capture.png, docs/station-review.png, docs/station-plant.png," \
  "docs/station-plant-captured.png and docs/station-plant-capture.png regenerated"
# The web review in headless Chromium, as its browser test leaves them (the login, a curator's
# list, a leaf after its approval, a plant; a technician's list of its own station).
(cd "$root/build/ci" && ./tests/leafdig_lab_cli_tests --gtest_filter=WebCli.ACuratorAndATechnicianInHeadlessChromium >/dev/null)
for page in login sessions leaf plant technician; do cp "$root/build/ci/web-screenshots/web-$page.png" "$root/docs/web-$page.png"; done
