#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job: `rayunits report` on the built-in
# default workload. Arguments are passed to `rayunits report` (e.g. --out DIR).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$ROOT/scripts/install-deps.sh"
"$ROOT/scripts/build.sh"
BUILD="${RU_BUILD_DIR:-$ROOT/build}"
exec "$BUILD/model/cli/rayunits" report "$@"
