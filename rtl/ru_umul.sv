// ru_umul: unsigned N x N -> 2N multiplier, a carry-save (3:2) tree of the N partial
// products plus one final adder, with optional pipeline registers inside (used by
// ru_fp_mul; the unit's other data rides along in aux).
//
// Shape (ru_fp_pkg::csa_rows/csa_levels): level 0 = the N partial products; level k turns
// each group of three rows into a sum row and a carry row (full adders, two XOR levels)
// and passes the 0..2 leftover rows on; after L = csa_levels(N) levels two rows are left
// and one adder forms the product. Rows are 2N bits wide; the carry out of bit 2N-1 is
// dropped, which is exact because the product fits in 2N bits.
// CutMask bit k-1 (k = 1..L): register the rows after level k; bit L: register the product.
module ru_umul #(
  parameter int unsigned N = 24,
  parameter int unsigned AuxW = 1,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutMask = '0
) (
  input  logic            clk_i,
  input  logic            rst_ni,
  input  logic            valid_i,
  input  logic [N-1:0]    a_i,
  input  logic [N-1:0]    b_i,
  input  logic [AuxW-1:0] aux_i,
  output logic            valid_o,
  output logic [2*N-1:0]  p_o,
  output logic [AuxW-1:0] aux_o
);

  localparam int unsigned PW = 2 * N;
  localparam int unsigned L = ru_fp_pkg::csa_levels(N);

  for (genvar k = 0; k <= L; k++) begin : gen_lvl
    localparam int unsigned R = ru_fp_pkg::csa_rows(N, k);
    logic [R*PW-1:0] rows;  // after the optional register
    logic            valid;
    logic [AuxW-1:0] aux;
    if (k == 0) begin : gen_pp
      for (genvar j = 0; j < N; j++) begin : gen_row
        logic [N-1:0] pp;
        assign pp = a_i & {N{b_i[j]}};
        assign rows[j*PW+:PW] = {{N{1'b0}}, pp} << j;
      end
      assign valid = valid_i;
      assign aux   = aux_i;
    end else begin : gen_csa
      localparam int unsigned RI = ru_fp_pkg::csa_rows(N, k - 1);
      localparam int unsigned G = RI / 3;
      logic [RI*PW-1:0] in;
      logic [R*PW-1:0]  d;
      assign in = gen_lvl[k-1].rows;
      for (genvar g = 0; g < G; g++) begin : gen_fa
        logic [PW-1:0] x, y, z;
        assign x = in[(3*g)*PW+:PW];
        assign y = in[(3*g+1)*PW+:PW];
        assign z = in[(3*g+2)*PW+:PW];
        assign d[(2*g)*PW+:PW] = x ^ y ^ z;
        assign d[(2*g+1)*PW+:PW] = {
          (x[PW-2:0] & y[PW-2:0]) | (x[PW-2:0] & z[PW-2:0]) | (y[PW-2:0] & z[PW-2:0]), 1'b0
        };
      end
      if (RI % 3 != 0) begin : gen_pass
        assign d[R*PW-1:2*G*PW] = in[RI*PW-1:3*G*PW];
      end
      ru_pipe #(
        .Width(R * PW + AuxW),
        .Depth(CutMask[k-1] ? 1 : 0)
      ) u_cut (
        .clk_i,
        .rst_ni,
        .valid_i(gen_lvl[k-1].valid),
        .data_i ({d, gen_lvl[k-1].aux}),
        .valid_o(valid),
        .data_o ({rows, aux})
      );
    end
  end

  logic [PW-1:0] p;
  assign p = gen_lvl[L].rows[PW-1:0] + gen_lvl[L].rows[2*PW-1:PW];

  ru_pipe #(
    .Width(PW + AuxW),
    .Depth(CutMask[L] ? 1 : 0)
  ) u_cut_p (
    .clk_i,
    .rst_ni,
    .valid_i(gen_lvl[L].valid),
    .data_i ({p, gen_lvl[L].aux}),
    .valid_o(valid_o),
    .data_o ({p_o, aux_o})
  );

endmodule
