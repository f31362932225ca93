// ru_fp_sqrt: floating-point square root y = round(sqrt(a)), correctly rounded, docs/FORMAT.md.
//
// Parameters: ExpW (2..11), FracW (1..52), Stages (latency in cycles, 0 = combinational),
// Subnormals (1 gradual underflow, 0 flush-to-zero), Round (0 RNE, 1 RTZ, 2 RDN, 3 RUP).
// CutSel is internal; leave it. Fully pipelined: one operation per cycle (the recurrence
// is unrolled), out_valid_o = in_valid_i delayed by Stages.
//
// Algorithm: the significand is normalized to [1, 2) (leading-zero count + shift for a
// subnormal operand; not needed with flush-to-zero), a = m * 2^e. If e is odd the significand
// is doubled and e lowered by one, so the radicand m' is in [1, 4), e even, and the root
// sqrt(m') * 2^(e/2) has its significand in [1, 2): no normalization after the recurrence.
// With A = m' * 2^(FracW+1) (FracW+3 bits) and D = A * 2^(FracW+1) (2*(FracW+2) bits, taken two
// bits at a time, most significant pair P_0 first), an unrolled restoring radix-2 recurrence
// produces the FracW+2 bits of R = floor(sqrt(D)), i.e. {1, fraction, guard} of the root:
//   q_1 = 1, r_1 = P_0 - 1 (P_0 >= 1 as m' >= 1: the first root bit is always 1)
//   step k: t = 4 r_k + P_k; trial = 4 q_k + 1; b = (t >= trial);
//           r_{k+1} = b ? t - trial : t;  q_{k+1} = 2 q_k + b
// with r_k = D_k - q_k^2 <= 2 q_k (D_k = the first k pairs), so step k works on k+3 bits.
// The final remainder D - R^2 is the sticky bit (non-zero <=> the root is inexact). Then the
// shared round-and-pack (the root of a subnormal can be tiny in very small formats, e.g.
// e2m1: tininess, underflow and flush-to-zero go through it as in the other units; the root
// never overflows). Special cases: NaN -> canonical NaN (invalid for a signaling NaN);
// negative non-zero (-INF included) -> canonical NaN, invalid; +-0 -> +-0 (with flush-to-zero
// also a subnormal operand, read as a zero of its sign); +INF -> +INF. No other flags.
//
// Datapath segments and the cut position after each (FracW+4 segments):
//   seg 0             unpack/classify, normalization, exponent halving, root bit 0 | cut 0
//   seg 1..FracW+1    recurrence step k (one (k+3)-bit subtract + mux)             | cut k
//   seg FracW+2       round-and-pack: tininess, denormalization                    | cut FracW+2
//   seg FracW+3       round-and-pack: increment; special-result mux -> y_o, flags_o
// Stages registers go to the cut positions that minimize the deepest stage under the
// depth estimates of ru_fp_pkg::sqrt_seg_w (ru_pipe_pkg::cut_mask), i.e. they are spread among
// the recurrence steps. Useful maximum: Stages = FracW+3 (every cut registered). Any larger
// Stages is accepted; the registers beyond FracW+3 are placed at the output.
module ru_fp_sqrt #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts,
  // Weights of the automatic placement: '0 = the depth estimates of ru_fp_pkg::sqrt_seg_w; else
  // packed 8-bit weights per segment (`rayunits synth --placement delay` passes delays measured
  // by STA in the cell library, synth/README.md).
  parameter logic [ru_pipe_pkg::WW-1:0] SegW = '0
) (
  input  logic                clk_i,
  input  logic                rst_ni,
  input  logic                in_valid_i,
  input  logic [ExpW+FracW:0] a_i,
  output logic                out_valid_o,
  output logic [ExpW+FracW:0] y_o,
  output logic [4:0]          flags_o
);

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam int unsigned N = FracW + 1;      // significand width
  localparam int unsigned AW = FracW + 3;     // radicand A = m' * 2^(FracW+1)
  localparam int unsigned NSteps = FracW + 2; // root bits (bit 0 in seg 0, steps 1..NSteps-1)
  localparam int unsigned ExpIW = ru_fp_pkg::exp_iw(ExpW, FracW);
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(
      CutSel,
      ru_pipe_pkg::pick_w(SegW, ru_fp_pkg::sqrt_seg_w(ExpW, FracW, Subnormals)),
      ru_fp_pkg::sqrt_nseg(FracW), Stages);
  // Useful maximum of Stages (a register at every cut position) and the registers placed at the
  // output (Stages - popcount(Cuts); with automatic placement: those beyond MaxUsefulStages).
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(ru_fp_pkg::sqrt_nseg(FracW));
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_fp_sqrt: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  localparam int signed Bias = (1 << (ExpW - 1)) - 1;
  // side information: {sign, exp, nan, invalid, inf, zero}
  localparam int unsigned AuxW = ExpIW + 5;

  // ---- seg 0: unpack, special cases, normalize, exponent, root bit 0 ------------------------
  logic sa, za, ia, na, sna;
  logic [ExpW-1:0] ea;
  logic [N-1:0] ma;
  logic unused_sub_a;

  ru_fp_classify #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals)) u_cls_a (
    .x_i(a_i), .sign_o(sa), .exp_o(ea), .sig_o(ma), .zero_o(za), .sub_o(unused_sub_a),
    .inf_o(ia), .nan_o(na), .snan_o(sna)
  );

  // normalized significand (a 1-bit "shift" = none with flush-to-zero: the operand is
  // normal or zero, and zeros take the special path)
  logic [N-1:0]            na_sig;
  logic signed [ExpIW-1:0] na_exp;
  logic                    unused_nz_a;
  ru_fp_normalize #(.Width(N), .ExpIW(ExpIW), .Full(Subnormals)) u_norm_a (
    .sig_i(ma), .exp_i(ExpIW'(ea)), .sig_o(na_sig), .exp_o(na_exp), .zero_o(unused_nz_a)
  );

  // unbiased exponent e; odd e: radicand 2m, exponent e - 1 (the arithmetic shift floors)
  logic signed [ExpIW-1:0] s0_ue, s0_exp;
  logic                    s0_odd;
  logic [AW-1:0]           s0_rad;
  assign s0_ue  = na_exp - ExpIW'(Bias);
  assign s0_odd = s0_ue[0];
  assign s0_exp = (s0_ue >>> 1) + ExpIW'(Bias);
  assign s0_rad = s0_odd ? {na_sig, 2'b00} : {1'b0, na_sig, 1'b0};

  logic s0_nan, s0_invalid, s0_inf, s0_zero;
  assign s0_nan     = na | (sa & ~za);    // NaN operand, or negative non-zero (-INF included)
  assign s0_invalid = sna | (sa & ~za & ~na);
  assign s0_inf     = ia;                 // +INF (negative INF is overridden by s0_nan)
  assign s0_zero    = za;                 // +-0 (the result keeps the sign)

  // root bit 0 = 1: r_1 = P_0 - 1 with P_0 = s0_rad[AW-1:AW-2] in 1..3
  logic [1:0] s0_r;
  assign s0_r = s0_rad[AW-1:AW-2] - 2'd1;

  // ---- cut 0 ----------------------------------------------------------------------------
  logic            c0_valid;
  logic [1:0]      c0_r;
  logic [AW-1:0]   c0_rad;
  logic [AuxW-1:0] c0_aux;
  ru_pipe #(.Width(2 + AW + AuxW), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({s0_r, s0_rad, sa, s0_exp, s0_nan, s0_invalid, s0_inf, s0_zero}),
    .valid_o(c0_valid),
    .data_o ({c0_r, c0_rad, c0_aux})
  );

  // ---- seg 1..NSteps-1: restoring recurrence, step k produces root bit k -------------------
  // step k: remainder in k+1 bits, root so far k bits; out k+2 and k+1 bits.
  for (genvar k = 1; k < NSteps; k++) begin : gen_step
    logic [k:0]      r_in;            // partial remainder in (<= 2 q_in)
    logic [k-1:0]    q_in;            // root bits so far (MSB first, q_in[k-1] = 1)
    logic [k+1:0]    r_d, r;          // next remainder / after the cut
    logic [k:0]      q_d, q;          // root bits after this step / after the cut
    logic [AW-1:0]   rad_in, rad;     // radicand (its pair P_k is consumed here)
    logic            valid_in, valid;
    logic [AuxW-1:0] aux_in, aux;
    logic [1:0]      pair;
    logic [k+2:0]    t;
    logic [k+3:0]    diff;
    if (k == 1) begin : gen_first
      assign r_in     = c0_r;
      assign q_in     = 1'b1;
      assign rad_in   = c0_rad;
      assign valid_in = c0_valid;
      assign aux_in   = c0_aux;
    end else begin : gen_next
      assign r_in     = gen_step[k-1].r;
      assign q_in     = gen_step[k-1].q;
      assign rad_in   = gen_step[k-1].rad;
      assign valid_in = gen_step[k-1].valid;
      assign aux_in   = gen_step[k-1].aux;
    end
    // P_k of D = {A, (FracW+1) zeros}: bits [2*(NSteps-1-k)+1 -: 2] of D
    if (2 * (NSteps - 1 - k) >= FracW + 1) begin : gen_pair_a
      assign pair = rad_in[2*(NSteps-1-k)-(FracW+1)+1 -: 2];
    end else if (2 * (NSteps - 1 - k) + 1 >= FracW + 1) begin : gen_pair_half
      assign pair = {rad_in[0], 1'b0};
    end else begin : gen_pair_zero
      assign pair = 2'b00;
    end
    assign t    = {r_in, pair};
    assign diff = {1'b0, t} - {2'b00, q_in, 2'b01};
    // t < 4 q_in + 1 when not taken, t - trial <= 4 q_in + 2 when taken: both fit k+2 bits
    assign r_d  = diff[k+3] ? t[k+1:0] : diff[k+1:0];
    assign q_d  = {q_in, ~diff[k+3]};
    ru_pipe #(.Width((k + 2) + (k + 1) + AW + AuxW), .Depth(Cuts[k] ? 1 : 0)) u_cut (
      .clk_i, .rst_ni,
      .valid_i(valid_in),
      .data_i ({r_d, q_d, rad_in, aux_in}),
      .valid_o(valid),
      .data_o ({r, q, rad, aux})
    );
    logic unused_top;
    assign unused_top = t[k+2] ^ diff[k+2];  // only enters the comparison
  end

  // ---- seg NSteps, cut NSteps, seg NSteps+1: round and pack, special results ------------------
  localparam int unsigned Last = NSteps - 1;  // the last step
  logic [NSteps-1:0]       root;
  logic                    rem_nz, c_sign, c_nan, c_invalid, c_inf, c_zero;
  logic signed [ExpIW-1:0] c_exp;
  logic [AW-1:0]           unused_rad;
  assign root       = gen_step[Last].q;
  assign rem_nz     = |gen_step[Last].r;
  assign unused_rad = gen_step[Last].rad;
  assign {c_sign, c_exp, c_nan, c_invalid, c_inf, c_zero} = gen_step[Last].aux;

  logic [W-1:0] rp_y, y;
  logic         rp_of, rp_uf, rp_nx, r_valid, r_sign, r_nan, r_invalid, r_inf, r_zero;
  logic [4:0]   flags;
  ru_fp_round_pack #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round), .AuxW(5),
    .Cut(Cuts[NSteps] ? 1 : 0)
  ) u_rp (
    .clk_i, .rst_ni,
    .valid_i(gen_step[Last].valid),
    .aux_i({c_sign, c_nan, c_invalid, c_inf, c_zero}),
    .sign_i(1'b0), .exp_i(c_exp), .sig_i(root), .sticky_i(rem_nz),
    .valid_o(r_valid), .aux_o({r_sign, r_nan, r_invalid, r_inf, r_zero}),
    .y_o(rp_y), .of_o(rp_of), .uf_o(rp_uf), .nx_o(rp_nx)
  );

  always_comb begin
    y     = rp_y;
    flags = {2'b00, rp_of, rp_uf, rp_nx};
    if (r_nan) begin
      y     = {1'b0, {ExpW{1'b1}}, 1'b1, {(FracW - 1) {1'b0}}};
      flags = {r_invalid, 4'b0000};
    end else if (r_inf) begin
      y     = {1'b0, {ExpW{1'b1}}, {FracW{1'b0}}};
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
