// ru_fp_div: floating-point divide y = round(a / b), correctly rounded, docs/FORMAT.md.
//
// Parameters: ExpW (2..11), FracW (1..52), Stages (latency in cycles, 0 = combinational),
// Subnormals (1 gradual underflow, 0 flush-to-zero), Round (0 RNE, 1 RTZ, 2 RDN, 3 RUP).
// CutSel is internal; leave it. Fully pipelined: one operation per cycle (the recurrence
// is unrolled), out_valid_o = in_valid_i delayed by Stages.
//
// Algorithm: both significands are normalized to [1, 2) (leading-zero count + shift for
// subnormal operands; not needed with flush-to-zero). An unrolled restoring radix-2 digit
// recurrence produces FracW+3 quotient bits of ma/mb in (1/2, 2), weights 2^0 .. 2^-(FracW+2):
//   r_0 = ma;  step i: d = r_i - mb; q_i = (d >= 0); r_{i+1} = 2 * (q_i ? d : r_i)
// and the final partial remainder is the sticky bit (non-zero <=> the quotient is inexact).
// If q_0 = 0 the quotient is below 1 and the result exponent is one lower. Then the shared
// round-and-pack. Special cases: NaN operand, 0/0, INF/INF -> canonical NaN (invalid for
// 0/0, INF/INF and signaling NaNs); finite non-zero / 0 -> INF with divzero; INF/x and x/0
// -> INF; 0/x and x/INF -> 0 (sign = sign(a) xor sign(b)).
//
// Datapath segments and the cut position after each (FracW+6 segments):
//   seg 0             unpack/classify, operand normalization, exponent difference | cut 0
//   seg 1..FracW+3    recurrence step k-1 (one (FracW+3)-bit subtract + mux)      | cut k
//   seg FracW+4       quotient select, round-and-pack: tininess, denormalization  | cut FracW+4
//   seg FracW+5       round-and-pack: increment, overflow; special-result mux -> y_o, flags_o
// Stages registers go to the cut positions that minimize the deepest stage under the
// depth estimates of ru_fp_pkg::div_seg_w (ru_pipe_pkg::cut_mask), i.e. they are spread among
// the recurrence steps. Useful maximum: Stages = FracW+5 (every cut registered). Any larger
// Stages is accepted; the registers beyond FracW+5 are placed at the output.
module ru_fp_div #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts,
  // Weights of the automatic placement: '0 = the depth estimates of ru_fp_pkg::div_seg_w; else
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
  localparam int unsigned N = FracW + 1;      // significand width
  localparam int unsigned RW = FracW + 2;     // partial remainder width (r < 2 * mb)
  localparam int unsigned NSteps = FracW + 3; // quotient bits
  localparam int unsigned ExpIW = ru_fp_pkg::exp_iw(ExpW, FracW);
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(
      CutSel,
      ru_pipe_pkg::pick_w(SegW, ru_fp_pkg::div_seg_w(ExpW, FracW, Subnormals)),
      ru_fp_pkg::div_nseg(FracW), Stages);
  // Useful maximum of Stages (a register at every cut position) and the registers placed at the
  // output (Stages - popcount(Cuts); with automatic placement: those beyond MaxUsefulStages).
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(ru_fp_pkg::div_nseg(FracW));
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_fp_div: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  localparam int signed Bias = (1 << (ExpW - 1)) - 1;
  // side information: {sign, exp, nan, invalid, inf, divzero, zero}
  localparam int unsigned AuxW = ExpIW + 6;

  // ---- seg 0: unpack, special cases, normalize, exponent ------------------------------------
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

  // normalized significands (a 1-bit "shift" = none with flush-to-zero: operands are
  // normal or zero, and zeros take the special path)
  logic [N-1:0]            na_sig, nb_sig;
  logic signed [ExpIW-1:0] na_exp, nb_exp;
  logic                    unused_nz_a, unused_nz_b;
  ru_fp_normalize #(.Width(N), .ExpIW(ExpIW), .Full(Subnormals)) u_norm_a (
    .sig_i(ma), .exp_i(ExpIW'(ea)), .sig_o(na_sig), .exp_o(na_exp), .zero_o(unused_nz_a)
  );
  ru_fp_normalize #(.Width(N), .ExpIW(ExpIW), .Full(Subnormals)) u_norm_b (
    .sig_i(mb), .exp_i(ExpIW'(eb)), .sig_o(nb_sig), .exp_o(nb_exp), .zero_o(unused_nz_b)
  );

  logic zero_by_zero, inf_by_inf;
  logic s0_nan, s0_invalid, s0_inf, s0_divzero, s0_zero;
  logic signed [ExpIW-1:0] s0_exp;
  assign zero_by_zero = za & zb;
  assign inf_by_inf   = ia & ib;
  assign s0_nan       = na | nb | zero_by_zero | inf_by_inf;
  assign s0_invalid   = sna | snb | zero_by_zero | inf_by_inf;
  assign s0_inf       = ia | zb;          // overridden by s0_nan
  assign s0_divzero   = zb & ~ia;         // only used when the result is not NaN
  assign s0_zero      = za | ib;          // overridden by s0_nan / s0_inf
  assign s0_exp       = na_exp - nb_exp + ExpIW'(Bias);

  // ---- cut 0 ----------------------------------------------------------------------------
  logic            c0_valid;
  logic [N-1:0]    c0_ma, c0_mb;
  logic [AuxW-1:0] c0_aux;
  ru_pipe #(.Width(2 * N + AuxW), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({na_sig, nb_sig, sa ^ sb, s0_exp, s0_nan, s0_invalid, s0_inf, s0_divzero, s0_zero}),
    .valid_o(c0_valid),
    .data_o ({c0_ma, c0_mb, c0_aux})
  );

  // ---- seg 1..NSteps: restoring recurrence, step k produces quotient bit q[NSteps-1-k] ----
  for (genvar k = 0; k < NSteps; k++) begin : gen_step
    logic [RW-1:0]   r_in, r_d, r;    // partial remainder in / next / after the cut
    logic [N-1:0]    dv_in, dv;       // divisor
    logic [k:0]      q_d, q;          // quotient bits so far (MSB first)
    logic            valid_in, valid;
    logic [AuxW-1:0] aux_in, aux;
    logic [RW:0]     diff;
    if (k == 0) begin : gen_first
      assign r_in     = {1'b0, c0_ma};
      assign dv_in    = c0_mb;
      assign valid_in = c0_valid;
      assign aux_in   = c0_aux;
    end else begin : gen_next
      assign r_in     = gen_step[k-1].r;
      assign dv_in    = gen_step[k-1].dv;
      assign valid_in = gen_step[k-1].valid;
      assign aux_in   = gen_step[k-1].aux;
    end
    assign diff = {1'b0, r_in} - {2'b00, dv_in};
    // r_in < 2 * dv_in, so the kept remainder is < dv_in and doubling it fits RW bits
    assign r_d  = diff[RW] ? {r_in[RW-2:0], 1'b0} : {diff[RW-2:0], 1'b0};
    if (k == 0) begin : gen_q0
      assign q_d = ~diff[RW];
    end else begin : gen_qn
      assign q_d = {gen_step[k-1].q, ~diff[RW]};
    end
    ru_pipe #(.Width(RW + N + k + 1 + AuxW), .Depth(Cuts[k+1] ? 1 : 0)) u_cut (
      .clk_i, .rst_ni,
      .valid_i(valid_in),
      .data_i ({r_d, dv_in, q_d, aux_in}),
      .valid_o(valid),
      .data_o ({r, dv, q, aux})
    );
    logic unused_top;
    assign unused_top = r_in[RW-1] ^ diff[RW-1];  // remainder MSB only enters the subtraction
  end

  // ---- seg NSteps+1, cut NSteps+1, seg NSteps+2: select, round and pack, special results -------------------------------
  localparam int unsigned Last = NSteps - 1;
  logic [NSteps-1:0]       quo;
  logic                    rem_nz, c_sign, c_nan, c_invalid, c_inf, c_divzero, c_zero;
  logic signed [ExpIW-1:0] c_exp, rp_exp;
  logic [FracW+1:0]        rp_sig;
  logic                    rp_sticky;
  logic [N-1:0]            unused_dv;
  assign quo       = gen_step[Last].q;
  assign rem_nz    = |gen_step[Last].r;
  assign unused_dv = gen_step[Last].dv;
  assign {c_sign, c_exp, c_nan, c_invalid, c_inf, c_divzero, c_zero} = gen_step[Last].aux;
  // quotient in [1, 2): bits quo[N+1:1], quo[0] into the sticky; in (1/2, 1): quo[N:0], exp - 1
  assign rp_sig    = quo[NSteps-1] ? quo[NSteps-1:1] : quo[NSteps-2:0];
  assign rp_sticky = rem_nz | (quo[NSteps-1] & quo[0]);
  assign rp_exp    = quo[NSteps-1] ? c_exp : c_exp - ExpIW'(1);

  logic [W-1:0] rp_y, y;
  logic         rp_of, rp_uf, rp_nx, r_valid, r_sign, r_nan, r_invalid, r_inf, r_divzero;
  logic         r_zero;
  logic [4:0]   flags;
  ru_fp_round_pack #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round), .AuxW(6),
    .Cut(Cuts[NSteps+1] ? 1 : 0)
  ) u_rp (
    .clk_i, .rst_ni,
    .valid_i(gen_step[Last].valid),
    .aux_i({c_sign, c_nan, c_invalid, c_inf, c_divzero, c_zero}),
    .sign_i(c_sign), .exp_i(rp_exp), .sig_i(rp_sig), .sticky_i(rp_sticky),
    .valid_o(r_valid), .aux_o({r_sign, r_nan, r_invalid, r_inf, r_divzero, r_zero}),
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
      flags = {1'b0, r_divzero, 3'b000};
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
