#!/usr/bin/env bash
# run_pnr.sh — place and route one rayunits unit with qflow (osu018) — issue 13 section 3.
#
# usage: synth/pnr/run_pnr.sh [OPTIONS] UNIT [RAYUNITS-SYNTH-ARGS...]
#   e.g. synth/pnr/run_pnr.sh --clock-ns 5 fp_mul --format e8m23 --stages 3
#        synth/pnr/run_pnr.sh --clock-ns 10 noise --stages 4
#
# UNIT and the arguments after it are passed to `rayunits synth UNIT ... --generic-only
# --keep`, which writes the wrapper (ru_<unit>_..._sN.sv) and generic.ys (the RTL file list).
# Yosys reads those files and writes one flattened plain-Verilog module (internal names
# hidden, so qflow's write_blif -buf adds no alias buffers); qflow then runs, one step per
# call, in WORK (outside the repository):
#   synthesize (yosys+abc to osu018, blifFanout) ; place (graywolf) ; sta (OpenSTA + vesta,
#   pre-route) ; route (qrouter) ; backanno (rc2dly; OpenSTA with SDF + vesta with .dly) ;
#   migrate (magic: DEF -> mag, extraction) ; drc (magic) ; lvs (netgen) ; gdsii (magic)
# plus our own OpenSTA run on the qrouter-extracted SPEF (repaired by fix_spef.py; qflow's
# own OpenSTA call reads only the SDF interconnect delays), and pnr_report.py, which
# writes OUT/summary.json (one object) and OUT/layout.png. The small logs go to OUT/logs/.
#
# Resumable: a step whose marker WORK/.done/STEP exists (with the same key, e.g. the clock)
# is skipped; redoing a step invalidates the steps that depend on it. A failing step is
# recorded (WORK/failures.txt: step, exit status, the log's error line) and the steps not
# depending on it still run; the summary names it. Exit status: 0 all steps passed,
# 1 some step failed (summary still written), 2 usage error or missing tool.
#
# Options:
#   --clock-ns T       target clock period in ns for the STA (default 10). qflow's mapping is
#                      not timing-driven; the clock sets the SDC/vesta period only.
#   --work DIR         work directory (default /tmp/ru-pnr/<unit and args>, e.g. fp_mul_format_e8m23_stages_3)
#   --out DIR          results directory (default synth/results/pnr/<unit>)
#   --rayunits PATH    rayunits binary (default: build-me/ then build/ under the repo)
#   --step-timeout S   timeout of each tool step in seconds (default 14400)
#   --nice N           niceness of the tool steps (default 10)
#   --redo LIST        comma-separated steps to rerun (and what depends on them)
#   --fresh            delete WORK first
#   --graywolf-fast N  TimberWolfSC "fast" parameter (layout/TOP.par: TWSC*fast : N): the
#                      annealer tries N times fewer moves per temperature (default 0 = qflow's
#                      setting). 46,760 cells of the noise unit take ~4 h at the default here.
#   (--graywolf-no-global-route, TWSC*do.global.route : off, was removed in session 8: with
#   TimberWolfSC's global router off no ROOT.pin is written — the pin and net file qflow's
#   place2def reads to write the DEF nets — so `place` fails on a fresh work directory with
#   "GrayWolf failure: No file ROOT.pin"; the session-7 runs with it had read a .pin left in
#   the work directory by an earlier run. The option now stops with that explanation.)
#   --density D        qflow's initial_density (0 < D <= 1): decongest.tcl adds fill cells before
#                      placement so that cells cover about D of the core (default: unset, qflow
#                      packs the rows). Without GrayWolf's global route (which spaces the rows
#                      for routing) a dense noise unit left 10,383 of its first 28,800 nets
#                      unrouted in qrouter's first pass.
#   --no-checks        skip migrate, drc, lvs and gdsii
#   --route-no-cleanup qrouter's standard_route without its cleanup stage (stage 3, run twice,
#                      re-routes every net once more to shorten it): the route ends when stage 2
#                      has no failed net. For large blocks on a loaded machine: stage 3 of a
#                      23,000-net block ran at ~25 nets per minute beside other jobs (session 17).
#                      Recorded in meta.json ("route_cleanup").
#   --until STEP       stop after STEP (the report is still written)
#   --archive FILE     after the run, write the work directory's state (every finished step's
#                      outputs and markers; without GrayWolf's large intermediate .cel/.scel/.pin/
#                      .pth/.sav files, which no later step reads) to FILE (.tar.xz), written to a
#                      temporary name and renamed. For flows longer than a session: e.g. place in
#                      one session with `--until place --archive F`, check F in, route in the next.
#   --restore FILE     before the run, unpack FILE into an empty (or missing) work directory; the
#                      path the archive was made in is rewritten to the new one in qflow's scripts.
#   --source-v FILE    place and route FILE, a flat plain-Verilog module named UNIT (no
#                      RAYUNITS-SYNTH-ARGS; rayunits is not called): used by run_pnr_stages.sh for
#                      the blocks it cuts out of a unit
#   -h, --help         this text
set -u -o pipefail

