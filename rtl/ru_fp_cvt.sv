// ru_fp_cvt: conversions between the unit's format F, a second format G and IntW-bit two's
// complement integers, docs/FORMAT.md semantics (golden model: ru::num::convert, from_int and
// to_int in model/src/num/softfloat.cpp).
//
//   op_i = 0 f2f      a_i[InW-1:0]  a value of G   -> y_o[W-1:0]    round_F(a)
//   op_i = 1 i2f      a_i[IntW-1:0] signed integer -> y_o[W-1:0]    round_F(a)
//   op_i = 2 f2i      a_i[W-1:0]    a value of F   -> y_o[IntW-1:0] round(a) with mode Round
//   op_i = 3 f2i_rtz  a_i[W-1:0]    a value of F   -> y_o[IntW-1:0] round(a) toward zero (C cast)
// The other bits of a_i are ignored; the bits of y_o above the result are zero.
// f2f and i2f round once into F with the unit's Round and Subnormals: overflow, underflow and
// inexact as for an arithmetic result; a NaN gives F's canonical NaN (invalid if signaling);
// +-INF and +-0 keep their sign; an FTZ G (InSubnormals = 0) reads its subnormals as zero; the
// integer 0 gives +0. f2i/f2i_rtz round first, then a result outside
// [-2^(IntW-1), 2^(IntW-1) - 1] saturates to the nearer end with invalid only (NaN gives
// 2^(IntW-1) - 1), as IEEE 754 convertToInteger with saturation (RISC-V fcvt.w); an in-range
// rounded result raises inexact when it is not exact; an FTZ F reads its subnormals as zero.
//
// Parameters: ExpW (2..11), FracW (1..52), Subnormals, Round (0 RNE, 1 RTZ, 2 RDN, 3 RUP):
// the format F; InExpW, InFracW, InSubnormals: G (e.g. F = e8m23, G = e7m16 widens; F = e7m16,
// G = e8m23 narrows; two instances give both directions); IntW (2..64); Stages (latency in
// cycles, 0 = combinational). CutSel is internal; leave it. Fully pipelined: one operation per
// cycle, out_valid_o = in_valid_i delayed by Stages.
//
// Algorithm. f2f and i2f share one path: the source significand (G's {hidden bit, fraction},
// or the integer's magnitude) is left-aligned in SW = max(InFracW + 1, IntW) bits with the
// F-biased exponent of its top bit, normalized (leading-zero count + shift), cut to the
// FracW + 2 bits round-and-pack takes (the rest ORed into its sticky bit), and its exponent is
// clamped into round-and-pack's range: at 2^ExpW - 1 (it overflows there as it would further
// up) and at -(FracW + 3) (every bit goes to the sticky bit there as it would further down).
// f2i: with s the unbiased exponent of F's bit FracW (sig = {hidden, fraction}, value =
// sig * 2^(s - FracW)), Z = sig << (s + 1) holds the value with IntW + 1 integer bits and
// FracW + 1 fraction bits for -1 <= s <= IntW; s > IntW saturates (|a| >= 2^(IntW+1)), s < -1
// means |a| < 1/2 (integer 0, guard 0, sticky 1). The integer part is rounded with the guard
// bit and the sticky OR of the rest (ru_fp_pkg::round_up), range-checked and negated.
//
// Datapath segments and the cut position after each:
//   seg 0  unpack/classify F and G, integer magnitude, path select, exponents  | cut 0
//   seg 1  normalize + clamp (f2f, i2f); integer shift (f2i)                     | cut 1
//   seg 2  round-and-pack: tininess, denormalization; integer round increment    | cut 2
//   seg 3  round-and-pack: increment, overflow; integer range check and negation;
//          special-result and op mux -> y_o, flags_o
// Stages registers go to the cut positions that minimize the deepest stage under the depth
// estimates of ru_fp_pkg::cvt_seg_w (ru_pipe_pkg::cut_mask). Useful maximum: Stages = 3.
// Any larger Stages is accepted; the registers beyond 3 are placed at the output.
module ru_fp_cvt #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned InExpW = 8,
  parameter int unsigned InFracW = 23,
  parameter int unsigned InSubnormals = 1,
  parameter int unsigned IntW = 32,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts,
  // Weights of the automatic placement: '0 = the depth estimates of ru_fp_pkg::cvt_seg_w; else
  // packed 8-bit weights per segment (`rayunits synth --placement delay`, synth/README.md).
  parameter logic [ru_pipe_pkg::WW-1:0] SegW = '0,
  localparam int unsigned W = 1 + ExpW + FracW,
  localparam int unsigned InW = 1 + InExpW + InFracW,
  localparam int unsigned AW = ru_fp_pkg::max2(ru_fp_pkg::max2(W, InW), IntW),
  localparam int unsigned YW = ru_fp_pkg::max2(W, IntW)
) (
  input  logic          clk_i,
  input  logic          rst_ni,
  input  logic          in_valid_i,
  input  logic [AW-1:0] a_i,
  input  logic [1:0]    op_i,
  output logic          out_valid_o,
  output logic [YW-1:0] y_o,
  output logic [4:0]    flags_o
);

  localparam int unsigned N = FracW + 1;                            // F significand width
  localparam int unsigned RW = FracW + 2;                           // round-and-pack significand
  localparam int unsigned SW = ru_fp_pkg::max2(InFracW + 1, IntW);  // shared normalizer width
  localparam int unsigned ZW = N + IntW + 1;                        // f2i window
  localparam int unsigned ShZW = ru_fp_pkg::clog2p(IntW + 2);       // f2i shift amount 0..IntW+1
  localparam int unsigned CW =
      ru_fp_pkg::max2(ru_fp_pkg::max2(ExpW, InExpW), ru_fp_pkg::clog2p(SW + 2)) + 3;
  localparam int unsigned ExpIW = ru_fp_pkg::exp_iw(ExpW, FracW);
  localparam logic signed [CW-1:0] BiasF = CW'((1 << (ExpW - 1)) - 1);
  localparam logic signed [CW-1:0] BiasG = CW'((1 << (InExpW - 1)) - 1);
  localparam logic signed [CW-1:0] ExpHi = CW'((1 << ExpW) - 1);  // clamp: overflows here
  localparam logic signed [CW-1:0] ExpLo = -CW'(FracW + 3);        // clamp: all sticky here
  localparam logic signed [CW-1:0] IntTop = BiasF + CW'(IntW - 1);  // exponent of a_i[IntW-1]
  localparam logic signed [CW-1:0] SMax = CW'(IntW);                // f2i: s > SMax saturates
  localparam logic signed [CW-1:0] MinusOne = -1;                   // f2i: s < -1 is |a| < 1/2
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(
      CutSel,
      ru_pipe_pkg::pick_w(SegW, ru_fp_pkg::cvt_seg_w(ExpW, FracW, Subnormals, InExpW, InFracW,
                                                     IntW)),
      ru_fp_pkg::cvt_nseg(), Stages);
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(ru_fp_pkg::cvt_nseg());
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_fp_cvt: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  if (IntW < 2 || IntW > 64) begin : gen_intw_check
    $error("ru_fp_cvt: IntW must be 2..64, got %0d", IntW);
  end

  // ---- seg 0: unpack, path select, exponents ---------------------------------------------
  // G operand (f2f)
  logic             g_s, g_z, g_inf, g_nan, g_snan, unused_g_sub;
  logic [InExpW-1:0] g_e;
  logic [InFracW:0] g_m;
  ru_fp_classify #(.ExpW(InExpW), .FracW(InFracW), .Subnormals(InSubnormals)) u_cls_g (
    .x_i(a_i[InW-1:0]), .sign_o(g_s), .exp_o(g_e), .sig_o(g_m), .zero_o(g_z), .sub_o(unused_g_sub),
    .inf_o(g_inf), .nan_o(g_nan), .snan_o(g_snan)
  );
  // F operand (f2i)
  logic            f_s, f_z, f_inf, f_nan, unused_f_snan, unused_f_sub;
  logic [ExpW-1:0] f_e;
  logic [N-1:0]    f_m;
  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_f (
    .x_i(a_i[W-1:0]), .sign_o(f_s), .exp_o(f_e), .sig_o(f_m), .zero_o(f_z), .sub_o(unused_f_sub),
    .inf_o(f_inf), .nan_o(f_nan), .snan_o(unused_f_snan)
  );
  // integer operand (i2f): -2^(IntW-1) has the magnitude 2^(IntW-1), which fits IntW bits
  logic            x_s;
  logic [IntW-1:0] x_mag;
  assign x_s   = a_i[IntW-1];
  assign x_mag = x_s ? IntW'(0) - a_i[IntW-1:0] : a_i[IntW-1:0];

  // f2f / i2f: left-aligned significand, exponent of its top bit (F-biased), special cases
  logic                 s0_i2f, s0_sign, s0_nan, s0_inv, s0_inf, s0_zero;
  logic [SW-1:0]        s0_sig;
  logic signed [CW-1:0] s0_exp;
  assign s0_i2f  = op_i[0];
  assign s0_sign = s0_i2f ? x_s : g_s;
  assign s0_sig  = s0_i2f ? SW'(x_mag) << (SW - IntW) : SW'(g_m) << (SW - InFracW - 1);
  assign s0_exp  = s0_i2f ? IntTop : $signed(CW'(g_e)) - BiasG + BiasF;
  assign s0_nan  = ~s0_i2f & g_nan;
  assign s0_inv  = ~s0_i2f & g_snan;
  assign s0_inf  = ~s0_i2f & g_inf;
  assign s0_zero = s0_i2f ? ~|x_mag : g_z;

  // f2i: s = unbiased exponent of sig bit FracW; shift amount s + 1 clamped into 0..IntW+1
  logic signed [CW-1:0] t0_s, t0_sh1;
  logic                 t0_big, t0_small;
  logic [ShZW-1:0]      t0_sh;
  assign t0_s     = $signed(CW'(f_e)) - BiasF;
  assign t0_big   = t0_s > SMax;
  assign t0_small = t0_s < MinusOne;
  assign t0_sh1   = t0_s + CW'(1);
  assign t0_sh    = (t0_big | t0_small) ? '0 : t0_sh1[ShZW-1:0];
  logic unused_sh1;
  assign unused_sh1 = ^t0_sh1[CW-1:ShZW];  // 0 <= s + 1 <= IntW + 1 where it is used

  // ---- cut 0 ----------------------------------------------------------------------------
  localparam int unsigned C0W = 2 + 5 + SW + CW + N + ShZW + 6;
  logic                 c0_valid, c0_sign, c0_nan, c0_inv, c0_inf, c0_zero;
  logic [1:0]           c0_op;
  logic [SW-1:0]        c0_sig;
  logic signed [CW-1:0] c0_exp;
  logic [N-1:0]         c0_fm;
  logic [ShZW-1:0]      c0_sh;
  logic                 c0_fs, c0_big, c0_small, c0_fnan, c0_finf, c0_fz;
  ru_pipe #(.Width(C0W), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({op_i, s0_sign, s0_nan, s0_inv, s0_inf, s0_zero, s0_sig, s0_exp, f_m, t0_sh,
              f_s, t0_big, t0_small, f_nan, f_inf, f_z}),
    .valid_o(c0_valid),
    .data_o ({c0_op, c0_sign, c0_nan, c0_inv, c0_inf, c0_zero, c0_sig, c0_exp, c0_fm, c0_sh,
              c0_fs, c0_big, c0_small, c0_fnan, c0_finf, c0_fz})
  );

  // ---- seg 1: normalize and clamp (f2f, i2f); integer shift (f2i) ----------------------------
  logic [SW-1:0]        n_sig;
  logic signed [CW-1:0] n_exp;
  logic                 unused_n_zero;
  ru_fp_normalize #(.Width(SW), .ExpIW(CW), .Full(1)) u_norm (
    .sig_i(c0_sig), .exp_i(c0_exp), .sig_o(n_sig), .exp_o(n_exp), .zero_o(unused_n_zero)
  );
  logic [RW-1:0]           s1_sig;
  logic                    s1_sticky;
  logic signed [ExpIW-1:0] s1_exp;
  if (SW > RW) begin : gen_cut_sig
    assign s1_sig    = n_sig[SW-1-:RW];
    assign s1_sticky = |n_sig[SW-RW-1:0];
  end else begin : gen_pad_sig
    assign s1_sig    = RW'(n_sig) << (RW - SW);
    assign s1_sticky = 1'b0;
  end
  assign s1_exp = (n_exp > ExpHi) ? ExpIW'(ExpHi) : (n_exp < ExpLo) ? ExpIW'(ExpLo) : ExpIW'(n_exp);

  // f2i: Z = sig << (s + 1): IntW + 1 integer bits, N fraction bits
  logic [ZW-1:0]   z;
  logic [IntW:0]   t1_int;
  logic            t1_g, t1_st;
  assign z      = ZW'(c0_fm) << c0_sh;
  assign t1_int = c0_small ? '0 : z[ZW-1:N];
  assign t1_g   = ~c0_small & z[N-1];
  assign t1_st  = c0_small | (|z[N-2:0]);

  // ---- cut 1 ----------------------------------------------------------------------------
  localparam int unsigned C1W = 2 + 5 + ExpIW + RW + 1 + (IntW + 1) + 2 + 5;
  logic                    c1_valid, c1_sign, c1_nan, c1_inv, c1_inf, c1_zero, c1_sticky;
  logic [1:0]              c1_op;
  logic signed [ExpIW-1:0] c1_exp;
  logic [RW-1:0]           c1_sig;
  logic [IntW:0]           c1_int;
  logic                    c1_g, c1_st, c1_fs, c1_big, c1_fnan, c1_finf, c1_fz;
  ru_pipe #(.Width(C1W), .Depth(Cuts[1] ? 1 : 0)) u_cut1 (
    .clk_i, .rst_ni,
    .valid_i(c0_valid),
    .data_i ({c0_op, c0_sign, c0_nan, c0_inv, c0_inf, c0_zero, s1_exp, s1_sig, s1_sticky, t1_int,
              t1_g, t1_st, c0_fs, c0_big, c0_fnan, c0_finf, c0_fz}),
    .valid_o(c1_valid),
    .data_o ({c1_op, c1_sign, c1_nan, c1_inv, c1_inf, c1_zero, c1_exp, c1_sig, c1_sticky, c1_int,
              c1_g, c1_st, c1_fs, c1_big, c1_fnan, c1_finf, c1_fz})
  );

  // ---- seg 2 (+ round-and-pack A), cut 2, seg 3 (+ round-and-pack B) ---------------------------
  // f2i rounding: the magnitude's increment (op 3 f2i_rtz: toward zero)
  logic          t2_up, t2_nx;
  logic [IntW+1:0] t2_mag;
  assign t2_up  = ru_fp_pkg::round_up(c1_op[0] ? 1 : Round, c1_fs, c1_int[0], c1_g, c1_st);
  assign t2_mag = (IntW + 2)'(c1_int) + (IntW + 2)'(t2_up);
  assign t2_nx  = c1_g | c1_st;

  localparam int unsigned AuxW = 2 + 5 + (IntW + 2) + 6;
  logic [W-1:0]    rp_y;
  logic            rp_of, rp_uf, rp_nx, r_valid;
  logic [1:0]      r_op;
  logic            r_sign, r_nan, r_inv, r_inf, r_zero;
  logic [IntW+1:0] r_mag;
  logic            r_nx, r_fs, r_big, r_fnan, r_finf, r_fz;
  ru_fp_round_pack #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round), .AuxW(AuxW),
    .Cut(Cuts[2] ? 1 : 0)
  ) u_rp (
    .clk_i, .rst_ni,
    .valid_i(c1_valid),
    .aux_i({c1_op, c1_sign, c1_nan, c1_inv, c1_inf, c1_zero, t2_mag, t2_nx, c1_fs, c1_big, c1_fnan,
            c1_finf, c1_fz}),
    .sign_i(c1_sign), .exp_i(c1_exp), .sig_i(c1_sig), .sticky_i(c1_sticky),
    .valid_o(r_valid),
    .aux_o({r_op, r_sign, r_nan, r_inv, r_inf, r_zero, r_mag, r_nx, r_fs, r_big, r_fnan, r_finf,
            r_fz}),
    .y_o(rp_y), .of_o(rp_of), .uf_o(rp_uf), .nx_o(rp_nx)
  );

  // f2i range check: [-2^(IntW-1), 2^(IntW-1) - 1]
  localparam logic [IntW+1:0] PosLim = (IntW + 2)'(1) << (IntW - 1);
  localparam logic [IntW-1:0] IntMax = {1'b0, {(IntW - 1) {1'b1}}};
  localparam logic [IntW-1:0] IntMin = {1'b1, {(IntW - 1) {1'b0}}};
  logic            t3_sat;
  logic [IntW-1:0] t3_val;
  assign t3_sat = r_fnan | r_finf | r_big | (r_fs ? (r_mag > PosLim) : (r_mag >= PosLim));
  assign t3_val = r_fs ? IntW'(0) - r_mag[IntW-1:0] : r_mag[IntW-1:0];
  logic [IntW-1:0] t3_sat_val;  // NaN and +: the largest integer, -: the smallest
  assign t3_sat_val = (r_fnan | ~r_fs) ? IntMax : IntMin;
  logic unused_op0;
  assign unused_op0 = r_op[0];  // f2i vs f2i_rtz: decided in seg 2

  logic [YW-1:0] y;
  logic [4:0]    flags;
  always_comb begin
    if (r_op[1]) begin  // f2i, f2i_rtz
      y     = YW'(t3_val);
      flags = {4'b0000, r_nx};
      if (r_fz) begin
        y     = '0;
        flags = '0;
      end else if (t3_sat) begin
        y     = YW'(t3_sat_val);
        flags = 5'b10000;
      end
    end else begin  // f2f, i2f
      y     = YW'(rp_y);
      flags = {2'b00, rp_of, rp_uf, rp_nx};
      if (r_nan) begin
        y     = YW'({1'b0, {ExpW{1'b1}}, 1'b1, {(FracW - 1) {1'b0}}});
        flags = {r_inv, 4'b0000};
      end else if (r_inf) begin
        y     = YW'({r_sign, {ExpW{1'b1}}, {FracW{1'b0}}});
        flags = '0;
      end else if (r_zero) begin
        y     = YW'({r_sign, {(ExpW + FracW) {1'b0}}});
        flags = '0;
      end
    end
  end

  // ---- output registers (Stages beyond the cuts used) ------------------------------------
  ru_pipe #(.Width(YW + 5), .Depth(OutRegs)) u_out (
    .clk_i, .rst_ni,
    .valid_i(r_valid),
    .data_i ({y, flags}),
    .valid_o(out_valid_o),
    .data_o ({y_o, flags_o})
  );

endmodule
