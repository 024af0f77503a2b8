#!/usr/bin/env bash
# Regenerates the README's screenshots (docs/station-capture.png, docs/station-review.png)
# with the station's own end-to-end test: a simulated capture under Xvfb at 1366 × 768, the
# smallest screen the station is laid out for. Needs the `ci` build (./scripts/setup.sh ci).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=$(mktemp -d)
LEAFDIG_E2E_SCREEN=1366x768 "$root/tests/station/e2e.sh" "$root/build/ci/ui/station/leafdig-station" "$out"
cp "$out/capture.png" "$root/docs/station-capture.png"
cp "$out/review.png" "$root/docs/station-review.png"
rm -rf "$out"
echo "update-screenshots: docs/station-capture.png and docs/station-review.png regenerated"