prog=run_pnr.sh
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
tech=osu018
techdir=/usr/share/qflow/tech/$tech

die() { echo "$prog: error: $*" >&2; exit 2; }
usage() { sed -n '2,/^set -u/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }

route_cleanup=true clock_ns=10 work= out= rayunits= step_timeout=14400 niceness=10 redo= fresh=0 checks=1 until= gw_fast=0 gw_groute=on density= archive= restore= source_v=
while [ $# -gt 0 ]; do
  case "$1" in
    --clock-ns) [ $# -ge 2 ] || die "--clock-ns needs a value"; clock_ns=$2; shift 2 ;;
    --work) [ $# -ge 2 ] || die "--work needs a value"; work=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || die "--out needs a value"; out=$2; shift 2 ;;
    --rayunits) [ $# -ge 2 ] || die "--rayunits needs a value"; rayunits=$2; shift 2 ;;
    --step-timeout) [ $# -ge 2 ] || die "--step-timeout needs a value"; step_timeout=$2; shift 2 ;;
    --nice) [ $# -ge 2 ] || die "--nice needs a value"; niceness=$2; shift 2 ;;
    --redo) [ $# -ge 2 ] || die "--redo needs a value"; redo=$2; shift 2 ;;
    --until) [ $# -ge 2 ] || die "--until needs a value"; until=$2; shift 2 ;;
    --graywolf-fast) [ $# -ge 2 ] || die "--graywolf-fast needs a value"; gw_fast=$2; shift 2 ;;
    --graywolf-no-global-route) die "--graywolf-no-global-route was removed: without TimberWolfSC's global route no .pin file is written and qflow's place2def cannot write the DEF nets (see --help)" ;;
    --density) [ $# -ge 2 ] || die "--density needs a value"; density=$2; shift 2 ;;
    --archive) [ $# -ge 2 ] || die "--archive needs a value"; archive=$2; shift 2 ;;
    --restore) [ $# -ge 2 ] || die "--restore needs a value"; restore=$2; shift 2 ;;
    --source-v) [ $# -ge 2 ] || die "--source-v needs a value"; source_v=$2; shift 2 ;;
    --fresh) fresh=1; shift ;;
    --no-checks) checks=0; shift ;;
    --route-no-cleanup) route_cleanup=false; shift ;;
    -h|--help) usage; exit 0 ;;
    --*) die "unknown option $1 (accepted: --clock-ns --work --out --rayunits --step-timeout --nice --redo --until --graywolf-fast --density --archive --restore --source-v --fresh --no-checks --route-no-cleanup --help)" ;;
    *) break ;;
  esac
