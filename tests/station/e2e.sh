#!/usr/bin/env bash
# End to end under Xvfb (Mesa llvmpipe): the station with simulated devices captures a whole
# leaf; the session must be complete in the database, the preview must have drawn geometry
# (triangles and non-background pixels), and screenshots are kept for people to look at. Then
# the station digitizes the sample plant where it stands (the plant capture view).
# Usage: e2e.sh STATION_BINARY OUTPUT_DIR
set -euo pipefail
station=$1
out=$2
rm -rf "$out"
mkdir -p "$out"
# Mesa and fontconfig keep caches for the process lifetime; not leafdig's leaks. ASan returning
# freed pages to the system (madvise page by page) made Mesa's cache thread take minutes to end
# at exit on a loaded machine: keep them.
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0:allocator_release_to_os_interval_ms=-1"
report=$(timeout 300 xvfb-run -a -s "-screen 0 ${LEAFDIG_E2E_SCREEN:-1366x768}x24" "$station" --simulate --speed 10 --seed 2 \
  --db "$out/station.sqlite" --settings "$out/station.ini" --screenshot "$out/capture.png" \
  --review-screenshot "$out/review.png" --quit-when-complete 2>"$out/stderr.txt")
echo "$report"
line=$(echo "$report" | grep '^complete session ') || { echo "no completion line"; cat "$out/stderr.txt"; exit 1; }
triangles=$(echo "$line" | awk '{print $5}')
pixels=$(echo "$line" | awk '{print $7}')
[ "$triangles" -gt 1000 ] || { echo "preview drew only $triangles triangles"; exit 1; }
[ "$pixels" -gt 2000 ] || { echo "preview is blank ($pixels pixels differ from the background)"; exit 1; }
[ -s "$out/capture.png" ] || { echo "no screenshot"; exit 1; }
[ -s "$out/review.png" ] || { echo "no review screenshot"; exit 1; }
# The review shows the blade area with its 95 % interval (issue 16).
echo "$report" | grep -q '^review metrics: Blade area [0-9]' || { echo "no blade area in the review"; exit 1; }
echo "$report" | grep -q '^review metrics: 95 % interval [0-9]* – [0-9]* mm²' ||
  { echo "no area interval in the review"; exit 1; }
python3 - "$out/station.sqlite" <<'PY'
import sqlite3, sys
db = sqlite3.connect(f"file:{sys.argv[1]}?mode=ro", uri=True)
status, = db.execute("SELECT status FROM sessions WHERE id=1").fetchone()
markers, = db.execute("SELECT count(*) FROM markers WHERE session_id=1").fetchone()
readings, = db.execute("SELECT count(*) FROM thickness_readings WHERE session_id=1").fetchone()
assert status == "complete", status
assert markers == 71, markers
assert readings == 21, readings
print("station e2e: session complete,", markers, "markers,", readings, "readings")
PY
# A plant digitized where it stands, in the station (the plant capture view): the sample plant
# by the virtual technician, the window saved while node 2's full leaf is taken.
src=$(cd "$(dirname "$0")/../.." && pwd)
report=$(timeout 300 xvfb-run -a -s "-screen 0 ${LEAFDIG_E2E_SCREEN:-1366x768}x24" "$station" --simulate --speed 40 \
  --no-audio --db "$out/plant.sqlite" --settings "$out/station.ini" \
  --plant-markers "$src/data/plants/sample.plant-markers.json" --screenshot "$out/plant-capture.png" \
  --screenshot-when "Node 2 · leaf · Row 9" --quit-when-complete 2>"$out/plant-stderr.txt")
echo "$report"
echo "$report" | grep -q '^plant screenshot at "Node 2 · leaf · Row 9" saved' ||
  { echo "no plant capture screenshot"; cat "$out/plant-stderr.txt"; exit 1; }
line=$(echo "$report" | grep '^plant complete session ') || { echo "no plant completion line"; exit 1; }
set -- $line
# plant complete session ID nodes N leaves L preview_triangles T
[ "$6" = 5 ] && [ "$8" = 3 ] || { echo "the plant is not the sample's 5 nodes and 3 leaves: $line"; exit 1; }
[ "${10}" -gt 1000 ] || { echo "the plant preview drew only ${10} triangles"; exit 1; }
[ -s "$out/plant-capture.png" ] || { echo "no plant capture screenshot file"; exit 1; }
python3 - "$out/plant.sqlite" <<'PY'
import sqlite3, sys
db = sqlite3.connect(f"file:{sys.argv[1]}?mode=ro", uri=True)
kind, status = db.execute("SELECT kind, status FROM sessions WHERE id=1").fetchone()
assert (kind, status) == ("plant", "complete"), (kind, status)
print("station e2e: plant session complete")
PY
# The Field tab: a check of the simulated steel bench's field with the sample jig, the window saved
# with its verdict and error map once every divot is taken (issue 50).
report=$(timeout 300 xvfb-run -a -s "-screen 0 ${LEAFDIG_E2E_SCREEN:-1366x768}x24" "$station" --simulate --speed 20 \
  --no-audio --db "$out/field.sqlite" --settings "$out/station.ini" --distortion "$src/data/fields/steel-bench.field.json" \
  --check-field --screenshot "$out/field-check.png" --quit-when-complete 2>"$out/field-stderr.txt")
echo "$report"
echo "$report" | grep -q '^field check done map_arrows 44$' || { echo "no field check with its map"; cat "$out/field-stderr.txt"; exit 1; }
echo "$report" | grep -q '^field:   verdict: correctable' || { echo "the bent field is not correctable"; exit 1; }
[ -s "$out/field-check.png" ] || { echo "no field check screenshot"; exit 1; }
python3 - "$out/field.sqlite" <<'PY'
import sqlite3, sys
db = sqlite3.connect(f"file:{sys.argv[1]}?mode=ro", uri=True)
rows = db.execute("SELECT verdict FROM field_checks").fetchall()
assert rows == [("correctable",)], rows
print("station e2e: the field checked and stored")
PY
