// ru_fp_mul: floating-point multiply y = round(a * b), docs/FORMAT.md semantics.
//
// Parameters: ExpW (2..11), FracW (1..52), Stages (latency in cycles, 0 = combinational),
// Subnormals (1 gradual underflow, 0 flush-to-zero), Round (0 RNE, 1 RTZ, 2 RDN, 3 RUP).
// CutSel is internal (ru_fp_dot3 uses it to place this unit's registers itself); leave it.
// Fully pipelined: one operation per cycle, out_valid_o = in_valid_i delayed by Stages.
//
// Datapath segments (L = ru_fp_pkg::csa_levels(FracW+1): 2 for e4m3, 5 for e5m10,
// 7 for e8m23, 9 for e11m52) and the cut position after each:
//   seg 0      unpack/classify a and b, special cases, exponent sum      | cut 0
//   seg 1..L   carry-save level k of the significand product (ru_umul)   | cut k
//   seg L+1    final carry-propagate adder                               | cut L+1
//   seg L+2    normalize (lzc + shift; a 1-bit shift when Subnormals=0)  | cut L+2
//   seg L+3    round-and-pack: tininess, denormalization                 | cut L+3
//   seg L+4    round-and-pack: increment, overflow; special-result mux   -> y_o, flags_o
// Stages registers go to the cut positions that minimize the deepest stage under the
// depth estimates of ru_fp_pkg::mul_seg_w (ru_pipe_pkg::cut_mask). Useful maximum:
// Stages = L+4 (every cut registered). Any larger Stages is accepted; the registers beyond
// L+4 are placed at the output.
module ru_fp_mul #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts,
  // Weights of the automatic placement: '0 = the depth estimates of ru_fp_pkg::mul_seg_w; else
  // packed 8-bit weights per segment (`rayunits synth --placement delay` passes delays measured
  // by STA in the cell library, synth/README.md).
  parameter logic [ru_pipe_pkg::WW-1:0] SegW = '0
) (
  input  logic                clk_i,
  input  logic                rst_ni,
  input  logic                in_valid_i,
  input  logic [ExpW+FracW:0] a_i,
  input  logic [ExpW+FracW:0] b_i,
  output logic                out_valid_o,
  output logic [ExpW+FracW:0] y_o,
  output logic [4:0]          flags_o
);

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam int unsigned N = FracW + 1;  // significand width
  localparam int unsigned ExpIW = ru_fp_pkg::exp_iw(ExpW, FracW);
  localparam int unsigned L = ru_fp_pkg::csa_levels(N);
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(
      CutSel,
      ru_pipe_pkg::pick_w(SegW, ru_fp_pkg::mul_seg_w(ExpW, FracW, Subnormals)),
      ru_fp_pkg::mul_nseg(FracW), Stages);
  // Useful maximum of Stages (a register at every cut position) and the registers placed at the
  // output (Stages - popcount(Cuts); with automatic placement: those beyond MaxUsefulStages).
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(ru_fp_pkg::mul_nseg(FracW));
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_fp_mul: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  localparam int signed Bias = (1 << (ExpW - 1)) - 1;
  // side information that travels with the significands: {sign, exp, nan, inf, zero, invalid}
  localparam int unsigned AuxW = ExpIW + 5;

  // ---- seg 0: unpack, special cases, exponent ------------------------------------------
  logic sa, sb, za, zb, ia, ib, na, nb, sna, snb;
  logic [ExpW-1:0] ea, eb;
  logic [N-1:0] ma, mb;
  logic unused_sub_a, unused_sub_b;

  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_a (
    .x_i(a_i), .sign_o(sa), .exp_o(ea), .sig_o(ma), .zero_o(za), .sub_o(unused_sub_a),
    .inf_o(ia), .nan_o(na), .snan_o(sna)
  );
  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_b (
    .x_i(b_i), .sign_o(sb), .exp_o(eb), .sig_o(mb), .zero_o(zb), .sub_o(unused_sub_b),
    .inf_o(ib), .nan_o(nb), .snan_o(snb)
  );

  logic s0_sign, s0_nan, s0_inf, s0_zero, s0_invalid, inf_times_zero;
  logic signed [ExpIW-1:0] s0_exp;
  assign inf_times_zero = (ia & zb) | (za & ib);
  assign s0_sign    = sa ^ sb;
  assign s0_nan     = na | nb | inf_times_zero;
  assign s0_invalid = sna | snb | inf_times_zero;
  assign s0_inf     = ia | ib;  // overridden by s0_nan
  assign s0_zero    = za | zb;  // overridden by s0_nan / s0_inf
  // biased exponent of the product if its MSB sits at bit 2N-1 (normalize subtracts lz)
  assign s0_exp     = ExpIW'(ea) + ExpIW'(eb) - ExpIW'(Bias - 1);

  // ---- cut 0 ----------------------------------------------------------------------------
  logic            c0_valid;
  logic [N-1:0]    c0_ma, c0_mb;
  logic [AuxW-1:0] c0_aux;
  ru_pipe #(.Width(2 * N + AuxW), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({ma, mb, s0_sign, s0_exp, s0_nan, s0_inf, s0_zero, s0_invalid}),
    .valid_o(c0_valid),
    .data_o ({c0_ma, c0_mb, c0_aux})
  );

  // ---- seg 1..L+1: significand product (cuts 1..L+1 inside) ------------------------------
  logic            c1_valid;
  logic [2*N-1:0]  c1_prod;
  logic [AuxW-1:0] c1_aux;
  ru_umul #(.N(N), .AuxW(AuxW), .CutMask(Cuts >> 1)) u_umul (
    .clk_i, .rst_ni,
    .valid_i(c0_valid),
    .a_i    (c0_ma),
    .b_i    (c0_mb),
    .aux_i  (c0_aux),
    .valid_o(c1_valid),
    .p_o    (c1_prod),
    .aux_o  (c1_aux)
  );

  // ---- seg L+2: normalize ----------------------------------------------------------------
  logic                    c1_sign, c1_nan, c1_inf, c1_zero, c1_invalid;
  logic signed [ExpIW-1:0] c1_exp, n_exp;
  logic [2*N-1:0]          n_prod;
  logic                    n_sticky, unused_n_zero;
  assign {c1_sign, c1_exp, c1_nan, c1_inf, c1_zero, c1_invalid} = c1_aux;

  ru_fp_normalize #(.Width(2 * N), .ExpIW(ExpIW), .Full(Subnormals)) u_norm (
    .sig_i(c1_prod), .exp_i(c1_exp), .sig_o(n_prod), .exp_o(n_exp), .zero_o(unused_n_zero)
  );
  assign n_sticky = |n_prod[N-2:0];

  // ---- cut L+2 ---------------------------------------------------------------------------
  logic                    c2_valid, c2_sign, c2_nan, c2_inf, c2_zero, c2_invalid, c2_sticky;
  logic signed [ExpIW-1:0] c2_exp;
  logic [N:0]              c2_sig;
  ru_pipe #(.Width(N + 1 + AuxW + 1), .Depth(Cuts[L+2] ? 1 : 0)) u_cut2 (
    .clk_i, .rst_ni,
    .valid_i(c1_valid),
    .data_i ({n_prod[2*N-1:N-1], n_sticky, c1_sign, n_exp, c1_nan, c1_inf, c1_zero,
              c1_invalid}),
    .valid_o(c2_valid),
    .data_o ({c2_sig, c2_sticky, c2_sign, c2_exp, c2_nan, c2_inf, c2_zero, c2_invalid})
  );

  // ---- seg L+3, cut L+3, seg L+4: round and pack, special results -------------------------
  logic [W-1:0] rp_y, y;
  logic         rp_of, rp_uf, rp_nx, r_valid, r_sign, r_nan, r_inf, r_zero, r_invalid;
  logic [4:0]   flags;
  ru_fp_round_pack #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round), .AuxW(5),
    .Cut(Cuts[L+3] ? 1 : 0)
  ) u_rp (
    .clk_i, .rst_ni,
    .valid_i(c2_valid), .aux_i({c2_sign, c2_nan, c2_inf, c2_zero, c2_invalid}),
    .sign_i(c2_sign), .exp_i(c2_exp), .sig_i(c2_sig), .sticky_i(c2_sticky),
    .valid_o(r_valid), .aux_o({r_sign, r_nan, r_inf, r_zero, r_invalid}),
    .y_o(rp_y), .of_o(rp_of), .uf_o(rp_uf), .nx_o(rp_nx)
  );

  always_comb begin
    y     = rp_y;
    flags = {2'b00, rp_of, rp_uf, rp_nx};
    if (r_nan) begin
      y     = {1'b0, {ExpW{1'b1}}, 1'b1, {(FracW - 1) {1'b0}}};
      flags = {r_invalid, 4'b0000};
    end else if (r_inf) begin
      y     = {r_sign, {ExpW{1'b1}}, {FracW{1'b0}}};
      flags = '0;
    end else if (r_zero) begin
      y     = {r_sign, {(ExpW + FracW) {1'b0}}};
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