done
[ $# -ge 1 ] || die "missing UNIT (usage: $prog [OPTIONS] UNIT [RAYUNITS-SYNTH-ARGS...])"
unit=$1; shift
unit_args=("$@")
[[ "$clock_ns" =~ ^[0-9]+(\.[0-9]+)?$ ]] || die "--clock-ns must be a positive number, got '$clock_ns'"
[ -z "$density" ] || [[ "$density" =~ ^(0\.[0-9]*[1-9][0-9]*|1(\.0*)?)$ ]] || die "--density must be a number in (0, 1], got '$density'"
[[ "$gw_fast" =~ ^[0-9]+$ ]] || die "--graywolf-fast must be a whole number, got '$gw_fast'"
[[ "$step_timeout" =~ ^[0-9]+$ ]] || die "--step-timeout must be whole seconds, got '$step_timeout'"
if [ -n "$source_v" ]; then
  [ -f "$source_v" ] || die "--source-v: no such file '$source_v'"
  [ ${#unit_args[@]} = 0 ] || die "--source-v takes no RAYUNITS-SYNTH-ARGS after UNIT (got: ${unit_args[*]})"
  [[ "$unit" =~ ^[A-Za-z_][A-Za-z0-9_]*$ ]] || die "--source-v: UNIT must be the module's name, got '$unit'"
  grep -q "^module $unit *(" "$source_v" || die "--source-v: '$source_v' has no 'module $unit ('"
  source_v=$(cd "$(dirname "$source_v")" && pwd)/$(basename "$source_v")
fi

all_steps="source synthesize place sta route backanno opensta_spef migrate drc lvs gdsii"
for s in ${redo//,/ } ${until}; do
  [[ " $all_steps " == *" $s "* ]] || die "unknown step '$s' (steps: $all_steps)"
done

# --- tools -----------------------------------------------------------------------------
need() { command -v "$1" >/dev/null 2>&1 || die "missing tool '$1' (Debian package $2)"; }
need yosys yosys
need qflow qflow
need tcsh tcsh
need graywolf graywolf
need qrouter qrouter
need magic magic
need netgen-lvs netgen-lvs
need sta opensta
need timeout coreutils
py=/usr/bin/python3
[ -x "$py" ] || die "missing tool '$py' (Debian package python3)"
"$py" -c 'import matplotlib' 2>/dev/null || die "missing Python module matplotlib for $py (Debian package python3-matplotlib)"
[ -f "$techdir/$tech.sh" ] || die "missing qflow technology $techdir/$tech.sh (Debian package qflow-tech-osu018)"
if [ -n "$source_v" ]; then
  rayunits=none
elif [ -z "$rayunits" ]; then
  for c in "$repo/build-me/model/cli/rayunits" "${RU_BUILD_DIR:-$repo/build}/model/cli/rayunits"; do
    [ -x "$c" ] && { rayunits=$c; break; }
  done
fi
[ "$rayunits" = none ] || { [ -n "$rayunits" ] && [ -x "$rayunits" ]; } || die "rayunits binary not found (build it: cmake -B build-me -DRU_TB=OFF && ninja -C build-me rayunits; or pass --rayunits PATH)"

t0_total=$(date +%s)
config="$unit${unit_args[*]:+ ${unit_args[*]}}"
tag=$(echo "$config" | sed 's/--//g; s/[^A-Za-z0-9=.]\{1,\}/_/g')
work=${work:-/tmp/ru-pnr/$tag}
out=${out:-$repo/synth/results/pnr/$unit}
if [ "$fresh" = 1 ]; then rm -rf "$work"; fi
if [ -n "$restore" ]; then
  [ -f "$restore" ] || die "--restore: no such file '$restore'"
  command -v xz >/dev/null 2>&1 || die "missing tool 'xz' (Debian package xz-utils)"
  [ ! -d "$work/.done" ] || [ -z "$(ls -A "$work/.done")" ] ||
    die "--restore: work directory $work already has finished steps (use --fresh to replace them)"
  mkdir -p "$work"
  xz -dc "$restore" | tar -C "$work" -xf - || die "--restore: cannot unpack '$restore'"
  from=$(cat "$work/archived_from" 2>/dev/null || echo "")
  now=$(cd "$work" && pwd)
  if [ -n "$from" ] && [ "$from" != "$now" ]; then
    grep -rlF --exclude-dir=log --exclude-dir=keep "$from" "$work" | while read -r f; do sed -i "s|$from|$now|g" "$f"; done
  fi
  echo "$prog: restored $restore into $now (archived from ${from:-?}; done: $(ls "$work/.done" | tr '\n' ' '))"
fi
mkdir -p "$work"/{source,synthesis,layout,log,keep,.done,.time} "$out/logs"
work=$(cd "$work" && pwd)
rm -f "$work/failures.txt"
top=$(cat "$work/top" 2>/dev/null || echo "")
echo "$prog: $config, clock ${clock_ns} ns, work $work, results $out"

# --- step machinery --------------------------------------------------------------------
children() {
  case "$1" in
    source) echo synthesize ;;
    synthesize) echo place ;;
    place) echo "sta route" ;;
    route) echo "backanno migrate" ;;
    backanno) echo opensta_spef ;;
    migrate) echo "drc lvs gdsii" ;;
  esac
}
invalidate() { local c; for c in $(children "$1"); do rm -f "$work/.done/$c"; invalidate "$c"; done; }
for s in ${redo//,/ }; do rm -f "$work/.done/$s"; invalidate "$s"; done

stopped=0
fail() { # step rc line
  echo "$1 rc=$2 $3" >> "$work/failures.txt"
  echo "$prog: step $1 FAILED (exit $2): $3" >&2
}
# run_step STEP KEY DEPS... -- COMMAND...   (skips when done with the same key)
run_step() {
  local step=$1 key=$2; shift 2
  local deps=()
  while [ "$1" != "--" ]; do deps+=("$1"); shift; done; shift
  if [ "$stopped" = 1 ]; then return 0; fi
  local dep
  for dep in "${deps[@]}"; do
    if [ ! -f "$work/.done/$dep" ]; then
      echo "$prog: skip $step (needs $dep)"
      echo "$step skipped: needs $dep" >> "$work/failures.txt"
      return 0
    fi
  done
  if [ -f "$work/.done/$step" ] && [ "$(cat "$work/.done/$step")" = "$key" ]; then
    echo "$prog: $step already done ($(cat "$work/.time/$step" 2>/dev/null || echo ?) s), skipped"
  else
    rm -f "$work/.done/$step"; invalidate "$step"
    echo "$prog: $step ... ($(date +%H:%M:%S))"
    local t0=$(date +%s) rc=0
    (cd "$work" && "$@") > "$work/keep/$step.out" 2>&1 || rc=$?
    local dt=$(( $(date +%s) - t0 ))
    echo "$dt" > "$work/.time/$step"
    local err
    err=$(step_error "$step")
    if [ "$rc" = 124 ]; then
      fail "$step" "$rc" "timed out after ${step_timeout} s"
    elif [ "$rc" != 0 ] || [ -n "$err" ]; then
      [ -n "$err" ] || err=$(grep -m1 -i 'error' "$work/keep/$step.out" || tail -1 "$work/keep/$step.out")
      fail "$step" "$rc" "$err"
    else
      echo "$key" > "$work/.done/$step"
      echo "$prog: $step done in $dt s"
    fi
  fi
  [ -n "$until" ] && [ "$step" = "$until" ] && stopped=1
  return 0
}
tool() { nice -n "$niceness" timeout "$step_timeout" "$@"; }
qf() { # qflow STEP: run it, keep a copy of its log (later qflow steps delete earlier logs)
  local s=$1 log=$2 rc=0
  tool qflow -T "$tech" "$s" "$top" || rc=$?
  [ -z "$log" ] || [ ! -f "log/$log" ] || cp "log/$log" "keep/$log"
  return $rc
}
# A qflow step can exit 0 and still have failed: look for its own error lines.
step_error() {
  local o="$work/keep/$1.out"
  case "$1" in
    synthesize) grep -m1 -E 'Errors detected|ERROR:|failure|Premature exit' "$o" ;;
    place) grep -m1 -E 'Premature exit|failure|Error' "$o" | grep -v 'LEF Read' ;;
    route) grep -q 'Final: No failed routes!' "$o" || grep -m1 -E 'Final: Failed net routes|Premature exit|failure|Error' "$o" || echo "qrouter did not report 'Final: No failed routes!'" ;;
    drc) grep -q '^drc = ' "$work/keep/drc.log" 2>/dev/null || echo "no 'drc = N' line in drc.log" ;;
    lvs) grep -q 'Total errors = 0' "$work/keep/lvs.log" 2>/dev/null || grep -m1 -E 'Total errors = [1-9]|Netlists do not match' "$work/keep/lvs.log" 2>/dev/null || echo "no LVS result in lvs.log" ;;
    gdsii) grep -m1 -E 'Cannot open .*GDS' "$work/keep/gdsii.log" 2>/dev/null ;;
    opensta_spef) grep -q 'slack (' "$work/keep/opensta_spef.txt" 2>/dev/null || echo "no slack in OpenSTA output" ;;
  esac
}

