// ru_fp_dot3_core: the datapath of the 3-term dot product
//   y = round(round(round(u0*v0) + round(u1*v1)) + round(u2*v2))     (docs/FORMAT.md, not fused)
// with the register placement given per level by the instantiating unit: three ru_fp_mul in one
// level (MulStages/MulCuts), u0*v0 + u1*v1 in the next (Add1Stages/Add1Cuts; the third product
// and the product flags wait in an ru_pipe meanwhile), the third product added in the last
// (Add2Stages/Add2Cuts; the earlier flags wait beside it). flags_o is the OR of the flags of all
// five operations. Vectors packed {z, y, x} (u0 in the least significant bits).
// Latency = MulStages + Add1Stages + Add2Stages; one dot product per cycle.
//
// Used by ru_fp_dot3 (which places Stages registers over the whole chain, ru_pipe_pkg::cut_mask)
// and by the ray-triangle units (per-level placement from ru_pipe_pkg; they leave flags_o
// unconnected, so synthesis removes the flag delay lines).
module ru_fp_dot3_core #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned MulStages = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] MulCuts = ru_pipe_pkg::AutoCuts,
  parameter int unsigned Add1Stages = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] Add1Cuts = ru_pipe_pkg::AutoCuts,
  parameter int unsigned Add2Stages = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] Add2Cuts = ru_pipe_pkg::AutoCuts
) (
  input  logic                        clk_i,
  input  logic                        rst_ni,
  input  logic                        valid_i,
  input  logic [3*(1+ExpW+FracW)-1:0] u_i,
  input  logic [3*(1+ExpW+FracW)-1:0] v_i,
  output logic                        valid_o,
  output logic [ExpW+FracW:0]         y_o,
  output logic [4:0]                  flags_o
);

  localparam int unsigned W = 1 + ExpW + FracW;

  // ---- products ----------------------------------------------------------------------------
  logic [2:0]     p_valid;
  logic [3*W-1:0] p;
  logic [14:0]    p_flags;
  for (genvar i = 0; i < 3; i++) begin : gen_mul
    ru_fp_mul #(
      .ExpW(ExpW), .FracW(FracW), .Stages(MulStages), .Subnormals(Subnormals), .Round(Round),
      .CutSel(MulCuts)
    ) u_mul (
      .clk_i, .rst_ni,
      .in_valid_i (valid_i),
      .a_i        (u_i[i*W+:W]),
      .b_i        (v_i[i*W+:W]),
      .out_valid_o(p_valid[i]),
      .y_o        (p[i*W+:W]),
      .flags_o    (p_flags[i*5+:5])
    );
  end

  // ---- s = p0 + p1; p2 and the product flags wait ---------------------------------------------
  logic         s_valid, d_valid;
  logic [W-1:0] s, d_p2;
  logic [4:0]   s_flags, d_flags;
  ru_fp_add #(
    .ExpW(ExpW), .FracW(FracW), .Stages(Add1Stages), .Subnormals(Subnormals), .Round(Round),
    .CutSel(Add1Cuts)
  ) u_add1 (
    .clk_i, .rst_ni,
    .in_valid_i (p_valid[0]),
    .a_i        (p[0+:W]),
    .b_i        (p[W+:W]),
    .op_i       (1'b0),
    .out_valid_o(s_valid),
    .y_o        (s),
    .flags_o    (s_flags)
  );
  ru_pipe #(.Width(W + 5), .Depth(Add1Stages)) u_wait1 (
    .clk_i, .rst_ni,
    .valid_i(p_valid[0]),
    .data_i ({p[2*W+:W], p_flags[0+:5] | p_flags[5+:5] | p_flags[10+:5]}),
    .valid_o(d_valid),
    .data_o ({d_p2, d_flags})
  );

  // ---- y = s + p2 ---------------------------------------------------------------------------
  logic       unused_valid;
  logic [4:0] y_flags, e_flags;
  assign unused_valid = d_valid ^ p_valid[1] ^ p_valid[2];  // all equal to the used ones
  ru_fp_add #(
    .ExpW(ExpW), .FracW(FracW), .Stages(Add2Stages), .Subnormals(Subnormals), .Round(Round),
    .CutSel(Add2Cuts)
  ) u_add2 (
    .clk_i, .rst_ni,
    .in_valid_i (s_valid),
    .a_i        (s),
    .b_i        (d_p2),
    .op_i       (1'b0),
    .out_valid_o(valid_o),
    .y_o        (y_o),
    .flags_o    (y_flags)
  );
  logic unused_e_valid;
  ru_pipe #(.Width(5), .Depth(Add2Stages)) u_wait2 (
    .clk_i, .rst_ni,
    .valid_i(s_valid),
    .data_i (s_flags | d_flags),
    .valid_o(unused_e_valid),
    .data_o (e_flags)
  );
  assign flags_o = y_flags | e_flags;

endmodule
