#!/usr/bin/env bash
# Architecture rules as a check (docs/architecture.md):
#  1. Qt headers only under ui/.
#  2. Dependencies point one way: ui -> acquisition -> {devices, db, model}; db may use
#     model; devices and model use no other leafdig module but names, which every module
#     may use and which uses none.
# Usage: check-layering.sh [REPO_ROOT]
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root" || exit 2
fail=0
sources() { find "$@" -type f \( -name '*.h' -o -name '*.hpp' -o -name '*.cpp' -o -name '*.cc' \) 2>/dev/null; }

qt=$(sources model devices db acquisition | xargs -r grep -lE '#\s*include\s*[<"](Q[A-Za-z]+|Qt[A-Za-z]*/)' || true)
if [ -n "$qt" ]; then
  echo "Qt header outside ui/:"; echo "$qt"; fail=1
fi

# 3. OpenCV only in model/src/leaf2d/leaf_scan.cpp (behind leaf_scan.hpp; heavy to compile).
cv=$(sources model devices db acquisition ui tests | grep -v '^model/src/leaf2d/leaf_scan.cpp$' | xargs -r grep -lE '#\s*include\s*[<"]opencv2/' || true)
if [ -n "$cv" ]; then
  echo "OpenCV header outside model/src/leaf2d/leaf_scan.cpp:"; echo "$cv"; fail=1
fi

# 4. libpq only in db/src/pg.hpp (the lab server's thin client layer) and the tests' own
#    PostgreSQL helper.
pq=$(sources model devices db acquisition ui tests | grep -v -e '^db/src/pg.hpp$' -e '^tests/support/pg_cluster.hpp$' | xargs -r grep -lE '#\s*include\s*[<"]libpq-fe.h' || true)
if [ -n "$pq" ]; then
  echo "libpq header outside db/src/pg.hpp:"; echo "$pq"; fail=1
fi

# 5. pybind11 only in python/leafdig_module.cpp (the one translation unit of the Python module).
py=$(sources model devices db acquisition ui tests python | grep -v '^python/leafdig_module.cpp$' | xargs -r grep -lE '#\s*include\s*[<"]pybind11/' || true)
if [ -n "$py" ]; then
  echo "pybind11 outside python/leafdig_module.cpp:"; echo "$py"; fail=1
fi

# 5b. cpp-httplib only in ui/cli/web/http.cpp (the web review's one HTTP translation unit) and
#     the web test and the lab benchmark that drive it as a client.
hl=$(sources model devices db acquisition ui tests python | grep -v -e '^ui/cli/web/http.cpp$' -e '^tests/cli/web_cli_test.cpp$' -e '^tests/bench/lab_bench.cpp$' | xargs -r grep -lE '#\s*include\s*[<"]httplib.h' || true)
if [ -n "$hl" ]; then
  echo "cpp-httplib outside ui/cli/web/http.cpp:"; echo "$hl"; fail=1
fi

check() {  # module, forbidden modules...
  local module=$1; shift
  for other in "$@"; do
    hits=$(sources "$module" | xargs -r grep -lE "#\s*include\s*[<\"]leafdig/$other/" || true)
    if [ -n "$hits" ]; then
      echo "$module/ must not include leafdig/$other/ (dependencies point ui -> acquisition -> {devices, db, model}):"
      echo "$hits"; fail=1
    fi
  done
}
check names model devices db acquisition ui
check model devices db acquisition ui
check devices model db acquisition ui
check db devices acquisition ui
check acquisition ui

# 5. Rooms inside devices/ (devices/README.md): codecs and transports use only the root;
#    links and sim use codecs and transports, never each other. A room is its header folder
#    and its source folder; a source includes another room's private header as "room/x.hpp".
roomCheck() {  # module, room, forbidden rooms...
  local module=$1 room=$2; shift 2
  for other in "$@"; do
    hits=$(sources "$module/include/leafdig/$module/$room" "$module/src/$room" |
      xargs -r grep -lE "#\s*include\s*[<\"](leafdig/$module/)?$other/" || true)
    if [ -n "$hits" ]; then
      echo "$module/$room must not include $module/$other ($module/README.md: the rooms and their directions):"
      echo "$hits"; fail=1
    fi
  done
}
roomCheck devices codecs transports links sim
roomCheck devices transports codecs links sim
roomCheck devices links sim
roomCheck devices sim links
# The root of a module with rooms uses no room.
rootCheck() {  # module, what its root holds, rooms...
  local module=$1 what=$2; shift 2
  local rooms; rooms=$(IFS='|'; echo "$*")
  local hits
  hits=$(find "$module/include/leafdig/$module" "$module/src" -maxdepth 1 -type f \( -name '*.hpp' -o -name '*.cpp' \) |
    xargs -r grep -lE "#\s*include\s*[<\"](leafdig/$module/)?($rooms)/" || true)
  if [ -n "$hits" ]; then
    echo "the root of $module/ ($what) must not include a room:"; echo "$hits"; fail=1
  fi
}
rootCheck devices "errors, samples" codecs transports links sim

# 6. Rooms inside model/ (model/README.md), each using only the rooms before it:
#    field, spline, leaf, mesh, metrics, then synth, leaf2d and plant (never each other), then
#    archive (the archives' plants, read into plants), then io and study (never each other).
roomCheck model field spline leaf mesh metrics synth leaf2d plant archive io study
roomCheck model spline leaf mesh metrics synth leaf2d plant archive io study
roomCheck model leaf mesh metrics synth leaf2d plant archive io study
roomCheck model mesh metrics synth leaf2d plant archive io study
roomCheck model metrics synth leaf2d plant archive io study
roomCheck model synth leaf2d plant archive io study
roomCheck model leaf2d synth plant archive io study
roomCheck model plant synth leaf2d archive io study
roomCheck model archive io study
roomCheck model io study
roomCheck model study io
rootCheck model "errors, limits, files, image headers, JSON text" field spline leaf mesh metrics synth leaf2d plant archive io study

# 7. Rooms inside acquisition/ (acquisition/README.md): protocol, then session, then review; live
#    after session, sim after live, run after sim; review never uses live, sim or run, and they
#    never use review; field (the field check and what a capture applies of it) uses only
#    protocol, and every room after it may use it. The root holds nothing.
roomCheck acquisition protocol field session review live sim run
roomCheck acquisition field session review live sim run
roomCheck acquisition session review live sim run
roomCheck acquisition review live sim run
roomCheck acquisition live review sim run
roomCheck acquisition sim review run
roomCheck acquisition run review
rootCheck acquisition "nothing" protocol session review live sim run field

# 8. Sizes and cycles (issue 48): in the product's code (names, model, devices, db, acquisition,
#    ui, python; tests excepted) no source file over 700 lines, no folder over 14 sources
#    (.cpp), and no include cycle between files of a module (a file is its .hpp and .cpp
#    together: x.cpp including y.hpp while y.cpp includes x.hpp is a cycle).
if ! python3 "$here/check_sizes_cycles.py" .; then fail=1; fi
[ $fail -eq 0 ] && echo "layering ok: Qt only in ui/, OpenCV only in leaf_scan.cpp, libpq only in db/src/pg.hpp, cpp-httplib only in ui/cli/web/http.cpp, pybind11 only in python/leafdig_module.cpp, dependencies point one way, devices/, model/ and acquisition/ rooms in their directions, no file over 700 lines, no folder over 14 sources, no include cycle in a module"
exit $fail
