// ru_fp_round_pack: round a finite non-zero exact value into the format and pack it
// (shared by every rayunits arithmetic unit). Implements docs/FORMAT.md "Rounding":
//
//   value = sig_i * 2^(exp_i - bias - FracW - 1) (+ a non-zero tail below sig_i[0] iff
//   sticky_i), sig_i = {1, fraction, guard} normalized (sig_i[FracW+1] = 1), exp_i signed
//   biased exponent with unbounded range (<= 0 means below the normal range).
//
// 1. Tininess AFTER rounding: round to FracW+1 bits with unbounded exponent; tiny iff the
//    result is below 2^emin, i.e. exp_i < 0, or exp_i = 0 and the rounding does not carry
//    the all-ones significand up to 2^emin.
// 2. Subnormals = 1: the significand is shifted right by 1 - exp_i (bits shifted out go to
//    the sticky bit) so that it is rounded on the subnormal grid 2^(emin-FracW); the
//    exponent field becomes 0. Subnormals = 0 (flush-to-zero): tiny results become +-0
//    with underflow + inexact.
// 3. Rounding (truth table, g = first dropped bit, s = OR of the rest, l = kept LSB):
//      RNE: g & (s | l)    RTZ: never    RDN: (g | s) & neg    RUP: (g | s) & ~neg
//    (ru_fp_pkg::round_up). The round-up bit is added to the concatenation
//    {exponent, fraction}: a carry out of the fraction increments the exponent (a
//    subnormal becomes the smallest normal, 1.11..1 becomes 10.0..0), and a carry into the
//    all-ones exponent is the overflow to INF, so no separate renormalization is needed.
// 4. Overflow (rounded exponent >= all ones): INF or the largest finite value depending on
//    mode and sign (ru_fp_pkg::ovf_to_inf), flags overflow + inexact.
// Flags: of_o overflow, uf_o underflow (tiny and inexact; always with flush-to-zero),
// nx_o inexact. Special operands/results (NaN, INF, exact zero) are the caller's business.
//
// Cut = 1 puts a pipeline register between steps 1-2 (tininess, denormalization) and
// steps 3-4 (round increment, overflow, packing); the caller's side information (aux_i) and
// valid bit travel through it. Cut = 0: combinational, valid_o = valid_i, aux_o = aux_i.
module ru_fp_round_pack #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned AuxW = 1,
  parameter int unsigned Cut = 0,
  localparam int unsigned ExpIW = ru_fp_pkg::exp_iw(ExpW, FracW)
) (
  input  logic                    clk_i,
  input  logic                    rst_ni,
  input  logic                    valid_i,
  input  logic [AuxW-1:0]         aux_i,
  input  logic                    sign_i,
  input  logic signed [ExpIW-1:0] exp_i,
  input  logic [FracW+1:0]        sig_i,
  input  logic                    sticky_i,
  output logic                    valid_o,
  output logic [AuxW-1:0]         aux_o,
  output logic [ExpW+FracW:0]     y_o,
  output logic                    of_o,
  output logic                    uf_o,
  output logic                    nx_o
);

  localparam int unsigned SigW = FracW + 2;
  localparam int unsigned ShW = ru_fp_pkg::clog2p(SigW + 1);
  localparam logic signed [ExpIW-1:0] ExpOnes = ExpIW'((1 << ExpW) - 1);

  // 1. tininess after rounding
  logic up_norm, tiny, below;
  assign up_norm = ru_fp_pkg::round_up(Round, sign_i, sig_i[1], sig_i[0], sticky_i);
  assign below   = (exp_i <= 0);
  assign tiny    = (exp_i < 0) | ((exp_i == 0) & ~(&sig_i[FracW+1:1] & up_norm));

  // 2. denormalization
  logic [SigW-1:0] sig_s;
  logic            sticky_s;
  if (Subnormals != 0) begin : gen_denorm
    logic signed [ExpIW-1:0] sh_full;
    logic [ShW-1:0]          sh;
    logic [SigW-1:0]         lost;
    assign sh_full = ExpIW'(1) - exp_i;
    // shift by 1 - exp_i when exp_i <= 0, at most SigW (everything into the sticky bit)
    assign sh = !below ? '0 : (sh_full > ExpIW'(SigW)) ? ShW'(SigW) : sh_full[ShW-1:0];
    assign {sig_s, lost} = {sig_i, {SigW{1'b0}}} >> sh;
    assign sticky_s = sticky_i | (|lost);
  end else begin : gen_ftz
    assign sig_s    = sig_i;
    assign sticky_s = sticky_i;
  end
  logic signed [ExpIW-1:0] exp_pack;
  assign exp_pack = below ? '0 : exp_i;

  // ---- optional cut ------------------------------------------------------------------------
  logic                    c_sign, c_tiny, c_sticky;
  logic [SigW-1:0]         c_sig;
  logic signed [ExpIW-1:0] c_exp;
  ru_pipe #(.Width(AuxW + 3 + SigW + ExpIW), .Depth(Cut)) u_cut (
    .clk_i, .rst_ni,
    .valid_i,
    .data_i ({aux_i, sign_i, tiny, sticky_s, sig_s, exp_pack}),
    .valid_o,
    .data_o ({aux_o, c_sign, c_tiny, c_sticky, c_sig, c_exp})
  );

  // 3. rounding: {exponent, fraction} + round-up
  logic                    up;
  logic [ExpIW+FracW-1:0]  packed_r;
  logic signed [ExpIW-1:0] exp_r;
  assign up       = ru_fp_pkg::round_up(Round, c_sign, c_sig[1], c_sig[0], c_sticky);
  assign packed_r = {c_exp, c_sig[FracW:1]} + (ExpIW + FracW)'(up);
  assign exp_r    = packed_r[ExpIW+FracW-1:FracW];

  // 4. overflow, flush-to-zero, flags
  logic ovf, inexact;
  assign inexact = c_sig[0] | c_sticky;
  assign ovf     = ~c_tiny & (exp_r >= ExpOnes);

  always_comb begin
    y_o  = {c_sign, packed_r[ExpW+FracW-1:0]};
    of_o = 1'b0;
    uf_o = c_tiny & inexact;
    nx_o = inexact;
    if (ovf) begin
      y_o  = ru_fp_pkg::ovf_to_inf(Round, c_sign) ? {c_sign, {ExpW{1'b1}}, {FracW{1'b0}}}
                                                   : {c_sign, {(ExpW - 1) {1'b1}}, 1'b0,
                                                      {FracW{1'b1}}};
      of_o = 1'b1;
      nx_o = 1'b1;
    end else if (c_tiny && Subnormals == 0) begin
      y_o  = {c_sign, {(ExpW + FracW) {1'b0}}};
      uf_o = 1'b1;
      nx_o = 1'b1;
    end
  end

  logic unused_sig;
  assign unused_sig = c_sig[SigW-1];  // integer bit: implied by the exponent field

endmodule
