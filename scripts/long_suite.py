#!/usr/bin/env python3
"""Runs the long test suite (ctest label `long`) so that it can be resumed across sessions.

The whole long suite takes longer than one working session on the 2-core machine. This runner
records every finished test at once (one JSON line in a state file), so a stopped run loses only
the tests that were running, and the next invocation runs only what has not passed yet.

    scripts/long_suite.py --commit REV [-j N] [-R REGEX] [--retry-failed]   (the usual way)
    scripts/long_suite.py [--build DIR] [-j N] [-R REGEX] [--retry-failed]
    scripts/long_suite.py --status (--commit REV | --build DIR)

--commit REV runs the suite of that commit in its own worktree (/tmp/rayunits-long/<commit>,
configured with -DRU_TB_LONG=ON and built first; RU_RTL_CACHE inside it): edits of the working tree
cannot reach it (the run-time RTL builds of `rayunits rtl` compile the source tree they come from),
and a later session, on this machine or a fresh one, resumes it with the same command. Its state
is tests/long_results/<key>.jsonl in this repository: commit it with the code it belongs to.
Without --commit: the build tree DIR of this working tree, state in DIR/long-suite/<key>.jsonl.

<key> is a hash of the committed tree without README.md (a README-only commit keeps a run's
results, any other change is a new run). Without --commit, a working tree with uncommitted changes
to tracked files other than README.md is refused: results must belong to a commit. The failed
tests' output goes to <state>/<key>/<test>.log (tests/long_results/<key>/ with --commit).

Scheduling: a test takes as many of the N slots as its PROCESSORS property (at most N); fixture
setup tests run before the tests that require them, once per run (a passed setup is not repeated:
its outputs stay in the build tree); every test runs under its own TIMEOUT (ctest -R '^name$').
"""
import argparse
import datetime
import hashlib
import json
import os
import re
import signal
import subprocess
import sys
import threading
import time


def fail(msg):
    print(f"long_suite: {msg}", file=sys.stderr)
    sys.exit(2)


def git(root, *args):
    return subprocess.run(["git", "-C", root, *args], check=True, capture_output=True,
                          text=True).stdout


def code_key(root, rev="HEAD", check_dirty=True):
    """Hash of the committed tree of rev without README.md; refuses a dirty tracked tree."""
    if check_dirty:
        dirty = [line[3:] for line in git(root, "status", "--porcelain", "--untracked-files=no")
                 .splitlines() if line[3:] != "README.md"]
        if dirty:
            fail(f"uncommitted changes to tracked files ({', '.join(dirty[:3])}"
                 f"{', ...' if len(dirty) > 3 else ''}); commit first: results must belong to a commit")
    tree = [line for line in git(root, "ls-tree", "-r", rev).splitlines()
            if line.split("\t", 1)[1] != "README.md"]
    commit = git(root, "rev-parse", "--short", rev).strip()
    return hashlib.sha1("\n".join(tree).encode()).hexdigest()[:12], commit


def worktree(root, commit, build_it):
    """The worktree of commit under /tmp/rayunits-long, configured and (build_it) built."""
    wt = os.path.join(os.environ.get("RU_LONG_WORKTREES", "/tmp/rayunits-long"), commit)
    if not os.path.exists(os.path.join(wt, ".git")):
        os.makedirs(os.path.dirname(wt), exist_ok=True)
        subprocess.run(["git", "-C", root, "worktree", "prune"], check=False)
        r = subprocess.run(["git", "-C", root, "worktree", "add", "--detach", wt, commit],
                           capture_output=True, text=True)
        if r.returncode != 0:
            fail(f"cannot make the worktree {wt}: {r.stderr.strip().splitlines()[-1:]}")
    build = os.path.join(wt, "build")
    if build_it:
        print(f"long_suite: building {commit} in {build} (configure -DRU_TB_LONG=ON, ninja)", flush=True)
        steps = [["cmake", "-S", wt, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                  "-DRU_TB=ON", "-DRU_TB_LONG=ON"], ["ninja", "-C", build]]
        log = os.path.join(wt, "long_suite_build.log")
        # ccache hashes paths relative to the worktree: worktrees of other commits share its entries
        env = dict(os.environ, CCACHE_BASEDIR=wt)
        with open(log, "a") as f:
            for step in steps:
                if subprocess.run(step, stdout=f, stderr=subprocess.STDOUT, env=env).returncode != 0:
                    fail(f"building {commit} failed: {' '.join(step[:2])} ... (log {log})")
    return wt, build


def list_tests(build, regex):
    cmd = ["ctest", "--show-only=json-v1", "-L", "long"]
    if regex:
        cmd += ["-R", regex]
    out = subprocess.run(cmd, cwd=build, capture_output=True, text=True)
    if out.returncode != 0:
        fail(f"ctest could not list the tests in {build}: {out.stderr.strip().splitlines()[-1:]}")
    tests = []
    for t in json.loads(out.stdout)["tests"]:
        props = {p["name"]: p["value"] for p in t.get("properties", [])}
        tests.append({
            "name": t["name"],
            "processors": int(props.get("PROCESSORS", 1)),
            "setup": props.get("FIXTURES_SETUP", []),
            "required": props.get("FIXTURES_REQUIRED", []),
        })
    return tests


