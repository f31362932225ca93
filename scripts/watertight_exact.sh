#!/usr/bin/env bash
# Watertightness grid of issue 14: plain Fig. 3.6, Fig. 3.6 + tie-break, ray_tri_exact (exactly
# once) and Moller-Trumbore on the built-in closed meshes and on closed meshes from Debian's CGAL
# demo data (package libcgal-demo: /usr/share/doc/libcgal-demo/data.tar.gz), at e5m10 e6m12 e7m16
# e8m23 e11m52. Every run appends one row to the CSV; scripts/watertight_table.py turns it into the
# README/docs tables.
#   scripts/watertight_exact.sh [OUT.csv] [RAYS] [NEAR_VERTEX_RAYS]
# The CGAL meshes are normalised to |x| <= 0.5; they are scaled by 64 (3torus: 16) so that e5m10
# does not underflow (--scale).
set -euo pipefail
out=${1:-watertight_exact.csv}
rays=${2:-4000}
near=${3:-2000}
here=$(cd "$(dirname "$0")/.." && pwd)
ru=${RU:-$here/build/model/cli/rayunits}
data=${CGAL_DATA:-/tmp/ru-cgal-data}
if [[ ! -d $data/data/meshes ]]; then
  tarball=/usr/share/doc/libcgal-demo/data.tar.gz
  [[ -f $tarball ]] || { echo "watertight_exact.sh: $tarball missing (apt-get install libcgal-demo)" >&2; exit 2; }
  mkdir -p "$data" && tar -xzf "$tarball" -C "$data" data/meshes
fi
m=$data/data/meshes
meshes=("--scene icosphere" "--scene uvsphere" "--scene torus" "--scene cube"
        "--mesh $m/elephant.off --scale 64" "--mesh $m/camel.off --scale 64" "--mesh $m/knot1.off --scale 64"
        "--mesh $m/fandisk.off --scale 64" "--mesh $m/eight.off --scale 64" "--mesh $m/3torus.off --scale 16")
for mesh in "${meshes[@]}"; do
  for f in e5m10 e6m12 e7m16 e8m23 e11m52; do
    for tri in "robust" "robust --tie-break" "exact" "mt"; do
      # shellcheck disable=SC2086
      "$ru" study watertight $mesh --format $f --tri $tri --rays "$rays" --near-vertex "$near" --threads 2 \
        --quiet --csv "$out" | tail -1 | sed "s|^|$mesh $f $tri: |"
    done
  done
done
