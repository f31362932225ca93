#!/usr/bin/env bash
# scripts/long_suite.py on a scratch CMake project: a failing test is recorded with its log and
# turns the exit code non-zero; a second run repeats nothing that passed; --retry-failed reruns
# the failure; a fixture setup runs before the test that requires it; a stopped run records
# nothing for the test it interrupted and the next run resumes it; a dirty tree is refused.
set -euo pipefail
RUNNER="$(cd "$(dirname "$0")/../.." && pwd)/scripts/long_suite.py"
W="$(mktemp -d)"; trap 'rm -rf "$W"' EXIT
check() { if ! eval "$1"; then echo "FAILED: $1"; tail -5 "$W"/o* 2>/dev/null; exit 1; fi; }
mkdir -p "$W/src"
cat > "$W/src/CMakeLists.txt" <<'CM'
cmake_minimum_required(VERSION 3.20)
project(scratch NONE)
enable_testing()
set(B ${CMAKE_BINARY_DIR})
add_test(NAME L.passes COMMAND sh -c "echo x >> ${B}/passes.count")
add_test(NAME L.fails_until_fixed COMMAND sh -c "echo planted failure; test -e ${B}/fixed")
add_test(NAME L.setup COMMAND sh -c "touch ${B}/fixture")
add_test(NAME L.needs_setup COMMAND sh -c "test -e ${B}/fixture")
add_test(NAME L.skips COMMAND sh -c "exit 77")
add_test(NAME L.slow COMMAND sh -c "test -e ${B}/slow.go || { setsid sleep 300 & echo $! > ${B}/orphan.pid; sleep 30; }")
add_test(NAME fast COMMAND true)
set_tests_properties(L.passes L.fails_until_fixed L.setup L.needs_setup L.skips L.slow
                     PROPERTIES LABELS long)
set_tests_properties(L.setup PROPERTIES FIXTURES_SETUP fx)
set_tests_properties(L.needs_setup PROPERTIES FIXTURES_REQUIRED fx)
set_tests_properties(L.skips PROPERTIES SKIP_RETURN_CODE 77)
set_tests_properties(L.passes PROPERTIES PROCESSORS 4)
CM
git -C "$W/src" init -q && git -C "$W/src" add -A && git -C "$W/src" -c user.email=t@t -c user.name=t commit -qm scratch
cmake -S "$W/src" -B "$W/b" > /dev/null
PY=python3; [[ -x /usr/bin/python3 ]] && PY=/usr/bin/python3  # not a pyenv shim: signals reach the runner
R=($PY "$RUNNER" --repo "$W/src" --build "$W/b" -j 2)

# 1. A stopped run: the slow test is interrupted and recorded nowhere, its whole process tree stopped.
"${R[@]}" -R 'L.slow' > "$W/o0" 2>&1 & pid=$!
sleep 2; kill -TERM $pid; set +e; wait $pid; rc=$?; set -e
check '[[ $rc == 130 ]]'
check '! grep -q "\"L.slow\"" "$W"/b/long-suite/*.jsonl'
# ... and what it started in a session of its own (as rayunits starts yosys) is stopped with it
gone() { local st; st=$(sed 's/.*) //' "/proc/$1/stat" 2>/dev/null | cut -d' ' -f1); [[ -z $st || $st == Z ]]; }  # a zombie is dead
check '[[ -s "$W/b/orphan.pid" ]] && gone "$(cat "$W/b/orphan.pid")"'

# 2. The whole run: one failure (exit 1), its log kept; the setup before its user; 'fast' not run.
touch "$W/b/slow.go"
set +e; "${R[@]}" > "$W/o1" 2>&1; rc=$?; set -e
check '[[ $rc == 1 ]]'
check 'grep -q "6 tests; 4 passed, 1 failed, 1 skipped, 0 not run" "$W/o1"'
check 'grep -q "FAILED L.fails_until_fixed" "$W/o1"'
check 'grep -q "planted failure" "$W"/b/long-suite/*/L.fails_until_fixed.log'
check '! grep -q " fast$" "$W/o1"'
check '[[ $(grep -n "L.setup$" "$W/o1" | cut -d: -f1) -lt $(grep -n "L.needs_setup$" "$W/o1" | cut -d: -f1) ]]'

# 3. Again: nothing that passed runs twice; the failure stays until --retry-failed.
set +e; "${R[@]}" > "$W/o2" 2>&1; rc=$?; set -e
check '[[ $rc == 1 ]] && grep -q "running 0 with" "$W/o2"'
check '[[ $(wc -l < "$W/b/passes.count") == 1 ]]'
touch "$W/b/fixed"
"${R[@]}" --retry-failed > "$W/o3" 2>&1
check 'grep -q "running 1 with" "$W/o3" && grep -q "5 passed, 0 failed, 1 skipped, 0 not run" "$W/o3"'
"${R[@]}" --status > "$W/o4"

# 4. A README-only change keeps the results; a code change is refused until committed.
echo readme > "$W/src/README.md"; git -C "$W/src" add README.md
git -C "$W/src" -c user.email=t@t -c user.name=t commit -qm readme
"${R[@]}" --status > "$W/o5"
check 'grep -q "5 passed" "$W/o5"'
echo "# changed" >> "$W/src/CMakeLists.txt"
set +e; "${R[@]}" --status > "$W/o6" 2>&1; rc=$?; set -e
check '[[ $rc == 2 ]] && [[ $(wc -l < "$W/o6") == 1 ]] && grep -q "uncommitted changes to tracked files (CMakeLists.txt)" "$W/o6"'
# 5. --commit: the suite of a commit in its own worktree (working-tree edits do not matter), the
# state under tests/long_results/ of the repository, resumed by the same command.
git -C "$W/src" checkout -q -- CMakeLists.txt
sha=$(git -C "$W/src" rev-parse --short HEAD)
echo "# an edit of the working tree" >> "$W/src/CMakeLists.txt"
export RU_LONG_WORKTREES="$W/wt"
set +e; $PY "$RUNNER" --repo "$W/src" --commit "$sha" -j 2 -R "L.(passes|fails|skips)" > "$W/o7" 2>&1; rc=$?; set -e
check '[[ $rc == 1 ]] && [[ -d "$W/wt/$sha/build" ]] && grep -q "1 failed" "$W/o7"'
check 'ls "$W"/src/tests/long_results/*.jsonl > /dev/null && ! grep -q "an edit" "$W/wt/$sha/CMakeLists.txt"'
set +e; $PY "$RUNNER" --repo "$W/src" --commit "$sha" -R "L.(passes|fails|skips)" > "$W/o8" 2>&1; rc=$?; set -e
check '[[ $rc == 1 ]] && grep -q "running 0 with" "$W/o8"'
set +e; $PY "$RUNNER" --repo "$W/src" --commit nosuchrev > "$W/o9" 2>&1; rc=$?; set -e
check '[[ $rc == 2 ]] && grep -q "not a commit" "$W/o9"'
git -C "$W/src" worktree remove --force "$W/wt/$sha"
echo "long_suite runner: all checks passed"