def read_state(path, sessions=None):
    state = {}
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                line = line.strip()
                if not line:
                    continue
                try:
                    rec = json.loads(line)
                except json.JSONDecodeError:
                    continue  # a line cut by a kill: the test runs again
                if "test" in rec:
                    state[rec["test"]] = rec
                elif sessions is not None and "wall_seconds" in rec:
                    sessions.append(rec)
    return state


def now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")


class Runner:
    def __init__(self, build, state_path, log_dir, slots, commit):
        self.build, self.state_path, self.log_dir = build, state_path, log_dir
        self.slots, self.free, self.commit = slots, slots, commit
        self.lock = threading.Condition()
        self.procs = set()
        self.stopping = False
        self.counts = {"passed": 0, "failed": 0, "skipped": 0}

    def record(self, rec):
        with self.lock:
            with open(self.state_path, "a") as f:
                f.write(json.dumps(rec) + "\n")

    def run_one(self, test, need, index, total):
        name = test["name"]
        t0 = time.monotonic()
        # -FA: fixture setups are scheduled by this runner, not repeated by ctest per test.
        cmd = ["ctest", "-L", "long", "-R", "^" + re.escape(name) + "$", "-FA", ".*",
               "--output-on-failure", "--no-tests=error"]
        p = subprocess.Popen(cmd, cwd=self.build, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True, start_new_session=True)
        with self.lock:
            self.procs.add(p)
        out, _ = p.communicate()
        with self.lock:
            self.procs.discard(p)
            self.free += need
            self.lock.notify_all()
            if self.stopping:
                return
        secs = round(time.monotonic() - t0, 1)
        if p.returncode == 0:
            status = "skipped" if re.search(r"\*\*\*Skipped|Not Run", out) else "passed"
        else:
            status = "failed"
            os.makedirs(self.log_dir, exist_ok=True)
            with open(os.path.join(self.log_dir, re.sub(r"[^\w.-]", "_", name) + ".log"), "w") as f:
                f.write(out)
        self.record({"test": name, "status": status, "seconds": secs, "finished": now(),
                     "commit": self.commit})
        with self.lock:
            self.counts[status] += 1
            done = sum(self.counts.values())
        print(f"[{done}/{total}] {status:7s} {secs:8.1f} s  {name}", flush=True)

    def run(self, tests):
        threads = []
        total = len(tests)
        for i, test in enumerate(tests):
            need = min(max(test["processors"], 1), self.slots)
            with self.lock:
                while self.free < need and not self.stopping:
                    self.lock.wait()
                if self.stopping:
                    break
                self.free -= need
            th = threading.Thread(target=self.run_one, args=(test, need, i, total))
            th.start()
            threads.append(th)
        for th in threads:
            th.join()

    def stop(self, *_):
        with self.lock:
            self.stopping = True
            for p in self.procs:
                kill_tree(p.pid)
            self.lock.notify_all()


def descendants(pid):
    """pid and every process below it (from /proc: parents of every process)."""
    children = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as f:
                    ppid = int(f.read().rsplit(")", 1)[1].split()[1])
                children.setdefault(ppid, []).append(int(d))
            except (OSError, ValueError, IndexError):
                pass  # gone meanwhile
    out, todo = [], [pid]
    while todo:
        q = todo.pop()
        out.append(q)
        todo += children.get(q, [])
    return out


def kill_tree(pid):
    """Stops a test and everything it started. Children of a test may run in their own process
    groups or sessions (rayunits starts yosys, verilator, ... so): killing ctest's group leaves
    them running as orphans, reparented out of reach. So: freeze the whole tree (SIGSTOP until no
    new process appears, a frozen process starts none), SIGTERM and SIGCONT every member (their
    handlers clean up temporary directories), SIGKILL what is left after a grace period."""
    seen = []
    for _ in range(10):
        tree = descendants(pid)
        new = [q for q in tree if q not in seen]
        if not new:
            break
        for q in new:
            try:
                os.kill(q, signal.SIGSTOP)
            except ProcessLookupError:
                pass
        seen += new
    for sig in (signal.SIGTERM, signal.SIGCONT):
        for q in seen:
            try:
                os.kill(q, sig)
            except ProcessLookupError:
                pass
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline and any(os.path.exists(f"/proc/{q}") and not zombie(q) for q in seen):
        time.sleep(0.1)
    for q in seen:
        try:
            os.kill(q, signal.SIGKILL)
        except ProcessLookupError:
            pass


def zombie(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] == "Z"
    except OSError:
        return True


