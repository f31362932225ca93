#!/usr/bin/env bash
# run_pnr_stages.sh — place and route a pipelined unit as one block per pipeline stage
# (issue 13 section 3).
#
# usage: synth/pnr/run_pnr_stages.sh [OPTIONS] [RUN_PNR-OPTIONS...] UNIT [RAYUNITS-SYNTH-ARGS...]
#   e.g. synth/pnr/run_pnr_stages.sh --clock-ns 10 --density 0.65 noise --stages 4
#
# Why: the whole noise unit (46,760 cells) takes longer to place (GrayWolf) and route
# (qrouter) on this 2-core machine than a session lasts, and a step cut short restarts
# (synth/results/pnr/README.md). Its pipeline stages are each a fraction of it.
#
# 1. `rayunits synth UNIT ARGS --generic-only --keep` writes the wrapper and the RTL file list.
# 2. Yosys: `proc; flatten; opt; memory; opt; techmap t:*dff*; opt_clean -purge` ->
#    WORK/full.json; split_stages.py ranks the flip-flops and gives every cell its stage
#    (block s = the logic feeding the rank-s flip-flops plus those flip-flops); Yosys `submod`
#    cuts the blocks out (WORK/split.json), split_stages.py --plain-ports renames their ports,
#    and each block is written as flat plain Verilog (WORK/blocks/TOP_stN.v).
# 3. Check: the blocks put back together (`flatten`) are proved equivalent to the unit (Yosys
#    equiv_make / equiv_struct / equiv_simple / equiv_induct / equiv_status -assert); stop if not.
# 4. run_pnr.sh --source-v for each block (JOBS at a time), results in OUT/TOP_stN/.
# 5. pnr_stages_report.py: OUT/summary.json (sums and the worst stage) and OUT/layout.png.
#
# Options (the others are passed to run_pnr.sh for every block: --clock-ns --nice --density
# --graywolf-fast --step-timeout --no-checks --route-no-cleanup --until --redo --fresh):
#   --jobs N          blocks placed and routed at once (default 2)
#   --work DIR        work directory (default /tmp/ru-pnr/stages_<unit and args>)
#   --out DIR         results directory (default synth/results/pnr/<unit>_stages)
#   --rayunits PATH   rayunits binary (default: build-me/ then build/ under the repo)
#   --no-equiv        skip step 3
#   --cut-only        stop after step 3 (the blocks in WORK/blocks/, WORK/equiv.ys; no OUT)
#   -h, --help        this text
# Resumable as run_pnr.sh is: rerunning the same command skips every finished step of every block.
# Exit status: 0 every block passed every step, 1 some step failed, 2 usage error or missing tool.
set -u -o pipefail

prog=run_pnr_stages.sh
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
die() { echo "$prog: error: $*" >&2; exit 2; }
usage() { sed -n '2,/^set -u/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }

jobs=2 work= out= rayunits= equiv=1 fresh=0 cut_only=0
pnr_opts=()
while [ $# -gt 0 ]; do
  case "$1" in
    --jobs) [ $# -ge 2 ] || die "--jobs needs a value"; jobs=$2; shift 2 ;;
    --work) [ $# -ge 2 ] || die "--work needs a value"; work=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || die "--out needs a value"; out=$2; shift 2 ;;
    --rayunits) [ $# -ge 2 ] || die "--rayunits needs a value"; rayunits=$2; shift 2 ;;
    --no-equiv) equiv=0; shift ;;
    --cut-only) cut_only=1; shift ;;
    --fresh) fresh=1; pnr_opts+=("$1"); shift ;;
    --no-checks|--route-no-cleanup) pnr_opts+=("$1"); shift ;;
    --clock-ns|--nice|--density|--graywolf-fast|--step-timeout|--until|--redo)
      [ $# -ge 2 ] || die "$1 needs a value"; pnr_opts+=("$1" "$2"); shift 2 ;;
    -h|--help) usage; exit 0 ;;
    --*) die "unknown option $1 (accepted: --jobs --work --out --rayunits --no-equiv --cut-only --clock-ns --nice --density --graywolf-fast --step-timeout --until --redo --fresh --no-checks --route-no-cleanup --help)" ;;
    *) break ;;
  esac
