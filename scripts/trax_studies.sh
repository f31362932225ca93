#!/usr/bin/env bash
# Regenerates every checked-in TRaX study (docs/trax/, docs/pareto/chip): the commands the README
# and docs/TRAX.md quote, in order. Usage: scripts/trax_studies.sh [RAYUNITS] (default: the
# build-me tree's binary). The bunny studies need scripts/install-deps.sh --long. ~3 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
R=${1:-build-me/model/cli/rayunits}
export PATH=/usr/bin:$PATH  # Debian's python3 (matplotlib) for the plots
run() { echo "+ rayunits $*" >&2; "$R" "$@" > /dev/null; }
run study trax --kind all --size 32x32 --out docs/trax --quiet
run study trax --kind formats --size 64x64 --out docs/trax --quiet
run study trax --kind texture --scene noisy --size 64x64 --out docs/trax/noisy --quiet
run study trax --kind texture --scene smoke --size 64x64 --out docs/trax/smoke --quiet
run study trax --kind formats --formats e5m10,e6m12,e8m23 --size 64x64 --config docs/trax/word_banks/config.toml \
  --out docs/trax/word_banks --quiet
run study trax --kind formats --scene bunny --size 64x64 --out docs/trax/bunny --quiet
for e in 0.35 0.7; do
  run study trax --kind formats --scene bunny --formats e6m12,e8m23 --size 64x64 \
    --config docs/trax/bunny/efficiency_$e/config.toml --out docs/trax/bunny/efficiency_$e --quiet
done
run trax --scene bunny --size 64x64 --config docs/trax/bunny/box_e5m8/config.toml --out docs/trax/bunny/box_e5m8
run pareto docs/trax/trax_formats.csv --x psnr_db --y area_mm2 --z rays_per_s \
  --target 'psnr_db>=40' --target 'error_pct<=0.1' --all --plot-axes 1,3 \
  --title 'TRaX chip per format (docs/trax/trax_formats.csv)' --out docs/pareto/chip
