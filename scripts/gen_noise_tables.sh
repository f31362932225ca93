#!/usr/bin/env bash
# Regenerates the noise unit's tables (model/include/rayunits/noise/noise_tables_data.hpp and
# rtl/ru_noise_tables.svh) with the one generator, model/src/noise/tables_gen.cpp.
#   scripts/gen_noise_tables.sh           write the files
#   scripts/gen_noise_tables.sh --check   compare only (exit 1 if they differ)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${RU_BUILD_DIR:-$ROOT/build}"
"$ROOT/scripts/build.sh" >/dev/null
if [[ "${1:-}" == "--check" ]]; then
  exec "$BUILD/model/cli/rayunits" noise tables --check --root "$ROOT"
fi
exec "$BUILD/model/cli/rayunits" noise tables --write --root "$ROOT"
