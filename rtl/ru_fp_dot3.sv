// ru_fp_dot3: 3-term dot product y = round(round(round(a0*b0) + round(a1*b1)) + round(a2*b2)),
// docs/FORMAT.md: three products and two additions, each rounded in the format (not fused);
// flags_o is the OR of the flags of all five operations. a_i = {a2, a1, a0} and
// b_i = {b2, b1, b0} (W bits each, a0 in the least significant bits).
//
// Built from three ru_fp_mul (in parallel), an ru_fp_add for p0 + p1 and an ru_fp_add for
// (p0 + p1) + p2 (ru_fp_dot3_core, shared with the ray-triangle units); p2 and the first flags
// wait in ru_pipe delay lines meanwhile.
//
// Parameters: ExpW (2..11), FracW (1..52), Stages (latency in cycles, 0 = combinational),
// Subnormals (1 gradual underflow, 0 flush-to-zero), Round (0 RNE, 1 RTZ, 2 RDN, 3 RUP).
// Fully pipelined: one dot product per cycle.
//
// Pipelining: the datapath is a level chain (ru_pipe_pkg) mul - add - add: the segments of
// ru_fp_mul (Lm = ru_fp_pkg::mul_nseg(FracW) segments, see ru_fp_mul) followed twice by the six
// of ru_fp_add; ru_pipe_pkg::unit_cuts places the Stages registers on that chain and each level
// gets its slice through the instances' CutSel parameter. A register on the boundary
// mul -> add or add -> add is the producing instance's output register. Cut positions:
//   0 .. Lm-2            inside the multipliers (see ru_fp_mul)
//   Lm-1                 multiplier outputs
//   Lm .. Lm+4           inside the first adder (see ru_fp_add)
//   Lm+5                 first adder output (p2 and the product flags are delayed to match)
//   Lm+6 .. Lm+10        inside the second adder
// Useful maximum: Stages = Lm + 11 = L + 16 (MaxUsefulStages; Lm = 7 for e4m3, 10 for e5m10,
// 12 for e8m23, 14 for e11m52). Any larger Stages is accepted; the extra registers are placed
// at the output.
module ru_fp_dot3 #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0
) (
  input  logic                      clk_i,
  input  logic                      rst_ni,
  input  logic                      in_valid_i,
  input  logic [3*(ExpW+FracW+1)-1:0] a_i,
  input  logic [3*(ExpW+FracW+1)-1:0] b_i,
  output logic                      out_valid_o,
  output logic [ExpW+FracW:0]       y_o,
  output logic [4:0]                flags_o
);

  // ---- register placement (ru_pipe_pkg): the level chain mul - add - add ---------------------
  localparam int unsigned NLev = 3;
  localparam logic [4*ru_pipe_pkg::MaxLev-1:0] Kinds =
      {52'd0, ru_fp_pkg::KAdd, ru_fp_pkg::KAdd, ru_fp_pkg::KMul};
  `include "ru_level_chain.svh"

  ru_fp_dot3_core #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
    .MulStages(lat(0)), .MulCuts(lcut(0)), .Add1Stages(lat(1)), .Add1Cuts(lcut(1)),
    .Add2Stages(lat(2)), .Add2Cuts(lcut(2))
  ) u_core (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .u_i    (a_i),
    .v_i    (b_i),
    .valid_o(out_valid_o),
    .y_o,
    .flags_o
  );

endmodule
