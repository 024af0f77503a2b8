#!/usr/bin/env bash
# Installs the Debian package on a clean Debian 12 (a minimal bookworm made by debootstrap
# in a temporary directory) with `apt install ./leafdig_*.deb`, which must pull every
# dependency by itself; then runs `leafdig doctor --json` there (the udev rule must be
# reported installed), builds a leaf from the installed sample, renders and segments a scan
# and builds its 2-D leaf (OpenCV), and starts the station off-screen. Needs root and
# Debian's mirror; takes a few minutes, so it is not part of the test command
# (docs/packaging.md has its last result).
# Usage: scripts/check-package-on-clean-debian.sh PATH/leafdig_<version>_amd64.deb
set -euo pipefail
deb=$(readlink -f "$1")
[ "$(id -u)" -eq 0 ] || { echo "run as root (debootstrap and chroot)"; exit 2; }
command -v debootstrap >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null
root=$(mktemp -d /tmp/leafdig-clean-XXXXXX)
trap 'umount "$root/proc" 2>/dev/null || true; rm -rf "$root"' EXIT
mirror=http://deb.debian.org/debian
debootstrap --variant=minbase bookworm "$root" "$mirror" >"$root.log" 2>&1 || { tail -20 "$root.log"; exit 1; }
mount -t proc proc "$root/proc"
cp "$deb" "$root/tmp/"
run() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root DEBIAN_FRONTEND=noninteractive "$@"; }
run apt-get update -qq
run apt-get install -y -qq "/tmp/$(basename "$deb")" >"$root/tmp/install.log" 2>&1 || { tail -30 "$root/tmp/install.log"; exit 1; }
echo "installed with its dependencies: $(grep -c '^Setting up' "$root/tmp/install.log") packages set up"
run leafdig --version
run leafdig doctor --json >"$root/tmp/doctor.json" || true
grep -q '"udev rule"' "$root/tmp/doctor.json" || { cat "$root/tmp/doctor.json"; echo "doctor does not report the udev rule"; exit 1; }
python3 - "$root/tmp/doctor.json" <<'PY'
import json, sys
checks = json.load(open(sys.argv[1]))
rule = [c for c in checks if c.get("check") == "udev rule"]
assert rule and rule[0].get("ok") is True, rule
print("doctor: udev rule:", rule[0]["detail"])
PY
run leafdig model build /usr/share/leafdig/samples/lower-leaf-n10.markers.json -o /tmp/leaf.glb --json >/dev/null
echo "leafdig model build: $(stat -c %s "$root/tmp/leaf.glb") bytes of GLB from the installed sample"
run leafdig synth scan --shape ovate --length 150 --petiole-length 30 -o /tmp/scan.png --truth /tmp/scan.truth.json
run leafdig leaf2d build /tmp/scan.png --dpi 300 -o /tmp/leaf2d.glb >"$root/tmp/leaf2d.txt"
grep -q "area constraint" "$root/tmp/leaf2d.txt" || { cat "$root/tmp/leaf2d.txt"; echo "leaf2d build failed"; exit 1; }
echo "leafdig leaf2d build: a scan rendered and segmented (OpenCV), $(stat -c %s "$root/tmp/leaf2d.glb") bytes of GLB"
run env QT_QPA_PLATFORM=offscreen leafdig-station --version
echo "clean Debian 12: the package installs, doctor reports the udev rule, both programs run"
