#!/usr/bin/python3
"""Resumable driver for the standard-cell (osu018) measurements of issue 13, sections 4 and 5.

Every measurement is one `rayunits synth ... --flow osu018 --clock LIST --json FILE` run (or, for
the labelled NAND2-eq estimate column, one `--generic-only` run). Each run writes
synth/results/cell/<name>.jsonl: first to a hidden temp name, renamed when the run succeeded, so
nothing half-written remains; a run whose output exists is skipped, so the driver resumes across
sessions. A failed run leaves <name>.failed.json (command, exit status, last stderr lines, wall
time) and is not retried unless --retry-failed. Each row gets "point" (the run's name),
"command" (the exact command, binary written as `rayunits`) and "built_from".

Run kinds (in priority order; -j N workers take the first runnable one):
  ends   --clock 200ps,1000ns: the fastest mapping ABC finds (every target below a unit's minimum
         delay gives the same netlist, so 200 ps stands for "as fast as possible") and the
         smallest (a target far above the delay: area-oriented mapping).
  curve  targets between those ends: the achieved periods of the fast (P0) and relaxed (P1) ends,
         P0 + {0.25, 0.5, 0.75} (P1 - P0) (none when P1 < 1.02 P0); needs the point's `ends` run.
  match  one unit at one clock T: the smallest Stages with a mapping (at T or at T - 500 ps: ABC's
         target does not include the registers' clock-to-Q and setup) whose STA period is <= T, by
         bisection between the Stages the `ends` runs bracket; rows of every Stages tried.
  generic  --generic-only (NAND2-eq estimate, fo4-v1 depth), beside the cell rows.

Usage: /usr/bin/python3 synth/cell/run.py [-j 2] [--only REGEX] [--list] [--retry-failed]
                                          [--rayunits PATH] [--built-from TEXT]
Then: /usr/bin/python3 synth/cell/tables.py (tables .md and the area-delay plot).
"""
import argparse
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "synth", "results", "cell")

FAST_PS = 200
RELAXED_PS = 1000000
CURVE_FRACTIONS = (0.25, 0.5, 0.75)

# Maximum useful Stages of (unit, format), asked from the binary (the registry, checked against the
# RTL by ctest Registry.MaxUsefulStagesMatchRtl): `rayunits synth U --format F --stages 1000`
# fails with "... supports --stages 0..N". Filled by max_stages().
RAYUNITS = None
_MAX_STAGES = {}


def max_stages(unit, fmt):
    key = (unit, fmt)
    if key not in _MAX_STAGES:
        cmd = [RAYUNITS, "synth", unit] + (["--format", fmt] if fmt else []) + ["--stages", "1000", "--generic-only"]
        p = subprocess.run(cmd, capture_output=True, text=True)
        m = re.search(r"supports --stages (\d+)\.\.(\d+)", p.stderr)
        if not m:
            sys.exit(f"run.py: cannot read the maximum Stages of {unit} {fmt or ''} from {RAYUNITS}: {p.stderr.strip()}")
        _MAX_STAGES[key] = int(m.group(2))
    return _MAX_STAGES[key]

FP_UNITS = ["fp_add", "fp_mul", "fp_div", "fp_sqrt", "fp_fma", "fp_cmp", "fp_dot3", "fp_dot3_fused", "fp_cvt"]
FORMATS = ["e5m10", "e7m16", "e8m23"]
# Clocks (ps) of the matched-clock comparison (noise vs fp_add + fp_mul vs fp_dot3, e8m23).
# (fp_mul e8m23 reaches 5.55 ns at best, so 5 ns cannot be matched; noise reaches 5.9 ns at Stages 5.)
MATCH_CLOCKS = [6500, 9000]
MATCH_MARGIN_PS = 500
MATCH_UNITS = [("noise", None), ("fp_add", "e8m23"), ("fp_mul", "e8m23"), ("fp_dot3", "e8m23"), ("noise_trunc", None)]
NOISE_UNITS = ["noise", "noise_trunc"]  # Kensler's datapath and the truncated one (issue 15)
# Register placement by depth estimates vs by measured delays (synth --placement delay), at equal
# Stages, fastest mapping: the units with their own placement and these Stages (below the maximum).
PLACE_UNITS = ["fp_add", "fp_mul", "fp_div", "fp_cmp"]


