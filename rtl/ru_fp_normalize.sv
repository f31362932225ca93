// ru_fp_normalize: shift a significand left until its MSB is one and lower the exponent by
// the same amount (shared by ru_fp_add, ru_fp_mul, ru_fp_div).
//
// Full = 1: leading-zero count (ru_lzc) + barrel shift, any number of leading zeros.
// Full = 0: the caller guarantees sig_i[Width-1:Width-2] != 0 (e.g. a product of two
//           normal significands), so at most one position is shifted: a 2:1 mux.
// exp_o = exp_i - shift (signed, ExpIW bits). An all-zero sig_i gives sig_o = 0 and
// zero_o = 1 (exp_o is then meaningless).
module ru_fp_normalize #(
  parameter int unsigned Width = 8,
  parameter int unsigned ExpIW = 10,
  parameter int unsigned Full = 1
) (
  input  logic [Width-1:0]        sig_i,
  input  logic signed [ExpIW-1:0] exp_i,
  output logic [Width-1:0]        sig_o,
  output logic signed [ExpIW-1:0] exp_o,
  output logic                    zero_o
);

  if (Full != 0) begin : gen_full
    localparam int unsigned CntW = ru_fp_pkg::clog2p(Width + 1);
    logic [CntW-1:0] cnt;
    ru_lzc #(.Width(Width)) u_lzc (
      .in_i  (sig_i),
      .cnt_o (cnt),
      .zero_o(zero_o)
    );
    assign sig_o = sig_i << cnt;
    assign exp_o = exp_i - ExpIW'(cnt);
  end else begin : gen_one
    assign zero_o = ~|sig_i;
    assign sig_o  = sig_i[Width-1] ? sig_i : {sig_i[Width-2:0], 1'b0};
    assign exp_o  = sig_i[Width-1] ? exp_i : exp_i - ExpIW'(1);
  end

endmodule