# --- steps -----------------------------------------------------------------------------
step_source() {
  local keepdir
  if [ -n "$source_v" ]; then
    cp "$source_v" "source/$unit.v" && echo "$unit" > top && cp "$source_v" "keep/$unit.v" || return 1
    write_project_vars
    return 0
  fi
  tool "$rayunits" synth "$unit" "${unit_args[@]}" --generic-only --keep --json keep/generic.json > keep/rayunits_synth.txt 2>&1 || return $?
  cat keep/rayunits_synth.txt
  top=$(sed -n '1s/^\(ru_[A-Za-z0-9_]*\): .*/\1/p' keep/rayunits_synth.txt)
  [ -n "$top" ] || { echo "error: no top module on the first line of rayunits synth output"; return 1; }
  echo "$top" > top
  keepdir=$(sed -n 's/^ *kept *//p' keep/rayunits_synth.txt | tail -1)
  [ -f "$keepdir/generic.ys" ] || { echo "error: no kept directory in rayunits output"; return 1; }
  cp "$keepdir"/*.sv "$keepdir/generic.ys" "$keepdir/generic.log" keep/ 2>/dev/null
  cp "$keepdir"/ltp.txt keep/ 2>/dev/null
  {
    grep '^read_verilog' "$keepdir/generic.ys"
    echo "hierarchy -check -top $top"
    echo "proc; flatten; opt; rename -hide w:* x:* %d; opt_clean -purge"
    echo "check -assert"
    echo "write_verilog -noattr source/$top.v"
  } > keep/flatten.ys
  tool yosys -q -l keep/flatten.log -s keep/flatten.ys || return $?
  rm -rf "$keepdir"
  write_project_vars
}
write_project_vars() {
  # qflow options: OpenSTA and vesta both; the SDC uses the unit's clock port clk_i.
  cat > project_vars.sh <<EOF
#!/usr/bin/tcsh -f
# written by synth/pnr/run_pnr.sh
set run_opensta = 1
set run_vesta = 1
set vesta_options = "--period $(awk "BEGIN{print $clock_ns*1000}") --long"
EOF
}
step_sdc() {
  cat > synthesis/$top.sdc <<EOF
create_clock -name clk -period $clock_ns [get_ports clk_i]
set_input_delay 0 -clock clk [delete_from_list [all_inputs] [get_ports clk_i]]
set_output_delay 0 -clock clk [all_outputs]
EOF
  sed -i "s/^set vesta_options = .*/set vesta_options = \"--period $(awk "BEGIN{print $clock_ns*1000}") --long\"/" project_vars.sh
}
step_sta() {
  step_sdc
  qf sta sta.log || return $?
  # OpenSTA's part of the qflow log, max paths per group (qflow reports min_max x 1000)
  own_sta pre > keep/opensta_pre.txt 2>&1
}
step_backanno() {
  step_sdc
  qf backanno post_sta.log || return $?
  cp keep/backanno.out keep/opensta_sdf_qflow.txt 2>/dev/null
  own_sta sdf > keep/opensta_sdf.txt 2>&1
}
own_sta() { # pre | sdf | spef
  local mode=$1
  (
    cd synthesis || exit 1
    {
      echo "read_liberty $techdir/osu018_stdcells.lib"
      echo "read_verilog $top.rtlnopwr.v"
      echo "link_design $top"
      case $mode in
        sdf) echo "read_sdf $top.sdf" ;;
        spef) echo "read_spef ${top}_fixed.spef" ;;
      esac
      echo "read_sdc $top.sdc"
      echo "report_checks -path_delay max -group_count 1 -digits 3"
      echo "report_wns -digits 3"
      echo "report_tns -digits 3"
      echo "exit"
    } > own_sta_$mode.tcl
    tool sta own_sta_$mode.tcl
  )
}
step_opensta_spef() {
  step_sdc
  local r
  r=$("$py" "$here/fix_spef.py" synthesis/$top.spef synthesis/${top}_fixed.spef synthesis/$top.rtlnopwr.v) || return 1
  { echo "spef_fix: $r"; own_sta spef; } > keep/opensta_spef.txt 2>&1
  cat keep/opensta_spef.txt
}