def place_stage_list(unit, fmt):
    m = max_stages(unit, fmt)
    return sorted(s for s in {1, 2, 3, 4, m // 2} if 0 < s < m)


def pname(unit, fmt, stages):
    return f"{unit}_{fmt}_s{stages}" if fmt else f"{unit}_s{stages}"


def fp_stage_list(unit, fmt):
    m = max_stages(unit, fmt)
    return sorted({0, m // 2, m})


def timeout_for(unit, fmt):
    if unit.startswith("ray_tri"):
        return 4 * 3600
    if unit in ["ray_box"] + NOISE_UNITS:
        return 3600
    return 1800


def make_runs():
    """The run list, highest priority first."""
    runs = []

    def ends(unit, fmt, s, split=False, params=None):
        # params: RTL options (--param NAME=V), named in the point (ray_box_e8m23_s0_OptConservative2)
        tag = "".join(f"_{k}{v}" for k, v in (params or {}).items())
        base = dict(unit=unit, fmt=fmt, stages=s, timeout=timeout_for(unit, fmt), point=pname(unit, fmt, s) + tag)
        if params:
            base["extra"] = [a for k, v in params.items() for a in ("--param", f"{k}={v}")]
        if split:  # the big units: the relaxed (area) end first, each its own run
            runs.append(dict(base, kind="ends", name=base["point"] + ".relaxed", clocks=[RELAXED_PS], big=True))
            runs.append(dict(base, kind="ends", name=base["point"] + ".fast", clocks=[FAST_PS], big=True))
        else:
            runs.append(dict(base, kind="ends", name=base["point"] + ".ends", clocks=[FAST_PS, RELAXED_PS]))

    def curve(unit, fmt, s):
        p = pname(unit, fmt, s)
        runs.append(dict(unit=unit, fmt=fmt, stages=s, timeout=timeout_for(unit, fmt), point=p, kind="curve",
                         name=p + ".curve", needs=[p + ".ends"]))

    def generic(unit, fmt, s):
        p = pname(unit, fmt, s)
        runs.append(dict(unit=unit, fmt=fmt, stages=s, timeout=timeout_for(unit, fmt), point=p, kind="generic",
                         name=p + ".generic"))

    def placement(unit, fmt, s):
        p = pname(unit, fmt, s)
        for how in ("depth", "delay"):
            runs.append(dict(unit=unit, fmt=fmt, stages=s, timeout=timeout_for(unit, fmt), point=p, kind="ends",
                             name=f"{p}.place_{how}", clocks=[FAST_PS],
                             extra=["--placement", how] if how == "delay" else ["--stage-periods"]))

    def each_point(add):  # the FP units at their Stages list, then the noise units Stages 1..max
        for u in FP_UNITS:
            for f in FORMATS:
                for s in fp_stage_list(u, f):
                    add(u, f, s)
        for n in NOISE_UNITS:
            for s in range(1, max_stages(n, None) + 1):
                add(n, None, s)

    each_point(ends)
    for clk in MATCH_CLOCKS:
        for u, f in MATCH_UNITS:
            smax = max_stages(u, f)
            st = range(1, smax + 1) if u in NOISE_UNITS else fp_stage_list(u, f)
            runs.append(dict(unit=u, fmt=f, stages=None, smax=smax, clock=clk, kind="match",
                             timeout=timeout_for(u, f), point=None,
                             needs=[pname(u, f, s) + ".ends" for s in st],
                             name=f"match_{u}{'_' + f if f else ''}_{clk}ps"))
    each_point(generic)
    # The ray units next (at most one ray-triangle run at a time: the other worker does the curves).
    ends("ray_box", "e8m23", 0)
    ends("ray_box", "e8m23", 7)
    ends("ray_box", "e8m23", 26)
    # the conservative (1) and d-conservative (2) slab tests (issue 14 section 4): their cost
    for mode in (1, 2):
        for s in (0, 7):
            ends("ray_box", "e8m23", s, params={"OptConservative": mode})
    tri = len(runs)
    ends("ray_tri_mt", "e8m23", 0, split=True)
    ends("ray_tri_robust", "e8m23", 0, split=True)
    ends("ray_tri_mt", "e8m23", 33, split=True)
    ends("ray_tri_robust", "e8m23", 29, split=True)
    # the one-reciprocal robust variant (issue 14 section 3) beside the literal one and MT
    ends("ray_tri_robust", "e8m23", 0, split=True, params={"OptRecip": 1})
    # the exactly-once unit (issue 14 section 1: fast pipeline, filter, order buffer, exact side
    # path) beside ru_ray_tri_robust at equal Stages; not at Stages 0 (Yosys/ABC ran out of 22 GB
    # on its one combinational cone)
    ends("ray_tri_exact", "e5m10", 6, split=True)
    ends("ray_tri_robust", "e5m10", 6, split=True)
    ends("ray_tri_exact", "e8m23", 29, split=True)
    # the side path's digit step bounds the clock (ru_exact_path e5m10: 36.6 ns at DigitW 16, 21.8 ns
    # at DigitW 4): the whole unit with the narrow digit
    ends("ray_tri_exact", "e5m10", 6, split=True, params={"DigitW": 4})
    ends("ray_box", "e7m16", 0)
    ends("ray_tri_mt", "e7m16", 0, split=True)
    ends("ray_tri_robust", "e7m16", 0, split=True)
    # every relaxed (area) end of the ray-triangle units before any fast end: the area ratio first
    runs[tri:] = sorted(runs[tri:], key=lambda r: 0 if r["name"].endswith(".relaxed") else 1)
    each_point(curve)
    for u in PLACE_UNITS:
        for f in FORMATS:
            for s in place_stage_list(u, f):
                placement(u, f, s)
    # Stages 0 of the noise unit: Yosys's elaboration of ru_noise (hierarchy, AST derive) ran 23 min
    # without finishing here, where Stages 1..7 take about a minute: last, with a long time limit.
    for n in NOISE_UNITS:
        ends(n, None, 0)
        runs[-1]["timeout"] = 3 * 3600
        curve(n, None, 0)
        generic(n, None, 0)
    return runs


def out_path(name):
    return os.path.join(OUT, name + ".jsonl")


def failed_path(name):
    return os.path.join(OUT, name + ".failed.json")


def read_rows(path):
    with open(path) as f:
        return [json.loads(l) for l in f if l.strip()]


def synth_cmd(rayunits, run, stages, clocks, json_path, generic=False):
    cmd = [rayunits, "synth", run["unit"]]
    if run["fmt"]:
        cmd += ["--format", run["fmt"]]
    cmd += ["--stages", str(stages)]
    if generic:
        cmd += ["--generic-only"]
    else:
        cmd += ["--flow", "osu018"]
        if clocks:
            cmd += ["--clock", ",".join(f"{int(round(c))}ps" for c in clocks)]
    cmd += run.get("extra", [])
    cmd += ["--timeout", str(run["timeout"]), "--json", json_path]
    return cmd


def shown(cmd, json_name):
    c = ["rayunits"] + cmd[1:]
    c[-1] = json_name
    return " ".join(shlex.quote(x) for x in c)


class Driver:
    def __init__(self, args):
        self.args = args
        self.lock = threading.Lock()
        self.log_lock = threading.Lock()
        self.procs = {}
        self.stop = False

    def log(self, msg):
        with self.log_lock:
            print(time.strftime("%H:%M:%S"), msg, flush=True)

    def one_synth(self, run, stages, clocks, tmp, generic=False):
        """Runs one synth; returns (rows, seconds) or raises RuntimeError with the details."""
        cmd = synth_cmd(self.args.rayunits, run, stages, clocks, tmp, generic)
        show = shown(cmd, os.path.basename(out_path(run["name"])))
        t0 = time.time()
        # Own process group, so that an interrupt or the overall limit ends the tools it started too.
        p = subprocess.Popen(["nice", "-n", "10"] + cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                             start_new_session=True)
        with self.lock:
            self.procs[run["name"]] = p
        try:
            _, err = p.communicate(timeout=run["timeout"] * max(1, len(clocks or [1])) + 600)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGTERM)
            try:
                p.wait(15)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
            _, err = p.communicate()
            err = (err or "") + "\n(driver: killed after its overall time limit)"
        finally:
            with self.lock:
                self.procs.pop(run["name"], None)
        dt = time.time() - t0
        if p.returncode != 0 or not os.path.exists(tmp):
            raise RuntimeError(json.dumps({"command": show, "exit_status": p.returncode, "seconds": round(dt, 1),
                                           "stderr_tail": (err or "").strip().splitlines()[-8:]}))
        rows = read_rows(tmp)
        os.unlink(tmp)
        for r in rows:
            r["point"] = run["name"]
            r["command"] = show
            r["driver_seconds"] = round(dt, 1)
            if self.args.built_from:
                r["built_from"] = self.args.built_from
        return rows, dt

    def with_abc_retry(self, run, stages, clocks, tmp):
        """one_synth; when ABC dies on one target (buffer/upsize: 'node N has no fanout', Yosys then
        "Can't open ABC output file"), that target is replaced and the run repeated (at most 3 times):
        the fast end's 200 ps by 500, 1000, 2000 ps; any other target by 3 % more. The rows say so."""
        notes = []
        for attempt in range(4):
            try:
                rows, dt = self.one_synth(run, stages, clocks, tmp)
                for r in rows:
                    if notes:
                        r["driver_note"] = "; ".join(notes)
                return rows, dt
            except RuntimeError as e:
                info = json.loads(str(e))
                m = re.search(r"abc -liberty -D (\d+)\) failed.*Can't open ABC output file", " ".join(info["stderr_tail"]))
                if not m or attempt == 3:
                    raise
                bad = int(m.group(1))
                ladder = [200, 500, 1000, 2000]
                new = ladder[ladder.index(bad) + 1] if bad in ladder[:-1] else int(round(bad * 1.03))
                clocks = [new if int(round(c)) == bad else c for c in clocks]
                notes.append(f"ABC failed at -D {bad} (buffer/upsize: 'node N has no fanout'); replaced by {new} ps")
                self.log(f"  {run['name']}: ABC failed at -D {bad}; retrying with {new} ps")

    def execute(self, run):
        name = run["name"]
        final = out_path(name)
        tmp = os.path.join(OUT, "." + name + ".tmp")
        rows = []
        if run["kind"] == "ends":
            rows, dt = self.with_abc_retry(run, run["stages"], run["clocks"], tmp)
        elif run["kind"] == "generic":
            rows, dt = self.one_synth(run, run["stages"], [], tmp, generic=True)
        elif run["kind"] == "curve":
            a = read_rows(out_path(run["needs"][0]))
            fast = min(r["period_ps"] for r in a)
            slow = max(r["period_ps"] for r in a)
            clocks = [round((fast + f * (slow - fast)) / 10) * 10 for f in CURVE_FRACTIONS] if slow > 1.02 * fast else []
            if not clocks:  # the two ends are within 2 %: nothing between them
                rows, dt = [{"point": name, "unit": run["unit"], "format": run["fmt"], "stages": run["stages"],
                             "note": "no curve: the fast and relaxed ends are within 2 % in period",
                             "fast_period_ps": fast, "relaxed_period_ps": slow}], 0.0
            else:
                rows, dt = self.with_abc_retry(run, run["stages"], clocks, tmp)
        elif run["kind"] == "match":
            # Smallest Stages that meets the clock, by bisection between lo (above every Stages whose
            # measured fastest mapping misses it) and hi (the smallest measured Stages whose fastest
            # mapping meets it, else the maximum); assumes the achievable period falls with Stages.
            clk = run["clock"]
            lo, hi = 0, run["smax"]
            for s in range(run["smax"] + 1):
                p = out_path(pname(run["unit"], run["fmt"], s) + ".ends")
                if os.path.exists(p):
                    fast = min(r["period_ps"] for r in read_rows(p))
                    if fast > clk:
                        lo = max(lo, s + 1)
                    elif s < hi and s >= lo:
                        hi = s
            dt, first = 0.0, (lo, hi)
            tried = {}
            while lo <= run["smax"] and (lo < hi or lo not in tried):
                s = (lo + hi) // 2 if lo < hi else lo
                # ABC's -D does not see the harness registers' clock-to-Q and setup (~0.4 ns), so a
                # mapping at the clock itself can miss it by a little where a tighter one meets it
                # (noise Stages 5: 6,564 ps at a 6,500 ps target, 5,942 ps at 200 ps): each Stages is
                # mapped at the clock and MATCH_MARGIN_PS below it; it meets the clock when either
                # mapping's STA period is within it.
                r1, d1 = self.with_abc_retry(run, s, [clk, clk - MATCH_MARGIN_PS], tmp)
                dt += d1
                for r in r1:
                    r["meets_match_clock"] = r["period_ps"] <= clk
                rows += r1
                ok = any(r["meets_match_clock"] for r in r1)
                tried[s] = ok
                self.log(f"  {name}: Stages {s}: periods {[r['period_ps'] for r in r1]} ps, meets {clk} ps: {ok}")
                if ok:
                    hi = s
                else:
                    lo = s + 1
            if not any(r.get("meets_match_clock") for r in rows):
                rows.append({"unit": run["unit"], "format": run["fmt"], "match_clock_ps": clk, "point": name,
                             "note": f"no Stages up to {run['smax']} meets {clk} ps (measured fastest mappings)"})
            for r in rows:
                r["match_clock_ps"] = clk
                r["match_search"] = f"bisection over Stages {first[0]}..{first[1]}"
        with open(tmp, "w") as f:
            for r in rows:
                f.write(json.dumps(r, sort_keys=True) + "\n")
        os.replace(tmp, final)
        if os.path.exists(failed_path(name)):
            os.unlink(failed_path(name))
        return dt

    def main(self):
        os.makedirs(OUT, exist_ok=True)
        runs = make_runs()
        if self.args.only:
            runs = [r for r in runs if re.search(self.args.only, r["name"])]
        if self.args.list:
            for r in runs:
                st = "done" if os.path.exists(out_path(r["name"])) else (
                    "failed" if os.path.exists(failed_path(r["name"])) else "todo")
                print(f"{st:6} {r['name']}")
            return 0
        todo = [r for r in runs if not os.path.exists(out_path(r["name"])) and
                (self.args.retry_failed or not os.path.exists(failed_path(r["name"])))]
        self.log(f"{len(todo)} runs to do of {len(runs)} (-j {self.args.jobs})")
        running = set()
        todo_all = list(todo)
        cv = threading.Condition()
        failures = []

        def gone(n, pending):  # not done and never going to be (failed, or not in this run)
            return not os.path.exists(out_path(n)) and (os.path.exists(failed_path(n)) or n not in pending)

        def ready(r):  # a match only uses its needs to skip Stages: a failed one does not stop it
            pending = {x["name"] for x in todo} | running
            return all(os.path.exists(out_path(n)) or (r["kind"] == "match" and gone(n, pending))
                       for n in r.get("needs", []))

        def blocked(r):  # a needed run failed or is not going to run: give up on r
            pending = {x["name"] for x in todo} | running
            return r["kind"] != "match" and any(gone(n, pending) for n in r.get("needs", []))

        def worker():
            while not self.stop:
                with cv:
                    while True:
                        todo[:] = [r for r in todo if not blocked(r)]
                        big_running = any(x.get("big") for x in todo_all if x["name"] in running)
                        pick = next((r for r in todo if ready(r) and not (r.get("big") and big_running)), None)
                        if pick or not todo:
                            break
                        cv.wait(5)
                    if not pick or self.stop:
                        return
                    todo.remove(pick)
                    running.add(pick["name"])
                self.log(f"start {pick['name']}")
                try:
                    dt = self.execute(pick)
                    self.log(f"done  {pick['name']} ({dt:.1f} s)")
                except RuntimeError as e:
                    if self.stop:
                        return
                    tmp = os.path.join(OUT, "." + pick["name"] + ".tmp")
                    if os.path.exists(tmp):
                        os.unlink(tmp)
                    with open(failed_path(pick["name"]), "w") as f:
                        f.write(str(e) + "\n")
                    failures.append(pick["name"])
                    self.log(f"FAIL  {pick['name']}: {str(e)[:300]}")
                with cv:
                    running.discard(pick["name"])
                    cv.notify_all()

        threads = [threading.Thread(target=worker, daemon=True) for _ in range(self.args.jobs)]
        try:
            for t in threads:
                t.start()
            for t in threads:
                while t.is_alive():
                    t.join(1)
        except KeyboardInterrupt:
            self.log("interrupted: killing running syntheses")
            self.stop = True
            with self.lock:
                procs = list(self.procs.values())
            # rayunits ends the tools it started on SIGINT/SIGTERM (SIGTERM: a background job started by a
            # non-interactive shell ignores SIGINT);
            # SIGKILL only after a grace period.
            for p in procs:
                try:
                    os.killpg(p.pid, signal.SIGTERM)
                except ProcessLookupError:
                    pass
            t0 = time.time()
            while time.time() - t0 < 15 and any(p.poll() is None for p in procs):
                time.sleep(0.2)
            for p in procs:
                if p.poll() is None:
                    os.killpg(p.pid, signal.SIGKILL)
            return 130
        self.log(f"finished; {len(failures)} failed: {' '.join(failures)}")
        return 1 if failures else 0


def _on_term(signum, frame):
    raise KeyboardInterrupt


def main():
    # SIGTERM and SIGINT both stop the driver cleanly (running syntheses are ended, nothing renamed).
    signal.signal(signal.SIGTERM, _on_term)
    signal.signal(signal.SIGINT, _on_term)
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-j", "--jobs", type=int, default=2, help="runs at once (at most 2 on the shared machine)")
    ap.add_argument("--only", help="regular expression: only runs whose name matches")
    ap.add_argument("--list", action="store_true", help="list runs and their state")
    ap.add_argument("--retry-failed", action="store_true")
    ap.add_argument("--rayunits", default=os.path.join(ROOT, "build", "model", "cli", "rayunits"))
    ap.add_argument("--built-from", default="", help="recorded in every row (which sources the binary was built from)")
    args = ap.parse_args()
    args.jobs = max(1, min(args.jobs, 2))
    global RAYUNITS
    RAYUNITS = args.rayunits
    return Driver(args).main()


if __name__ == "__main__":
    sys.exit(main())
