#!/usr/bin/env bash
# Installs what leafdig needs on Debian 12 (only what is missing), then configures and
# builds one preset. Usage: scripts/setup.sh [PRESET]   (default: release; `main`: only what the
# main job needs). LEAFDIG_BUILD_TARGETS="a b …" builds only those targets of the preset.
#
# Debian packages: build tools (cmake, ninja-build, g++, ccache), libraries (libeigen3-dev,
# nlohmann-json3-dev, libcli11-dev, libtinygltf-dev, libgtest-dev, libgmock-dev,
# libbenchmark-dev, libsqlite3-dev, libsqlitecpp-dev, libssl-dev, libserialport-dev,
# libhidapi-dev, libusb-1.0-0-dev, and for meshing libcgal-dev (constrained Delaunay),
# libmeshoptimizer-dev (the meshing study's peer simplifier), libassimp-dev (reading meshes
# to compare), libopencv-dev (segmenting leaf scans, model/src/leaf2d/leaf_scan.cpp only), libpq-dev
# (the lab's PostgreSQL server, db/src/pg.cpp only), libcpp-httplib-dev (the web review's HTTP,
# ui/cli/web/http.cpp only: docs/decisions.md says why this library)), postgresql (the server the lab tests
# start in a temporary directory; its packaged cluster is not used) with openssl (their TLS
# certificate),
# clang + libclang-rt-14-dev (libFuzzer targets), clang-format-14 (the format check), Qt 6 for the station (qt6-base-dev,
# qt6-multimedia-dev for the sound cues, qt6-charts-dev for the review plots,
# libqt6opengl6-dev, libgl-dev) with Mesa's software OpenGL and Xvfb for its tests
# (libgl1-mesa-dri, xvfb, xauth, fonts-dejavu-core), checkers used by the tests (assimp-utils,
# nodejs, npm, python3 with its sqlite3 module: reads the station's database as another tool would),
# `import leafdig` (python/, docs/python.md): pybind11-dev, python3-dev, python3-numpy and
# python3-pytest and python3-matplotlib (docs/python.md's figure) for its tests; and for the Debian package: dpkg-dev (cpack's dpkg-shlibdeps), desktop-file-utils, file; chromium (the web review's
# browser test, headless). npm: the Khronos glTF validator, Ajv (JSON Schema) and puppeteer-core
# (drives Debian's chromium; it downloads no browser), pinned by tests/tools/package-lock.json.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
preset=${1:-release}

# The main job (preset `main`: leafdig and leafdig-station) needs only these: build tools, the
# libraries its programs link, Qt for the station.
packages=(cmake ninja-build g++ ccache pkg-config libeigen3-dev nlohmann-json3-dev libcli11-dev
          libtinygltf-dev libsqlite3-dev libserialport-dev libhidapi-dev libusb-1.0-0-dev
          libsqlitecpp-dev libssl-dev libcgal-dev libmeshoptimizer-dev libassimp-dev libopencv-dev libpq-dev
          libcpp-httplib-dev
          qt6-base-dev libqt6opengl6-dev qt6-multimedia-dev qt6-charts-dev libgl-dev libgl1-mesa-dri)
# Every other preset builds the tests, benchmarks, fuzzers or the Python module, and the tests
# run checkers, a PostgreSQL server, Xvfb and the Debian package's tools.
if [ "$preset" != main ]; then
  packages+=(libgtest-dev libgmock-dev libbenchmark-dev assimp-utils clang libclang-rt-14-dev clang-format-14
             postgresql openssl xvfb xauth fonts-dejavu-core python3 dpkg-dev desktop-file-utils file
             pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib chromium)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js may come from Debian (nodejs + npm) or already be on the machine (the tests' checkers).
if [ "$preset" != main ] && { ! command -v node >/dev/null || ! command -v npm >/dev/null; }; then
  missing+=(nodejs npm)
fi
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=(); [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [ "$preset" != main ] &&
   { [ ! -d "$root/tests/tools/node_modules/gltf-validator" ] || [ ! -d "$root/tests/tools/node_modules/ajv" ] ||
     [ ! -d "$root/tests/tools/node_modules/puppeteer-core" ]; }; then
  echo "setup: installing the Khronos glTF validator, Ajv and puppeteer-core (npm)"
  (cd "$root/tests/tools" && npm ci --no-audit --no-fund --loglevel=error)
fi
# three.js for the web review's 3-D view (ui/cli/web/vendor, pinned by its package-lock.json),
# embedded in leafdig at build time. The main job serves no web review: its build goes without.
if [ "$preset" != main ] && [ ! -f "$root/ui/cli/web/vendor/node_modules/three/build/three.module.min.js" ]; then
  echo "setup: installing three.js for the web review (npm)"
  (cd "$root/ui/cli/web/vendor" && npm ci --no-audit --no-fund --loglevel=error)
fi

cd "$root"
cmake --preset "$preset" >/dev/null
targets=()
if [ -n "${LEAFDIG_BUILD_TARGETS:-}" ]; then
  read -ra named <<<"$LEAFDIG_BUILD_TARGETS"
  targets=(--target "${named[@]}")
fi
cmake --build --preset "$preset" -j"$(nproc)" "${targets[@]}"
