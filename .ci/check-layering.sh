#!/usr/bin/env bash
# Architecture rules as a check (docs/ARCHITECTURE.md):
#  1. Qt headers only under ui/.
#  2. Dependencies point one way: ui -> acquisition -> {devices, db, model}; db may use
#     model; devices and model use no other leafdig module.
# Usage: check-layering.sh [REPO_ROOT]
set -u
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root" || exit 2
fail=0
sources() { find "$@" -type f \( -name '*.h' -o -name '*.hpp' -o -name '*.cpp' -o -name '*.cc' \) 2>/dev/null; }

qt=$(sources model devices db acquisition | xargs -r grep -lE '#\s*include\s*[<"](Q[A-Za-z]+|Qt[A-Za-z]*/)' || true)
if [ -n "$qt" ]; then
  echo "Qt header outside ui/:"; echo "$qt"; fail=1
fi

# 3. OpenCV only in model/src/leaf_scan.cpp (behind leaf_scan.hpp; heavy to compile).
cv=$(sources model devices db acquisition ui tests | grep -v '^model/src/leaf_scan.cpp$' | xargs -r grep -lE '#\s*include\s*[<"]opencv2/' || true)
if [ -n "$cv" ]; then
  echo "OpenCV header outside model/src/leaf_scan.cpp:"; echo "$cv"; fail=1
fi

# 4. libpq only in db/src/pg.hpp (the lab server's thin client layer) and the tests' own
#    PostgreSQL helper.
pq=$(sources model devices db acquisition ui tests | grep -v -e '^db/src/pg.hpp$' -e '^tests/support/pg_cluster.hpp$' | xargs -r grep -lE '#\s*include\s*[<"]libpq-fe.h' || true)
if [ -n "$pq" ]; then
  echo "libpq header outside db/src/pg.hpp:"; echo "$pq"; fail=1
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
check model devices db acquisition ui
check devices model db acquisition ui
check db devices acquisition ui
check acquisition ui
[ $fail -eq 0 ] && echo "layering ok: Qt only in ui/, OpenCV only in leaf_scan.cpp, libpq only in db/src/pg.hpp, dependencies point one way"
exit $fail
