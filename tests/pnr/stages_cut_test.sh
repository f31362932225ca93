#!/usr/bin/env bash
# PnrStages.CutIsEquivalentAndPlantedErrorsAreCaught (issue 13 section 3): synth/pnr/run_pnr_stages.sh
# --cut-only cuts fp_add e5m10 Stages 2 into its stage blocks and proves them equivalent to the unit;
# the same proof fails on a planted change of one cell of the cut netlist; split_stages.py refuses an
# unbalanced pipeline (a cell feeding flip-flops of two ranks) in one line. No qflow needed.
# usage: stages_cut_test.sh RAYUNITS-BINARY        exit 0 pass, 1 fail, 77 skipped (no yosys)
set -u -o pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
rayunits=$1
command -v yosys >/dev/null 2>&1 || { echo "skipped: no yosys"; exit 77; }
py=/usr/bin/python3
t=$(mktemp -d /tmp/ru_stages_cut.XXXXXX)
trap 'rm -rf "$t"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# 1. the cut and its proof
"$repo/synth/pnr/run_pnr_stages.sh" --rayunits "$rayunits" --work "$t/w" --out "$t/o" --cut-only \
  fp_add --format e5m10 --stages 2 > "$t/cut.log" 2>&1 || { cat "$t/cut.log"; fail "run_pnr_stages.sh --cut-only failed"; }
grep -q 'equivalent' "$t/cut.log" || { cat "$t/cut.log"; fail "no equivalence line"; }
# fp_add e5m10 Stages 2: two flip-flop ranks, and logic after the last rank drives the outputs:
# three blocks, the third without flip-flops
for s in 1 2 3; do
  [ -s "$t/w/blocks/ru_fp_add_e5m10_s2_st$s.v" ] || fail "block $s not written"
  grep -q "^module ru_fp_add_e5m10_s2_st$s(" "$t/w/blocks/ru_fp_add_e5m10_s2_st$s.v" || fail "block $s: no plain module header"
done
[ ! -e "$t/w/blocks/ru_fp_add_e5m10_s2_st4.v" ] || fail "a fourth block"
[ ! -e "$t/o" ] || fail "--cut-only wrote the results directory"
"$py" - "$t/w/stages.json" <<'PY' || fail "stages.json"
import json, sys
r = json.load(open(sys.argv[1]))
assert [b["stage"] for b in r["blocks"]] == [1, 2, 3], r
assert all(b["cells"] > 0 for b in r["blocks"]), r
assert [b["ff_bits"] > 0 for b in r["blocks"]] == [True, True, False], r
assert r["output_driven_combinationally"] and r["flip_flop_ranks"] == 2, r
PY

# 2. a planted change of one cell is caught by the same proof
"$py" - "$t/w/split.json" "$t/planted.json" <<'PY' || fail "could not plant"
import json, sys
d = json.load(open(sys.argv[1]))
swap = {"$and": "$or", "$or": "$and", "$xor": "$xnor", "$add": "$sub", "$sub": "$add"}
for name, m in d["modules"].items():
    if "_st" not in name:
        continue
    for c in m["cells"].values():
        if c["type"] in swap:
            c["type"] = swap[c["type"]]
            json.dump(d, open(sys.argv[2], "w"))
            sys.exit(0)
sys.exit(1)
PY
sed "s|read_json $t/w/split.json|read_json $t/planted.json|" "$t/w/equiv.ys" > "$t/planted.ys"
grep -q "$t/planted.json" "$t/planted.ys" || fail "equiv.ys does not read split.json"
if yosys -q -l "$t/planted.log" -s "$t/planted.ys" > /dev/null 2>&1; then fail "a planted change passed the equivalence proof"; fi
grep -q 'unproven' "$t/planted.log" || { tail -5 "$t/planted.log"; fail "the planted change failed for another reason"; }

# 3. an unbalanced pipeline is refused
cat > "$t/unbal.v" <<'V'
module unbal(input clk_i, input [3:0] a_i, output reg [3:0] q1_o, output reg [3:0] q2_o);
  wire [3:0] s = a_i + 4'd1;
  always @(posedge clk_i) begin q1_o <= s; q2_o <= q1_o ^ s; end
endmodule
V
yosys -q -p "read_verilog $t/unbal.v; hierarchy -top unbal; proc; opt; techmap t:*dff*; opt_clean; write_json $t/unbal.json" > /dev/null 2>&1 || fail "yosys on unbal.v"
if "$py" "$repo/synth/pnr/split_stages.py" "$t/unbal.json" "$t/unbal_out.json" unbal > "$t/unbal.out" 2> "$t/unbal.err"; then
  fail "an unbalanced pipeline was accepted"
fi
[ "$(wc -l < "$t/unbal.err")" = 1 ] && grep -q 'not balanced' "$t/unbal.err" || { cat "$t/unbal.err"; fail "not one clear line"; }
[ ! -e "$t/unbal_out.json" ] || fail "output written for a refused design"
echo "PASS"
