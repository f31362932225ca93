#!/usr/bin/env bash
# Issue 14 §3 (model side): error of t, beta, gamma against exact rationals and wrong hit
# decisions of Fig. 3.6 taken literally (3 divisions), the cheaper robust variants recip
# (1/V + 3 mul) and deferred (t_min*V < Va < t_max*V, no division) and Moller-Trumbore, on the
# synthetic benchmark and on bunny/dragon render traces (primary + shadow rays, double).
#   scripts/study_tri_outputs.sh [SIZE] [OUTDIR]     (bunny/dragon need libcgal-demo data)
# Writes OUTDIR/NAME.csv (one row per format, e7..e8 x m8..m25) and OUTDIR/NAME.txt (printed tables).
set -euo pipefail
size=${1:-128}
here=$(cd "$(dirname "$0")/.." && pwd)
out=${2:-$here/docs/units/study_tri_outputs}
ru=${RU:-$here/build/model/cli/rayunits}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$tmp"
"$ru" study tri-outputs --synthetic 2048 --csv synthetic.csv --quiet > "$out/synthetic.txt"
mv synthetic.csv "$out/"
for s in bunny dragon; do
  rcmd=(render --scene "$s" --format double --tri robust --size "$size" --threads 1 --quiet --out "$s.png"
        --trace-out "$s.trace")
  "$ru" "${rcmd[@]}" > render.txt
  { echo "# trace: rayunits ${rcmd[*]} -> $(grep '^rays:' render.txt)"
    "$ru" study tri-outputs --trace "$s.trace" --csv "${s}_all.csv" --quiet; } > "$out/${s}_all.txt"
  mv "${s}_all.csv" "$out/"
  rm -f "$s.trace"
  echo "$s: $(sed -n 3p "$out/${s}_all.txt")"
done
