#!/usr/bin/env bash
# Installs what is missing, builds, runs the tests.
#   scripts/test.sh          fast suite (ctest -LE long)
#   scripts/test.sh --long   everything, including the exhaustive/slow suites (label `long`)
# Extra arguments after the options go to ctest (e.g. -R fp_mul).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
LONG=0
if [[ "${1:-}" == "--long" ]]; then LONG=1; shift; fi
if [[ $LONG == 1 ]]; then "$ROOT/scripts/install-deps.sh" --long; else "$ROOT/scripts/install-deps.sh"; fi
if [[ $LONG == 1 ]]; then
  "$ROOT/scripts/build.sh" -DRU_TB_LONG=ON   # the long-label RTL test executables
else
  "$ROOT/scripts/build.sh"
fi
BUILD="${RU_BUILD_DIR:-$ROOT/build}"
cd "$BUILD"
if [[ $LONG == 1 ]]; then
  ctest --output-on-failure -j "$(nproc)" "$@"
else
  ctest --output-on-failure -j "$(nproc)" -LE long "$@"
fi
