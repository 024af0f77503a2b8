#!/usr/bin/env bash
# The Debian package as a user gets it: `cpack -G DEB` in a build directory; then its control
# data (name, version, the libraries it depends on), its files (programs, udev rule, desktop
# entry and icon, sample leaves, schemas, documents), the desktop entry through
# desktop-file-validate, and the unpacked programs run.
# Usage: check-deb.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
fail() { echo "check-deb: $*" >&2; exit 1; }
(cd "$build" && cpack -G DEB -B "$work" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack failed"; }
deb=$(ls "$work"/leafdig_*_amd64.deb 2>/dev/null | head -1)
[ -n "$deb" ] || fail "no leafdig_<version>_amd64.deb in $work"
[ "$(dpkg-deb -f "$deb" Package)" = leafdig ] || fail "package name"
[ "$(dpkg-deb -f "$deb" Architecture)" = amd64 ] || fail "architecture"
depends=$(dpkg-deb -f "$deb" Depends)
echo "$depends" | grep -q "python3-numpy" || fail "Depends lacks python3-numpy (import leafdig): $depends"
for lib in libqt6widgets6 libqt6opengl6 libqt6charts6 libqt6multimedia6 libserialport0 libhidapi libusb-1.0-0 libsqlite3-0 libssl3 \
           libcpp-httplib0.11; do
  echo "$depends" | grep -q "$lib" || fail "Depends lacks $lib: $depends"
done
dpkg-deb -c "$deb" | awk '{print $6}' >"$work/contents.txt"
for f in ./usr/bin/leafdig ./usr/bin/leafdig-station ./usr/lib/udev/rules.d/70-leafdig.rules \
         ./usr/share/applications/leafdig-station.desktop ./usr/share/icons/hicolor/scalable/apps/leafdig.svg \
         ./usr/share/leafdig/samples/lower-leaf-n10.markers.json \
         ./usr/share/leafdig/schema/leafdig.markers-1.schema.json ./usr/share/doc/leafdig/README.md \
         ./usr/share/leafdig/protocols/tobacco.plant-protocol.json ./usr/share/leafdig/protocols/maize.plant-protocol.json \
         ./usr/share/leafdig/plants/sample.plant-markers.json ./usr/share/doc/leafdig/plants.md ./usr/share/doc/leafdig/web.md \
         ./usr/share/leafdig/fields/steel-bench.field.json ./usr/share/leafdig/fields/three-level.jig.json \
         ./usr/share/doc/leafdig/schema.md ./usr/lib/python3/dist-packages/leafdig/__init__.py \
         ./usr/lib/python3/dist-packages/leafdig/_leafdig.cpython-311-x86_64-linux-gnu.so; do
  grep -qx "$f" "$work/contents.txt" || fail "the package lacks $f"
done
dpkg-deb -e "$deb" "$work/control"
[ -x "$work/control/postinst" ] || fail "no postinst (udev reload)"
dpkg-deb -x "$deb" "$work/root"
desktop-file-validate "$work/root/usr/share/applications/leafdig-station.desktop" >"$work/desktop.txt" 2>&1 ||
  fail "desktop entry invalid: $(cat "$work/desktop.txt")"
# Hints too (two main categories put the station in the menu twice).
[ ! -s "$work/desktop.txt" ] || fail "desktop-file-validate: $(cat "$work/desktop.txt")"
# Stripped programs that run, and build a leaf from the installed sample.
file "$work/root/usr/bin/leafdig" 2>/dev/null | grep -q "not stripped" && fail "leafdig is not stripped"
"$work/root/usr/bin/leafdig" --version | grep -q "$(dpkg-deb -f "$deb" Version)" || fail "leafdig --version"
"$work/root/usr/bin/leafdig" model build "$work/root/usr/share/leafdig/samples/lower-leaf-n10.markers.json" \
  -o "$work/leaf.glb" >/dev/null || fail "the installed leafdig cannot build the installed sample"
[ -s "$work/leaf.glb" ] || fail "no GLB written"
# The installed plant protocols read, and the installed sample plant measures.
for p in "$work"/root/usr/share/leafdig/protocols/*.plant-protocol.json; do
  "$work/root/usr/bin/leafdig" plant protocol "$p" >/dev/null || fail "the installed leafdig refuses $(basename "$p")"
done
"$work/root/usr/bin/leafdig" plant measure "$work/root/usr/share/leafdig/plants/sample.plant-markers.json" \
  --mtg "$work/plant.mtg" >/dev/null || fail "the installed leafdig cannot measure the installed sample plant"
[ -s "$work/plant.mtg" ] || fail "no MTG written"
# The installed leafdig checks a simulated field against the installed jig (its default).
"$work/root/usr/bin/leafdig" field check --simulate --speed 20 --json --db "$work/field.sqlite" </dev/null |
  tail -1 | grep -q '"verdict":"pass"' || fail "the installed leafdig cannot check a field against its jig"
QT_QPA_PLATFORM=offscreen "$work/root/usr/bin/leafdig-station" --version >/dev/null 2>&1 || fail "leafdig-station --version"
# The installed Python module imports with the system Python and builds the installed sample.
PYTHONPATH="$work/root/usr/lib/python3/dist-packages" /usr/bin/python3 -c "
import leafdig, sys
assert leafdig.__version__ == sys.argv[1], leafdig.__version__
leaf = leafdig.build_leaf(sys.argv[2])
assert leaf.metrics['blade_area_mm2'] > 0
" "$(dpkg-deb -f "$deb" Version)" "$work/root/usr/share/leafdig/samples/lower-leaf-n10.markers.json" ||
  fail "the installed Python module does not import or build the installed sample"
echo "check-deb: $(basename "$deb") ($(du -k "$deb" | cut -f1) KiB): control, files, desktop entry programs and the Python module OK"
