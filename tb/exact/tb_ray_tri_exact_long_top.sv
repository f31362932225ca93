/* verilator lint_off DECLFILENAME */
// tb/exact: the long suite's parameterizations of ru_ray_tri_exact (tb_ray_tri_exact_cfg.sv) in
// one Verilated model; listed in ray_tri_exact_test.cpp (kConfigs with RU_TB_EXACT_LONG).
module tb_ray_tri_exact_long_top (
  input  logic clk_i,
  input  logic rst_ni,
  input  logic in_valid_0,
  output logic in_ready_0,
  input  logic [17*32-1:0] ops_0,
  output logic out_valid_0,
  output logic hit_0,
  output logic [2:0] why_0,
  output logic [3*32-1:0] tbg_0,
  output logic slow_0,
  input  logic in_valid_1,
  output logic in_ready_1,
  input  logic [17*32-1:0] ops_1,
  output logic out_valid_1,
  output logic hit_1,
  output logic [2:0] why_1,
  output logic [3*32-1:0] tbg_1,
  output logic slow_1,
  input  logic in_valid_2,
  output logic in_ready_2,
  input  logic [17*32-1:0] ops_2,
  output logic out_valid_2,
  output logic hit_2,
  output logic [2:0] why_2,
  output logic [3*32-1:0] tbg_2,
  output logic slow_2,
  input  logic in_valid_3,
  output logic in_ready_3,
  input  logic [17*32-1:0] ops_3,
  output logic out_valid_3,
  output logic hit_3,
  output logic [2:0] why_3,
  output logic [3*32-1:0] tbg_3,
  output logic slow_3,
  input  logic in_valid_4,
  output logic in_ready_4,
  input  logic [17*32-1:0] ops_4,
  output logic out_valid_4,
  output logic hit_4,
  output logic [2:0] why_4,
  output logic [3*32-1:0] tbg_4,
  output logic slow_4,
  input  logic in_valid_5,
  output logic in_ready_5,
  input  logic [17*32-1:0] ops_5,
  output logic out_valid_5,
  output logic hit_5,
  output logic [2:0] why_5,
  output logic [3*32-1:0] tbg_5,
  output logic slow_5
);
  // 0: e5m10 Stages 0
  tb_ray_tri_exact_cfg #(.ExpW(5), .FracW(10), .Subnormals(1), .Round(0), .Stages(0), .DigitW(16), .Slack(1), .Plant(0)) u0 (
    .clk_i, .rst_ni, .in_valid_i(in_valid_0), .in_ready_o(in_ready_0), .ops_i(ops_0), .out_valid_o(out_valid_0),
    .hit_o(hit_0), .why_o(why_0), .tbg_o(tbg_0), .slow_o(slow_0));
  // 1: e8m23 Stages 6 Slack 2
  tb_ray_tri_exact_cfg #(.ExpW(8), .FracW(23), .Subnormals(1), .Round(0), .Stages(6), .DigitW(32), .Slack(2), .Plant(0)) u1 (
    .clk_i, .rst_ni, .in_valid_i(in_valid_1), .in_ready_o(in_ready_1), .ops_i(ops_1), .out_valid_o(out_valid_1),
    .hit_o(hit_1), .why_o(why_1), .tbg_o(tbg_1), .slow_o(slow_1));
  // 2: e4m3-ftz Stages 3 Slack 0
  tb_ray_tri_exact_cfg #(.ExpW(4), .FracW(3), .Subnormals(0), .Round(0), .Stages(3), .DigitW(8), .Slack(0), .Plant(0)) u2 (
    .clk_i, .rst_ni, .in_valid_i(in_valid_2), .in_ready_o(in_ready_2), .ops_i(ops_2), .out_valid_o(out_valid_2),
    .hit_o(hit_2), .why_o(why_2), .tbg_o(tbg_2), .slow_o(slow_2));
  // 3: e6m12 RTZ Stages 2
  tb_ray_tri_exact_cfg #(.ExpW(6), .FracW(12), .Subnormals(1), .Round(1), .Stages(2), .DigitW(8), .Slack(1), .Plant(0)) u3 (
    .clk_i, .rst_ni, .in_valid_i(in_valid_3), .in_ready_o(in_ready_3), .ops_i(ops_3), .out_valid_o(out_valid_3),
    .hit_o(hit_3), .why_o(why_3), .tbg_o(tbg_3), .slow_o(slow_3));
  // 4: e5m10 Stages 2 plant 1 (shrunk edge bound)
  tb_ray_tri_exact_cfg #(.ExpW(5), .FracW(10), .Subnormals(1), .Round(0), .Stages(2), .DigitW(16), .Slack(1), .Plant(1)) u4 (
    .clk_i, .rst_ni, .in_valid_i(in_valid_4), .in_ready_o(in_ready_4), .ops_i(ops_4), .out_valid_o(out_valid_4),
    .hit_o(hit_4), .why_o(why_4), .tbg_o(tbg_4), .slow_o(slow_4));
  // 5: e5m10 Stages 2 plant 2 (no early stop)
  tb_ray_tri_exact_cfg #(.ExpW(5), .FracW(10), .Subnormals(1), .Round(0), .Stages(2), .DigitW(16), .Slack(1), .Plant(2)) u5 (
    .clk_i, .rst_ni, .in_valid_i(in_valid_5), .in_ready_o(in_ready_5), .ops_i(ops_5), .out_valid_o(out_valid_5),
    .hit_o(hit_5), .why_o(why_5), .tbg_o(tbg_5), .slow_o(slow_5));
endmodule
