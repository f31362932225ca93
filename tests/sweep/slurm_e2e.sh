#!/usr/bin/env bash
# A real single-node Slurm for `rayunits sweep --emit-slurm` (issue 17 §2; ctest label `long`).
#
# Usage: tests/sweep/slurm_e2e.sh RAYUNITS_BINARY
#
# Generates a munge key and a minimal slurm.conf in a temporary directory (this machine's name,
# cores and memory; proctrack/linuxproc, task/none, jobacct_gather/none so that it runs in a
# container), starts munged, slurmctld and slurmd from it, then:
#   1. runs a small grid locally (`rayunits sweep --out`),
#   2. emits the same grid for Slurm, submits sweep.sbatch, cancels one array task while it runs
#      (scancel JOB_3), waits, collects: the cancelled task must be reported missing, rerun.sbatch
#      must name exactly it, and the other rows must equal the local run's,
#   3. submits rerun.sbatch, waits, collects again: every row equals the local run's, exit 0.
# Every daemon it started is stopped on exit (trap). Exit 77 (ctest SKIP_RETURN_CODE) only when
# not root or a package is missing, saying which.
set -euo pipefail

RU=${1:?usage: slurm_e2e.sh RAYUNITS_BINARY}
RU=$(readlink -f "$RU")
skip() { echo "slurm_e2e: SKIP: $*" >&2; exit 77; }
[[ $(id -u) -eq 0 ]] || skip "not root (the daemons run as root here: SlurmUser=root)"
for c in munged mungekey slurmctld slurmd sbatch squeue scancel scontrol sinfo python3; do
  command -v "$c" >/dev/null || skip "'$c' not found: scripts/install-deps.sh --long (slurm-wlm munge)"
done
[[ -x $RU ]] || { echo "slurm_e2e: no rayunits binary '$RU'" >&2; exit 1; }

