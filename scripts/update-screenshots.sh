#!/usr/bin/env bash
# Regenerates the README's screenshots (docs/station-capture.png, docs/station-review.png,
# docs/station-plant.png) with the station itself under Xvfb at 1366 × 768, the smallest
# screen the station is laid out for: the end-to-end test's simulated capture and review,
# then the Plant view on the sample plan with that capture approved in its library. Needs
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
echo "update-screenshots: docs/station-capture.png, docs/station-review.png and docs/station-plant.png regenerated"
