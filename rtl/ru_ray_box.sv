// ru_ray_box: ray-box slab test (Williams et al., Mirth's ray_box_int; dissertation §2.1), bit
// for bit the golden model ru::units::ray_box<Soft> (model/include/rayunits/units/ray_box.hpp;
// the dataflow contract is docs/UNITS.md).
//
// Ports (W = 1+ExpW+FracW; vectors packed {z, y, x}, x in the low W bits):
//   org_i [3W] ray origin o; rdir_i [3W] reciprocal direction inv = 1/d (+-INF for d_k = 0);
//   tmin_i, tmax_i [W] the ray interval; bmin_i, bmax_i [3W] the box [lo, hi];
//   hit_o      t_enter <= t_exit, t_enter != +INF, t_exit != -INF and no input is a NaN;
//   t_enter_o  maxNum(t_min, tn_x, tn_y, tn_z);  t_exit_o  minNum(t_max, tf_x, tf_y, tf_z)
//              (every input, hit or not; a NaN slab bound (0*INF: the origin on a slab plane
//              of a ray parallel to it) is ignored by minNum/maxNum).
// Parameters: ExpW, FracW, Subnormals, Round (the format); Stages (latency, registers placed
// by ru_pipe_pkg on the chain add - mul - cmp - cmp - cmp); OptConservative (0, 1, 2):
//   0  plain:  tn_k = (near_k - o_k) * inv_k, tf_k = (far_k - o_k) * inv_k, rounded with Round;
//   1  conservative (never misses a box the exact slab test hits):
//        dn_k = (near_k - o_k) rounded RUP if inv_k < 0 else RDN,  tn_k = RDN(dn_k * inv_k)
//        df_k = (far_k  - o_k) rounded RDN if inv_k < 0 else RUP,  tf_k = RUP(df_k * inv_k)
//      with near_k = inv_k < 0 ? hi_k : lo_k, far_k the other plane. The rounding direction of
//      a subtraction depends on the data, so each subtracter has a fixed direction and the
//      operands are swapped instead: RUP(x - y) = -RDN(y - x) bit for bit for every non-NaN
//      result (zeros included: an exact zero is +0 under RUP and -0 under RDN; flushed or
//      rounded results are symmetric), so
//        dn_k = inv_k < 0 ? -RDN(o_k - hi_k) : RDN(lo_k - o_k)     (one RDN subtracter)
//        df_k = inv_k < 0 ? -RUP(o_k - lo_k) : RUP(hi_k - o_k)     (one RUP subtracter)
//      (a NaN result is not negated: it stays the canonical NaN). Flush-to-zero formats
//      (Subnormals = 0): a directed result flushed to a zero on the wrong side (underflow flag,
//      zero result, -0 from RDN / +0 from RUP) is replaced by the smallest normal of its sign
//      (ru::units::ftz_bound); with subnormals such a result cannot occur, so no logic is built.
//   2  d-conservative (issue 14 section 4; never misses a box that the exact slab test hits
//      for the ray direction d itself, when rdir_i = RNE(1/d) in the format): as 1, but the
//      true 1/d is only known to lie in [a_k, b_k] = inv_k's neighbours in the format, clamped
//      at inv_k's zero and at infinity (ru::units::reciprocal_bounds), and each product takes
//      the end that gives its bound:
//        tn_k = RDN(dn_k * (dn_k < 0 ? b_k : a_k)),  tf_k = RUP(df_k * (df_k < 0 ? a_k : b_k))
//      (the sign bit of the difference selects; a zero difference takes the end away from zero,
//      b_k for inv_k > 0 and a_k for inv_k < 0, so that 0*INF stays the NaN every mode ignores). a_k, b_k are an incrementer and a decrementer
//      on inv_k's magnitude, computed beside the subtracters (off their path); the cost is the
//      two incrementers, the second operand register of each multiplier pair and a mux.
// Fully pipelined: one test per cycle, out_valid_o = in_valid_i delayed by Stages cycles.
//
// Dataflow in 5 levels (6 sub, 6 mul, 7 compares):
//   L0 add  the six slab-plane differences
//   L1 mul  the six slab bounds tn_k, tf_k
//   L2 cmp  max(tn_x, tn_y), max(tn_z, t_min), min(tf_x, tf_y), min(tf_z, t_max)
//   L3 cmp  t_enter = max(..), t_exit = min(..)
//   L4 cmp  le(t_enter, t_exit); then hit (gates: the INF tests and the NaN-input test are bit
//           tests)
// The model's chain max(max(max(t_min, tn_x), tn_y), tn_z) is evaluated as a tree: maxNum of
// the format is associative and commutative bit for bit (NaN operands ignored, both-NaN gives
// the canonical NaN, -0 < +0, equal non-zero values have equal bits, FTZ flushes every operand
// first), so the result is the same and one compare level shorter.
module ru_ray_box #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned OptConservative = 0
) (
  input  logic                        clk_i,
  input  logic                        rst_ni,
  input  logic                        in_valid_i,
  input  logic [3*(ExpW+FracW+1)-1:0] org_i,
  input  logic [3*(ExpW+FracW+1)-1:0] rdir_i,
  input  logic [ExpW+FracW:0]         tmin_i,
  input  logic [ExpW+FracW:0]         tmax_i,
  input  logic [3*(ExpW+FracW+1)-1:0] bmin_i,
  input  logic [3*(ExpW+FracW+1)-1:0] bmax_i,
  output logic                        out_valid_o,
  output logic                        hit_o,
  output logic [ExpW+FracW:0]         t_enter_o,
  output logic [ExpW+FracW:0]         t_exit_o
);

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam int unsigned V3 = 3 * W;
  localparam int unsigned RDN = 2;
  localparam int unsigned RUP = 3;
  localparam bit DCons = OptConservative == 2;
  localparam int unsigned RoundN = (OptConservative != 0) ? RDN : Round;  // tn_k side
  localparam int unsigned RoundF = (OptConservative != 0) ? RUP : Round;  // tf_k side
  localparam logic [W-1:0] PosInf = {1'b0, {ExpW{1'b1}}, {FracW{1'b0}}};
  localparam logic [W-1:0] NegInf = {1'b1, {ExpW{1'b1}}, {FracW{1'b0}}};

  // ---- register placement (ru_pipe_pkg) -----------------------------------------------
  localparam int unsigned NLev = 5;
  localparam logic [4*ru_pipe_pkg::MaxLev-1:0] Kinds = {44'd0, ru_fp_pkg::KCmp, ru_fp_pkg::KCmp,
      ru_fp_pkg::KCmp, ru_fp_pkg::KMul, ru_fp_pkg::KAdd};
  `include "ru_level_chain.svh"
  // data-only delay lines (ru_pipe; the level instances carry the valid bits)
  logic [3:0] unused_dly_valid;

  function automatic logic f_nan(input logic [W-2:0] x);  // magnitude bits
    f_nan = (&x[W-2:FracW]) & (|x[FracW-1:0]);
  endfunction
  // Flush-to-zero bound fix-up of a directed result (see the header).
  function automatic logic [W-1:0] f_ftz_bound(input logic [W-1:0] x, input logic uf,
                                               input logic neg_zero_wrong);
    if (uf && (x[W-2:0] == '0) && (x[W-1] == neg_zero_wrong))
      f_ftz_bound = {x[W-1], {(ExpW - 1){1'b0}}, 1'b1, {FracW{1'b0}}};
    else f_ftz_bound = x;
  endfunction

  // ---- any NaN input (bit tests) --------------------------------------------------------------
  logic any_nan0;
  always_comb begin
    any_nan0 = f_nan(tmin_i[W-2:0]) | f_nan(tmax_i[W-2:0]);
    for (int unsigned k = 0; k < 3; k++)
      any_nan0 = any_nan0 | f_nan(org_i[k*W+:W-1]) | f_nan(rdir_i[k*W+:W-1]) |
                 f_nan(bmin_i[k*W+:W-1]) | f_nan(bmax_i[k*W+:W-1]);
  end

  // ---- L0: slab-plane differences -------------------------------------------------------------
  logic [2:0]    neg0;  // sign of inv_k
  logic [V3-1:0] xn, yn, xf, yf;  // operands of the near and far subtracters
  always_comb begin
    for (int unsigned k = 0; k < 3; k++) begin
      neg0[k] = rdir_i[k*W+W-1];
      if (OptConservative != 0) begin
        // dn: RDN(lo - o) or RDN(o - hi) (negated later); df: RUP(hi - o) or RUP(o - lo)
        xn[k*W+:W] = neg0[k] ? org_i[k*W+:W] : bmin_i[k*W+:W];
        yn[k*W+:W] = neg0[k] ? bmax_i[k*W+:W] : org_i[k*W+:W];
        xf[k*W+:W] = neg0[k] ? org_i[k*W+:W] : bmax_i[k*W+:W];
        yf[k*W+:W] = neg0[k] ? bmin_i[k*W+:W] : org_i[k*W+:W];
      end else begin
        // near - o, far - o
        xn[k*W+:W] = neg0[k] ? bmax_i[k*W+:W] : bmin_i[k*W+:W];
        yn[k*W+:W] = org_i[k*W+:W];
        xf[k*W+:W] = neg0[k] ? bmin_i[k*W+:W] : bmax_i[k*W+:W];
        yf[k*W+:W] = org_i[k*W+:W];
      end
    end
  end

  logic [V3-1:0] dn_r, df_r;
  logic [14:0]   dn_fl, df_fl;
  logic [5:0]    v0;
  for (genvar k = 0; k < 3; k++) begin : gen_sub
    ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(0)), .Subnormals(Subnormals),
                .Round(RoundN), .CutSel(lcut(0))) u_sub_n (
      .clk_i, .rst_ni, .in_valid_i, .a_i(xn[k*W+:W]), .b_i(yn[k*W+:W]), .op_i(1'b1),
      .out_valid_o(v0[2*k]), .y_o(dn_r[k*W+:W]), .flags_o(dn_fl[k*5+:5]));
    ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(0)), .Subnormals(Subnormals),
                .Round(RoundF), .CutSel(lcut(0))) u_sub_f (
      .clk_i, .rst_ni, .in_valid_i, .a_i(xf[k*W+:W]), .b_i(yf[k*W+:W]), .op_i(1'b1),
      .out_valid_o(v0[2*k+1]), .y_o(df_r[k*W+:W]), .flags_o(df_fl[k*5+:5]));
  end
  // reciprocal bounds [a_k, b_k] of 1/d (OptConservative 2): magnitudes one step away from and
  // towards zero in the format, clamped at zero and infinity (a NaN gives itself twice; it
  // already makes the result a miss).
  localparam logic [W-2:0] MagInf = {{ExpW{1'b1}}, {FracW{1'b0}}};
  localparam logic [W-2:0] MagMinN = {{(ExpW - 1){1'b0}}, 1'b1, {FracW{1'b0}}};
  logic [V3-1:0] ra0, rb0;
  always_comb begin
    for (int unsigned k = 0; k < 3; k++) begin
      logic [W-2:0] mag, away, toward;
      mag = rdir_i[k*W+:W-1];
      if (mag == MagInf || f_nan(mag)) away = mag;
      else if (mag == '0 && Subnormals == 0) away = MagMinN;
      else away = mag + 1'b1;
      if (f_nan(mag)) toward = mag;
      else if (mag == '0 || (mag == MagMinN && Subnormals == 0)) toward = '0;
      else toward = mag - 1'b1;
      ra0[k*W+:W] = {neg0[k], neg0[k] ? away : toward};
      rb0[k*W+:W] = {neg0[k], neg0[k] ? toward : away};
    end
  end

  logic [V3-1:0] ra1, rb1;
  logic [2:0]    neg1;
  if (DCons) begin : gen_wait0_d
    ru_pipe #(.Width(2 * V3 + 3), .Depth(lat(0))) u_wait0 (
      .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[0]), .data_i({ra0, rb0, neg0}),
      .data_o({ra1, rb1, neg1}));
  end else begin : gen_wait0
    ru_pipe #(.Width(V3 + 3), .Depth(lat(0))) u_wait0 (
      .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[0]), .data_i({rdir_i, neg0}),
      .data_o({ra1, neg1}));
    assign rb1 = ra1;
    logic unused_rab0;
    assign unused_rab0 = ^{ra0, rb0};
  end

  // ---- L1: slab bounds --------------------------------------------------------------------------
  logic [V3-1:0] dn, df, rn, rf;  // multiplier operands
  always_comb begin
    for (int unsigned k = 0; k < 3; k++) begin
      dn[k*W+:W] = dn_r[k*W+:W];
      df[k*W+:W] = df_r[k*W+:W];
      if (OptConservative != 0) begin
        if (Subnormals == 0) begin
          dn[k*W+:W] = f_ftz_bound(dn[k*W+:W], dn_fl[k*5+1], 1'b1);
          df[k*W+:W] = f_ftz_bound(df[k*W+:W], df_fl[k*5+1], 1'b0);
        end
        if (neg1[k] && !f_nan(dn[k*W+:W-1])) dn[k*W+W-1] = ~dn[k*W+W-1];
        if (neg1[k] && !f_nan(df[k*W+:W-1])) df[k*W+W-1] = ~df[k*W+W-1];
      end
      // plain and conservative: ra1 = rb1 = inv. A zero difference takes the end away from
      // zero (inv's sign: a for inv < 0, b for inv > 0), so that 0*INF stays a NaN.
      if (dn[k*W+:W-1] == '0) rn[k*W+:W] = neg1[k] ? ra1[k*W+:W] : rb1[k*W+:W];
      else rn[k*W+:W] = dn[k*W+W-1] ? rb1[k*W+:W] : ra1[k*W+:W];
      if (df[k*W+:W-1] == '0) rf[k*W+:W] = neg1[k] ? ra1[k*W+:W] : rb1[k*W+:W];
      else rf[k*W+:W] = df[k*W+W-1] ? ra1[k*W+:W] : rb1[k*W+:W];
    end
  end

  logic [V3-1:0] tn_r, tf_r;
  logic [14:0]   tn_fl, tf_fl;
  logic [5:0]    v1;
  for (genvar k = 0; k < 3; k++) begin : gen_mul
    ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(1)), .Subnormals(Subnormals),
                .Round(RoundN), .CutSel(lcut(1))) u_mul_n (
      .clk_i, .rst_ni, .in_valid_i(v0[0]), .a_i(dn[k*W+:W]), .b_i(rn[k*W+:W]),
      .out_valid_o(v1[2*k]), .y_o(tn_r[k*W+:W]), .flags_o(tn_fl[k*5+:5]));
    ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(1)), .Subnormals(Subnormals),
                .Round(RoundF), .CutSel(lcut(1))) u_mul_f (
      .clk_i, .rst_ni, .in_valid_i(v0[0]), .a_i(df[k*W+:W]), .b_i(rf[k*W+:W]),
      .out_valid_o(v1[2*k+1]), .y_o(tf_r[k*W+:W]), .flags_o(tf_fl[k*5+:5]));
  end
  logic [W-1:0] tmin2, tmax2;
  ru_pipe #(.Width(2 * W), .Depth(span(0, 2))) u_wait01 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[1]), .data_i({tmin_i, tmax_i}), .data_o({tmin2, tmax2}));

  logic [V3-1:0] tn, tf;
  always_comb begin
    for (int unsigned k = 0; k < 3; k++) begin
      tn[k*W+:W] = tn_r[k*W+:W];
      tf[k*W+:W] = tf_r[k*W+:W];
      if (OptConservative != 0 && Subnormals == 0) begin
        tn[k*W+:W] = f_ftz_bound(tn[k*W+:W], tn_fl[k*5+1], 1'b1);
        tf[k*W+:W] = f_ftz_bound(tf[k*W+:W], tf_fl[k*5+1], 1'b0);
      end
    end
  end
  logic unused_flags;
  assign unused_flags = ^{dn_fl, df_fl, tn_fl, tf_fl};

  // ---- L2, L3: t_enter, t_exit ------------------------------------------------------------------
  logic [4*W-1:0] ca, cb, cy;
  logic [11:0]    cop;
  logic [3:0]     v2;
  logic [19:0]    unused_c2_flags;
  assign ca = {tf[2*W+:W], tf[0+:W], tn[2*W+:W], tn[0+:W]};
  assign cb = {tmax2, tf[W+:W], tmin2, tn[W+:W]};
  assign cop = {3'd3, 3'd3, 3'd4, 3'd4};  // max, max, min, min
  for (genvar i = 0; i < 4; i++) begin : gen_c2
    ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(2)), .Subnormals(Subnormals), .CutSel(lcut(2)))
        u_cmp (
      .clk_i, .rst_ni, .in_valid_i(v1[0]), .a_i(ca[i*W+:W]), .b_i(cb[i*W+:W]),
      .op_i(cop[i*3+:3]), .out_valid_o(v2[i]), .y_o(cy[i*W+:W]),
      .flags_o(unused_c2_flags[i*5+:5]));
  end

  logic [W-1:0] t_enter, t_exit;
  logic [1:0]   v3;
  logic [9:0]   unused_c3_flags;
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(3)), .Subnormals(Subnormals), .CutSel(lcut(3)))
      u_enter (
    .clk_i, .rst_ni, .in_valid_i(v2[0]), .a_i(cy[0+:W]), .b_i(cy[W+:W]), .op_i(3'd4),
    .out_valid_o(v3[0]), .y_o(t_enter), .flags_o(unused_c3_flags[0+:5]));
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(3)), .Subnormals(Subnormals), .CutSel(lcut(3)))
      u_exit (
    .clk_i, .rst_ni, .in_valid_i(v2[0]), .a_i(cy[2*W+:W]), .b_i(cy[3*W+:W]), .op_i(3'd3),
    .out_valid_o(v3[1]), .y_o(t_exit), .flags_o(unused_c3_flags[5+:5]));

  // ---- L4: t_enter <= t_exit, hit -------------------------------------------------------------
  logic [W-1:0] le_y;
  logic [4:0]   unused_le_flags;
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(4)), .Subnormals(Subnormals), .CutSel(lcut(4)))
      u_le (
    .clk_i, .rst_ni, .in_valid_i(v3[0]), .a_i(t_enter), .b_i(t_exit), .op_i(3'd1),
    .out_valid_o, .y_o(le_y), .flags_o(unused_le_flags));

  logic any_nan3, any_nan4, inf_ok3, inf_ok4;
  ru_pipe #(.Width(1), .Depth(span(0, 4))) u_wait_nan (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[2]), .data_i(any_nan0), .data_o(any_nan3));
  assign inf_ok3 = (t_enter != PosInf) && (t_exit != NegInf);
  ru_pipe #(.Width(2 + 2 * W), .Depth(lat(4))) u_wait4 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[3]), .data_i({any_nan3, inf_ok3, t_enter, t_exit}),
    .data_o({any_nan4, inf_ok4, t_enter_o, t_exit_o}));
  assign hit_o = le_y[0] & inf_ok4 & ~any_nan4;

  logic unused_misc;
  assign unused_misc = ^{v0[5:1], v1[5:1], v2[3:1], v3[1], le_y[W-1:1], unused_c2_flags,
                         unused_c3_flags, unused_le_flags};

endmodule
