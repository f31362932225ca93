#!/usr/bin/env bash
# How often ray_tri_exact's exact side path decides, on the ray/triangle tests of real renders
# (issue 14): each scene is rendered with `render --trace-out` (the renderer's own unit is
# ray_tri_robust, `render --tri robust`), and the trace is replayed by `study exact-path`.
#   scripts/exact_path_renders.sh [SIZE] [FILTERS]   (bunny/dragon need libcgal-demo data: install-deps.sh --long)
# FILTERS: the fast path's error bounds to compare, comma-separated (study exact-path --filter;
# default permanent-format, the RTL's; e.g. permanent,permanent-format,exponent).
set -euo pipefail
size=${1:-128}
filters=${2:-permanent-format}
here=$(cd "$(dirname "$0")/.." && pwd)
ru=${RU:-$here/build/model/cli/rayunits}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '| scene | format | filter | tests | exact path | for edge signs | for the interval | fast path decides | decisions != robust |\n|---|---|---|---|---|---|---|---|---|\n'
for s in default cornell bunny dragon; do
  for f in e7m16 e8m23 e11m52; do
    "$ru" render --scene "$s" --format "$f" --size "$size" --threads 1 --quiet --out "$tmp/x.png" --trace-out "$tmp/t.trace" > /dev/null
    for fl in ${filters//,/ }; do
      o=$("$ru" study exact-path --trace "$tmp/t.trace" --format "$f" --filter "$fl" --threads 2)
      tests=$(sed -n 's/^tests=\([0-9]*\) slow=\([0-9]*\) fast_percent=\(.*\)$/\1/p' <<< "$o")
      slow=$(sed -n 's/^tests=\([0-9]*\) slow=\([0-9]*\) fast_percent=\(.*\)$/\2/p' <<< "$o")
      fast=$(sed -n 's/^tests=\([0-9]*\) slow=\([0-9]*\) fast_percent=\(.*\)$/\3/p' <<< "$o")
      edge=$(sed -n 's/^exact path taken: .*: \([0-9]*\) for edge signs.*/\1/p' <<< "$o")
      intv=$(sed -n 's/^exact path taken: .*, \([0-9]*\) for the interval$/\1/p' <<< "$o")
      diff=$(sed -n 's/^hits: .*decisions that differ: \([0-9]*\)$/\1/p' <<< "$o")
      echo "| $s | $f | $fl | $tests | $slow | $edge | $intv | $fast % | $diff |"
    done
  done
done
rm -f "$tmp/t.trace"
