// ru_fp_dot3: 3-term dot product y = round(round(round(a0*b0) + round(a1*b1)) + round(a2*b2)),
// docs/FORMAT.md: three products and two additions, each rounded in the format (not fused);
// flags_o is the OR of the flags of all five operations. a_i = {a2, a1, a0} and
// b_i = {b2, b1, b0} (W bits each, a0 in the least significant bits).
//
// Built from three ru_fp_mul (in parallel), an ru_fp_add for p0 + p1 and an ru_fp_add for
// (p0 + p1) + p2; p2 and the first flags wait in ru_fp_pipe delay lines meanwhile.
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

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam int unsigned Lm = ru_fp_pkg::mul_nseg(FracW);
  localparam int unsigned La = ru_fp_pkg::add_nseg();
  localparam logic [63:0] Cuts = ru_fp_pkg::cut_mask(
      ru_fp_pkg::dot3_seg_w(ExpW, FracW, Subnormals), ru_fp_pkg::dot3_nseg(FracW), Stages);
  localparam int unsigned OutRegs = ru_fp_pkg::out_regs(Cuts, Stages);
  // per-instance masks (bit 63 clear = explicit) and latencies
  localparam logic [63:0] MulCuts = Cuts & ((64'd1 << (Lm - 1)) - 64'd1);
  localparam logic [63:0] Add1Cuts = (Cuts >> Lm) & ((64'd1 << (La - 1)) - 64'd1);
  localparam logic [63:0] Add2Cuts = (Cuts >> (Lm + La)) & ((64'd1 << (La - 1)) - 64'd1);
  localparam int unsigned MulStages = ru_fp_pkg::popcount(MulCuts) + 32'(Cuts[Lm-1]);
  localparam int unsigned Add1Stages = ru_fp_pkg::popcount(Add1Cuts) + 32'(Cuts[Lm+La-1]);
  localparam int unsigned Add2Stages = ru_fp_pkg::popcount(Add2Cuts) + OutRegs;

  // ---- products ----------------------------------------------------------------------------
  logic [2:0]     p_valid;
  logic [3*W-1:0] p;
  logic [14:0]    p_flags;
  for (genvar i = 0; i < 3; i++) begin : gen_mul
    ru_fp_mul #(
      .ExpW(ExpW), .FracW(FracW), .Stages(MulStages), .Subnormals(Subnormals), .Round(Round),
      .CutSel(MulCuts)
    ) u_mul (
      .clk_i, .rst_ni,
      .in_valid_i (in_valid_i),
      .a_i        (a_i[i*W+:W]),
      .b_i        (b_i[i*W+:W]),
      .out_valid_o(p_valid[i]),
      .y_o        (p[i*W+:W]),
      .flags_o    (p_flags[i*5+:5])
    );
  end

  // ---- s = p0 + p1; p2 and the product flags wait ---------------------------------------------
  logic         s_valid, d_valid;
  logic [W-1:0] s, d_p2;
  logic [4:0]   s_flags, d_flags;
  ru_fp_add #(
    .ExpW(ExpW), .FracW(FracW), .Stages(Add1Stages), .Subnormals(Subnormals), .Round(Round),
    .CutSel(Add1Cuts)
  ) u_add1 (
    .clk_i, .rst_ni,
    .in_valid_i (p_valid[0]),
    .a_i        (p[0+:W]),
    .b_i        (p[W+:W]),
    .op_i       (1'b0),
    .out_valid_o(s_valid),
    .y_o        (s),
    .flags_o    (s_flags)
  );
  ru_fp_pipe #(.Width(W + 5), .Depth(Add1Stages)) u_wait1 (
    .clk_i, .rst_ni,
    .valid_i(p_valid[0]),
    .data_i ({p[2*W+:W], p_flags[0+:5] | p_flags[5+:5] | p_flags[10+:5]}),
    .valid_o(d_valid),
    .data_o ({d_p2, d_flags})
  );

  // ---- y = s + p2 ---------------------------------------------------------------------------
  logic       unused_valid;
  logic [4:0] y_flags, e_flags;
  assign unused_valid = d_valid ^ p_valid[1] ^ p_valid[2];  // all equal to the used ones
  ru_fp_add #(
    .ExpW(ExpW), .FracW(FracW), .Stages(Add2Stages), .Subnormals(Subnormals), .Round(Round),
    .CutSel(Add2Cuts)
  ) u_add2 (
    .clk_i, .rst_ni,
    .in_valid_i (s_valid),
    .a_i        (s),
    .b_i        (d_p2),
    .op_i       (1'b0),
    .out_valid_o(out_valid_o),
    .y_o        (y_o),
    .flags_o    (y_flags)
  );
  logic unused_e_valid;
  ru_fp_pipe #(.Width(5), .Depth(Add2Stages)) u_wait2 (
    .clk_i, .rst_ni,
    .valid_i(s_valid),
    .data_i (s_flags | d_flags),
    .valid_o(unused_e_valid),
    .data_o (e_flags)
  );
  assign flags_o = y_flags | e_flags;

endmodule
