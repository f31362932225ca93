// ru_ray_tri_cross: cross product y = u x v, cross() of model/include/rayunits/units/vec.hpp:
//   y.x = u.y*v.z - u.z*v.y;  y.y = u.z*v.x - u.x*v.z;  y.z = u.x*v.y - u.y*v.x
// (each product rounded, left product minus right product): six ru_fp_mul in one pipeline
// level (MulStages, MulCuts), then three ru_fp_add subtracters in the next (SubStages,
// SubCuts); see ru_pipe_pkg. Vectors packed {z, y, x}. Latency = MulStages + SubStages.
module ru_ray_tri_cross #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned MulStages = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] MulCuts = ru_pipe_pkg::AutoCuts,
  parameter int unsigned SubStages = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] SubCuts = ru_pipe_pkg::AutoCuts
) (
  input  logic                        clk_i,
  input  logic                        rst_ni,
  input  logic                        valid_i,
  input  logic [3*(1+ExpW+FracW)-1:0] u_i,
  input  logic [3*(1+ExpW+FracW)-1:0] v_i,
  output logic                        valid_o,
  output logic [3*(1+ExpW+FracW)-1:0] y_o
);

  localparam int unsigned W = 1 + ExpW + FracW;

  // component c: left = u[c+1] * v[c+2], right = u[c+2] * v[c+1] (indices mod 3)
  logic [3*W-1:0] left, right;
  logic [5:0]     pvalid;
  logic [29:0]    unused_flags;
  for (genvar c = 0; c < 3; c++) begin : gen_mul
    localparam int unsigned C1 = (c + 1) % 3;
    localparam int unsigned C2 = (c + 2) % 3;
    ru_fp_mul #(
      .ExpW(ExpW), .FracW(FracW), .Stages(MulStages), .Subnormals(Subnormals), .Round(Round),
      .CutSel(MulCuts)
    ) u_mul_l (
      .clk_i, .rst_ni,
      .in_valid_i (valid_i),
      .a_i        (u_i[C1*W+:W]),
      .b_i        (v_i[C2*W+:W]),
      .out_valid_o(pvalid[2*c]),
      .y_o        (left[c*W+:W]),
      .flags_o    (unused_flags[10*c+:5])
    );
    ru_fp_mul #(
      .ExpW(ExpW), .FracW(FracW), .Stages(MulStages), .Subnormals(Subnormals), .Round(Round),
      .CutSel(MulCuts)
    ) u_mul_r (
      .clk_i, .rst_ni,
      .in_valid_i (valid_i),
      .a_i        (u_i[C2*W+:W]),
      .b_i        (v_i[C1*W+:W]),
      .out_valid_o(pvalid[2*c+1]),
      .y_o        (right[c*W+:W]),
      .flags_o    (unused_flags[10*c+5+:5])
    );
  end
  logic unused_pvalid;
  assign unused_pvalid = ^pvalid[5:1];

  ru_ray_tri_vsub #(
    .ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round), .Stages(SubStages),
    .CutSel(SubCuts)
  ) u_sub (
    .clk_i, .rst_ni,
    .valid_i(pvalid[0]),
    .u_i    (left),
    .v_i    (right),
    .valid_o,
    .y_o
  );

endmodule