run_step source 1 -- step_source
top=$(cat "$work/top" 2>/dev/null || echo "")
[ -n "$top" ] || { echo "$prog: error: source step failed: $(cat "$work/failures.txt" 2>/dev/null)" >&2; exit 1; }
run_step synthesize 1 source -- qf synthesize synth.log
step_place() {
  # qflow copies the technology's .par into layout/ when it is missing or older
  [ -f layout/$top.par ] || cp "$techdir/$tech.par" layout/$top.par
  sed -i '/^TWSC\*fast/d' layout/$top.par
  [ "$gw_fast" = 0 ] || echo "TWSC*fast : $gw_fast" >> layout/$top.par
  sed -i "s/^TWSC\*do\.global\.route.*/TWSC*do.global.route  : $gw_groute/" layout/$top.par
  sed -i '/^set initial_density/d' project_vars.sh
  [ -z "$density" ] || echo "set initial_density = $density" >> project_vars.sh
  qf place place.log || return $?
  cp layout/$top.par keep/graywolf.par
  [ ! -f layout/$top.out ] || grep -E '^ *-?[0-9]+: [0-9.e+]+ ' layout/$top.out > keep/graywolf_iterations.txt
}
run_step place "graywolf_fast=$gw_fast groute=$gw_groute density=$density" synthesize -- step_place
run_step sta "clock=$clock_ns" place -- step_sta
step_route() {
  # qflow's placement writes the router script; its last argument is standard_route's nocleanup
  sed -i "s/^\(qrouter::standard_route [^ ]* false\).*/\1$([ "$route_cleanup" = true ] || echo ' true')/" layout/$top.cfg
  qf route route.log
}
run_step route "$([ "$route_cleanup" = true ] && echo 1 || echo nocleanup)" place -- step_route
run_step backanno "clock=$clock_ns" route -- step_backanno
run_step opensta_spef "clock=$clock_ns" backanno -- step_opensta_spef
if [ "$checks" = 1 ]; then
  run_step migrate 1 route -- qf migrate migrate.log
  run_step drc 1 migrate -- qf drc drc.log
  run_step lvs 1 migrate -- qf lvs lvs.log
  run_step gdsii 1 migrate -- qf gdsii gdsii.log
