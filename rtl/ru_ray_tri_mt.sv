// ru_ray_tri_mt: Moller-Trumbore ray-triangle intersection (dissertation Eq. 3.2), bit for bit
// the golden model ru::units::ray_tri_mt<Soft> (model/include/rayunits/units/ray_tri.hpp;
// the dataflow contract is docs/UNITS.md).
//
// Ports: the same as ru_ray_tri_robust (W = 1+ExpW+FracW; vectors packed {z, y, x}):
//   a_i, d_i, p0_i, p1_i, p2_i [3W]; tmin_i, tmax_i [W];
//   hit_o   beta >= 0, gamma >= 0, beta + gamma <= 1, not |V| < eps (option), t_min < t < t_max
//   why_o   ru::units::TriMiss: 0 hit, 1 outside (beta/gamma/sum), 3 |V| < eps, 4 interval
//   t_o = Va * (1/V), beta_o = V1 * (1/V), gamma_o = V2 * (1/V);
//   vol_o [5W] {V2, V1, +0 (V0 is not computed), Va, V} (zero unless OptVolOut = 1).
// Parameters: ExpW, FracW, Subnormals, Round, Stages (latency; ru_pipe_pkg places the
// registers), OptEpsTest + EpsBits (|V| < eps misses), OptVolOut. One test per cycle,
// out_valid_o = in_valid_i delayed by Stages cycles.
//
// Dataflow (27 mul, 24 add/sub, 1 div), in 10 levels:
//   L0 add  e1 = p1-p0, e2 = p2-p0, s = a-p0                                       (9 sub)
//   L1 mul  q = cross(d, e2), r = cross(s, e1)                                     (12 mul)
//   L2 add                                                                          (6 sub)
//   L3 mul  V = dot(q, e1), V1 = dot(q, s), V2 = dot(r, d), Va = dot(r, e2)  (12 mul, 8 add)
//   L4 add
//   L5 add
//   L6 div  inv = 1 / V; beside it |V| < eps (ru_fp_cmp lt)
//   L7 mul  beta = V1 * inv, gamma = V2 * inv, t = Va * inv                          (3 mul)
//   L8 add  sum = beta + gamma; beside it t_min < t, t < t_max (ru_fp_cmp lt) and the
//           bit tests beta >= +0, gamma >= +0 (results are never subnormal in FTZ formats:
//           x >= +0 <=> !NaN & (!sign | zero), exactly ru_fp_cmp le(+0, x))
//   L9 cmp  sum <= 1 (ru_fp_cmp le); then hit/why (gates)
module ru_ray_tri_mt #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned OptEpsTest = 0,
  parameter EpsBits = 0,  // untyped: -GEpsBits=<decimal> works for any width
  parameter int unsigned OptVolOut = 0
) (
  input  logic                      clk_i,
  input  logic                      rst_ni,
  input  logic                      in_valid_i,
  input  logic [3*(ExpW+FracW+1)-1:0] a_i,
  input  logic [3*(ExpW+FracW+1)-1:0] d_i,
  input  logic [3*(ExpW+FracW+1)-1:0] p0_i,
  input  logic [3*(ExpW+FracW+1)-1:0] p1_i,
  input  logic [3*(ExpW+FracW+1)-1:0] p2_i,
  input  logic [ExpW+FracW:0]       tmin_i,
  input  logic [ExpW+FracW:0]       tmax_i,
  output logic                      out_valid_o,
  output logic                      hit_o,
  output logic [2:0]                why_o,
  output logic [ExpW+FracW:0]       t_o,
  output logic [ExpW+FracW:0]       beta_o,
  output logic [ExpW+FracW:0]       gamma_o,
  output logic [5*(ExpW+FracW+1)-1:0] vol_o
);

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam int unsigned V3 = 3 * W;
  localparam logic [W-1:0] Eps = W'(EpsBits);
  localparam logic [W-1:0] One = W'((1 << (ExpW - 1)) - 1) << FracW;

  // ---- register placement (ru_pipe_pkg) -----------------------------------------------
  localparam int unsigned NLev = 10;
  // level kinds, level 0 in the low nibble: add mul add mul add add div mul add cmp
  localparam logic [4*ru_pipe_pkg::MaxLev-1:0] Kinds = {24'd0, ru_fp_pkg::KCmp, ru_fp_pkg::KAdd,
      ru_fp_pkg::KMul, ru_fp_pkg::KDiv, ru_fp_pkg::KAdd, ru_fp_pkg::KAdd,
      ru_fp_pkg::KMul, ru_fp_pkg::KAdd, ru_fp_pkg::KMul, ru_fp_pkg::KAdd};
  `include "ru_level_chain.svh"
  // data-only delay lines (ru_pipe; the level instances carry the valid bits)
  logic [13:0] unused_dly_valid;

  // ---- L0: edges and a - p0 ----------------------------------------------------------------
  logic [V3-1:0] e1, e2, sv;
  logic [2:0]    v0;
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_e1 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(p1_i), .v_i(p0_i), .valid_o(v0[0]), .y_o(e1));
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_e2 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(p2_i), .v_i(p0_i), .valid_o(v0[1]), .y_o(e2));
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_s (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(a_i), .v_i(p0_i), .valid_o(v0[2]), .y_o(sv));
  logic [V3-1:0] d1;
  ru_pipe #(.Width(V3), .Depth(lat(0))) u_wait0_d (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[0]), .data_i(d_i), .data_o(d1));

  // ---- L1, L2: q = d x e2, r = s x e1 ----------------------------------------------------------
  logic [V3-1:0] q, r;
  logic [1:0]    v2;
  ru_ray_tri_cross #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                     .MulStages(lat(1)), .MulCuts(lcut(1)), .SubStages(lat(2)), .SubCuts(lcut(2))) u_q (
    .clk_i, .rst_ni, .valid_i(v0[0]), .u_i(d1), .v_i(e2), .valid_o(v2[0]), .y_o(q));
  ru_ray_tri_cross #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                     .MulStages(lat(1)), .MulCuts(lcut(1)), .SubStages(lat(2)), .SubCuts(lcut(2))) u_r (
    .clk_i, .rst_ni, .valid_i(v0[0]), .u_i(sv), .v_i(e1), .valid_o(v2[1]), .y_o(r));
  logic [V3-1:0] e1_2, e2_2, s_2, d_2;
  ru_pipe #(.Width(V3), .Depth(span(1, 3))) u_wait12_e1 (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[1]), .data_i(e1), .data_o(e1_2));
  ru_pipe #(.Width(V3), .Depth(span(1, 3))) u_wait12_e2 (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[2]), .data_i(e2), .data_o(e2_2));
  ru_pipe #(.Width(V3), .Depth(span(1, 3))) u_wait12_s (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[3]), .data_i(sv), .data_o(s_2));
  ru_pipe #(.Width(V3), .Depth(span(1, 3))) u_wait12_d (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[4]), .data_i(d1), .data_o(d_2));
  // t_min, t_max wait for L0..L7
  logic [W-1:0] tmin8, tmax8;
  ru_pipe #(.Width(W), .Depth(span(0, 8))) u_wait_tmin (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[5]), .data_i(tmin_i), .data_o(tmin8));
  ru_pipe #(.Width(W), .Depth(span(0, 8))) u_wait_tmax (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[6]), .data_i(tmax_i), .data_o(tmax8));

  // ---- L3..L5: the four volumes -----------------------------------------------------------------
  logic [W-1:0] vol_v, vol_v1, vol_v2, vol_va;
  logic [3:0]   v5;
  logic [19:0] unused_dot_flags;  // the volumes' flags are not outputs of the unit
  ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                   .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                   .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_dv (
    .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(q), .v_i(e1_2), .valid_o(v5[0]), .y_o(vol_v),
    .flags_o(unused_dot_flags[0*5+:5]));
  ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                   .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                   .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_dv1 (
    .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(q), .v_i(s_2), .valid_o(v5[1]), .y_o(vol_v1),
    .flags_o(unused_dot_flags[1*5+:5]));
  ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                   .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                   .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_dv2 (
    .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(r), .v_i(d_2), .valid_o(v5[2]), .y_o(vol_v2),
    .flags_o(unused_dot_flags[2*5+:5]));
  ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                   .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                   .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_dva (
    .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(r), .v_i(e2_2), .valid_o(v5[3]), .y_o(vol_va),
    .flags_o(unused_dot_flags[3*5+:5]));

  // ---- L6: inv = 1 / V; beside it |V| < eps ------------------------------------------------------
  logic [W-1:0] inv;
  logic         v6;
  logic [4:0]   unused_div_flags;
  ru_fp_div #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals), .Round(Round),
              .CutSel(lcut(6))) u_div (
    .clk_i, .rst_ni, .in_valid_i(v5[0]), .a_i(One), .b_i(vol_v),
    .out_valid_o(v6), .y_o(inv), .flags_o(unused_div_flags));
  logic [W-1:0] v1_6, v2_6, va_6;
  ru_pipe #(.Width(3 * W), .Depth(lat(6))) u_wait6 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[7]), .data_i({vol_v1, vol_v2, vol_va}), .data_o({v1_6, v2_6, va_6}));

  logic small6;
  if (OptEpsTest != 0) begin : gen_eps
    logic [W-1:0] lt_y;
    logic [4:0]   unused_eps_flags;
    logic         unused_eps_valid;
    ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals)) u_eps (
      .clk_i, .rst_ni, .in_valid_i(v5[0]),
      .a_i({1'b0, vol_v[W-2:0]}), .b_i(Eps), .op_i(3'd0),
      .out_valid_o(unused_eps_valid), .y_o(lt_y), .flags_o(unused_eps_flags));
    assign small6 = lt_y[0];
    logic [W-2:0] unused_eps_hi;
    assign unused_eps_hi = lt_y[W-1:1];
  end else begin : gen_no_eps
    assign small6 = 1'b0;
  end

  // ---- L7: beta, gamma, t ------------------------------------------------------------------------
  logic [W-1:0] q_beta, q_gamma, q_t;
  logic [2:0]   v7;
  logic [14:0]  unused_mul_flags;
  ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(7)), .Subnormals(Subnormals), .Round(Round),
              .CutSel(lcut(7))) u_beta (
    .clk_i, .rst_ni, .in_valid_i(v6), .a_i(v1_6), .b_i(inv),
    .out_valid_o(v7[0]), .y_o(q_beta), .flags_o(unused_mul_flags[0+:5]));
  ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(7)), .Subnormals(Subnormals), .Round(Round),
              .CutSel(lcut(7))) u_gamma (
    .clk_i, .rst_ni, .in_valid_i(v6), .a_i(v2_6), .b_i(inv),
    .out_valid_o(v7[1]), .y_o(q_gamma), .flags_o(unused_mul_flags[5+:5]));
  ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(7)), .Subnormals(Subnormals), .Round(Round),
              .CutSel(lcut(7))) u_t (
    .clk_i, .rst_ni, .in_valid_i(v6), .a_i(va_6), .b_i(inv),
    .out_valid_o(v7[2]), .y_o(q_t), .flags_o(unused_mul_flags[10+:5]));
  logic small7;
  ru_pipe #(.Width(1), .Depth(lat(7))) u_wait7 (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[8]), .data_i(small6), .data_o(small7));

  // ---- L8: sum = beta + gamma; beside it the interval test and beta, gamma >= 0 ------------------
  logic [W-1:0] sum;
  logic         v8;
  logic [4:0]   unused_sum_flags;
  ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(8)), .Subnormals(Subnormals), .Round(Round),
              .CutSel(lcut(8))) u_sum (
    .clk_i, .rst_ni, .in_valid_i(v7[0]), .a_i(q_beta), .b_i(q_gamma), .op_i(1'b0),
    .out_valid_o(v8), .y_o(sum), .flags_o(unused_sum_flags));
  logic [W-1:0] lo_y, hi_y;
  logic [9:0]   unused_iv_flags;
  logic [1:0]   unused_iv_valid;
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(8)), .Subnormals(Subnormals)) u_lo (
    .clk_i, .rst_ni, .in_valid_i(v7[0]), .a_i(tmin8), .b_i(q_t), .op_i(3'd0),
    .out_valid_o(unused_iv_valid[0]), .y_o(lo_y), .flags_o(unused_iv_flags[0+:5]));
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(8)), .Subnormals(Subnormals)) u_hi (
    .clk_i, .rst_ni, .in_valid_i(v7[0]), .a_i(q_t), .b_i(tmax8), .op_i(3'd0),
    .out_valid_o(unused_iv_valid[1]), .y_o(hi_y), .flags_o(unused_iv_flags[5+:5]));
  logic [2*W-3:0] unused_iv_hi;
  assign unused_iv_hi = {lo_y[W-1:1], hi_y[W-1:1]};

  function automatic logic f_ge0(input logic [W-1:0] x);  // x >= +0 for an operation result
    logic nan, zero;
    nan = (&x[W-2:FracW]) & (|x[FracW-1:0]);
    zero = ~|x[W-2:0];
    f_ge0 = ~nan & (~x[W-1] | zero);
  endfunction
  logic ge7;
  assign ge7 = f_ge0(q_beta) & f_ge0(q_gamma);
  logic ge8, small8, in_range8;
  ru_pipe #(.Width(2), .Depth(lat(8))) u_wait8 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[9]), .data_i({ge7, small7}), .data_o({ge8, small8}));
  assign in_range8 = lo_y[0] & hi_y[0];
  logic [W-1:0] t8, beta8, gamma8;
  ru_pipe #(.Width(3 * W), .Depth(lat(8))) u_wait8_v (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[10]), .data_i({q_t, q_beta, q_gamma}), .data_o({t8, beta8, gamma8}));

  // ---- L9: sum <= 1 ------------------------------------------------------------------------------
  logic [W-1:0] le_y;
  logic [4:0]   unused_le_flags;
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(9)), .Subnormals(Subnormals), .CutSel(lcut(9))) u_le (
    .clk_i, .rst_ni, .in_valid_i(v8), .a_i(sum), .b_i(One), .op_i(3'd1),
    .out_valid_o(out_valid_o), .y_o(le_y), .flags_o(unused_le_flags));
  logic [W-2:0] unused_le_hi;
  assign unused_le_hi = le_y[W-1:1];
  logic ge9, small9, in_range9;
  ru_pipe #(.Width(3), .Depth(lat(9))) u_wait9 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[11]), .data_i({ge8, small8, in_range8}), .data_o({ge9, small9, in_range9}));
  ru_pipe #(.Width(3 * W), .Depth(lat(9))) u_wait9_v (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[12]), .data_i({t8, beta8, gamma8}), .data_o({t_o, beta_o, gamma_o}));

  logic in_tri;
  assign in_tri = ge9 & le_y[0];
  always_comb begin
    if (!in_tri) why_o = 3'd1;
    else if (small9) why_o = 3'd3;
    else if (!in_range9) why_o = 3'd4;
    else why_o = 3'd0;
  end
  assign hit_o = (why_o == 3'd0);

  // diagnostics: V and Va wait for L6..L9, V1 and V2 for L6..L9 (from u_wait6 on)
  if (OptVolOut != 0) begin : gen_vol
    logic [4*W-1:0] vols;
    assign vols = {vol_v2, vol_v1, vol_va, vol_v};
    logic [4*W-1:0] vols9;
    ru_pipe #(.Width(4 * W), .Depth(span(6, 10))) u_wait_vol (
      .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[13]), .data_i(vols), .data_o(vols9));
    assign vol_o = {vols9[3*W+:W], vols9[2*W+:W], {W{1'b0}}, vols9[W+:W], vols9[0+:W]};
  end else begin : gen_no_vol
    assign vol_o = '0;
  end

  logic unused_valid;
  assign unused_valid = ^{v0[2:1], v2[1], v5[3:1], v7[2:1]};

endmodule
