/* verilator lint_off DECLFILENAME */
// tb/exact: several parameterizations of ru_exact_path in one Verilated model (one build). Each
// instance N has its own ports in_valid_N, in_ready_N, op_N, ops_N (17 operands a.xyz d.xyz
// p0.xyz p1.xyz p2.xyz tmin tmax, 32 bits each, operand i in bits [32i +: 32], low bits used),
// out_valid_N, res_N. The configurations are listed in exact_path_test.cpp (kConfigs), in order.
module tb_exact_path_cfg #(
  parameter int unsigned ExpW = 5,
  parameter int unsigned FracW = 10,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned DigitW = 16,
  parameter int unsigned Plant = 0
) (
  input  logic clk_i,
  input  logic rst_ni,
  input  logic in_valid_i,
  output logic in_ready_o,
  input  logic [1:0] op_i,
  input  logic [17*32-1:0] ops_i,
  output logic out_valid_o,
  output logic [1:0] res_o
);
  localparam int unsigned W = ExpW + FracW + 1;
  logic [3*W-1:0] v [5];
  for (genvar g = 0; g < 5; g++) begin : g_vec
    for (genvar c = 0; c < 3; c++) begin : g_c
      assign v[g][c*W +: W] = ops_i[(3*g+c)*32 +: W];
    end
  end
  ru_exact_path #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .DigitW(DigitW), .Plant(Plant)) u_dut (
    .clk_i, .rst_ni, .in_valid_i, .in_ready_o, .op_i, .a_i(v[0]), .d_i(v[1]), .p0_i(v[2]), .p1_i(v[3]),
    .p2_i(v[4]), .tmin_i(ops_i[15*32 +: W]), .tmax_i(ops_i[16*32 +: W]), .out_valid_o, .res_o);
  if (W < 32) begin : g_unused
    logic unused;
    always_comb begin
      unused = 1'b0;
      for (int i = 0; i < 17; i++) unused ^= ^ops_i[i*32+W +: 32-W];
    end
  end
endmodule

module tb_exact_path_top (
  input  logic clk_i,
  input  logic rst_ni,
  input  logic in_valid_0, in_valid_1, in_valid_2, in_valid_3, in_valid_4, in_valid_5, in_valid_6, in_valid_7,
  output logic in_ready_0, in_ready_1, in_ready_2, in_ready_3, in_ready_4, in_ready_5, in_ready_6, in_ready_7,
  input  logic [1:0] op_0, op_1, op_2, op_3, op_4, op_5, op_6, op_7,
  input  logic [17*32-1:0] ops_0, ops_1, ops_2, ops_3, ops_4, ops_5, ops_6, ops_7,
  output logic out_valid_0, out_valid_1, out_valid_2, out_valid_3, out_valid_4, out_valid_5, out_valid_6,
  output logic out_valid_7,
  output logic [1:0] res_0, res_1, res_2, res_3, res_4, res_5, res_6, res_7
);
  // e5m10 D16, e8m23 D32, e3m2 D4, e6m12 D8, e4m3-ftz D8; e5m10 planted 1 (no tie terms),
  // 2 (one product's sign), 3 (inclusive lower bound)
  tb_exact_path_cfg #(.ExpW(5), .FracW(10), .Subnormals(1), .DigitW(16), .Plant(0)) u0 (.clk_i, .rst_ni, .in_valid_i(in_valid_0),
    .in_ready_o(in_ready_0), .op_i(op_0), .ops_i(ops_0), .out_valid_o(out_valid_0), .res_o(res_0));
  tb_exact_path_cfg #(.ExpW(8), .FracW(23), .Subnormals(1), .DigitW(32), .Plant(0)) u1 (.clk_i, .rst_ni, .in_valid_i(in_valid_1),
    .in_ready_o(in_ready_1), .op_i(op_1), .ops_i(ops_1), .out_valid_o(out_valid_1), .res_o(res_1));
  tb_exact_path_cfg #(.ExpW(3), .FracW(2), .Subnormals(1), .DigitW(4), .Plant(0)) u2 (.clk_i, .rst_ni, .in_valid_i(in_valid_2),
    .in_ready_o(in_ready_2), .op_i(op_2), .ops_i(ops_2), .out_valid_o(out_valid_2), .res_o(res_2));
  tb_exact_path_cfg #(.ExpW(6), .FracW(12), .Subnormals(1), .DigitW(8), .Plant(0)) u3 (.clk_i, .rst_ni, .in_valid_i(in_valid_3),
    .in_ready_o(in_ready_3), .op_i(op_3), .ops_i(ops_3), .out_valid_o(out_valid_3), .res_o(res_3));
  tb_exact_path_cfg #(.ExpW(4), .FracW(3), .Subnormals(0), .DigitW(8), .Plant(0)) u4 (.clk_i, .rst_ni,
    .in_valid_i(in_valid_4), .in_ready_o(in_ready_4), .op_i(op_4), .ops_i(ops_4), .out_valid_o(out_valid_4),
    .res_o(res_4));
  tb_exact_path_cfg #(.ExpW(5), .FracW(10), .Subnormals(1), .DigitW(16), .Plant(1)) u5 (.clk_i, .rst_ni, .in_valid_i(in_valid_5),
    .in_ready_o(in_ready_5), .op_i(op_5), .ops_i(ops_5), .out_valid_o(out_valid_5), .res_o(res_5));
  tb_exact_path_cfg #(.ExpW(5), .FracW(10), .Subnormals(1), .DigitW(16), .Plant(2)) u6 (.clk_i, .rst_ni, .in_valid_i(in_valid_6),
    .in_ready_o(in_ready_6), .op_i(op_6), .ops_i(ops_6), .out_valid_o(out_valid_6), .res_o(res_6));
  tb_exact_path_cfg #(.ExpW(5), .FracW(10), .Subnormals(1), .DigitW(16), .Plant(3)) u7 (.clk_i, .rst_ni, .in_valid_i(in_valid_7),
    .in_ready_o(in_ready_7), .op_i(op_7), .ops_i(ops_7), .out_valid_o(out_valid_7), .res_o(res_7));
endmodule