fi

# --- report ----------------------------------------------------------------------------
steps_json=$(for s in $all_steps; do
  t=$(cat "$work/.time/$s" 2>/dev/null || echo null)
  st=skipped; [ -f "$work/.done/$s" ] && st=ok
  grep -q "^$s rc=" "$work/failures.txt" 2>/dev/null && st=failed
  printf '"%s": {"status": "%s", "wall_s": %s},' "$s" "$st" "$t"
done | sed 's/,$//')
failures_json=$("$py" -c 'import json,sys; print(json.dumps([l.rstrip("\n") for l in open(sys.argv[1])] if __import__("os").path.exists(sys.argv[1]) else []))' "$work/failures.txt")
ver() { dpkg-query -W -f='${Version}' "$1" 2>/dev/null || echo unknown; }
generic_json=$(cat "$work/keep/generic.json" 2>/dev/null || echo null)
total_s=0; for s in $all_steps; do t=$(cat "$work/.time/$s" 2>/dev/null || echo 0); total_s=$((total_s + t)); done
cat > "$work/meta.json" <<EOF
{
  "unit": "$unit",
  "config": "$config",
  "top": "$top",
  "work_dir": "$work",
  "library": "osu018 (OSU 0.18 um standard cells, qflow-tech-osu018 $(ver qflow-tech-osu018))",
  "clock_ns": $clock_ns,
  "graywolf_fast": $gw_fast,
  "graywolf_global_route": "$gw_groute",
  "route_cleanup": $route_cleanup,
  "initial_density": "${density:-unset}",
  "clock_target_mhz": $(awk "BEGIN{printf \"%.1f\", 1000/$clock_ns}"),
  "command": "synth/pnr/run_pnr.sh --clock-ns $clock_ns$( [ "$gw_fast" = 0 ] || echo " --graywolf-fast $gw_fast")$( [ -z "$density" ] || echo " --density $density")$( [ "$route_cleanup" = true ] || echo " --route-no-cleanup")$( [ -z "$source_v" ] || echo " --source-v $source_v") $config",
  "tools": {"qflow": "$(ver qflow)", "yosys": "$(ver yosys)", "graywolf": "$(ver graywolf)",
            "qrouter": "$(ver qrouter)", "magic": "$(ver magic)", "netgen-lvs": "$(ver netgen-lvs)",
            "opensta": "$(ver opensta)", "vesta": "qflow $(ver qflow)"},
  "sta_tools": "qflow sta/backanno steps run both OpenSTA (run_opensta=1) and vesta (run_vesta=1); the headline post-route numbers are OpenSTA on the repaired SPEF",
  "steps": {$steps_json},
  "failures": $failures_json,
  "wall_time_steps_s": $total_s,
  "generic": $generic_json
}
EOF
"$py" "$here/pnr_report.py" --work "$work" --top "$top" --out "$out" --meta "$work/meta.json" || echo "$prog: report failed" >&2
# small logs worth keeping
for f in rayunits_synth.txt flatten.ys synth.log graywolf.par graywolf_iterations.txt place.log sta.log route.log post_sta.log opensta_pre.txt \
         opensta_sdf.txt opensta_spef.txt migrate.log drc.log lvs.log gdsii.log failures.txt; do
  src="$work/keep/$f"; [ "$f" = failures.txt ] && src="$work/failures.txt"
  [ -f "$src" ] || continue
  sz=$(stat -c %s "$src")
  if [ "$f" = gdsii.log ]; then  # thousands of identical "Cell X is unavailable" lines
    { grep -v 'is unavailable.  It could not be expanded' "$src" | head -c 30000
      echo "[run_pnr.sh: $(grep -c 'is unavailable' "$src") lines 'Cell X is unavailable.  It could not be expanded.' removed; cells: $(sed -n 's/^Cell \([^ ]*\) is unavailable.*/\1/p' "$src" | sort -u | tr '\n' ' ')]"
    } > "$out/logs/$f"
  elif [ "$sz" -gt 40000 ]; then  # keep the head and the tail of a large log
    { head -c 12000 "$src"; printf '\n\n[... %s bytes in all; the middle cut by run_pnr.sh ...]\n\n' "$sz"; tail -c 24000 "$src"; } > "$out/logs/$f"
  else
    cp "$src" "$out/logs/$f"
  fi
done
cp "$work/keep/$top.sv" "$out/logs/" 2>/dev/null
echo "$prog: wrote $out/summary.json ($(( $(date +%s) - t0_total )) s this call; steps total ${total_s} s)"
if [ -n "$archive" ]; then
  command -v xz >/dev/null 2>&1 || die "missing tool 'xz' (Debian package xz-utils)"
  echo "$work" > "$work/archived_from"
  mkdir -p "$(dirname "$archive")"
  tmp="$archive.tmp.$$"
  if tar -C "$work" --exclude='./layout/*.cel' --exclude='./layout/*.cel.bak' --exclude='./layout/*.scel' \
       --exclude='./layout/*.pin' --exclude='./layout/*.pth' --exclude='./layout/*.sav' -cf - . | xz -T1 -6 > "$tmp"; then
    mv "$tmp" "$archive"
    echo "$prog: archived the work directory to $archive ($(stat -c %s "$archive") bytes; done: $(ls "$work/.done" | tr '\n' ' '))"
  else
    rm -f "$tmp"; echo "$prog: error: writing the archive $archive failed" >&2; exit 1
  fi
fi
[ -s "$work/failures.txt" ] && { echo "$prog: failures:"; cat "$work/failures.txt"; exit 1; }
exit 0
