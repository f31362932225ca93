#!/usr/bin/env bash
# Configures and builds rayunits into build/ (override with RU_BUILD_DIR). Used by run.sh and test.sh.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${RU_BUILD_DIR:-$ROOT/build}"
JOBS="${RU_JOBS:-$(nproc)}"
if [[ ! -f "$BUILD/build.ninja" ]]; then
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$BUILD" -j "$JOBS"
