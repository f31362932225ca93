/* verilator lint_off DECLFILENAME */
// tb/exact: one parameterization of ru_ray_tri_exact with the ports of the test tops
// (tb_ray_tri_exact_top.sv: the fast suite's; tb_ray_tri_exact_long_top.sv: several in one
// Verilated model, one build). Each instance N of a top has its own ports in_valid_N, in_ready_N, ops_N (17 operands a.xyz d.xyz p0.xyz
// p1.xyz p2.xyz tmin tmax, 32 bits each, operand i in bits [32i +: 32], low bits used),
// out_valid_N, hit_N, why_N, tbg_N ({gamma, beta, t}, 32 bits each, low bits used), slow_N.
// The configurations are listed in ray_tri_exact_test.cpp (kConfigs), in order; a test there
// checks that list against the top's file.
module tb_ray_tri_exact_cfg #(
  parameter int unsigned ExpW = 5,
  parameter int unsigned FracW = 10,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned Stages = 0,
  parameter int unsigned DigitW = 16,
  parameter int unsigned Slack = 1,
  parameter int unsigned Plant = 0
) (
  input  logic clk_i,
  input  logic rst_ni,
  input  logic in_valid_i,
  output logic in_ready_o,
  input  logic [17*32-1:0] ops_i,
  output logic out_valid_o,
  output logic hit_o,
  output logic [2:0] why_o,
  output logic [3*32-1:0] tbg_o,
  output logic slow_o
);
  localparam int unsigned W = ExpW + FracW + 1;
  logic [3*W-1:0] v [5];
  for (genvar g = 0; g < 5; g++) begin : g_vec
    for (genvar c = 0; c < 3; c++) begin : g_c
      assign v[g][c*W +: W] = ops_i[(3*g+c)*32 +: W];
    end
  end
  logic [W-1:0] t, beta, gamma;
  ru_ray_tri_exact #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round), .Stages(Stages),
                     .DigitW(DigitW), .Slack(Slack), .Plant(Plant)) u_dut (
    .clk_i, .rst_ni, .in_valid_i, .in_ready_o, .a_i(v[0]), .d_i(v[1]), .p0_i(v[2]), .p1_i(v[3]), .p2_i(v[4]),
    .tmin_i(ops_i[15*32 +: W]), .tmax_i(ops_i[16*32 +: W]), .out_valid_o, .hit_o, .why_o, .t_o(t),
    .beta_o(beta), .gamma_o(gamma), .slow_o);
  assign tbg_o = {32'(gamma), 32'(beta), 32'(t)};
  if (W < 32) begin : g_unused
    logic unused;
    always_comb begin
      unused = 1'b0;
      for (int i = 0; i < 17; i++) unused ^= ^ops_i[i*32+W +: 32-W];
    end
  end
endmodule
