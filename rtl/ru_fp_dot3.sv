// ru_fp_dot3: 3-term dot product y = round(round(round(a0*b0) + round(a1*b1)) + round(a2*b2)),
// docs/FORMAT.md: three products and two additions, each rounded in the format (not fused);
// flags_o is the OR of the flags of all five operations. a_i = {a2, a1, a0} and
// b_i = {b2, b1, b0} (W bits each, a0 in the least significant bits).
//
// Built from three ru_fp_mul (in parallel), an ru_fp_add for p0 + p1 and an ru_fp_add for
// (p0 + p1) + p2 (ru_fp_dot3_core, shared with the ray-triangle units); p2 and the first flags
// wait in ru_fp_pipe delay lines meanwhile.
//
// Parameters: ExpW (2..11), FracW (1..52), Stages (latency in cycles, 0 = combinational),
// Subnormals (1 gradual underflow, 0 flush-to-zero), Round (0 RNE, 1 RTZ, 2 RDN, 3 RUP).
// Fully pipelined: one dot product per cycle.
//
// Pipelining: the datapath is treated as one chain of segments, those of ru_fp_mul
// (Lm = ru_fp_pkg::mul_nseg(FracW) segments, see ru_fp_mul) followed twice by the six of
// ru_fp_add; ru_fp_pkg::cut_mask places the Stages registers on that chain and the masks are
// handed to the instances through their CutSel parameter. A register on the boundary
// mul -> add or add -> add is the producing instance's output register. Cut positions:
//   0 .. Lm-2            inside the multipliers (see ru_fp_mul)
//   Lm-1                 multiplier outputs
//   Lm .. Lm+4           inside the first adder (see ru_fp_add)
//   Lm+5                 first adder output (p2 and the product flags are delayed to match)
//   Lm+6 .. Lm+10        inside the second adder
// Useful maximum: Stages = Lm + 11 (Lm = 7 for e4m3, 10 for e5m10, 12 for e8m23, 14 for
// e11m52). Any larger Stages is accepted; the extra registers are placed at the output.
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

  localparam int unsigned Lm = ru_fp_pkg::mul_nseg(FracW);
  localparam int unsigned La = ru_fp_pkg::add_nseg();
  localparam logic [63:0] Cuts = ru_fp_pkg::cut_mask(
      ru_fp_pkg::dot3_seg_w(ExpW, FracW, Subnormals), ru_fp_pkg::dot3_nseg(FracW), Stages);
  // Useful maximum of Stages (a register at every cut position of the chain) and the registers
  // placed at the output (those beyond MaxUsefulStages).
  localparam int unsigned MaxUsefulStages = ru_fp_pkg::max_useful(ru_fp_pkg::dot3_nseg(FracW));
  localparam int unsigned OutRegs = ru_fp_pkg::out_regs(Cuts, Stages);
  if (OutRegs != ru_fp_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_fp_dot3: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  // per-instance masks (bit 63 clear = explicit) and latencies
  localparam logic [63:0] MulCuts = Cuts & ((64'd1 << (Lm - 1)) - 64'd1);
  localparam logic [63:0] Add1Cuts = (Cuts >> Lm) & ((64'd1 << (La - 1)) - 64'd1);
  localparam logic [63:0] Add2Cuts = (Cuts >> (Lm + La)) & ((64'd1 << (La - 1)) - 64'd1);
  localparam int unsigned MulStages = ru_fp_pkg::popcount(MulCuts) + 32'(Cuts[Lm-1]);
  localparam int unsigned Add1Stages = ru_fp_pkg::popcount(Add1Cuts) + 32'(Cuts[Lm+La-1]);
  localparam int unsigned Add2Stages = ru_fp_pkg::popcount(Add2Cuts) + OutRegs;

  ru_fp_dot3_core #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
    .MulStages(MulStages), .MulCuts(MulCuts), .Add1Stages(Add1Stages), .Add1Cuts(Add1Cuts),
    .Add2Stages(Add2Stages), .Add2Cuts(Add2Cuts)
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