def status(tests, state_path, key, commit):
    sessions = []
    state = read_state(state_path, sessions)
    names = [t["name"] for t in tests]
    recs = [state[n] for n in names if n in state]
    by = {s: [r for r in recs if r["status"] == s] for s in ("passed", "failed", "skipped")}
    missing = [n for n in names if n not in state]
    print(f"long suite, code key {key} (HEAD {commit}): {len(names)} tests; "
          f"{len(by['passed'])} passed, {len(by['failed'])} failed, {len(by['skipped'])} skipped, "
          f"{len(missing)} not run")
    if recs:
        secs = sum(r["seconds"] for r in recs)
        commits = sorted({r["commit"] for r in recs})
        print(f"  finished between {min(r['finished'] for r in recs)} and "
              f"{max(r['finished'] for r in recs)}; test time {secs / 3600:.2f} h "
              f"(sum over tests); commits {', '.join(commits)}")
    if sessions:
        wall = sum(s["wall_seconds"] for s in sessions)
        print(f"  wall time {wall / 3600:.2f} h in {len(sessions)} invocation(s)")
    for r in by["failed"]:
        print(f"  FAILED {r['test']} ({r['seconds']} s, {r['finished']})")
    return 0 if not missing and not by["failed"] else 1


RUNNER = None  # the running Runner, for the signal handler


def on_signal(*_):
    if RUNNER is None:  # before any test started: nothing to record
        print("long_suite: stopped", file=sys.stderr)
        sys.exit(130)
    RUNNER.stop()


def main():
    global RUNNER
    signal.signal(signal.SIGINT, on_signal)
    signal.signal(signal.SIGTERM, on_signal)
    root = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.environ.get("RU_BUILD_DIR", os.path.join(root, "build")),
                    help="a build tree configured with -DRU_TB_LONG=ON (default build/)")
    ap.add_argument("-j", type=int, default=os.cpu_count() or 1, help="parallel slots (default: cores)")
    ap.add_argument("-R", dest="regex", help="only tests whose names match (ctest -R)")
    ap.add_argument("--retry-failed", action="store_true", help="run failed tests again")
    ap.add_argument("--status", action="store_true", help="print what has run; run nothing")
    ap.add_argument("--commit", help="run the suite of this commit in its own worktree (state checked in)")
    ap.add_argument("--repo", default=root, help=argparse.SUPPRESS)  # the tests' scratch repository
    args = ap.parse_args()
    if args.j < 1:
        fail(f"-j {args.j}: needs at least one slot")
    if args.commit:
        r = subprocess.run(["git", "-C", args.repo, "rev-parse", "--verify", "--quiet",
                            args.commit + "^{commit}"], capture_output=True, text=True)
        if r.returncode != 0:
            fail(f"--commit {args.commit}: not a commit of {args.repo}")
        key, commit = code_key(args.repo, args.commit, check_dirty=False)
        wt, build = worktree(args.repo, commit, build_it=not args.status)
        os.environ["RU_RTL_CACHE"] = os.path.join(wt, "rtl-cache")
        state_dir = os.path.join(args.repo, "tests", "long_results")
    else:
        build = os.path.abspath(args.build)
        key, commit = code_key(args.repo)
        state_dir = os.path.join(build, "long-suite")
    state_path = os.path.join(state_dir, key + ".jsonl")
    if args.status and args.commit and not os.path.exists(os.path.join(build, "CTestTestfile.cmake")):
        # not built on this machine: what the checked-in state says
        tests = [{"name": n} for n in read_state(state_path)]
        sys.exit(status(tests, state_path, key, commit) if tests else fail(f"no state {state_path}"))
    if not os.path.exists(os.path.join(build, "CTestTestfile.cmake")):
        fail(f"{build} is not a configured build tree (expected CTestTestfile.cmake); "
             "configure with -DRU_TB_LONG=ON and build first")
    tests = list_tests(build, args.regex)
    if not tests:
        fail(f"no long tests in {build}" + (f" match -R {args.regex}" if args.regex else "")
             + " (was it configured with -DRU_TB_LONG=ON?)")
    os.makedirs(state_dir, exist_ok=True)
    state = read_state(state_path)
    if args.status:
        sys.exit(status(tests, state_path, key, commit))

    def wanted(t):
        rec = state.get(t["name"])
        return rec is None or (args.retry_failed and rec["status"] == "failed")
    todo = [t for t in tests if wanted(t)]
    # Fixture setups first, so that no test starts before the setup it requires has run.
    setups = [t for t in todo if t["setup"]]
    rest = [t for t in todo if not t["setup"]]
    print(f"long_suite: {len(tests)} long tests, {len(tests) - len(todo)} already recorded for "
          f"code key {key}; running {len(todo)} with -j {args.j} (state {state_path})", flush=True)
    runner = Runner(build, state_path, os.path.join(state_dir, key), args.j, commit)
    RUNNER = runner
    runner.record({"session": "start", "at": now(), "commit": commit, "jobs": args.j})
    t0 = time.monotonic()
    runner.run(setups)
    runner.run(rest)
    runner.record({"session": "stop" if runner.stopping else "end", "at": now(), "commit": commit,
                   "wall_seconds": round(time.monotonic() - t0, 1)})
    if runner.stopping:
        print("long_suite: stopped; run again to resume", file=sys.stderr)
        sys.exit(130)
    sys.exit(status(tests, state_path, key, commit))


if __name__ == "__main__":
    main()
