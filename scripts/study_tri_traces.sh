#!/usr/bin/env bash
# Issue 14 §5: Tables 3.2-3.4 (`rayunits study tri`) on ray/triangle traces captured from real
# renders, beside the synthetic benchmark and the dissertation (../shared/reference/).
#   scripts/study_tri_traces.sh [SIZE] [OUTDIR]     (bunny/dragon need libcgal-demo data: install-deps.sh --long)
# Each scene is rendered in double (`render --format double --tri robust`, one thread, so the trace
# order is fixed) twice: with hard shadows (primary + shadow rays) and with --no-shadows (primary
# rays only). Every tri record of the trace is used (no subsample). Writes, per run, OUTDIR/NAME/
# study_tri.txt (the printed tables, formula ranking and sign errors), study_tri_tables.csv and
# study_tri_signs.csv (no heat map; the 6,000-row formula CSV is not kept), then OUTDIR/summary.md
# (scripts/study_tri_summary.py) and OUTDIR/input_rounding.txt (scripts/study_tri_input_rounding.py
# on 2,000 records of the synthetic, bunny and dragon traces with shadows).
set -euo pipefail
size=${1:-128}
here=$(cd "$(dirname "$0")/.." && pwd)
out=${2:-$here/docs/units/study_tri}
ru=${RU:-$here/build/model/cli/rayunits}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$tmp"   # relative trace names, so the recorded commands carry no temporary path

run() {  # NAME HEADER ARGS...
  local name=$1 header=$2; shift 2
  mkdir -p "$out/$name"
  { echo "# $header"; "$ru" study tri "$@" --out "$name" --quiet --no-plot; } > "$out/$name/study_tri.txt"
  cp "$name/study_tri_tables.csv" "$name/study_tri_signs.csv" "$out/$name/"
  rm -rf "$name"
  echo "$name: $(sed -n 3p "$out/$name/study_tri.txt")"
}

run synthetic "synthetic benchmark (units/synthetic.hpp)" --synthetic 2048 --write-trace synthetic.trace
for s in bunny dragon; do
  for mode in all primary; do
    extra=()
    [ "$mode" = primary ] && extra=(--no-shadows)
    rcmd=(render --scene "$s" --format double --tri robust --size "$size" --threads 1 --quiet "${extra[@]}"
          --out "$s.png" --trace-out "$s.trace")
    "$ru" "${rcmd[@]}" > render.txt
    run "${s}_${mode}" "trace: rayunits ${rcmd[*]} -> $(grep '^rays:' render.txt)" --trace "$s.trace"
    [ "$mode" = all ] && mv "$s.trace" "$s.all.trace"
    rm -f "$s.trace"
  done
done

python3 "$here/scripts/study_tri_summary.py" "$out" > "$out/summary.md"
for t in synthetic.trace bunny.all.trace dragon.all.trace; do
  python3 "$here/scripts/study_tri_input_rounding.py" "$t" 2000 8 10 12 14 16 18 20 22 23
done > "$out/input_rounding.txt"
