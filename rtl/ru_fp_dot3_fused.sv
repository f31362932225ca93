// ru_fp_dot3_fused: fused 3-term dot product y = round(a0*b0 + a1*b1 + a2*b2), the exact sum of
// the three exact products rounded ONCE (docs/FORMAT.md dot3_fused, = ru::num::dot3_fused).
// Same ports as ru_fp_dot3: a_i = {a2, a1, a0}, b_i = {b2, b1, b0} (a0 in the low bits).
//
// Parameters: ExpW (2..11), FracW (1..52), Stages (latency in cycles, 0 = combinational),
// Subnormals (1 gradual underflow, 0 flush-to-zero), Round (0 RNE, 1 RTZ, 2 RDN, 3 RUP).
// CutSel is internal; leave it. Fully pipelined: one dot product per cycle.
//
// Algorithm (N = FracW+1). Subnormal operands are normalized first, so every non-zero product
// P_k = ma*mb is exact with 2N bits and P_k in [2^(2N-2), 2^(2N)), at exponent E_k = ea + eb
// (the products' LSB weights). The anchor A is a non-zero product of largest E; J and K are the
// other two (rotation of 0, 1, 2), d_J = E_A - E_J, d_K = E_A - E_K. The window has WW = 4N+4
// bits: A at bits [WW-1:K+1] with K = 2N+3 exact bits below it, bit 0 collects the bits shifted
// out ("jam"). A term is far when it is non-zero and d > K (it loses bits).
//   * no far term: all three are exact in the window;
//   * one far term F, the near one (N') not cancelling A: F's lost bits are jammed. X = A + N'
//     is a non-zero multiple of 2^(K-1) window units (|X| >= 2^(K-1): if d_N' <= 1 it is a
//     multiple of 2^K, if d_N' >= 2 then |N'| <= |A|/2 up to its last bit) while |F| < 2^(2N) =
//     2^(K-3), so the sum stays above 2^(K-2), its guard bit lies above bit 1, and the window
//     sum lies in the same open interval between two even window integers as the exact sum;
//   * one far term and A + N' = 0 exactly (possible only for d_N' <= 1 with equal magnitudes,
//     opposite signs): the result is F alone, exactly: F takes the anchor's place;
//   (The bound is loose: X can only be small for d_N' <= 1, where it is a multiple of 2^K,
//   so K = 2N+1 also passes every test; K = 2N-1 and K = N+1 fail them, see tb/README.md.)
//   * two far terms: their sum Z has |Z| < 2^(2N+1) = 2^(K-2) window units; both are replaced
//     by one jam bit with the sign of Z (Z = 0 drops it). Sign and zero-ness of Z come from a
//     magnitude compare of P_J and P_K (exponents differ by <= 1, or the larger exponent wins).
// The signed sum of the three window terms (4N+7 bits, two's complement), its magnitude,
// leading-zero normalization, then the shared round-and-pack with the top N+1 bits and the
// sticky OR of the rest.
// Exact zero: all products zero of one sign keep it; otherwise +0 (-0 under RDN).
// Special cases: any NaN operand -> canonical NaN, invalid iff a signaling NaN or an inf*0
// product; else inf*0, or infinite products of both signs -> NaN, invalid; else an infinite
// product gives that infinity.
//
// Datapath segments (L = ru_fp_pkg::csa_levels(FracW+1)) and the cut position after each:
//   seg 0      unpack/classify the six operands, normalize subnormals, specials, E_k  | cut 0
//   seg 1      anchor choice, operand rotation, d_J, d_K, far flags, shift amounts    | cut 1
//   seg 2..L+1 carry-save level k of the three significand products (ru_umul)        | cut k+1
//   seg L+2    final product adders                                                  | cut L+2
//   seg L+3    align J and K (shift right, jam), cancel / Z-sign compares, selection | cut L+3
//   seg L+4    signed three-term sum, magnitude and sign                             | cut L+4
//   seg L+5    normalize (leading-zero count + shift of 4N+6 bits)                   | cut L+5
//   seg L+6    round-and-pack: tininess, denormalization                             | cut L+6
//   seg L+7    round-and-pack: increment, overflow; special-result mux -> y_o, flags_o
// Stages registers go to the cut positions that minimize the deepest stage under the depth
// estimates of ru_fp_pkg::dot3f_seg_w (ru_pipe_pkg::cut_mask). Useful maximum: Stages = L+7.
// Any larger Stages is accepted; the registers beyond L+7 are placed at the output.
module ru_fp_dot3_fused #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts,
  // Weights of the automatic placement: '0 = the depth estimates of ru_fp_pkg::dot3f_seg_w;
  // else packed 8-bit weights per segment (`rayunits synth --placement delay`, synth/README.md).
  parameter logic [ru_pipe_pkg::WW-1:0] SegW = '0
) (
  input  logic                          clk_i,
  input  logic                          rst_ni,
  input  logic                          in_valid_i,
  input  logic [3*(ExpW+FracW+1)-1:0]   a_i,
  input  logic [3*(ExpW+FracW+1)-1:0]   b_i,
  output logic                          out_valid_o,
  output logic [ExpW+FracW:0]           y_o,
  output logic [4:0]                    flags_o
);

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam int unsigned N = FracW + 1;       // significand width
  localparam int unsigned PW = 2 * N;          // product width
  localparam int unsigned K = 2 * N + 3;       // exact bits below the anchor
  localparam int unsigned WW = PW + K + 1;     // window (bit 0: jam)
  localparam int unsigned SW = WW + 3;         // signed sum
  localparam int unsigned MW = WW + 2;         // its magnitude
  localparam int unsigned ShW = ru_fp_pkg::clog2p(WW + 1);
  localparam int unsigned ExpIW = ru_fp_pkg::exp_iw(ExpW, FracW);
  localparam int unsigned EW = ExpIW + 1;      // product exponents and their differences
  localparam int unsigned L = ru_fp_pkg::csa_levels(N);
  localparam int unsigned NSeg = ru_fp_pkg::dot3f_nseg(FracW);
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(
      CutSel, ru_pipe_pkg::pick_w(SegW, ru_fp_pkg::dot3f_seg_w(ExpW, FracW, Subnormals)), NSeg, Stages);
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(NSeg);
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_fp_dot3_fused: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  localparam int signed Bias = (1 << (ExpW - 1)) - 1;
  localparam int unsigned SpW = 4;             // {nan, invalid, inf, inf_sign}
  localparam int unsigned ZW = 2;              // {all products zero, sign of that zero}

  // ---- seg 0: classify, normalize, specials, product exponents ------------------------------
  logic [3*N-1:0]  s0_ma, s0_mb;
  logic [3*EW-1:0] s0_e;
  logic [2:0]      s0_ps, s0_nz;
  logic [2:0]      p_nan, p_snan, p_itz, p_inf;
  for (genvar k = 0; k < 3; k++) begin : gen_op
    logic sa, sb, za, zb, ia, ib, na, nb, sna, snb, unused_sa, unused_sb, unused_za, unused_zb;
    logic [ExpW-1:0] ea, eb;
    logic [N-1:0]    ma, mb;
    logic signed [EW-1:0] nea, neb;
    ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_a (
      .x_i(a_i[k*W+:W]), .sign_o(sa), .exp_o(ea), .sig_o(ma), .zero_o(za), .sub_o(unused_sa),
      .inf_o(ia), .nan_o(na), .snan_o(sna)
    );
    ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_b (
      .x_i(b_i[k*W+:W]), .sign_o(sb), .exp_o(eb), .sig_o(mb), .zero_o(zb), .sub_o(unused_sb),
      .inf_o(ib), .nan_o(nb), .snan_o(snb)
    );
    if (Subnormals != 0) begin : gen_norm
      ru_fp_normalize #(.Width(N), .ExpIW(EW), .Full(1)) u_na (
        .sig_i(ma), .exp_i(EW'(ea)), .sig_o(s0_ma[k*N+:N]), .exp_o(nea), .zero_o(unused_za)
      );
      ru_fp_normalize #(.Width(N), .ExpIW(EW), .Full(1)) u_nb (
        .sig_i(mb), .exp_i(EW'(eb)), .sig_o(s0_mb[k*N+:N]), .exp_o(neb), .zero_o(unused_zb)
      );
    end else begin : gen_ftz
      assign s0_ma[k*N+:N] = ma;
      assign s0_mb[k*N+:N] = mb;
      assign nea = EW'(ea);
      assign neb = EW'(eb);
      assign {unused_za, unused_zb} = 2'b00;
    end
    assign s0_e[k*EW+:EW] = nea + neb;
    assign s0_ps[k]  = sa ^ sb;
    assign s0_nz[k]  = ~(za | zb) & ~(ia | ib) & ~(na | nb);
    assign p_nan[k]  = na | nb;
    assign p_snan[k] = sna | snb;
    assign p_itz[k]  = (ia | ib) & (za | zb);
    assign p_inf[k]  = (ia | ib) & ~(za | zb) & ~(na | nb);
  end

  logic           any_nan, pos_inf, neg_inf;
  logic [SpW-1:0] s0_spc;
  logic [ZW-1:0]  s0_z;
  assign any_nan = |p_nan;
  assign pos_inf = |(p_inf & ~s0_ps);
  assign neg_inf = |(p_inf & s0_ps);
  assign s0_spc = {any_nan | (|p_itz) | (pos_inf & neg_inf),
                   (|p_snan) | (|p_itz) | (~any_nan & pos_inf & neg_inf),
                   pos_inf | neg_inf, neg_inf};
  // all products zero: one sign is kept, mixed signs give +0 (-0 under RDN)
  assign s0_z = {~|s0_nz, (&s0_ps) | (~&(~s0_ps) & (Round == 2))};

  // ---- cut 0 ----------------------------------------------------------------------------
  logic            c0_valid;
  logic [3*N-1:0]  c0_ma, c0_mb;
  logic [3*EW-1:0] c0_e;
  logic [2:0]      c0_ps, c0_nz;
  logic [SpW-1:0]  c0_spc;
  logic [ZW-1:0]   c0_z;
  ru_pipe #(.Width(6 * N + 3 * EW + 6 + SpW + ZW), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({s0_ma, s0_mb, s0_e, s0_ps, s0_nz, s0_spc, s0_z}),
    .valid_o(c0_valid),
    .data_o ({c0_ma, c0_mb, c0_e, c0_ps, c0_nz, c0_spc, c0_z})
  );

  // ---- seg 1: anchor, rotation, differences ---------------------------------------------
  logic signed [EW-1:0] e0, e1, e2;
  assign {e2, e1, e0} = c0_e;
  logic [1:0] anc, ij, ik;
  always_comb begin
    if (c0_nz[0] && (!c0_nz[1] || e0 >= e1) && (!c0_nz[2] || e0 >= e2)) anc = 2'd0;
    else if (c0_nz[1] && (!c0_nz[2] || e1 >= e2)) anc = 2'd1;
    else anc = 2'd2;
  end
  assign ij = (anc == 2'd2) ? 2'd0 : anc + 2'd1;
  assign ik = (anc == 2'd0) ? 2'd2 : anc - 2'd1;

  logic signed [EW-1:0] ea_x, ej_x, ek_x, dj, dk, dlt;
  assign ea_x = c0_e[anc*EW+:EW];
  assign ej_x = c0_e[ij*EW+:EW];
  assign ek_x = c0_e[ik*EW+:EW];
  assign dj   = ea_x - ej_x;
  assign dk   = ea_x - ek_x;
  assign dlt  = ej_x - ek_x;          // E_J - E_K
  localparam logic signed [EW-1:0] KS = EW'(K);
  localparam logic signed [EW-1:0] WS = EW'(WW);
  logic nzj, nzk, farj, fark;
  assign nzj  = c0_nz[ij];
  assign nzk  = c0_nz[ik];
  assign farj = nzj & (dj > KS);
  assign fark = nzk & (dk > KS);
  logic [ShW-1:0] shj, shk;
  assign shj = (!nzj || dj > WS) ? ShW'(WW) : dj[ShW-1:0];
  assign shk = (!nzk || dk > WS) ? ShW'(WW) : dk[ShW-1:0];
  // d of the near term (the one not far) clamped to 0, 1, 2 (>= 2: it cannot cancel A)
  logic [1:0] dn;
  logic signed [EW-1:0] dnear;
  assign dnear = farj ? dk : dj;
  assign dn = (dnear == '0) ? 2'd0 : (dnear == EW'(1)) ? 2'd1 : 2'd2;
  // E_J - E_K: {J larger by exponent, K larger by exponent, +1, -1} (else 0)
  logic [3:0] dcls;
  assign dcls = {dlt > EW'(1), dlt < -EW'(1), dlt == EW'(1), dlt == -EW'(1)};
  // window exponents (biased exponent of the magnitude's MSB): E - bias + 3
  logic signed [ExpIW-1:0] xa, xf;
  assign xa = ExpIW'(ea_x - EW'(Bias) + EW'(3));
  assign xf = ExpIW'((farj ? ej_x : ek_x) - EW'(Bias) + EW'(3));
  logic [2:0] s1_sg;   // {sK, sJ, sA}
  assign s1_sg = {c0_ps[ik], c0_ps[ij], c0_ps[anc]};
  logic [3*N-1:0] s1_ma, s1_mb;  // rotated: {K, J, A}
  assign s1_ma = {c0_ma[ik*N+:N], c0_ma[ij*N+:N], c0_ma[anc*N+:N]};
  assign s1_mb = {c0_mb[ik*N+:N], c0_mb[ij*N+:N], c0_mb[anc*N+:N]};

  localparam int unsigned AuxW = 3 + 4 + 2 * ShW + 2 + 4 + 2 * ExpIW + SpW + ZW;
  logic [AuxW-1:0] s1_aux;
  assign s1_aux = {s1_sg, nzj, nzk, farj, fark, shj, shk, dn, dcls, xa, xf, c0_spc, c0_z};

  // ---- cut 1 ----------------------------------------------------------------------------
  logic            c1_valid;
  logic [3*N-1:0]  c1_ma, c1_mb;
  logic [AuxW-1:0] c1_aux;
  ru_pipe #(.Width(6 * N + AuxW), .Depth(Cuts[1] ? 1 : 0)) u_cut1 (
    .clk_i, .rst_ni,
    .valid_i(c0_valid),
    .data_i ({s1_ma, s1_mb, s1_aux}),
    .valid_o(c1_valid),
    .data_o ({c1_ma, c1_mb, c1_aux})
  );

  // ---- seg 2..L+2: the three products (cuts 2..L+2 inside) ------------------------------
  logic            p_valid, unused_v1, unused_v2;
  logic [PW-1:0]   pa, pj, pk;
  logic [AuxW-1:0] p_aux;
  logic            unused_x1, unused_x2;
  ru_umul #(.N(N), .AuxW(AuxW), .CutMask(Cuts >> 2)) u_mul_a (
    .clk_i, .rst_ni, .valid_i(c1_valid), .a_i(c1_ma[0+:N]), .b_i(c1_mb[0+:N]), .aux_i(c1_aux),
    .valid_o(p_valid), .p_o(pa), .aux_o(p_aux)
  );
  ru_umul #(.N(N), .AuxW(1), .CutMask(Cuts >> 2)) u_mul_j (
    .clk_i, .rst_ni, .valid_i(c1_valid), .a_i(c1_ma[N+:N]), .b_i(c1_mb[N+:N]), .aux_i(1'b0),
    .valid_o(unused_v1), .p_o(pj), .aux_o(unused_x1)
  );
  ru_umul #(.N(N), .AuxW(1), .CutMask(Cuts >> 2)) u_mul_k (
    .clk_i, .rst_ni, .valid_i(c1_valid), .a_i(c1_ma[2*N+:N]), .b_i(c1_mb[2*N+:N]), .aux_i(1'b0),
    .valid_o(unused_v2), .p_o(pk), .aux_o(unused_x2)
  );

  // ---- seg L+3: align, compares, selection ----------------------------------------------
  logic                    sa3, sj3, sk3, nzj3, nzk3, farj3, fark3;
  logic [ShW-1:0]          shj3, shk3;
  logic [1:0]              dn3;
  logic [3:0]              dcls3;
  logic signed [ExpIW-1:0] xa3, xf3;
  logic [SpW-1:0]          spc3;
  logic [ZW-1:0]           z3;
  assign {sk3, sj3, sa3, nzj3, nzk3, farj3, fark3, shj3, shk3, dn3, dcls3, xa3, xf3, spc3, z3} = p_aux;

  // J and K shifted into the window, lost bits jammed into bit 0
  logic [WW-1:0] tj_sh, tj_lost, tk_sh, tk_lost, tj, tk;
  assign {tj_sh, tj_lost} = {pj, {(K + 1) {1'b0}}, {WW{1'b0}}} >> shj3;
  assign {tk_sh, tk_lost} = {pk, {(K + 1) {1'b0}}, {WW{1'b0}}} >> shk3;
  assign tj = {tj_sh[WW-1:1], tj_sh[0] | (|tj_lost)};
  assign tk = {tk_sh[WW-1:1], tk_sh[0] | (|tk_lost)};

  // A + near = 0 (one far term): equal magnitudes at d_near 0 or 1, opposite signs
  logic [PW-1:0] pn;
  logic          sn, nzn, eq_an, cancel, far2;
  assign pn     = farj3 ? pk : pj;
  assign sn     = farj3 ? sk3 : sj3;
  assign nzn    = farj3 ? nzk3 : nzj3;
  assign eq_an  = (dn3 == 2'd0) ? (pa == pn) :
                  (dn3 == 2'd1) ? ({pa, 1'b0} == {1'b0, pn}) : 1'b0;
  assign cancel = (farj3 ^ fark3) & nzn & (sa3 != sn) & eq_an;
  assign far2   = farj3 & fark3;
  // Z = J + K (two far terms): J larger in magnitude? equal?
  logic [PW:0] cj, ck;
  logic        j_gt, jk_eq, z_sign, z_nz;
  assign cj     = dcls3[1] ? {pj, 1'b0} : {1'b0, pj};   // E_J = E_K + 1
  assign ck     = dcls3[0] ? {pk, 1'b0} : {1'b0, pk};   // E_K = E_J + 1
  assign j_gt   = dcls3[3] | (~dcls3[2] & (cj > ck));
  assign jk_eq  = ~dcls3[3] & ~dcls3[2] & (cj == ck);
  assign z_sign = j_gt ? sj3 : sk3;
  assign z_nz   = ~(jk_eq & (sj3 != sk3));

  logic [WW-1:0]           w1, w2, w3;
  logic                    g1, g2, g3;
  logic signed [ExpIW-1:0] x3;
  always_comb begin
    w1 = {pa, {(K + 1) {1'b0}}};
    g1 = sa3;
    w2 = tj;
    g2 = sj3;
    w3 = tk;
    g3 = sk3;
    x3 = xa3;
    if (cancel) begin           // the far term alone
      w1 = {farj3 ? pj : pk, {(K + 1) {1'b0}}};
      g1 = farj3 ? sj3 : sk3;
      w2 = '0;
      w3 = '0;
      x3 = xf3;
    end else if (far2) begin    // A and one jam bit with the sign of J + K
      w2 = {{(WW - 1) {1'b0}}, z_nz};
      g2 = z_sign;
      w3 = '0;
    end
  end

  // ---- cut L+3 ---------------------------------------------------------------------------
  logic                    c3_valid, c3_g1, c3_g2, c3_g3;
  logic [WW-1:0]           c3_w1, c3_w2, c3_w3;
  logic signed [ExpIW-1:0] c3_x;
  logic [SpW-1:0]          c3_spc;
  logic [ZW-1:0]           c3_z;
  ru_pipe #(.Width(3 * WW + 3 + ExpIW + SpW + ZW), .Depth(Cuts[L+3] ? 1 : 0)) u_cut3 (
    .clk_i, .rst_ni,
    .valid_i(p_valid),
    .data_i ({w1, w2, w3, g1, g2, g3, x3, spc3, z3}),
    .valid_o(c3_valid),
    .data_o ({c3_w1, c3_w2, c3_w3, c3_g1, c3_g2, c3_g3, c3_x, c3_spc, c3_z})
  );

  // ---- seg L+4: signed sum, magnitude ---------------------------------------------------
  logic [SW-1:0] v1, v2, v3, s4_sum;
  logic [MW-1:0] s4_mag;
  logic          s4_sign;
  assign v1 = c3_g1 ? -{3'b000, c3_w1} : {3'b000, c3_w1};
  assign v2 = c3_g2 ? -{3'b000, c3_w2} : {3'b000, c3_w2};
  assign v3 = c3_g3 ? -{3'b000, c3_w3} : {3'b000, c3_w3};
  assign s4_sum  = v1 + v2 + v3;
  assign s4_sign = s4_sum[SW-1];
  assign s4_mag  = s4_sign ? MW'(-s4_sum) : s4_sum[MW-1:0];   // |sum| < 3 * 2^WW < 2^MW

  // ---- cut L+4 ---------------------------------------------------------------------------
  logic                    c4_valid, c4_sign;
  logic [MW-1:0]           c4_mag;
  logic signed [ExpIW-1:0] c4_x;
  logic [SpW-1:0]          c4_spc;
  logic [ZW-1:0]           c4_z;
  ru_pipe #(.Width(MW + 1 + ExpIW + SpW + ZW), .Depth(Cuts[L+4] ? 1 : 0)) u_cut4 (
    .clk_i, .rst_ni,
    .valid_i(c3_valid),
    .data_i ({s4_mag, s4_sign, c3_x, c3_spc, c3_z}),
    .valid_o(c4_valid),
    .data_o ({c4_mag, c4_sign, c4_x, c4_spc, c4_z})
  );

  // ---- seg L+5: normalize ----------------------------------------------------------------
  logic [MW-1:0]           n_mag;
  logic signed [ExpIW-1:0] n_exp;
  logic                    n_zero;
  ru_fp_normalize #(.Width(MW), .ExpIW(ExpIW), .Full(1)) u_norm (
    .sig_i(c4_mag), .exp_i(c4_x), .sig_o(n_mag), .exp_o(n_exp), .zero_o(n_zero)
  );

  // ---- cut L+5 ---------------------------------------------------------------------------
  logic                    c5_valid, c5_sign, c5_zero, c5_sticky;
  logic [N:0]              c5_sig;
  logic signed [ExpIW-1:0] c5_exp;
  logic [SpW-1:0]          c5_spc;
  logic [ZW-1:0]           c5_z;
  ru_pipe #(.Width(N + 1 + 3 + ExpIW + SpW + ZW), .Depth(Cuts[L+5] ? 1 : 0)) u_cut5 (
    .clk_i, .rst_ni,
    .valid_i(c4_valid),
    .data_i ({n_mag[MW-1 -: N+1], |n_mag[MW-N-2:0], c4_sign, n_zero, n_exp, c4_spc, c4_z}),
    .valid_o(c5_valid),
    .data_o ({c5_sig, c5_sticky, c5_sign, c5_zero, c5_exp, c5_spc, c5_z})
  );

  // ---- seg L+6, cut L+6, seg L+7: round and pack, special results -------------------------
  logic [W-1:0]   rp_y, y;
  logic           rp_of, rp_uf, rp_nx, r_valid, r_zero;
  logic [4:0]     flags;
  logic [SpW-1:0] r_spc;
  logic [ZW-1:0]  r_z;
  logic           sp_nan, sp_invalid, sp_inf, sp_inf_sign, all_zero, all_zero_sign;
  assign {sp_nan, sp_invalid, sp_inf, sp_inf_sign} = r_spc;
  assign {all_zero, all_zero_sign} = r_z;

  ru_fp_round_pack #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round), .AuxW(1 + SpW + ZW),
    .Cut(Cuts[L+6] ? 1 : 0)
  ) u_rp (
    .clk_i, .rst_ni,
    .valid_i(c5_valid), .aux_i({c5_zero, c5_spc, c5_z}),
    .sign_i(c5_sign), .exp_i(c5_exp), .sig_i(c5_sig), .sticky_i(c5_sticky),
    .valid_o(r_valid), .aux_o({r_zero, r_spc, r_z}),
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
      // exact zero: all products zero keep their common sign; cancellation gives +0 (RDN -0)
      y     = {all_zero ? all_zero_sign : (Round == 2), {(ExpW + FracW) {1'b0}}};
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
