// tb/exact: the fast suite's parameterization of ru_ray_tri_exact (tb_ray_tri_exact_cfg.sv); listed
// in ray_tri_exact_test.cpp (kConfigs).
module tb_ray_tri_exact_top (
  input  logic clk_i,
  input  logic rst_ni,
  input  logic in_valid_0,
  output logic in_ready_0,
  input  logic [17*32-1:0] ops_0,
  output logic out_valid_0,
  output logic hit_0,
  output logic [2:0] why_0,
  output logic [3*32-1:0] tbg_0,
  output logic slow_0
);
  // 0: e5m10 Stages 2
  tb_ray_tri_exact_cfg #(.ExpW(5), .FracW(10), .Subnormals(1), .Round(0), .Stages(2), .DigitW(16), .Slack(1), .Plant(0)) u0 (
    .clk_i, .rst_ni, .in_valid_i(in_valid_0), .in_ready_o(in_ready_0), .ops_i(ops_0), .out_valid_o(out_valid_0),
    .hit_o(hit_0), .why_o(why_0), .tbg_o(tbg_0), .slow_o(slow_0));
endmodule
