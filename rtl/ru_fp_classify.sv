// ru_fp_classify: unpack and classify one operand (shared by every rayunits FP unit).
//
// Subnormals = 0 (flush-to-zero): a subnormal input reads as a zero of the same sign
// (docs/FORMAT.md, no flag). Outputs describe the operand after that flushing:
//   sign_o  the sign bit (kept for every class)
//   exp_o   effective biased exponent: the exponent field for normals, 1 for subnormals
//           and zeros (so value = sig_o * 2^(exp_o - bias - FracW) for every finite operand)
//   sig_o   significand with the hidden bit: {1, frac} normal, {0, frac} subnormal, 0 zero
//   zero_o, sub_o (subnormal, only with Subnormals = 1), inf_o, nan_o, snan_o
//   (signaling: fraction MSB clear; for FracW = 1 every NaN is quiet).
module ru_fp_classify #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Subnormals = 1
) (
  input  logic [ExpW+FracW:0] x_i,
  output logic                sign_o,
  output logic [ExpW-1:0]     exp_o,
  output logic [FracW:0]      sig_o,
  output logic                zero_o,
  output logic                sub_o,
  output logic                inf_o,
  output logic                nan_o,
  output logic                snan_o
);

  logic [ExpW-1:0]  exp_f;
  logic [FracW-1:0] frac_f;
  logic exp_zero, exp_ones, frac_zero;

  assign sign_o    = x_i[ExpW+FracW];
  assign exp_f     = x_i[ExpW+FracW-1:FracW];
  assign frac_f    = x_i[FracW-1:0];
  assign exp_zero  = ~|exp_f;
  assign exp_ones  = &exp_f;
  assign frac_zero = ~|frac_f;

  assign inf_o  = exp_ones & frac_zero;
  assign nan_o  = exp_ones & ~frac_zero;
  assign snan_o = nan_o & ~frac_f[FracW-1];
  assign sub_o  = (Subnormals != 0) & exp_zero & ~frac_zero;
  assign zero_o = exp_zero & (frac_zero | (Subnormals == 0));
  assign exp_o  = exp_zero ? ExpW'(1) : exp_f;
  assign sig_o  = zero_o ? '0 : {~exp_zero, frac_f};

endmodule
