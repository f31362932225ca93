#!/usr/bin/env bash
# scripts/search_table.py --genomes: the rows of named designs come from the search's files — a
# planted area in evaluations.jsonl and a planted verification status in front.csv appear in the
# table, a hand design's row comes from front.json, evaluations of an older context are not read,
# and a name the search did not evaluate is one line on stderr with exit 2; --pairs computes its
# ratios from the same rows (the planted area shows in them).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
SRC="$ROOT/sweeps/results/search/tri_e7m16_250MHz_mixed"
PY="${RU_PYTHON:-/usr/bin/python3}"; [ -x "$PY" ] || PY=python3
W="$(mktemp -d)"; trap 'rm -rf "$W"' EXIT
fail() { echo "FAILED: $1"; exit 1; }
cp "$SRC/front.json" "$SRC/front.csv" "$W/"
# a planted area for mt-q0-i0-p0-w2 (not reported) and a stale line of another context before it
grep -q '"genome":"mt-q0-i0-p0-w2"' "$SRC/evaluations.jsonl" || fail "the checked-in evaluations changed: update this test"
{ grep '"genome":"mt-q0-i0-p0-w2"' "$SRC/evaluations.jsonl" | sed 's/"context":"[0-9a-f]*"/"context":"0000000000000000"/; s/"area_um2":[0-9.]*/"area_um2":999/'
  sed '/"genome":"mt-q0-i0-p0-w2"/s/"area_um2":[0-9.]*/"area_um2":1234567/' "$SRC/evaluations.jsonl"; } > "$W/evaluations.jsonl"
# a planted verification failure of a reported design
grep -q '^mt-q0-i0-p0-w3,.*,pass$' "$W/front.csv" || fail "the checked-in front.csv changed: update this test"
sed -i 's/^\(mt-q0-i0-p0-w3,.*\),pass$/\1,FAIL (planted)/' "$W/front.csv"
out="$("$PY" "$ROOT/scripts/search_table.py" "$W" --genomes mt-q0-i0-p0-w2,mt-q0-i0-p0-w3,mt-q1-i0-p0)"
echo "$out"
grep -qF '| `mt-q0-i0-p0-w2` | 1,234,567 | 186 | 77 |' <<<"$out" || fail "planted area"
grep -qF '| FAIL (planted) |' <<<"$out" || fail "planted status"
grep -qF '| `mt-q1-i0-p0` (hand: mt) | 5,404,343 | 250 |' <<<"$out" || fail "hand design"
[ "$(grep -c '^| `' <<<"$out")" = 3 ] || fail "three rows"
# --pairs: the planted area reaches the ratios against the twin and the w2 sibling
pairs="$("$PY" "$ROOT/scripts/search_table.py" "$W" --pairs)"
grep -q '^mt-q0-i0-p0-w2: area 0.226, err 3.82$' <<<"$pairs" || fail "pairs: planted w2 against its twin"
grep -q '^mt-q0-i0-p0-w3: area 2.34, err 133, area_vs_w2 10.4, err_vs_w2 34.7$' <<<"$pairs" || fail "pairs: w3 against the planted w2"
grep -q '^w2 area: 0.226 \.\. ' <<<"$pairs" || fail "pairs: range"
set +e
err="$("$PY" "$ROOT/scripts/search_table.py" "$W" --genomes mt-q0-i0-p0-w2,no-such-design 2>&1 >/dev/null)"; rc=$?
set -e
[ "$rc" = 2 ] || fail "exit $rc for an unknown design"
[ "$(printf '%s\n' "$err" | wc -l)" = 1 ] && grep -q "no-such-design" <<<"$err" || fail "one line naming it: $err"
echo "search_table --genomes: ok"
