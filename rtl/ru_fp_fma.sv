// ru_fp_fma: fused multiply-add with ONE rounding, docs/FORMAT.md semantics (= ru::num::fma).
//   y = round( (-1)^op_i[1] * a * b + (-1)^op_i[0] * c ):
//   op_i = 0 fma a*b+c, 1 fms a*b-c, 2 fnms -(a*b)+c, 3 fnma -(a*b)-c (RISC-V fmadd, fmsub,
//   fnmsub, fnmadd). The op bits only flip the sign of the product / of c (a NaN stays a NaN).
//
// Parameters: ExpW (2..11), FracW (1..52), Stages (latency in cycles, 0 = combinational),
// Subnormals (1 gradual underflow, 0 flush-to-zero), Round (0 RNE, 1 RTZ, 2 RDN, 3 RUP).
// CutSel is internal; leave it. Fully pipelined: one operation per cycle, out_valid_o =
// in_valid_i delayed by Stages.
//
// Algorithm (N = FracW+1, every significand unnormalized as classify gives it, exponents the
// effective biased exponents, 1 for subnormals and zeros):
//   * the product P = ma*mb is exact (2N bits, ru_umul). It is never shifted: it sits at bits
//     [2N+2:3] of a window of WW = 3N+5 bits (three zero bits below it);
//   * c starts at the top of the window, bits [3N+4:2N+5], and is shifted right by
//     sh = 2N+2 - d, d = ec - ea - eb + bias + FracW (c's LSB weight over P's LSB weight), at
//     most WW; bits shifted out are ORed ("jammed") into bit 0. Jamming keeps the rounding exact:
//     the window sum then lies in the same open interval between two even window integers as
//     the exact sum, and whenever something was jammed the sum has its MSB at bit N+1 or above
//     (c is then below P's window position and P >= 2^(N-1)), so the guard bit is at bit 1 or
//     higher and bit 0 only feeds the sticky bit;
//   * d > 2N+2 (c at least 3 bits above P's top bit, c non-zero) or a zero product: c stays at
//     the top (sh = 0) and P is replaced by one jammed bit (P != 0); the window's exponent then
//     follows c (exp = ec + 1 for the window MSB) instead of the product (ea + eb - bias + FracW
//     + 5);
//   * effective subtraction (sign(p) != sign(c)): both c - p and p - c are formed, the one
//     that is not negative is taken (its sign is the result's sign), so no negation is needed;
//   * leading-zero normalization of the (WW+1)-bit sum, top N+1 bits + sticky into the shared
//     round-and-pack (tininess after rounding, subnormals or flush-to-zero, overflow).
// Exact zero results: x + (-x) and (+0) + (-0) give +0 (-0 under RDN); equal-signed zero
// terms keep their sign (-0 * 1 + -0 = -0). A zero product gives c exactly (no flag).
// Special cases: any NaN operand -> canonical NaN (invalid for a signaling NaN); inf * 0 ->
// NaN, invalid (also when c is a quiet NaN); inf*b + c with c = inf of the other sign -> NaN,
// invalid; else an infinite product or c gives that infinity (no flags).
//
// Datapath segments (L = ru_fp_pkg::csa_levels(FracW+1)) and the cut position after each:
//   seg 0      unpack/classify a, b, c, special cases, exponents, shift amount   | cut 0
//   seg 1      align c (shift right, sticky jammed into bit 0)                   | cut 1
//   seg 2..L+1 carry-save level k of the significand product (ru_umul)           | cut k+1
//   seg L+2    final product adder                                              | cut L+2
//   seg L+3    window add / subtract (c + p, c - p, p - c), select, sign        | cut L+3
//   seg L+4    normalize (leading-zero count + shift of WW+1 bits)              | cut L+4
//   seg L+5    round-and-pack: tininess, denormalization                        | cut L+5
//   seg L+6    round-and-pack: increment, overflow; special-result mux -> y_o, flags_o
// Stages registers go to the cut positions that minimize the deepest stage under the depth
// estimates of ru_fp_pkg::fma_seg_w (ru_pipe_pkg::cut_mask). Useful maximum: Stages = L+6
// (every cut registered). Any larger Stages is accepted; the registers beyond L+6 are placed at
// the output.
module ru_fp_fma #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts,
  // Weights of the automatic placement: '0 = the depth estimates of ru_fp_pkg::fma_seg_w; else
  // packed 8-bit weights per segment (`rayunits synth --placement delay` passes delays measured
  // by STA in the cell library, synth/README.md).
  parameter logic [ru_pipe_pkg::WW-1:0] SegW = '0
) (
  input  logic                clk_i,
  input  logic                rst_ni,
  input  logic                in_valid_i,
  input  logic [ExpW+FracW:0] a_i,
  input  logic [ExpW+FracW:0] b_i,
  input  logic [ExpW+FracW:0] c_i,
  input  logic [1:0]          op_i,
  output logic                out_valid_o,
  output logic [ExpW+FracW:0] y_o,
  output logic [4:0]          flags_o
);

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam int unsigned N = FracW + 1;       // significand width
  localparam int unsigned WW = 3 * N + 5;      // alignment window
  localparam int unsigned SW = WW + 1;         // sum (with carry)
  localparam int unsigned ShW = ru_fp_pkg::clog2p(WW + 1);
  localparam int unsigned ExpIW = ru_fp_pkg::exp_iw(ExpW, FracW);
  localparam int unsigned DW = ExpIW + 1;      // exponent difference d
  localparam int unsigned L = ru_fp_pkg::csa_levels(N);
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(
      CutSel,
      ru_pipe_pkg::pick_w(SegW, ru_fp_pkg::fma_seg_w(ExpW, FracW, Subnormals)),
      ru_fp_pkg::fma_nseg(FracW), Stages);
  // Useful maximum of Stages (a register at every cut position) and the registers placed at the
  // output (Stages - popcount(Cuts); with automatic placement: those beyond MaxUsefulStages).
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(ru_fp_pkg::fma_nseg(FracW));
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_fp_fma: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  localparam int signed Bias = (1 << (ExpW - 1)) - 1;
  // special-case bundle {nan, invalid, inf, inf_sign}
  localparam int unsigned SpW = 4;
  // side information through the multiplier: {c window, clamped, p non-zero, sub, sign p,
  // sign c, exp, specials}
  localparam int unsigned AuxW = WW + 5 + ExpIW + SpW;

  // ---- seg 0: unpack, special cases, exponents --------------------------------------------
  logic [W-1:0] c_eff;
  assign c_eff = {c_i[W-1] ^ op_i[0], c_i[W-2:0]};

  logic sa, sb, sc, za, zb, zc, ia, ib, ic, na, nb, nc, sna, snb, snc;
  logic [ExpW-1:0] ea, eb, ec;
  logic [N-1:0] ma, mb, mc;
  logic unused_sub_a, unused_sub_b, unused_sub_c;

  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_a (
    .x_i(a_i), .sign_o(sa), .exp_o(ea), .sig_o(ma), .zero_o(za), .sub_o(unused_sub_a),
    .inf_o(ia), .nan_o(na), .snan_o(sna)
  );
  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_b (
    .x_i(b_i), .sign_o(sb), .exp_o(eb), .sig_o(mb), .zero_o(zb), .sub_o(unused_sub_b),
    .inf_o(ib), .nan_o(nb), .snan_o(snb)
  );
  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_c (
    .x_i(c_eff), .sign_o(sc), .exp_o(ec), .sig_o(mc), .zero_o(zc), .sub_o(unused_sub_c),
    .inf_o(ic), .nan_o(nc), .snan_o(snc)
  );

  logic s0_sp, s0_sub, prod_inf, prod_zero, inf_times_zero, inf_minus_inf;
  logic [SpW-1:0] s0_spc;
  assign s0_sp          = sa ^ sb ^ op_i[1];
  assign s0_sub         = s0_sp ^ sc;
  assign prod_inf       = ia | ib;
  assign prod_zero      = za | zb;
  assign inf_times_zero = prod_inf & prod_zero;
  assign inf_minus_inf  = prod_inf & ic & s0_sub & ~na & ~nb;
  assign s0_spc = {na | nb | nc | inf_times_zero | inf_minus_inf,
                   sna | snb | snc | inf_times_zero | inf_minus_inf,
                   prod_inf | ic, prod_inf ? s0_sp : sc};

  // d = ec - ea - eb + bias + FracW: c's LSB weight over the product's LSB weight
  logic signed [DW-1:0]    s0_d, s0_shf;
  logic signed [ExpIW-1:0] s0_exp;
  logic                    s0_clamp;
  logic [ShW-1:0]          s0_sh;
  // (signed constants: a comparison with an unsigned operand would be unsigned)
  localparam logic signed [DW-1:0] DTop = DW'(2 * N + 2);  // c at the top of the window
  localparam logic signed [DW-1:0] ShMax = DW'(WW);         // c entirely below the window
  assign s0_d     = DW'(ec) - DW'(ea) - DW'(eb) + DW'(Bias + FracW);
  assign s0_clamp = prod_zero | (~zc & (s0_d > DTop));
  assign s0_shf   = DTop - s0_d;
  assign s0_sh    = s0_clamp ? '0 : (s0_shf > ShMax) ? ShW'(WW) : s0_shf[ShW-1:0];
  // biased exponent of the window sum if its MSB (bit SW-1) is set
  assign s0_exp   = s0_clamp ? ExpIW'(ec) + ExpIW'(1)
                             : ExpIW'(ea) + ExpIW'(eb) - ExpIW'(Bias) + ExpIW'(FracW + 5);

  // ---- cut 0 ----------------------------------------------------------------------------
  logic                    c0_valid, c0_clamp, c0_pnz, c0_sub, c0_sp, c0_sc;
  logic [N-1:0]            c0_ma, c0_mb, c0_mc;
  logic [ShW-1:0]          c0_sh;
  logic signed [ExpIW-1:0] c0_exp;
  logic [SpW-1:0]          c0_spc;
  ru_pipe #(.Width(3 * N + ShW + 5 + ExpIW + SpW), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({ma, mb, mc, s0_sh, s0_clamp, ~prod_zero, s0_sub, s0_sp, sc, s0_exp, s0_spc}),
    .valid_o(c0_valid),
    .data_o ({c0_ma, c0_mb, c0_mc, c0_sh, c0_clamp, c0_pnz, c0_sub, c0_sp, c0_sc, c0_exp,
              c0_spc})
  );

  // ---- seg 1: align c -------------------------------------------------------------------
  logic [WW-1:0] c_sh, c_lost, s1_cw;
  assign {c_sh, c_lost} = {c0_mc, {(2 * N + 5) {1'b0}}, {WW{1'b0}}} >> c0_sh;
  assign s1_cw = {c_sh[WW-1:1], c_sh[0] | (|c_lost)};

  // ---- cut 1 ----------------------------------------------------------------------------
  logic            c1_valid;
  logic [N-1:0]    c1_ma, c1_mb;
  logic [AuxW-1:0] c1_aux;
  ru_pipe #(.Width(2 * N + AuxW), .Depth(Cuts[1] ? 1 : 0)) u_cut1 (
    .clk_i, .rst_ni,
    .valid_i(c0_valid),
    .data_i ({c0_ma, c0_mb, s1_cw, c0_clamp, c0_pnz, c0_sub, c0_sp, c0_sc, c0_exp, c0_spc}),
    .valid_o(c1_valid),
    .data_o ({c1_ma, c1_mb, c1_aux})
  );

  // ---- seg 2..L+2: significand product (cuts 2..L+2 inside) -------------------------------
  logic            p_valid;
  logic [2*N-1:0]  p_prod;
  logic [AuxW-1:0] p_aux;
  ru_umul #(.N(N), .AuxW(AuxW), .CutMask(Cuts >> 2)) u_umul (
    .clk_i, .rst_ni,
    .valid_i(c1_valid),
    .a_i    (c1_ma),
    .b_i    (c1_mb),
    .aux_i  (c1_aux),
    .valid_o(p_valid),
    .p_o    (p_prod),
    .aux_o  (p_aux)
  );

  // ---- seg L+3: add / subtract in the window ---------------------------------------------
  logic [WW-1:0]           p_cw, p_pw;
  logic                    p_clamp, p_pnz, p_sub, p_sp, p_sc;
  logic signed [ExpIW-1:0] p_exp;
  logic [SpW-1:0]          p_spc;
  assign {p_cw, p_clamp, p_pnz, p_sub, p_sp, p_sc, p_exp, p_spc} = p_aux;
  assign p_pw = p_clamp ? WW'(p_pnz) : WW'({p_prod, 3'b000});

  logic [SW-1:0] s3_sum, s3_mag;
  logic [SW:0]   s3_cmp;   // c - p with its borrow
  logic [SW-1:0] s3_pmc;   // p - c
  logic          s3_neg, s3_sign;
  assign s3_sum  = {1'b0, p_cw} + {1'b0, p_pw};
  assign s3_cmp  = {2'b00, p_cw} - {2'b00, p_pw};
  assign s3_pmc  = {1'b0, p_pw} - {1'b0, p_cw};
  assign s3_neg  = s3_cmp[SW];
  assign s3_mag  = !p_sub ? s3_sum : s3_neg ? s3_pmc : s3_cmp[SW-1:0];
  assign s3_sign = (p_sub & ~s3_neg) ? p_sc : p_sp;

  // ---- cut L+3 ---------------------------------------------------------------------------
  logic                    c3_valid, c3_sign, c3_sub;
  logic [SW-1:0]           c3_mag;
  logic signed [ExpIW-1:0] c3_exp;
  logic [SpW-1:0]          c3_spc;
  ru_pipe #(.Width(SW + 2 + ExpIW + SpW), .Depth(Cuts[L+3] ? 1 : 0)) u_cut3 (
    .clk_i, .rst_ni,
    .valid_i(p_valid),
    .data_i ({s3_mag, s3_sign, p_sub, p_exp, p_spc}),
    .valid_o(c3_valid),
    .data_o ({c3_mag, c3_sign, c3_sub, c3_exp, c3_spc})
  );

  // ---- seg L+4: normalize ----------------------------------------------------------------
  logic [SW-1:0]           n_mag;
  logic signed [ExpIW-1:0] n_exp;
  logic                    n_zero;
  ru_fp_normalize #(.Width(SW), .ExpIW(ExpIW), .Full(1)) u_norm (
    .sig_i(c3_mag), .exp_i(c3_exp), .sig_o(n_mag), .exp_o(n_exp), .zero_o(n_zero)
  );

  // ---- cut L+4 ---------------------------------------------------------------------------
  logic                    c4_valid, c4_sign, c4_sub, c4_zero, c4_sticky;
  logic [N:0]              c4_sig;
  logic signed [ExpIW-1:0] c4_exp;
  logic [SpW-1:0]          c4_spc;
  ru_pipe #(.Width(N + 1 + 4 + ExpIW + SpW), .Depth(Cuts[L+4] ? 1 : 0)) u_cut4 (
    .clk_i, .rst_ni,
    .valid_i(c3_valid),
    .data_i ({n_mag[SW-1 -: N+1], |n_mag[SW-N-2:0], c3_sign, c3_sub, n_zero, n_exp, c3_spc}),
    .valid_o(c4_valid),
    .data_o ({c4_sig, c4_sticky, c4_sign, c4_sub, c4_zero, c4_exp, c4_spc})
  );

  // ---- seg L+5, cut L+5, seg L+6: round and pack, special results -------------------------
  logic [W-1:0]   rp_y, y;
  logic           rp_of, rp_uf, rp_nx, r_valid, r_sign, r_sub, r_zero;
  logic [4:0]     flags;
  logic [SpW-1:0] r_spc;
  logic           sp_nan, sp_invalid, sp_inf, sp_inf_sign;
  assign {sp_nan, sp_invalid, sp_inf, sp_inf_sign} = r_spc;

  ru_fp_round_pack #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round), .AuxW(3 + SpW),
    .Cut(Cuts[L+5] ? 1 : 0)
  ) u_rp (
    .clk_i, .rst_ni,
    .valid_i(c4_valid), .aux_i({c4_sign, c4_sub, c4_zero, c4_spc}),
    .sign_i(c4_sign), .exp_i(c4_exp), .sig_i(c4_sig), .sticky_i(c4_sticky),
    .valid_o(r_valid), .aux_o({r_sign, r_sub, r_zero, r_spc}),
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
      // exact zero: opposite-signed terms give +0 (-0 under RDN); equal signs keep the sign
      y     = {r_sub ? (Round == 2) : r_sign, {(ExpW + FracW) {1'b0}}};
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
