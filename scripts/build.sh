#!/usr/bin/env bash
# Configures and builds rayunits into build/ (override with RU_BUILD_DIR). Used by run.sh and test.sh.
# Extra arguments are passed to cmake's configure step (e.g. -DRU_TB_LONG=ON).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${RU_BUILD_DIR:-$ROOT/build}"
JOBS="${RU_JOBS:-$(nproc)}"
if [[ ! -f "$BUILD/build.ninja" || $# -gt 0 ]]; then
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
fi
cmake --build "$BUILD" -j "$JOBS"
