// ru_fp_add: floating-point add/subtract, docs/FORMAT.md semantics.
//   op_i = 0: y = round(a + b);  op_i = 1: y = round(a - b) (b's sign flipped; a NaN b still
//   gives the canonical NaN). Exact zero sums are +0 (-0 under RDN); x + x keeps the sign
//   of zeros (-0 + -0 = -0).
//
// Parameters: ExpW (2..11), FracW (1..52), Stages (latency in cycles, 0 = combinational),
// Subnormals (1 gradual underflow, 0 flush-to-zero), Round (0 RNE, 1 RTZ, 2 RDN, 3 RUP).
// CutSel is internal (ru_fp_dot3 uses it to place this unit's registers itself); leave it.
// Fully pipelined: one operation per cycle, out_valid_o = in_valid_i delayed by Stages.
//
// Algorithm: single path. The operand with the larger magnitude is x, the other y; y's
// significand is shifted right by the exponent difference d keeping three extra bits
// (guard, round, and a sticky bit that ORs everything shifted further: "jamming" it into
// the LSB keeps the rounding information exact for both addition and subtraction, since
// a cancellation by more than one bit only happens for d <= 1, where nothing is shifted
// out). |x| >= |y| makes the difference non-negative, so no negation is needed.
//
// Datapath segments and the cut position after each:
//   seg 0  unpack/classify, special cases, magnitude compare, |ea - eb|   | cut 0
//   seg 1  swap, align shift with sticky                                   | cut 1
//   seg 2  significand add / subtract                                      | cut 2
//   seg 3  normalize (leading-zero count + shift)                          | cut 3
//   seg 4  round-and-pack: tininess, denormalization                       | cut 4
//   seg 5  round-and-pack: increment, overflow; special-result mux         -> y_o, flags_o
// Stages registers go to the cut positions that minimize the deepest stage under the
// depth estimates of ru_fp_pkg::add_seg_w (ru_pipe_pkg::cut_mask). Useful maximum: Stages = 5
// (every cut registered). Any larger Stages is accepted; the registers beyond 5 are placed
// at the output.
module ru_fp_add #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts,
  // Weights of the automatic placement: '0 = the depth estimates of ru_fp_pkg::add_seg_w; else
  // packed 8-bit weights per segment (`rayunits synth --placement delay` passes delays measured
  // by STA in the cell library, synth/README.md).
  parameter logic [ru_pipe_pkg::WW-1:0] SegW = '0
) (
  input  logic                clk_i,
  input  logic                rst_ni,
  input  logic                in_valid_i,
  input  logic [ExpW+FracW:0] a_i,
  input  logic [ExpW+FracW:0] b_i,
  input  logic                op_i,
  output logic                out_valid_o,
  output logic [ExpW+FracW:0] y_o,
  output logic [4:0]          flags_o
);

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam int unsigned N = FracW + 1;   // significand width
  localparam int unsigned XW = FracW + 4;  // significand + guard, round, sticky
  localparam int unsigned SW = FracW + 5;  // sum (with carry)
  localparam int unsigned ShW = ru_fp_pkg::clog2p(XW + 1);
  localparam int unsigned ExpIW = ru_fp_pkg::exp_iw(ExpW, FracW);
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(
      CutSel,
      ru_pipe_pkg::pick_w(SegW, ru_fp_pkg::add_seg_w(ExpW, FracW, Subnormals)),
      ru_fp_pkg::add_nseg(), Stages);
  // Useful maximum of Stages (a register at every cut position) and the registers placed at the
  // output (Stages - popcount(Cuts); with automatic placement: those beyond MaxUsefulStages).
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(ru_fp_pkg::add_nseg());
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_fp_add: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  // special-case bundle {nan, invalid, inf, inf_sign}
  localparam int unsigned SpW = 4;

  // ---- seg 0: unpack, special cases, compare ---------------------------------------------
  logic [W-1:0] b_eff;
  assign b_eff = {b_i[W-1] ^ op_i, b_i[W-2:0]};

  logic sa, sb, ia, ib, na, nb, sna, snb;
  logic [ExpW-1:0] ea, eb;
  logic [N-1:0] ma, mb;
  // zeros need no special path (their significand is 0), subnormals none either
  logic unused_sub_a, unused_sub_b, unused_zero_a, unused_zero_b;

  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_a (
    .x_i(a_i), .sign_o(sa), .exp_o(ea), .sig_o(ma), .zero_o(unused_zero_a),
    .sub_o(unused_sub_a), .inf_o(ia), .nan_o(na), .snan_o(sna)
  );
  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_b (
    .x_i(b_eff), .sign_o(sb), .exp_o(eb), .sig_o(mb), .zero_o(unused_zero_b),
    .sub_o(unused_sub_b), .inf_o(ib), .nan_o(nb), .snan_o(snb)
  );

  logic [SpW-1:0]  s0_sp;
  logic            inf_minus_inf, s0_swap, a_ge_b_exp;
  logic [ExpW-1:0] s0_d, s0_ex;
  assign inf_minus_inf = ia & ib & (sa ^ sb);
  assign s0_sp = {na | nb | inf_minus_inf, sna | snb | inf_minus_inf, ia | ib, ia ? sa : sb};
  // |b| > |a| on the raw magnitudes (a flushed subnormal only meets zeros or larger values)
  assign s0_swap = b_i[W-2:0] > a_i[W-2:0];
  assign a_ge_b_exp = ea >= eb;
  assign s0_d  = a_ge_b_exp ? ea - eb : eb - ea;
  assign s0_ex = a_ge_b_exp ? ea : eb;

  // ---- cut 0 ----------------------------------------------------------------------------
  logic            c0_valid, c0_sa, c0_sb, c0_swap;
  logic [N-1:0]    c0_ma, c0_mb;
  logic [ExpW-1:0] c0_d, c0_ex;
  logic [SpW-1:0]  c0_sp;
  ru_pipe #(.Width(2 * N + 3 + 2 * ExpW + SpW), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({ma, mb, sa, sb, s0_swap, s0_d, s0_ex, s0_sp}),
    .valid_o(c0_valid),
    .data_o ({c0_ma, c0_mb, c0_sa, c0_sb, c0_swap, c0_d, c0_ex, c0_sp})
  );

  // ---- seg 1: swap and align ------------------------------------------------------------
  logic [N-1:0]   mx, my;
  logic           s1_sx, s1_sub;
  logic [ShW-1:0] sh;
  logic [XW-1:0]  s1_x, y_sh, lost, s1_y;
  assign mx     = c0_swap ? c0_mb : c0_ma;
  assign my     = c0_swap ? c0_ma : c0_mb;
  assign s1_sx  = c0_swap ? c0_sb : c0_sa;
  assign s1_sub = c0_sa ^ c0_sb;
  assign sh     = (c0_d > ExpW'(XW)) ? ShW'(XW) : ShW'(c0_d);
  assign s1_x   = {mx, 3'b000};
  assign {y_sh, lost} = {my, 3'b000, {XW{1'b0}}} >> sh;
  assign s1_y   = {y_sh[XW-1:1], y_sh[0] | (|lost)};

  // ---- cut 1 ----------------------------------------------------------------------------
  logic            c1_valid, c1_sx, c1_sub;
  logic [XW-1:0]   c1_x, c1_y;
  logic [ExpW-1:0] c1_ex;
  logic [SpW-1:0]  c1_sp;
  ru_pipe #(.Width(2 * XW + 2 + ExpW + SpW), .Depth(Cuts[1] ? 1 : 0)) u_cut1 (
    .clk_i, .rst_ni,
    .valid_i(c0_valid),
    .data_i ({s1_x, s1_y, s1_sx, s1_sub, c0_ex, c0_sp}),
    .valid_o(c1_valid),
    .data_o ({c1_x, c1_y, c1_sx, c1_sub, c1_ex, c1_sp})
  );

  // ---- seg 2: add / subtract --------------------------------------------------------------
  logic [SW-1:0] s2_sum;
  assign s2_sum = c1_sub ? {1'b0, c1_x} - {1'b0, c1_y} : {1'b0, c1_x} + {1'b0, c1_y};

  // ---- cut 2 ----------------------------------------------------------------------------
  logic            c2_valid, c2_sx, c2_sub;
  logic [SW-1:0]   c2_sum;
  logic [ExpW-1:0] c2_ex;
  logic [SpW-1:0]  c2_sp;
  ru_pipe #(.Width(SW + 2 + ExpW + SpW), .Depth(Cuts[2] ? 1 : 0)) u_cut2 (
    .clk_i, .rst_ni,
    .valid_i(c1_valid),
    .data_i ({s2_sum, c1_sx, c1_sub, c1_ex, c1_sp}),
    .valid_o(c2_valid),
    .data_o ({c2_sum, c2_sx, c2_sub, c2_ex, c2_sp})
  );

  // ---- seg 3: normalize -----------------------------------------------------------------
  // the sum's bit SW-1 has weight 2^(ex + 1 - bias): normalized exponent ex + 1 - lz
  logic [SW-1:0]           n_sum;
  logic signed [ExpIW-1:0] n_exp;
  logic                    n_zero;
  ru_fp_normalize #(.Width(SW), .ExpIW(ExpIW), .Full(1)) u_norm (
    .sig_i(c2_sum), .exp_i(ExpIW'(c2_ex) + ExpIW'(1)), .sig_o(n_sum), .exp_o(n_exp),
    .zero_o(n_zero)
  );

  // ---- cut 3 ----------------------------------------------------------------------------
  logic                    c3_valid, c3_sx, c3_sub, c3_zero, c3_sticky;
  logic [FracW+1:0]        c3_sig;
  logic signed [ExpIW-1:0] c3_exp;
  logic [SpW-1:0]          c3_sp;
  ru_pipe #(.Width(FracW + 2 + 1 + ExpIW + 3 + SpW), .Depth(Cuts[3] ? 1 : 0)) u_cut3 (
    .clk_i, .rst_ni,
    .valid_i(c2_valid),
    .data_i ({n_sum[SW-1:3], |n_sum[2:0], n_exp, n_zero, c2_sx, c2_sub, c2_sp}),
    .valid_o(c3_valid),
    .data_o ({c3_sig, c3_sticky, c3_exp, c3_zero, c3_sx, c3_sub, c3_sp})
  );

  // ---- seg 4, cut 4, seg 5: round and pack, special results -------------------------------
  logic [W-1:0] rp_y, y;
  logic         rp_of, rp_uf, rp_nx, r_valid, r_sx, r_sub, r_zero;
  logic [4:0]   flags;
  logic [SpW-1:0] r_sp;
  logic         sp_nan, sp_invalid, sp_inf, sp_inf_sign;
  assign {sp_nan, sp_invalid, sp_inf, sp_inf_sign} = r_sp;

  ru_fp_round_pack #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round), .AuxW(3 + SpW),
    .Cut(Cuts[4] ? 1 : 0)
  ) u_rp (
    .clk_i, .rst_ni,
    .valid_i(c3_valid), .aux_i({c3_sx, c3_sub, c3_zero, c3_sp}),
    .sign_i(c3_sx), .exp_i(c3_exp), .sig_i(c3_sig), .sticky_i(c3_sticky),
    .valid_o(r_valid), .aux_o({r_sx, r_sub, r_zero, r_sp}),
    .y_o(rp_y), .of_o(rp_of), .uf_o(rp_uf), .nx_o(rp_nx)
  );

  always_comb begin
    y     = rp_y;
    flags = {2'b00, rp_of, rp_uf, rp_nx};
    if (sp_nan) begin
      y     = {1'b0, {ExpW{1'b1}}, 1'b1, {(FracW - 1) {1'b0}}};
      flags = {sp_invalid, 4'b0000};
    end else if (sp_inf) begin
      y     = {sp_inf_sign, {ExpW{1'b1}}, {FracW{1'b0}}};
      flags = '0;
    end else if (r_zero) begin
      // exact zero: x + (-x) is +0 (-0 under RDN); equal-signed zeros keep their sign
      y     = {r_sub ? (Round == 2) : r_sx, {(ExpW + FracW) {1'b0}}};
      flags = '0;
    end
  end

  // ---- output registers (Stages beyond the cuts used) ------------------------------------
  ru_pipe #(.Width(W + 5), .Depth(OutRegs)) u_out (
    .clk_i, .rst_ni,
    .valid_i(r_valid),
    .data_i ({y, flags}),
    .valid_o(out_valid_o),
    .data_o ({y_o, flags_o})
  );

endmodule
