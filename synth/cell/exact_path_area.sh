#!/bin/sh
# Area of ru_exact_path (issue 14's exact side path), or with --unit STAGES of the whole
# exactly-once unit ru_ray_tri_exact around it (neither is a registry unit yet, so not through
# `rayunits synth`), or with --robust STAGES of ru_ray_tri_robust by the same steps (the baseline
# of that comparison; DIGITW is then ignored), with the cell flow's Yosys/ABC steps (model/src/synth/flow.cpp: synth -flatten,
# dfflibmap, abc -liberty with the flow's untargeted ABC script, stat -liberty), osu018.
# No STA and no register harness: the area only. The ABC commands below must stay
# cell_abc_script(0) (test CellFlow.ExactPathAreaScriptUsesTheFlowsAbcScript).
# Usage: synth/cell/exact_path_area.sh [--unit STAGES | --robust STAGES] EXPW FRACW DIGITW [OUTDIR]
# Writes OUTDIR/exact_path_eXmY_dD.txt, OUTDIR/ray_tri_exact_eXmY_sS_dD.txt or
# OUTDIR/ray_tri_robust_eXmY_sS.txt (Yosys stat -liberty); default OUTDIR synth/results/cell/exact_path.
set -eu
usage="usage: $0 [--unit STAGES | --robust STAGES] EXPW FRACW DIGITW [OUTDIR]"
st= which=path
if [ "${1:-}" = "--unit" ] || [ "${1:-}" = "--robust" ]; then
  [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }
  which=${1#--}
  st=$2
  shift 2
  case "$st" in *[!0-9]*|'') echo "$0: --$which takes a Stages number (got '$st')" >&2; exit 2 ;; esac
fi
[ $# -ge 3 ] || { echo "$usage" >&2; exit 2; }
e=$1 m=$2 dw=$3
case "$e$m$dw" in *[!0-9]*|'') echo "$0: EXPW FRACW DIGITW must be integers (got '$e' '$m' '$dw')" >&2; exit 2 ;; esac
[ "$e" -ge 2 ] && [ "$e" -le 8 ] && [ "$m" -ge 1 ] && [ "$m" -le 23 ] && [ "$dw" -ge 1 ] ||
  { echo "$0: ru_exact_path takes EXPW 2..8, FRACW 1..23, DIGITW >= 1 (got $e $m $dw)" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
out=${4:-$here/../results/cell/exact_path}
rtl=$here/../../rtl
if [ "$which" = robust ]; then
  top=ru_ray_tri_robust
  srcs=$(sed "s|^|$rtl/|" "$rtl/ru_ray_tri_robust.f" | tr '\n' ' ')
  params="-set Stages $st"
  name=ray_tri_robust_e${e}m${m}_s${st}
elif [ "$which" = unit ]; then
  top=ru_ray_tri_exact
  srcs=$(sed "s|^|$rtl/|" "$rtl/ru_ray_tri_exact.f" | tr '\n' ' ')
  params="-set Stages $st"
  name=ray_tri_exact_e${e}m${m}_s${st}_d${dw}
else
  top=ru_exact_path
  srcs=$rtl/ru_exact_path.sv
  params=
  name=exact_path_e${e}m${m}_d${dw}
fi
lib=/usr/share/qflow/tech/osu018/osu018_stdcells.lib
[ -f "$lib" ] || { echo "$0: $lib not found (Debian package qflow-tech-osu018)" >&2; exit 2; }
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf 'strash\nifraig\nscorr\ndc2\nstrash\ndch -f\nmap\ntopo\nbuffer -p\nupsize\ndnsize\n' > "$tmp/flow.abc"
yosys -q -p "read_liberty -lib $lib; read_verilog -sv $srcs;
  chparam -set ExpW $e -set FracW $m $([ "$which" = robust ] || echo "-set DigitW $dw") $params $top; synth -flatten -top $top;
  dfflibmap -liberty $lib; abc -liberty $lib -script $tmp/flow.abc; opt_clean -purge; check -assert;
  tee -q -o $tmp/stat.txt stat -liberty $lib"
mv "$tmp/stat.txt" "$out/$name.txt"
grep -E 'Chip area|Number of cells' "$out/$name.txt"
