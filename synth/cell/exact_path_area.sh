#!/bin/sh
# Area of ru_exact_path (issue 14's exact side path; a submodule of ru_ray_tri_exact, not a
# registry unit, so not through `rayunits synth`) with the cell flow's Yosys/ABC steps
# (model/src/synth/flow.cpp: synth -flatten, dfflibmap, abc -liberty with the flow's untargeted ABC
# script, stat -liberty), osu018. No STA and no register harness: the area only. The whole unit
# ru_ray_tri_exact is a registry unit: `rayunits synth ray_tri_exact --flow osu018` (area and STA
# clock; synth/cell/run.py). The ABC commands below must stay cell_abc_script(0) (test
# CellFlow.ExactPathAreaScriptUsesTheFlowsAbcScript).
# With --sta, the mapped netlist is also timed by OpenSTA (register to register; inputs and
# outputs at the clock edge, as the flow's register harness would see them; no wire load):
# OUTDIR/exact_path_eXmY_dD.sta.txt, the worst path (its arrival time plus the setup time is the
# module's shortest period).
# Usage: synth/cell/exact_path_area.sh [--sta] EXPW FRACW DIGITW [OUTDIR]
# Writes OUTDIR/exact_path_eXmY_dD.txt (Yosys stat -liberty); default OUTDIR synth/results/cell/exact_path.
set -eu
usage="usage: $0 [--sta] EXPW FRACW DIGITW [OUTDIR]"
sta=
if [ "${1:-}" = "--sta" ]; then sta=1; shift; fi
[ $# -ge 3 ] || { echo "$usage" >&2; exit 2; }
e=$1 m=$2 dw=$3
case "$e$m$dw" in *[!0-9]*|'') echo "$0: EXPW FRACW DIGITW must be integers (got '$e' '$m' '$dw')" >&2; exit 2 ;; esac
[ "$e" -ge 2 ] && [ "$e" -le 8 ] && [ "$m" -ge 1 ] && [ "$m" -le 23 ] && [ "$dw" -ge 1 ] ||
  { echo "$0: ru_exact_path takes EXPW 2..8, FRACW 1..23, DIGITW >= 1 (got $e $m $dw)" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
out=${4:-$here/../results/cell/exact_path}
rtl=$here/../../rtl
top=ru_exact_path
srcs=$rtl/ru_exact_path.sv
name=exact_path_e${e}m${m}_d${dw}
lib=/usr/share/qflow/tech/osu018/osu018_stdcells.lib
[ -f "$lib" ] || { echo "$0: $lib not found (Debian package qflow-tech-osu018)" >&2; exit 2; }
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf 'strash\nifraig\nscorr\ndc2\nstrash\ndch -f\nmap\ntopo\nbuffer -p\nupsize\ndnsize\n' > "$tmp/flow.abc"
yosys -q -p "read_liberty -lib $lib; read_verilog -sv $srcs;
  chparam -set ExpW $e -set FracW $m -set DigitW $dw $top; synth -flatten -top $top;
  dfflibmap -liberty $lib; abc -liberty $lib -script $tmp/flow.abc; opt_clean -purge; check -assert;
  tee -q -o $tmp/stat.txt stat -liberty $lib; write_verilog -noattr -noexpr $tmp/net.v"
if [ -n "$sta" ]; then
  command -v sta >/dev/null || { echo "$0: sta (OpenSTA, Debian package opensta) not found" >&2; exit 2; }
  printf '%s\n' "read_liberty $lib" "read_verilog $tmp/net.v" "link_design $top" \
    "create_clock -name clk -period 1000 [get_ports clk_i]" \
    "set_input_delay 0 -clock clk [delete_from_list [all_inputs] [get_ports clk_i]]" \
    "set_output_delay 0 -clock clk [all_outputs]" "set_false_path -from [get_ports rst_ni]" \
    "report_checks -path_delay max -format full -digits 3" > "$tmp/sta.tcl"
  (cd "$tmp" && sta -exit sta.tcl > sta.txt 2>&1) || { echo "$0: sta failed" >&2; exit 1; }
  grep -q "data arrival time" "$tmp/sta.txt" || { echo "$0: no path in the sta report" >&2; exit 1; }
  mv "$tmp/sta.txt" "$out/$name.sta.txt"
fi
mv "$tmp/stat.txt" "$out/$name.txt"
grep -E 'Chip area|Number of cells' "$out/$name.txt"
[ -z "$sta" ] || grep -m1 -E 'data arrival time' "$out/$name.sta.txt"
