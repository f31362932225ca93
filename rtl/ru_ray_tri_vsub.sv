// ru_ray_tri_vsub: componentwise vector difference y = u - v (three ru_fp_add, op_i = 1),
// vsub() of model/include/rayunits/units/vec.hpp. Vectors are packed {z, y, x}, x in the low
// W bits. One pipeline level of ru_ray_tri_robust / ru_ray_tri_mt: Stages and CutSel are
// handed to every subtracter (see ru_pipe_pkg). Latency = Stages.
module ru_ray_tri_vsub #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned Stages = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts
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

  logic [2:0]  valid;
  logic [14:0] unused_flags;
  for (genvar c = 0; c < 3; c++) begin : gen_sub
    ru_fp_add #(
      .ExpW(ExpW), .FracW(FracW), .Stages(Stages), .Subnormals(Subnormals), .Round(Round),
      .CutSel(CutSel)
    ) u_sub (
      .clk_i, .rst_ni,
      .in_valid_i (valid_i),
      .a_i        (u_i[c*W+:W]),
      .b_i        (v_i[c*W+:W]),
      .op_i       (1'b1),
      .out_valid_o(valid[c]),
      .y_o        (y_o[c*W+:W]),
      .flags_o    (unused_flags[c*5+:5])
    );
  end
  assign valid_o = valid[0];
  logic unused_valid;
  assign unused_valid = ^valid[2:1];

endmodule
