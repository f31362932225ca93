// ru_ray_tri_robust: Kensler's robust ray-triangle intersection (dissertation Fig. 3.6),
// bit for bit the golden model ru::units::ray_tri_robust<Soft>
// (model/include/rayunits/units/ray_tri.hpp; the dataflow contract is docs/UNITS.md).
//
// Ports (W = 1+ExpW+FracW; vectors packed {z, y, x}, x in the low W bits):
//   a_i [3W] ray origin, d_i [3W] ray direction, p0_i/p1_i/p2_i [3W] vertices,
//   tmin_i, tmax_i [W] the open interval (t_min, t_max) of accepted t;
//   hit_o   t_min < t < t_max, the volumes V0, V1, V2 not of mixed signs, and neither the
//           optional tie-break nor the optional |V| < eps test rejects;
//   why_o   ru::units::TriMiss: 0 hit, 1 sign (mixed V0..V2), 2 tie-break, 3 |V| < eps,
//           4 t outside the interval (incl. NaN t); the first failing condition in that order;
//   t_o = Va / V, beta_o = V1 / V, gamma_o = V2 / V (correctly rounded, every input);
//   vol_o [5W] {V2, V1, V0, Va, V} (diagnostics; zero unless OptVolOut = 1).
//
// Parameters: ExpW, FracW, Subnormals, Round (the format, every operation rounds with Round);
//   Stages       latency in cycles (0 = combinational), registers placed by ru_pipe_pkg;
//   OptTieBreak  1: when V_i is exactly zero, the triangle for which p_{i+1} is the
//                lexicographically smaller end point of the edge misses (Fig. 3.6's test);
//   OptEpsTest   1: |V| < eps misses, eps = EpsBits (a bit pattern of the format);
//   OptVolOut    1: drive vol_o (delay lines for the five volumes);
//   OptRecip     1: the cheaper variant ru::units::ray_tri_robust_recip (issue 14 section 3):
//                one reciprocal r = 1/V and three multiplications t = Va*r, beta = V1*r,
//                gamma = V2*r in place of the three divisions (level L6 div becomes L6 div
//                (one divider) + L7 mul; the compares move to L8; MaxUsefulStages grows by the
//                multiplier's L+5 segments).
// Fully pipelined: one test per cycle, out_valid_o = in_valid_i delayed by Stages cycles.
//
// Dataflow (operation for operation the model's; 39 mul, 43 add/sub, 3 div), in 8 levels:
//   L0 add  e0 = p1-p2, e1 = p2-p0, e2 = p0-p1; a-p0, a-p1, a-p2; p2-a          (21 sub)
//           s0 = lexmin_first(p1,p2), s1 = (p2,p0), s2 = (p0,p1): 18 ru_fp_cmp lt (beside)
//   L1 mul  cross(a - m_i, d) with a - m_i = s_i ? a - p_{i+1} : a - p_{i+2} (a mux:
//           the model's vsub(a, m_i) is one of the two differences computed in L0, the same
//           operation on the same operands); N = cross(e1, e0)                       (24 mul)
//   L2 add  the cross products' differences                                        (12 sub)
//   L3 mul  V0 = dot(c0, e0), V1 = dot(c1, e1), V2 = dot(c2, e2), V = dot(N, d),
//   L4 add  Va = dot(N, p2 - a): products, then x+y, then +z                  (15 mul, 10 add)
//   L5 add
//   L6 div  t = Va/V, beta = V1/V, gamma = V2/V; beside it |V| < eps (ru_fp_cmp lt) and the
//           sign logic of V0..V2
//   L7 cmp  t_min < t, t < t_max (ru_fp_cmp lt); then hit/why (gates)
// Comparisons of an operation result with +0 (V_i < 0, V_i > 0, V_i == 0) are bit tests:
// such a value is never subnormal in a flush-to-zero format (results are flushed), so
//   x < +0  <=>  sign & (exp|frac != 0) & !NaN;  x == 0 <=> exp|frac == 0 (NaN never equal),
// exactly ru_fp_cmp's lt/eq on these operands. Comparisons with inputs/constants (lexmin,
// t_min, t_max, eps) use ru_fp_cmp, which flushes subnormal inputs in FTZ formats.
module ru_ray_tri_robust #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned OptTieBreak = 0,
  parameter int unsigned OptEpsTest = 0,
  parameter EpsBits = 0,  // untyped: -GEpsBits=<decimal> works for any width
  parameter int unsigned OptVolOut = 0,
  parameter int unsigned OptRecip = 0
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

  // ---- register placement (ru_pipe_pkg) -----------------------------------------------
  localparam int unsigned R = (OptRecip != 0) ? 1 : 0;
  localparam int unsigned LCmp = 7 + R;  // level of the interval compares
  localparam int unsigned NLev = 8 + R;
  // level kinds, level 0 in the low nibble: add mul add mul add add div cmp
  // (OptRecip: add mul add mul add add div mul cmp)
  localparam logic [31:0] KindsL0to5 = {8'd0, ru_fp_pkg::KAdd, ru_fp_pkg::KAdd, ru_fp_pkg::KMul,
      ru_fp_pkg::KAdd, ru_fp_pkg::KMul, ru_fp_pkg::KAdd};
  localparam logic [4*ru_pipe_pkg::MaxLev-1:0] Kinds = (R != 0)
      ? {28'd0, ru_fp_pkg::KCmp, ru_fp_pkg::KMul, ru_fp_pkg::KDiv, KindsL0to5[23:0]}
      : {32'd0, ru_fp_pkg::KCmp, ru_fp_pkg::KDiv, KindsL0to5[23:0]};
  `include "ru_level_chain.svh"
  // data-only delay lines (ru_pipe; the level instances carry the valid bits)
  logic [16:0] unused_dly_valid;

  // ---- L0: edges, differences to a, lexicographic order of the edges' end points ---------------
  logic [V3-1:0] e0, e1, e2, ap0, ap1, ap2, p2a;
  logic [6:0]    v0;
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_e0 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(p1_i), .v_i(p2_i), .valid_o(v0[0]), .y_o(e0));
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_e1 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(p2_i), .v_i(p0_i), .valid_o(v0[1]), .y_o(e1));
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_e2 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(p0_i), .v_i(p1_i), .valid_o(v0[2]), .y_o(e2));
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_ap0 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(a_i), .v_i(p0_i), .valid_o(v0[3]), .y_o(ap0));
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_ap1 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(a_i), .v_i(p1_i), .valid_o(v0[4]), .y_o(ap1));
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_ap2 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(a_i), .v_i(p2_i), .valid_o(v0[5]), .y_o(ap2));
  ru_ray_tri_vsub #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                    .Stages(lat(0)), .CutSel(lcut(0))) u_p2a (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .u_i(p2_i), .v_i(a_i), .valid_o(v0[6]), .y_o(p2a));

  // lexmin_first(l, r) for the edge end-point pairs (p1,p2), (p2,p0), (p0,p1):
  //   l.x < r.x -> l; l.x > r.x -> r; then y, then z; all equal (or NaN) -> l
  logic [3*V3-1:0] lex_l, lex_r;  // pair i at [i*V3 +: V3]
  assign lex_l = {p0_i, p2_i, p1_i};
  assign lex_r = {p1_i, p0_i, p2_i};
  logic [8:0]    lt_lr, lt_rl;     // [3*pair + coordinate]: l.c < r.c, r.c < l.c
  logic [2:0]    s0q;              // s_i: lexmin_first picked l
  logic [17:0]   unused_cmp_valid;
  logic [18*W-1:0] cmp_y;
  logic [89:0]   unused_cmp_flags;
  for (genvar i = 0; i < 3; i++) begin : gen_lex
    for (genvar c = 0; c < 3; c++) begin : gen_coord
      localparam int unsigned K = 3 * i + c;
      ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(0)), .Subnormals(Subnormals)) u_lt (
        .clk_i, .rst_ni, .in_valid_i(in_valid_i),
        .a_i(lex_l[i*V3+c*W+:W]), .b_i(lex_r[i*V3+c*W+:W]), .op_i(3'd0),
        .out_valid_o(unused_cmp_valid[2*K]), .y_o(cmp_y[2*K*W+:W]),
        .flags_o(unused_cmp_flags[10*K+:5]));
      ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(0)), .Subnormals(Subnormals)) u_gt (
        .clk_i, .rst_ni, .in_valid_i(in_valid_i),
        .a_i(lex_r[i*V3+c*W+:W]), .b_i(lex_l[i*V3+c*W+:W]), .op_i(3'd0),
        .out_valid_o(unused_cmp_valid[2*K+1]), .y_o(cmp_y[(2*K+1)*W+:W]),
        .flags_o(unused_cmp_flags[10*K+5+:5]));
      assign lt_lr[K] = cmp_y[2*K*W];
      assign lt_rl[K] = cmp_y[(2*K+1)*W];
      logic [2*W-3:0] unused_cmp_hi;
      assign unused_cmp_hi = {cmp_y[2*K*W+1+:W-1], cmp_y[(2*K+1)*W+1+:W-1]};
    end
    assign s0q[i] = lt_lr[3*i] | (~lt_rl[3*i] & (lt_lr[3*i+1] | (~lt_rl[3*i+1] &
                    (lt_lr[3*i+2] | ~lt_rl[3*i+2]))));
  end

  // d, t_min, t_max wait for L0
  logic [V3-1:0] d1;
  ru_pipe #(.Width(V3), .Depth(lat(0))) u_wait0_d (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[0]), .data_i(d_i), .data_o(d1));

  // ---- L1, L2: cross products ---------------------------------------------------------------
  logic [V3-1:0] am0, am1, am2;
  assign am0 = s0q[0] ? ap1 : ap2;  // a - min(p1, p2)
  assign am1 = s0q[1] ? ap2 : ap0;  // a - min(p2, p0)
  assign am2 = s0q[2] ? ap0 : ap1;  // a - min(p0, p1)

  logic [V3-1:0] c0, c1, c2, nrm;
  logic [3:0]    v2;
  ru_ray_tri_cross #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                     .MulStages(lat(1)), .MulCuts(lcut(1)), .SubStages(lat(2)), .SubCuts(lcut(2))) u_c0 (
    .clk_i, .rst_ni, .valid_i(v0[0]), .u_i(am0), .v_i(d1), .valid_o(v2[0]), .y_o(c0));
  ru_ray_tri_cross #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                     .MulStages(lat(1)), .MulCuts(lcut(1)), .SubStages(lat(2)), .SubCuts(lcut(2))) u_c1 (
    .clk_i, .rst_ni, .valid_i(v0[0]), .u_i(am1), .v_i(d1), .valid_o(v2[1]), .y_o(c1));
  ru_ray_tri_cross #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                     .MulStages(lat(1)), .MulCuts(lcut(1)), .SubStages(lat(2)), .SubCuts(lcut(2))) u_c2 (
    .clk_i, .rst_ni, .valid_i(v0[0]), .u_i(am2), .v_i(d1), .valid_o(v2[2]), .y_o(c2));
  ru_ray_tri_cross #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                     .MulStages(lat(1)), .MulCuts(lcut(1)), .SubStages(lat(2)), .SubCuts(lcut(2))) u_n (
    .clk_i, .rst_ni, .valid_i(v0[0]), .u_i(e1), .v_i(e0), .valid_o(v2[3]), .y_o(nrm));

  // e0..e2, p2 - a, d wait for L1 + L2; the lexmin bits and t_min/t_max wait longer
  logic [V3-1:0] e0_2, e1_2, e2_2, p2a_2, d_2;
  ru_pipe #(.Width(V3), .Depth(span(1, 3))) u_wait12_e0 (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[1]), .data_i(e0), .data_o(e0_2));
  ru_pipe #(.Width(V3), .Depth(span(1, 3))) u_wait12_e1 (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[2]), .data_i(e1), .data_o(e1_2));
  ru_pipe #(.Width(V3), .Depth(span(1, 3))) u_wait12_e2 (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[3]), .data_i(e2), .data_o(e2_2));
  ru_pipe #(.Width(V3), .Depth(span(1, 3))) u_wait12_pa (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[4]), .data_i(p2a), .data_o(p2a_2));
  ru_pipe #(.Width(V3), .Depth(span(1, 3))) u_wait12_d (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[5]), .data_i(d1), .data_o(d_2));
  // t_min, t_max wait for L0..L6 (L0..L7 with OptRecip)
  logic [W-1:0] tmin7, tmax7;
  ru_pipe #(.Width(W), .Depth(span(0, LCmp))) u_wait_tmin (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[6]), .data_i(tmin_i), .data_o(tmin7));
  ru_pipe #(.Width(W), .Depth(span(0, LCmp))) u_wait_tmax (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[7]), .data_i(tmax_i), .data_o(tmax7));

  // ---- L3..L5: the five volumes --------------------------------------------------------------
  logic [W-1:0] vol_v, vol_va, vol_v0, vol_v1, vol_v2;
  logic [4:0]   v5;
  logic [24:0] unused_dot_flags;  // the volumes' flags are not outputs of the unit
  ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                   .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                   .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_dv0 (
    .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(c0), .v_i(e0_2), .valid_o(v5[0]), .y_o(vol_v0),
    .flags_o(unused_dot_flags[0*5+:5]));
  ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                   .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                   .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_dv1 (
    .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(c1), .v_i(e1_2), .valid_o(v5[1]), .y_o(vol_v1),
    .flags_o(unused_dot_flags[1*5+:5]));
  ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                   .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                   .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_dv2 (
    .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(c2), .v_i(e2_2), .valid_o(v5[2]), .y_o(vol_v2),
    .flags_o(unused_dot_flags[2*5+:5]));
  ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                   .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                   .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_dv (
    .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(nrm), .v_i(d_2), .valid_o(v5[3]), .y_o(vol_v),
    .flags_o(unused_dot_flags[3*5+:5]));
  ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                   .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                   .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_dva (
    .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(nrm), .v_i(p2a_2), .valid_o(v5[4]), .y_o(vol_va),
    .flags_o(unused_dot_flags[4*5+:5]));

  // ---- L6: divisions (OptRecip: one reciprocal, then L7 multiplications); beside them the
  // sign logic and |V| < eps ------------------------------------------------------------------
  logic [W-1:0] q_t, q_beta, q_gamma;
  logic [2:0]   v6;
  if (R == 0) begin : gen_div3
    logic [14:0]  unused_div_flags;
    ru_fp_div #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals), .Round(Round),
                .CutSel(lcut(6))) u_div_t (
      .clk_i, .rst_ni, .in_valid_i(v5[0]), .a_i(vol_va), .b_i(vol_v),
      .out_valid_o(v6[0]), .y_o(q_t), .flags_o(unused_div_flags[0+:5]));
    ru_fp_div #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals), .Round(Round),
                .CutSel(lcut(6))) u_div_beta (
      .clk_i, .rst_ni, .in_valid_i(v5[0]), .a_i(vol_v1), .b_i(vol_v),
      .out_valid_o(v6[1]), .y_o(q_beta), .flags_o(unused_div_flags[5+:5]));
    ru_fp_div #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals), .Round(Round),
                .CutSel(lcut(6))) u_div_gamma (
      .clk_i, .rst_ni, .in_valid_i(v5[0]), .a_i(vol_v2), .b_i(vol_v),
      .out_valid_o(v6[2]), .y_o(q_gamma), .flags_o(unused_div_flags[10+:5]));
    assign unused_dly_valid[16:15] = 2'b0;
  end else begin : gen_recip
    localparam logic [W-1:0] One = {2'b00, {(ExpW - 1){1'b1}}, {FracW{1'b0}}};  // 1.0
    logic [W-1:0]  rcp;
    logic          v6r;
    logic [19:0]   unused_rcp_flags;
    logic [W-1:0]  va7, v17, v27;
    ru_fp_div #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals), .Round(Round),
                .CutSel(lcut(6))) u_rcp (
      .clk_i, .rst_ni, .in_valid_i(v5[0]), .a_i(One), .b_i(vol_v),
      .out_valid_o(v6r), .y_o(rcp), .flags_o(unused_rcp_flags[0+:5]));
    ru_pipe #(.Width(2 * W), .Depth(lat(6))) u_wait6_v (
      .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[15]), .data_i({vol_v1, vol_v2}),
      .data_o({v17, v27}));
    ru_pipe #(.Width(W), .Depth(lat(6))) u_wait6_va (
      .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[16]), .data_i(vol_va), .data_o(va7));
    ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(7)), .Subnormals(Subnormals), .Round(Round),
                .CutSel(lcut(7))) u_mul_t (
      .clk_i, .rst_ni, .in_valid_i(v6r), .a_i(va7), .b_i(rcp),
      .out_valid_o(v6[0]), .y_o(q_t), .flags_o(unused_rcp_flags[5+:5]));
    ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(7)), .Subnormals(Subnormals), .Round(Round),
                .CutSel(lcut(7))) u_mul_beta (
      .clk_i, .rst_ni, .in_valid_i(v6r), .a_i(v17), .b_i(rcp),
      .out_valid_o(v6[1]), .y_o(q_beta), .flags_o(unused_rcp_flags[10+:5]));
    ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(7)), .Subnormals(Subnormals), .Round(Round),
                .CutSel(lcut(7))) u_mul_gamma (
      .clk_i, .rst_ni, .in_valid_i(v6r), .a_i(v27), .b_i(rcp),
      .out_valid_o(v6[2]), .y_o(q_gamma), .flags_o(unused_rcp_flags[15+:5]));
  end

  // Sign tests of V0..V2 against +0 (bit tests, see the header).
  function automatic logic f_nan(input logic [W-2:0] x);  // magnitude bits
    f_nan = (&x[W-2:FracW]) & (|x[FracW-1:0]);
  endfunction
  function automatic logic f_zero(input logic [W-2:0] x);
    f_zero = ~|x;
  endfunction
  logic [2:0] vneg, vpos, vzero;
  always_comb begin
    vneg[0] = vol_v0[W-1] & ~f_zero(vol_v0[W-2:0]) & ~f_nan(vol_v0[W-2:0]);
    vneg[1] = vol_v1[W-1] & ~f_zero(vol_v1[W-2:0]) & ~f_nan(vol_v1[W-2:0]);
    vneg[2] = vol_v2[W-1] & ~f_zero(vol_v2[W-2:0]) & ~f_nan(vol_v2[W-2:0]);
    vpos[0] = ~vol_v0[W-1] & ~f_zero(vol_v0[W-2:0]) & ~f_nan(vol_v0[W-2:0]);
    vpos[1] = ~vol_v1[W-1] & ~f_zero(vol_v1[W-2:0]) & ~f_nan(vol_v1[W-2:0]);
    vpos[2] = ~vol_v2[W-1] & ~f_zero(vol_v2[W-2:0]) & ~f_nan(vol_v2[W-2:0]);
    vzero[0] = f_zero(vol_v0[W-2:0]);
    vzero[1] = f_zero(vol_v1[W-2:0]);
    vzero[2] = f_zero(vol_v2[W-2:0]);
  end
  logic mixed5, tie5;
  assign mixed5 = (|vneg) & (|vpos);
  if (OptTieBreak != 0) begin : gen_tie
    logic [2:0] s5;  // lexmin bits at the input of L6
    ru_pipe #(.Width(3), .Depth(span(1, 6))) u_wait_s (
      .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[8]), .data_i(s0q), .data_o(s5));
    assign tie5 = |(vzero & s5);
  end else begin : gen_no_tie
    assign tie5 = 1'b0;
    logic [2:0] unused_vzero;
    assign unused_vzero = vzero;
  end

  logic small6;
  if (OptEpsTest != 0) begin : gen_eps
    logic [W-1:0] lt_y;
    logic [4:0]   unused_eps_flags;
    logic         unused_eps_valid;
    ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals)) u_eps (
      .clk_i, .rst_ni, .in_valid_i(v5[0]),
      .a_i({1'b0, vol_v[W-2:0]}), .b_i(Eps), .op_i(3'd0),
      .out_valid_o(unused_eps_valid), .y_o(lt_y), .flags_o(unused_eps_flags));
    if (R != 0) begin : gen_eps_wait
      logic unused_eps_dly_valid;
      ru_pipe #(.Width(1), .Depth(lat(7))) u_wait_eps (
        .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_eps_dly_valid), .data_i(lt_y[0]), .data_o(small6));
    end else begin : gen_eps_now
      assign small6 = lt_y[0];
    end
    logic [W-2:0] unused_eps_hi;
    assign unused_eps_hi = lt_y[W-1:1];
  end else begin : gen_no_eps
    assign small6 = 1'b0;
  end

  logic mixed6, tie6;
  ru_pipe #(.Width(2), .Depth(span(6, LCmp))) u_wait6 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[9]), .data_i({mixed5, tie5}), .data_o({mixed6, tie6}));

  // ---- L7 (L8 with OptRecip): t_min < t < t_max -----------------------------------------------
  logic [W-1:0] lo_y, hi_y;
  logic [9:0]   unused_iv_flags;
  logic         unused_iv_valid;
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(LCmp)), .Subnormals(Subnormals), .CutSel(lcut(LCmp))) u_lo (
    .clk_i, .rst_ni, .in_valid_i(v6[0]), .a_i(tmin7), .b_i(q_t), .op_i(3'd0),
    .out_valid_o(out_valid_o), .y_o(lo_y), .flags_o(unused_iv_flags[0+:5]));
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(LCmp)), .Subnormals(Subnormals), .CutSel(lcut(LCmp))) u_hi (
    .clk_i, .rst_ni, .in_valid_i(v6[0]), .a_i(q_t), .b_i(tmax7), .op_i(3'd0),
    .out_valid_o(unused_iv_valid), .y_o(hi_y), .flags_o(unused_iv_flags[5+:5]));
  logic [2*W-3:0] unused_iv_hi;
  assign unused_iv_hi = {lo_y[W-1:1], hi_y[W-1:1]};

  logic mixed7, tie7, small7;
  ru_pipe #(.Width(3), .Depth(lat(LCmp))) u_wait7 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[10]), .data_i({mixed6, tie6, small6}), .data_o({mixed7, tie7, small7}));
  ru_pipe #(.Width(W), .Depth(lat(LCmp))) u_wait7_t (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[11]), .data_i(q_t), .data_o(t_o));
  ru_pipe #(.Width(W), .Depth(lat(LCmp))) u_wait7_b (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[12]), .data_i(q_beta), .data_o(beta_o));
  ru_pipe #(.Width(W), .Depth(lat(LCmp))) u_wait7_g (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[13]), .data_i(q_gamma), .data_o(gamma_o));

  // diagnostics: the volumes wait for L6 and L7
  if (OptVolOut != 0) begin : gen_vol
    logic [5*W-1:0] vols;
    assign vols = {vol_v2, vol_v1, vol_v0, vol_va, vol_v};
    ru_pipe #(.Width(5 * W), .Depth(span(6, NLev))) u_wait_vol (
      .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[14]), .data_i(vols), .data_o(vol_o));
  end else begin : gen_no_vol
    assign vol_o = '0;
  end

  logic in_range;
  assign in_range = lo_y[0] & hi_y[0];
  always_comb begin
    if (mixed7) why_o = 3'd1;
    else if (tie7) why_o = 3'd2;
    else if (small7) why_o = 3'd3;
    else if (!in_range) why_o = 3'd4;
    else why_o = 3'd0;
  end
  assign hit_o = (why_o == 3'd0);

  logic unused_valid;
  assign unused_valid = ^{v0[6:1], v2[3:1], v5[4:1], v6[2:1]};

endmodule
