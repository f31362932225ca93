// ru_lzc: leading-zero count, a log2-depth tree.
//
// cnt_o = number of zeros above the most significant one of in_i (in_i[Width-1] is the
// first bit looked at); cnt_o = Width and zero_o = 1 when in_i is all zeros.
// The input is extended below its LSB by a single one (and zeros up to a power of two,
// P >= Width+1 leaves), so the tree never sees an all-zero vector. Each tree node merges
// an upper child (valid vu, count cu) and a lower child (vl, cl):
//   valid = vu | vl;  count = vu ? {0, cu} : {1, cl}.
module ru_lzc #(
  parameter int unsigned Width = 8,
  localparam int unsigned CntW = ru_fp_pkg::clog2p(Width + 1)
) (
  input  logic [Width-1:0] in_i,
  output logic [CntW-1:0]  cnt_o,
  output logic             zero_o
);

  localparam int unsigned P = 1 << CntW;  // leaves (>= Width + 1)

  logic [P-1:0] leaves;
  assign leaves = {in_i, 1'b1, {(P - Width - 1) {1'b0}}};

  // level l (1..CntW) has P >> l nodes, each with a valid bit and an l-bit count
  for (genvar l = 1; l <= CntW; l++) begin : gen_lvl
    localparam int unsigned Nodes = P >> l;
    logic [Nodes-1:0]   v;
    logic [Nodes*l-1:0] c;
    for (genvar n = 0; n < Nodes; n++) begin : gen_node
      if (l == 1) begin : gen_leaf
        assign v[n] = leaves[2*n+1] | leaves[2*n];
        assign c[n] = ~leaves[2*n+1];
      end else begin : gen_inner
        logic vu, vl;
        logic [l-2:0] cu, cl;
        assign vu = gen_lvl[l-1].v[2*n+1];
        assign vl = gen_lvl[l-1].v[2*n];
        assign cu = gen_lvl[l-1].c[(2*n+1)*(l-1)+:(l-1)];
        assign cl = gen_lvl[l-1].c[(2*n)*(l-1)+:(l-1)];
        assign v[n] = vu | vl;
        assign c[n*l+:l] = vu ? {1'b0, cu} : {1'b1, cl};
      end
    end
  end

  assign cnt_o  = gen_lvl[CntW].c;
  assign zero_o = ~|in_i;

  logic unused_root_valid;
  assign unused_root_valid = gen_lvl[CntW].v[0];  // always 1 (the appended one)

endmodule
