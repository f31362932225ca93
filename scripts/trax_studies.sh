#!/usr/bin/env bash
# Regenerates every checked-in TRaX study (docs/trax/, docs/pareto/chip): the commands the README
# and docs/TRAX.md quote, in order. Usage: scripts/trax_studies.sh [RAYUNITS] (default: the
# build-me tree's binary). The bunny studies need scripts/install-deps.sh --long. ~3-4 minutes.
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
# Fused multiply-add (chip.fma, docs/TRAX.md "Fused multiply-add"): the bunny and the smoke without and
# with it, the renderer's images of both (the chip's images: its noise unit), and the side-by-side table and plot.
F=docs/trax/fma
run study trax --kind formats --scene bunny --size 64x64 --config $F/config.toml --out $F/bunny --quiet
run study trax --kind formats --scene smoke --formats e6m12,e7m16,e8m23 --size 32x32 --out $F/smoke_plain --quiet
run study trax --kind formats --scene smoke --formats e6m12,e7m16,e8m23 --size 32x32 --config $F/config.toml \
  --out $F/smoke --quiet
mkdir -p $F/images
for sf in bunny:e6m12 smoke:e8m23; do
  s=${sf%%:*} f=${sf#*:}
  for m in plain fma; do
    flag=$([ $m = fma ] && echo --fma || true)
    run render --scene $s --format $f --noise fixed-trunc --size 256x256 $flag --compare --quiet --out $F/images/${s}_${f}_$m.png \
      --diff-out $F/images/${s}_${f}_${m}_diff.png --json $F/images/${s}_${f}_$m.json
  done
done
# fusing alone, in double: how far the fused double render is from the plain one (the noise unit's
# input quantization turns last-bit differences of a sample point into noise quanta)
run render --scene smoke --format double --noise fixed-trunc --size 256x256 --fma --compare --quiet \
  --out $F/images/smoke_double_fma.png --json $F/images/smoke_double_fma.json
echo "+ scripts/fma_compare.py" >&2
/usr/bin/python3 scripts/fma_compare.py $F docs/trax/bunny/trax_formats.csv $F/bunny/trax_formats.csv bunny \
  $F/smoke_plain/trax_formats.csv $F/smoke/trax_formats.csv smoke > /dev/null
run pareto docs/trax/trax_formats.csv --x psnr_db --y area_mm2 --z rays_per_s \
  --target 'psnr_db>=40' --target 'error_pct<=0.1' --all --plot-axes 1,3 \
  --title 'TRaX chip per format (docs/trax/trax_formats.csv)' --out docs/pareto/chip
