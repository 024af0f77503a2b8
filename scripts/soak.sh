#!/usr/bin/env bash
# The soak run (scripts/soak.py): leaves captured back to back with device faults, kill -9,
# a full disk and lab pushes, then every acknowledged event checked. Needs the `ci` build.
# Usage: scripts/soak.sh [--leaves N] [--minutes M] [--seed S]   (default 1000 leaves or 60 min)
#        scripts/soak.sh --short                                 (about 2 minutes: the test command's)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [ "${1:-}" = "--short" ]; then
  shift
  exec python3 "$root/scripts/soak.py" --leaves 25 --minutes 2 --push-every 6 "$@"
fi
exec python3 "$root/scripts/soak.py" "$@"