t_start=$(date +%s)
T=$(mktemp -d /tmp/ru-slurm-e2e.XXXXXX)
chmod 711 "$T"  # munged wants its socket directory reachable (x) and not writable by others
PIDS=()
say() { echo "slurm_e2e: [$(( $(date +%s) - t_start ))s] $*"; }
cleanup() {
  local rc=$?
  set +e
  if [[ -n ${JOBS_SUBMITTED:-} ]]; then scancel $JOBS_SUBMITTED 2>/dev/null; fi
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do kill "${PIDS[i]}" 2>/dev/null; done
  for p in "${PIDS[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$p" 2>/dev/null
    wait "$p" 2>/dev/null
  done
  if ((rc != 0 && rc != 77)); then
    echo "slurm_e2e: FAILED (exit $rc); logs kept in $T:" >&2
    for f in "$T"/slurmctld.log "$T"/slurmd.log "$T"/munged.log; do
      [[ -f $f ]] && { echo "--- $f (last lines)" >&2; tail -n 15 "$f" >&2; }
    done
  else
    rm -rf "$T"
  fi
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# ---- munge ------------------------------------------------------------------------------------
mkdir -p "$T/munge"
chmod 711 "$T/munge"
mungekey --create --keyfile="$T/munge/munge.key" >/dev/null
chmod 400 "$T/munge/munge.key"
munged -F -f --key-file="$T/munge/munge.key" --socket="$T/munge/munge.sock" \
  --pid-file="$T/munge/munged.pid" --log-file="$T/munged.log" --seed-file="$T/munge/munged.seed" 2>"$T/munged.err" &
PIDS+=($!)
for _ in $(seq 100); do [[ -S $T/munge/munge.sock ]] && break; sleep 0.1; done
[[ -S $T/munge/munge.sock ]] || { echo "slurm_e2e: munged did not start" >&2; exit 1; }

# ---- slurm.conf --------------------------------------------------------------------------------
NODE=$(hostname -s)
CPUS=$(nproc)
MEM_MB=$(( $(awk '/^MemTotal:/ {print $2}' /proc/meminfo) / 1024 * 9 / 10 ))
PORT=$(( 20000 + ($$ % 20000) ))  # two ports of our own, not the default 6817/6818
mkdir -p "$T/state" "$T/spool"
export SLURM_CONF=$T/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=rue2e
SlurmctldHost=$NODE
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$PORT
SlurmdPort=$((PORT + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge/munge.sock
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
KillWait=5
MinJobAge=300
PlugStackConfig=$T/plugstack.conf
NodeName=$NODE CPUs=$CPUS RealMemory=$MEM_MB State=UNKNOWN
PartitionName=rue2e Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
: >"$T/plugstack.conf"
slurmctld -D -c -f "$SLURM_CONF" >>"$T/slurmctld.log" 2>&1 &
PIDS+=($!)
slurmd -D -f "$SLURM_CONF" >>"$T/slurmd.log" 2>&1 &
PIDS+=($!)
state=""
for _ in $(seq 120); do
  state=$(sinfo -h -n "$NODE" -o %t 2>/dev/null || true)
  [[ $state == idle ]] && break
  sleep 0.5
done
[[ $state == idle ]] || { echo "slurm_e2e: node $NODE not idle (state '$state')" >&2; exit 1; }
say "Slurm $(scontrol --version | awk '{print $2}') up: node $NODE, $CPUS CPUs, ${MEM_MB} MB;" \
  "$(scontrol show config | grep -E '^MaxArraySize' | tr -s ' ')"

# ---- the grid: three short ray-box studies and one longer one (the task that is cancelled) ----
cat >"$T/grid.toml" <<'EOF'
name = "slurm-e2e"
[[grid]]
kind = "study"
study = "box"
format = ["e5m10", "e6m12", "e7m16"]
synthetic = 3000
threads = 1
[[grid]]
kind = "study"
study = "box"
format = "e8m23"
synthetic = 1500000
threads = 1
EOF
"$RU" sweep "$T/grid.toml" --out "$T/local" -j 2 2>"$T/local.err" || { cat "$T/local.err" >&2; exit 1; }
say "local run done: $(tail -n 1 "$T/local.err")"

C=$T/cluster
"$RU" sweep "$T/grid.toml" --emit-slurm "$C" --max-parallel 2 --time 10 --mem 1000 --cpus 1
grep -qx '#SBATCH --array=0-3%2' "$C/sweep.sbatch" || { echo "slurm_e2e: unexpected array line" >&2; exit 1; }

wait_job() {  # until no element of job $1 is pending or running
  for _ in $(seq 600); do
    [[ -z $(squeue -h -j "$1" -o %i 2>/dev/null) ]] && return 0
    sleep 0.5
  done
  echo "slurm_e2e: job $1 still in the queue after 300 s" >&2
  squeue >&2
  return 1
}

# compare.py: the collected rows against the local run's, row for row (everything but the
# times, the log path's timestamps and the task's host/ids), and results.csv without wall_s.
cat >"$T/compare.py" <<'EOF'
import csv, json, sys
local, cluster, want = sys.argv[1], sys.argv[2], [int(x) for x in sys.argv[3].split(",")]
def rows(d):
    return {r["index"]: r for r in map(json.loads, open(d + "/results.jsonl")) }
L, C = rows(local), rows(cluster)
keys = ["hash", "index", "kind", "label", "params", "deps", "argv", "status", "exit", "error", "result", "log"]
if sorted(C) != want:
    sys.exit("collected indices %s, expected %s" % (sorted(C), want))
for i in want:
    for k in keys:
        if L[i].get(k) != C[i].get(k):
            sys.exit("row %d differs in %s: local %r, slurm %r" % (i, k, L[i].get(k), C[i].get(k)))
    if "SLURM_ARRAY_JOB_ID" not in C[i].get("task", {}):
        sys.exit("row %d did not run as a Slurm array task: %r" % (i, C[i].get("task")))
def table(d):
    t = list(csv.reader(open(d + "/results.csv")))
    w = t[0].index("wall_s")
    return [r[:w] + r[w + 1:] for r in t]
if len(want) == len(L):
    if table(local) != table(cluster):
        sys.exit("results.csv differs from the local run's")
print("%d rows equal to the local run's" % len(want))
EOF

# ---- submit, cancel task 3 while it runs ----------------------------------------------------------
JOB=$(sbatch --parsable "$C/sweep.sbatch")
JOBS_SUBMITTED=$JOB
say "submitted array job $JOB"
running=""
for _ in $(seq 600); do
  running=$(squeue -h -j "$JOB" -t R -o %i 2>/dev/null | grep -x "${JOB}_3" || true)
  [[ -n $running ]] && break
  [[ -z $(squeue -h -j "$JOB" -o %i 2>/dev/null) ]] && break
  sleep 0.2
done
[[ -n $running ]] || { echo "slurm_e2e: task ${JOB}_3 never seen running" >&2; exit 1; }
sleep 1
scancel "${JOB}_3"
say "cancelled ${JOB}_3 while it ran"
wait_job "$JOB"
set +e
"$RU" sweep --collect "$C" 2>"$T/collect1.err"
rc=$?
set -e
cat "$T/collect1.err"
[[ $rc -eq 1 ]] || { echo "slurm_e2e: collect exit $rc, expected 1 (a task missing)" >&2; exit 1; }
grep -q "task 3 (.*): missing" "$T/collect1.err" || { echo "slurm_e2e: task 3 not reported missing" >&2; exit 1; }
grep -q "3 ok, 0 failed, 1 missing" "$T/collect1.err" || { echo "slurm_e2e: wrong counts" >&2; exit 1; }
[[ ! -e $C/results/3.json ]] || { echo "slurm_e2e: the cancelled task wrote a result" >&2; exit 1; }
grep -qx '#SBATCH --array=3%2' "$C/rerun.sbatch" || { echo "slurm_e2e: rerun.sbatch does not name exactly task 3:" >&2; grep array "$C/rerun.sbatch" >&2; exit 1; }
python3 "$T/compare.py" "$T/local" "$C" 0,1,2
say "collect: task 3 missing, rerun.sbatch --array=3%2, rows 0-2 equal to the local run's"

# ---- the rerun array recovers it ----------------------------------------------------------------
JOB2=$(sbatch --parsable "$C/rerun.sbatch")
JOBS_SUBMITTED="$JOB $JOB2"
say "submitted rerun job $JOB2"
wait_job "$JOB2"
"$RU" sweep --collect "$C" 2>"$T/collect2.err" || { cat "$T/collect2.err" >&2; exit 1; }
cat "$T/collect2.err"
[[ ! -e $C/rerun.sbatch ]] || { echo "slurm_e2e: rerun.sbatch left after a complete collect" >&2; exit 1; }
python3 "$T/compare.py" "$T/local" "$C" 0,1,2,3
# Idempotent: collecting again gives the same files.
cp "$C/results.jsonl" "$T/r1.jsonl"
cp "$C/results.csv" "$T/r1.csv"
"$RU" sweep --collect "$C" 2>/dev/null
cmp -s "$C/results.jsonl" "$T/r1.jsonl" && cmp -s "$C/results.csv" "$T/r1.csv" ||
  { echo "slurm_e2e: a second collect changed the table" >&2; exit 1; }
say "PASS: rerun recovered task 3; all 4 rows equal to the local run's; collect idempotent"
