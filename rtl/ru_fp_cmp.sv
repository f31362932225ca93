// ru_fp_cmp: comparisons and IEEE 754-2008 minNum/maxNum, docs/FORMAT.md semantics.
//
//   op_i | operation | y_o                                  | flags_o (only invalid)
//   -----|-----------|--------------------------------------|------------------------------
//   0    | lt  a < b | {0..0, result}; 0 if a NaN involved  | any NaN operand (signaling)
//   1    | le  a <= b| {0..0, result}; 0 if a NaN involved  | any NaN operand (signaling)
//   2    | eq  a == b| {0..0, result}; +0 == -0; NaN -> 0   | a signaling NaN operand
//   3    | min       | the smaller operand's bits           | a signaling NaN operand
//   4    | max       | the larger operand's bits            | a signaling NaN operand
//   5-7  | (reserved) behave exactly like 2 (eq)
// min/max: -0 < +0; one NaN operand -> the other operand; both NaN -> canonical NaN. With
// Subnormals = 0 subnormal operands are first flushed to zero of the same sign, so both
// the ordering and the returned bits are those of the flushed operand.
//
// Parameters: ExpW (2..11), FracW (1..52), Stages (latency in cycles, 0 = combinational),
// Subnormals (1 gradual underflow, 0 flush-to-zero). Round is accepted for a uniform
// interface and unused (nothing is rounded). Fully pipelined, one operation per cycle.
//
// Datapath segments and the cut position after each:
//   seg 0  unpack, flush subnormals (Subnormals = 0), classify NaNs/zeros  | cut 0
//   seg 1  sign-magnitude comparison of the (flushed) operands             | cut 1
//   seg 2  operation select, NaN handling                                  -> y_o, flags_o
// Stages registers go to the cut positions chosen by ru_pipe_pkg::cut_mask with the depth
// estimates of ru_fp_pkg::cmp_seg_w. Useful maximum: Stages = 2. Any larger Stages is
// accepted; registers that no cut needs are placed at the output.
module ru_fp_cmp #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts,
  // Weights of the automatic placement: '0 = the depth estimates of ru_fp_pkg::cmp_seg_w; else
  // packed 8-bit weights per segment (`rayunits synth --placement delay` passes delays measured
  // by STA in the cell library, synth/README.md).
  parameter logic [ru_pipe_pkg::WW-1:0] SegW = '0
) (
  input  logic                clk_i,
  input  logic                rst_ni,
  input  logic                in_valid_i,
  input  logic [ExpW+FracW:0] a_i,
  input  logic [ExpW+FracW:0] b_i,
  input  logic [2:0]          op_i,
  output logic                out_valid_o,
  output logic [ExpW+FracW:0] y_o,
  output logic [4:0]          flags_o
);

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(
      CutSel,
      ru_pipe_pkg::pick_w(SegW, ru_fp_pkg::cmp_seg_w(ExpW, FracW)),
      ru_fp_pkg::cmp_nseg(), Stages);
  // Useful maximum of Stages (a register at every cut position) and the registers placed at the
  // output (Stages - popcount(Cuts); with automatic placement: those beyond MaxUsefulStages).
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(ru_fp_pkg::cmp_nseg());
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_fp_cmp: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  localparam int unsigned ClsW = 4;  // {nan, snan, zero, sign}

  // ---- seg 0: unpack, flush, classify ------------------------------------------------------
  logic sa, sb, za, zb, na, nb, sna, snb;
  logic [ExpW-1:0] unused_ea, unused_eb;
  logic [FracW:0] unused_ma, unused_mb;
  logic unused_sub_a, unused_sub_b, unused_inf_a, unused_inf_b;
  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_a (
    .x_i(a_i), .sign_o(sa), .exp_o(unused_ea), .sig_o(unused_ma), .zero_o(za),
    .sub_o(unused_sub_a), .inf_o(unused_inf_a), .nan_o(na), .snan_o(sna)
  );
  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_b (
    .x_i(b_i), .sign_o(sb), .exp_o(unused_eb), .sig_o(unused_mb), .zero_o(zb),
    .sub_o(unused_sub_b), .inf_o(unused_inf_b), .nan_o(nb), .snan_o(snb)
  );
  // flushed operands: a zero (incl. a flushed subnormal) keeps only its sign
  logic [W-1:0] s0_a, s0_b;
  assign s0_a = za ? {sa, {(W - 1) {1'b0}}} : a_i;
  assign s0_b = zb ? {sb, {(W - 1) {1'b0}}} : b_i;

  // ---- cut 0 ----------------------------------------------------------------------------
  logic            c0_valid;
  logic [W-1:0]    c0_a, c0_b;
  logic [ClsW-1:0] c0_ca, c0_cb;
  logic [2:0]      c0_op;
  ru_pipe #(.Width(2 * W + 2 * ClsW + 3), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({s0_a, s0_b, na, sna, za, sa, nb, snb, zb, sb, op_i}),
    .valid_o(c0_valid),
    .data_o ({c0_a, c0_b, c0_ca, c0_cb, c0_op})
  );

  // ---- seg 1: compare -----------------------------------------------------------------------
  logic c0_sa, c0_sb, c0_za, c0_zb;
  logic mag_lt, mag_eq, s1_tlt, s1_eq, s1_lt;
  assign c0_sa  = c0_ca[0];
  assign c0_sb  = c0_cb[0];
  assign c0_za  = c0_ca[1];
  assign c0_zb  = c0_cb[1];
  assign mag_lt = c0_a[W-2:0] < c0_b[W-2:0];
  assign mag_eq = c0_a[W-2:0] == c0_b[W-2:0];
  // total order (-0 < +0) on non-NaN values
  always_comb begin
    case ({c0_sa, c0_sb})
      2'b10:   s1_tlt = 1'b1;
      2'b01:   s1_tlt = 1'b0;
      2'b00:   s1_tlt = mag_lt;
      default: s1_tlt = ~mag_lt & ~mag_eq;
    endcase
  end
  // numeric order: +0 == -0
  assign s1_eq = (mag_eq & (c0_sa == c0_sb)) | (c0_za & c0_zb);
  assign s1_lt = s1_tlt & ~(c0_za & c0_zb);

  // ---- cut 1 ----------------------------------------------------------------------------
  logic            c1_valid, c1_tlt, c1_eq, c1_lt;
  logic [W-1:0]    c1_a, c1_b;
  logic [ClsW-1:0] c1_ca, c1_cb;
  logic [2:0]      c1_op;
  ru_pipe #(.Width(2 * W + 2 * ClsW + 3 + 3), .Depth(Cuts[1] ? 1 : 0)) u_cut1 (
    .clk_i, .rst_ni,
    .valid_i(c0_valid),
    .data_i ({c0_a, c0_b, c0_ca, c0_cb, c0_op, s1_tlt, s1_eq, s1_lt}),
    .valid_o(c1_valid),
    .data_o ({c1_a, c1_b, c1_ca, c1_cb, c1_op, c1_tlt, c1_eq, c1_lt})
  );

  // ---- seg 2: select ----------------------------------------------------------------------
  logic c1_na, c1_nb, c1_sna, c1_snb, any_nan, any_snan;
  logic [W-1:0] y;
  logic [4:0]   flags;
  logic unused_cls;
  assign c1_na    = c1_ca[3];
  assign c1_sna   = c1_ca[2];
  assign c1_nb    = c1_cb[3];
  assign c1_snb   = c1_cb[2];
  assign any_nan  = c1_na | c1_nb;
  assign any_snan = c1_sna | c1_snb;
  assign unused_cls = ^{c1_ca[1:0], c1_cb[1:0]};

  always_comb begin
    y     = '0;
    flags = {any_snan, 4'b0000};
    case (c1_op)
      3'd0: begin  // lt (signaling)
        y[0]     = c1_lt & ~any_nan;
        flags[4] = any_nan;
      end
      3'd1: begin  // le (signaling)
        y[0]     = (c1_lt | c1_eq) & ~any_nan;
        flags[4] = any_nan;
      end
      3'd3, 3'd4: begin  // min / max
        if (c1_na && c1_nb) begin
          y = {1'b0, {ExpW{1'b1}}, 1'b1, {(FracW - 1) {1'b0}}};
        end else if (c1_na) begin
          y = c1_b;
        end else if (c1_nb) begin
          y = c1_a;
        end else begin
          // max picks b iff a < b, min iff not (total order, -0 < +0; equal = same bits)
          y = ((c1_op == 3'd4) ? c1_tlt : ~c1_tlt) ? c1_b : c1_a;
        end
      end
      default: begin  // 2 = eq (quiet); 5..7 reserved, same as eq
        y[0] = c1_eq & ~any_nan;
      end
    endcase
  end

  // ---- output registers (Stages beyond the cuts used) ------------------------------------
  ru_pipe #(.Width(W + 5), .Depth(OutRegs)) u_out (
    .clk_i, .rst_ni,
    .valid_i(c1_valid),
    .data_i ({y, flags}),
    .valid_o(out_valid_o),
    .data_o ({y_o, flags_o})
  );

  logic unused_round;
  assign unused_round = (Round != 0);

endmodule