done
[ $# -ge 1 ] || die "missing UNIT (usage: $prog [OPTIONS] UNIT [RAYUNITS-SYNTH-ARGS...])"
unit=$1; shift
unit_args=("$@")
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || die "--jobs must be a positive whole number, got '$jobs'"
command -v yosys >/dev/null 2>&1 || die "missing tool 'yosys' (Debian package yosys)"
py=/usr/bin/python3
[ -x "$py" ] || die "missing tool '$py' (Debian package python3)"
if [ -z "$rayunits" ]; then
  for c in "$repo/build-me/model/cli/rayunits" "${RU_BUILD_DIR:-$repo/build}/model/cli/rayunits"; do
    [ -x "$c" ] && { rayunits=$c; break; }
  done
fi
[ -n "$rayunits" ] && [ -x "$rayunits" ] || die "rayunits binary not found (build it: cmake -B build-me -DRU_TB=OFF && ninja -C build-me rayunits; or pass --rayunits PATH)"

config="$unit${unit_args[*]:+ ${unit_args[*]}}"
tag=$(echo "$config" | sed 's/--//g; s/[^A-Za-z0-9=.]\{1,\}/_/g')
work=${work:-/tmp/ru-pnr/stages_$tag}
out=${out:-$repo/synth/results/pnr/${unit}_stages}
[ "$fresh" = 0 ] || rm -rf "$work"
mkdir -p "$work/blocks" || die "cannot create $work"
work=$(cd "$work" && pwd); out=$(realpath -m "$out")  # OUT is created once the blocks exist
echo "$prog: $config, work $work, results $out"

# --- steps 1-3: cut the unit into stage blocks (once; redone with --fresh) ------------
if [ ! -f "$work/blocks.done" ]; then
  t0=$(date +%s)
  "$rayunits" synth "$unit" "${unit_args[@]}" --generic-only --keep --json "$work/generic.json" > "$work/rayunits_synth.txt" 2>&1 ||
    { cat "$work/rayunits_synth.txt" >&2; die "rayunits synth $config failed"; }
  top=$(sed -n '1s/^\(ru_[A-Za-z0-9_]*\): .*/\1/p' "$work/rayunits_synth.txt")
  keepdir=$(sed -n 's/^ *kept *//p' "$work/rayunits_synth.txt" | tail -1)
  [ -n "$top" ] && [ -f "$keepdir/generic.ys" ] || die "no top module or kept directory in the rayunits synth output ($work/rayunits_synth.txt)"
  mkdir -p "$work/rtl"
  cp "$keepdir"/*.sv "$work/rtl/"
  {
    grep '^read_verilog' "$keepdir/generic.ys" | sed "s|$keepdir/|$work/rtl/|"
    echo "hierarchy -check -top $top"
    echo "proc; flatten; opt; memory; opt; techmap t:*dff*; opt_clean -purge"
    echo "check -assert"
    echo "write_json $work/full.json"
  } > "$work/flatten.ys"
  rm -rf "$keepdir"
  yosys -q -l "$work/flatten.log" -s "$work/flatten.ys" > /dev/null || die "yosys flatten failed (log: $work/flatten.log)"
  "$py" "$here/split_stages.py" "$work/full.json" "$work/staged.json" "$top" --report "$work/stages.json" || die "split_stages.py failed"
  yosys -q -l "$work/submod.log" -p "read_json $work/staged.json; hierarchy -top $top; submod; write_json $work/submod.json" > /dev/null ||
    die "yosys submod failed (log: $work/submod.log)"
  "$py" "$here/split_stages.py" --plain-ports "$work/submod.json" "$work/split.json" "$top" || die "split_stages.py --plain-ports failed"
  nblocks=$("$py" -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["blocks"]))' "$work/stages.json")
  for s in $(seq 1 "$nblocks"); do
    b=${top}_st$s
    yosys -q -l "$work/blocks/$b.log" -p "read_json $work/split.json; hierarchy -top $b; rename -hide w:* x:* %d; opt_clean -purge; check -assert; write_verilog -noattr $work/blocks/$b.v" > /dev/null ||
      die "yosys could not write block $b (log: $work/blocks/$b.log)"
  done
  if [ "$equiv" = 1 ]; then
    echo "$prog: proving the $nblocks blocks together equivalent to $top (Yosys equiv_*) ..."
    cat > "$work/equiv.ys" <<EOF
read_json $work/full.json
rename $top gold
design -stash gold
read_json $work/split.json
hierarchy -top $top
flatten
rename $top gate
design -stash gate
design -copy-from gold -as gold gold
design -copy-from gate -as gate gate
equiv_make gold gate equiv
hierarchy -top equiv
equiv_struct -icells
equiv_simple -undef
equiv_induct -undef
equiv_status -assert
EOF
    yosys -q -l "$work/equiv.log" -s "$work/equiv.ys" > /dev/null ||
      die "the stage blocks are NOT equivalent to $top: $(grep -m1 'ERROR' "$work/equiv.log") (log: $work/equiv.log)"
    echo "$prog: equivalent ($(grep -A1 'Found [0-9]* \$equiv cells' "$work/equiv.log" | tail -1 | sed 's/^ *//'))"
  fi
  echo "$top" > "$work/top"
  echo "$(( $(date +%s) - t0 ))" > "$work/blocks.time"
  touch "$work/blocks.done"
fi
top=$(cat "$work/top")
cat "$work/rayunits_synth.txt" | head -1
blocks=$(cd "$work/blocks" && ls ${top}_st*.v | sed 's/\.v$//' | sort -V)
echo "$prog: blocks: $(echo $blocks)"

[ "$cut_only" = 0 ] || { echo "$prog: --cut-only: blocks in $work/blocks/"; exit 0; }

# --- step 4: place and route every block ------------------------------------------------
mkdir -p "$out" || die "cannot create $out"
run_block() {
  local b=$1
  "$here/run_pnr.sh" "${pnr_opts[@]}" --work "$work/pnr/$b" --out "$out/$b" --source-v "$work/blocks/$b.v" "$b" \
    > "$work/$b.pnr.log" 2>&1
  local rc=$?
  echo "$prog: $b finished (exit $rc): $(tail -1 "$work/$b.pnr.log")"
  return $rc
}
rc_all=0
running=0
for b in $blocks; do
  echo "$prog: $b ... ($(date +%H:%M:%S); log $work/$b.pnr.log)"
  run_block "$b" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || rc_all=1
    running=$((running - 1))
  fi
done
while [ "$running" -gt 0 ]; do wait -n || rc_all=1; running=$((running - 1)); done

# --- step 5: the unit's numbers from its blocks ----------------------------------------
cp "$work/stages.json" "$work/flatten.ys" "$out/" 2>/dev/null
[ ! -f "$work/equiv.log" ] || grep -A3 'Executing EQUIV_STATUS' "$work/equiv.log" > "$out/equiv_status.txt"
cmd="synth/pnr/run_pnr_stages.sh${pnr_opts[*]:+ ${pnr_opts[*]}} $config"
"$py" "$here/pnr_stages_report.py" --out "$out" --stages "$work/stages.json" --generic "$work/generic.json" \
  --command "${cmd/ --fresh/}" --equiv "$( [ "$equiv" = 1 ] && echo proved || echo skipped)" $blocks || { echo "$prog: report failed" >&2; exit 1; }
exit $rc_all
