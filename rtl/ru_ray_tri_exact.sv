// ru_ray_tri_exact: the exactly-once watertight ray-triangle unit (issue 14 section 1), bit for
// bit and cycle for cycle the golden model ru::units::ray_tri_exact<Soft> with
// ExactFilter::PermanentFormat (model/include/rayunits/units/ray_tri_exact.hpp, docs/UNITS.md
// "Exactly-once triangles"):
//   hit_o   the exact decision for the symbolically perturbed ray a + (eps, eps^2, eps^3): the
//           three perturbed edge signs agree and t_min < Va/V < t_max exactly;
//   why_o   0 hit, 1 sign (edge signs do not agree, or a non-finite operand), 4 interval;
//   t_o, beta_o, gamma_o   ray_tri_robust's (Fig. 3.6, three divisions), bit for bit;
//   slow_o  the exact side path took part in the decision (diagnostics, statistics).
// Ports as ru_ray_tri_robust (vectors packed {z, y, x}) plus in_ready_o: a test is accepted in a
// cycle with in_valid_i && in_ready_o.
//
// Structure:
//  * The fast pipeline (Stages registers placed over a chain of 12 FP levels by ru_pipe_pkg, the
//    project's one placement mechanism): ru_ray_tri_robust's volumes (same operations, same
//    order) and beside them the permanents P_k = (|l_x|+|r_x|)|z_x| + ... (the cross products'
//    products shared), the OR of the underflow flags of every operation of a volume and of its
//    permanent (tiny), the divisions, and the interval bound in format arithmetic with directed
//    rounding (exact_detail::fast_interval_format; powers of two by exponent addition):
//      L0 add   e0..e2, a - p0..p2, p2 - a (21 sub); lexicographic order (18 cmp)
//      L1 mul   4 cross products (24 mul)
//      L2 add   their differences and the permanents' sums (24 add)
//      L3 mul   5 volumes and 5 permanents (ru_fp_dot3_core, 30 mul, 20 add over L3..L5)
//      L4 add
//      L5 add
//      L6 div   t, beta, gamma (3 div); beside: certification |V| > 2^K7 P (exponent-shifted
//               comparisons), BV = PV 2^K7, Ba = Pa 2^K8, 2 BV < |V|
//      L7 mul   tq = RUP(|t| (1 + 2u)); D_lo = RTZ(t - t_min), D_hi = RTZ(t_max - t)
//      L8 mul   RUP(tq BV), RUP(tq |V|), RTZ(|D_lo| |V|), RTZ(|D_hi| |V|)
//      L9 add   RUP(Ba + tq BV)
//      L10 add  R = RUP(2 (..) + u RUP(tq |V|)) (for |t| < minnorm: + 2 minnorm |V|)
//      L11 cmp  R < RTZ(|D| |V|) for each bound; then the decision
//    An edge is certified when no operation of its volume/permanent underflowed and
//    |V_k| > 2^K7 P_k; the interval when V is certified and R decides both bounds.
//  * Undecided tests (an uncertain edge while the certified ones do not already disagree, or an
//    uncertain interval) go to ru_exact_path, one request at a time: the uncertain edges in
//    order 0, 1, 2 (stopping as soon as the known signs disagree), then the interval if the
//    signs agree and it is uncertain. Results leave in order.
//  * Order and flow control: a buffer of Cap = Stages + 1 + Slack entries holds the operands of
//    every accepted test until it leaves (written when accepted) and the fast-path state of every
//    test that reached the end of the pipeline while an older one is still waiting (written on
//    arrival, updated by the side path's results). in_ready_o = (tests accepted and not yet
//    output) < Cap: at most Cap tests are ever inside, so nothing is lost, and a decided test
//    flows at one per cycle with latency Stages (Cap > Stages).
// Timing (checked cycle by cycle by tb/exact against a C++ replay of these rules, exact_once_rtl_test):
//  * a test accepted in cycle c reaches the end of the pipeline in cycle c + Stages;
//  * there, if it is the oldest test inside and decided, out_valid_o is high in that cycle;
//    otherwise it is stored;
//  * a stored oldest test, in each cycle with no side-path request outstanding: if decided, it
//    leaves (out_valid_o); else its next request is issued to ru_exact_path (accepted at once:
//    the side path is idle). The side path's result (out_valid_o of ru_exact_path, its latency
//    formula in rtl/ru_exact_path.sv) updates the stored state at the end of that cycle; the test
//    is looked at again in the next cycle;
//  * one test leaves per cycle at most.
//
// Parameters: ExpW (2..8), FracW (1..23; 2.. with directed Round), Subnormals, Round (the format;
//   the unit's own operations round with Round, the interval bound with RUP/RTZ), Stages,
//   DigitW (ru_exact_path's multiplier digit), Slack (buffer entries beyond Stages + 1: the
//   pipeline keeps accepting while the side path works), Plant (tests only: 1 shrinks the edge
//   bound 2^K7 by 2^-8, wrong signs certified; 2 issues every uncertain edge, not stopping when
//   the known signs disagree: same results, other timing).
// Non-finite operands (INF/NaN in a, d, p0..p2): miss, why 1 (decided on the fast path).
module ru_ray_tri_exact #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Stages = 0,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned Round = 0,
  parameter int unsigned DigitW = 16,
  parameter int unsigned Slack = 1,
  parameter int unsigned Plant = 0
) (
  input  logic                        clk_i,
  input  logic                        rst_ni,
  input  logic                        in_valid_i,
  output logic                        in_ready_o,
  input  logic [3*(ExpW+FracW+1)-1:0] a_i,
  input  logic [3*(ExpW+FracW+1)-1:0] d_i,
  input  logic [3*(ExpW+FracW+1)-1:0] p0_i,
  input  logic [3*(ExpW+FracW+1)-1:0] p1_i,
  input  logic [3*(ExpW+FracW+1)-1:0] p2_i,
  input  logic [ExpW+FracW:0]         tmin_i,
  input  logic [ExpW+FracW:0]         tmax_i,
  output logic                        out_valid_o,
  output logic                        hit_o,
  output logic [2:0]                  why_o,
  output logic [ExpW+FracW:0]         t_o,
  output logic [ExpW+FracW:0]         beta_o,
  output logic [ExpW+FracW:0]         gamma_o,
  output logic                        slow_o
);

  localparam int unsigned W = 1 + ExpW + FracW;
  localparam int unsigned V3 = 3 * W;
  localparam integer EMax = (1 << ExpW) - 1;  // exponent field of INF/NaN
  localparam int unsigned Bias = (1 << (ExpW - 1)) - 1;

  // ---- filter constants (exact_detail::bound_exp, unit_roundoff) ---------------------------------
  // u = 2^-Q; K7, K8: the smallest K with ((1+u)^n - 1)/(1-u)^n <= 2^K for n = 7, 8
  // (exact_detail::bound_exp), derived here from the same inequality in integers:
  // (2^q + 1)^n - 2^(qn) <= 2^K (2^q - 1)^n (a wrong constant changes which tests the fast path
  // decides, which the cycle-exact test sees).
  localparam integer Q = (Round == 0) ? FracW + 1 : FracW;
  function automatic integer kbound(input integer q, input integer n);
    logic [383:0] a, b, lhs;
    integer i, k;
    a = 384'd1;
    b = 384'd1;
    for (i = 0; i < n; i = i + 1) begin
      a = a * ((384'd1 << q) + 384'd1);
      b = b * ((384'd1 << q) - 384'd1);
    end
    lhs = a - (384'd1 << (q * n));
    for (k = -q - 8; k < 64 && ((k >= 0) ? (lhs > (b << k)) : ((lhs << (-k)) > b)); k = k + 1) begin
    end
    kbound = k;
  endfunction
  localparam integer K7 = kbound(Q, 7) - ((Plant == 1) ? 8 : 0);
  localparam integer K8 = kbound(Q, 8);
  localparam integer BiasI = (1 << (ExpW - 1)) - 1;
  localparam integer EMinP1 = 2 - BiasI;  // emin + 1
  localparam logic [W-1:0] One2u = {1'b0, ExpW'(Bias), FracW'(1) << (FracW - Q + 1)};  // 1 + 2u
  if (Q < 2) begin : gen_q_check
    $error("ru_ray_tri_exact: FracW %0d too small for Round %0d", FracW, Round);
  end

  // ---- value tests on bit patterns (whole patterns passed; the sign bit unused by some) ----------
  /* verilator lint_off UNUSEDSIGNAL */
  function automatic logic f_nonfin(input logic [W-1:0] x);
    f_nonfin = &x[W-2:FracW];
  endfunction
  function automatic logic f_nan(input logic [W-1:0] x);
    f_nan = (&x[W-2:FracW]) & (|x[FracW-1:0]);
  endfunction
  function automatic logic f_zero(input logic [W-1:0] x);
    f_zero = ~|x[W-2:0];
  endfunction
  function automatic logic [W-1:0] f_abs(input logic [W-1:0] x);
    f_abs = {1'b0, x[W-2:0]};
  endfunction
  function automatic logic [V3-1:0] f_vabs(input logic [V3-1:0] v);
    f_vabs = {f_abs(v[2*W+:W]), f_abs(v[W+:W]), f_abs(v[0+:W])};
  endfunction
  // exact_detail::certified: |v| > 2^k |p| on normal values; gives up (0) on subnormal/non-finite
  function automatic logic f_cert(input logic [W-1:0] v, input logic [W-1:0] p, input integer k);
    integer ev, ep;
    ev = {{(32-ExpW){1'b0}}, v[W-2:FracW]};
    ep = {{(32-ExpW){1'b0}}, p[W-2:FracW]};
    if (ev == 0 || ev == EMax) f_cert = 1'b0;
    else if (ep == EMax || (ep == 0 && p[FracW-1:0] != '0)) f_cert = 1'b0;
    else if (ep == 0) f_cert = 1'b1;
    else if (ev - ep != k) f_cert = (ev - ep > k);
    else f_cert = v[FracW-1:0] > p[FracW-1:0];
  endfunction
  // exact_detail::scale2: {gave up, x 2^k} by exponent addition (exact for +-0 and normal results)
  function automatic logic [W:0] f_s2(input logic [W-1:0] x, input integer k);
    integer e, e2;
    e = {{(32-ExpW){1'b0}}, x[W-2:FracW]};
    e2 = e + k;
    if (e == 0 && x[FracW-1:0] == '0) f_s2 = {1'b0, x};
    else if (e == 0 || e == EMax || e2 < 1 || e2 >= EMax) f_s2 = {1'b1, x};
    else f_s2 = {1'b0, x[W-1], ExpW'(e2), x[FracW-1:0]};
  endfunction
  /* verilator lint_on UNUSEDSIGNAL */

  // ---- register placement (ru_pipe_pkg) -----------------------------------------------------------
  localparam int unsigned NLev = 12;
  localparam logic [4*ru_pipe_pkg::MaxLev-1:0] Kinds = {16'd0,
      ru_fp_pkg::KCmp, ru_fp_pkg::KAdd, ru_fp_pkg::KAdd, ru_fp_pkg::KMul, ru_fp_pkg::KMul, ru_fp_pkg::KDiv,
      ru_fp_pkg::KAdd, ru_fp_pkg::KAdd, ru_fp_pkg::KMul, ru_fp_pkg::KAdd, ru_fp_pkg::KMul, ru_fp_pkg::KAdd};
  `include "ru_level_chain.svh"
  logic [23:0] unused_dly_valid;

  // ---- flow control: accept ------------------------------------------------------------------------
  localparam int unsigned Cap = Stages + 1 + Slack;
  localparam int unsigned IW = (Cap > 1) ? $clog2(Cap) : 1;
  localparam int unsigned NW = $clog2(Cap + 1);
  logic [NW-1:0] inside_q;  // accepted and not yet output
  logic          accept, out_fire;
  assign in_ready_o = 32'(inside_q) < Cap;
  assign accept = in_valid_i & in_ready_o;

  // ---- L0 ------------------------------------------------------------------------------------------
  // differences: 0 e0 = p1-p2, 1 e1 = p2-p0, 2 e2 = p0-p1, 3 a-p0, 4 a-p1, 5 a-p2, 6 p2-a
  logic [7*V3-1:0] dl, dr, dy;
  assign dl = {p2_i, a_i, a_i, a_i, p0_i, p2_i, p1_i};
  assign dr = {a_i, p2_i, p1_i, p0_i, p1_i, p0_i, p2_i};
  logic [20:0] v0;
  logic [6:0]  uf0;  // underflow of a difference (any component)
  for (genvar i = 0; i < 7; i++) begin : gen_l0
    logic [14:0] fl;
    for (genvar c = 0; c < 3; c++) begin : gen_c
      ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(0)), .Subnormals(Subnormals), .Round(Round),
                  .CutSel(lcut(0))) u_sub (
        .clk_i, .rst_ni, .in_valid_i(accept), .a_i(dl[i*V3+c*W+:W]), .b_i(dr[i*V3+c*W+:W]), .op_i(1'b1),
        .out_valid_o(v0[3*i+c]), .y_o(dy[i*V3+c*W+:W]), .flags_o(fl[5*c+:5]));
    end
    assign uf0[i] = fl[1] | fl[6] | fl[11];
    logic [11:0] unused_fl;
    assign unused_fl = {fl[14:12], fl[10:7], fl[5:2], fl[0]};
  end
  logic [V3-1:0] e0, e1, e2, ap0, ap1, ap2, p2a;
  assign {p2a, ap2, ap1, ap0, e2, e1, e0} = dy;

  // lexmin_first(l, r) for the pairs (p1,p2), (p2,p0), (p0,p1) (as ru_ray_tri_robust)
  logic [3*V3-1:0] lex_l, lex_r;
  assign lex_l = {p0_i, p2_i, p1_i};
  assign lex_r = {p1_i, p0_i, p2_i};
  logic [8:0]  lt_lr, lt_rl;
  logic [2:0]  s0q;
  logic [17:0] unused_cmp_valid;
  for (genvar i = 0; i < 3; i++) begin : gen_lex
    for (genvar c = 0; c < 3; c++) begin : gen_coord
      localparam int unsigned K = 3 * i + c;
      logic [W-1:0] y1, y2;
      logic [9:0]   unused_fl;
      ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(0)), .Subnormals(Subnormals)) u_lt (
        .clk_i, .rst_ni, .in_valid_i(accept), .a_i(lex_l[i*V3+c*W+:W]), .b_i(lex_r[i*V3+c*W+:W]),
        .op_i(3'd0), .out_valid_o(unused_cmp_valid[2*K]), .y_o(y1), .flags_o(unused_fl[0+:5]));
      ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(0)), .Subnormals(Subnormals)) u_gt (
        .clk_i, .rst_ni, .in_valid_i(accept), .a_i(lex_r[i*V3+c*W+:W]), .b_i(lex_l[i*V3+c*W+:W]),
        .op_i(3'd0), .out_valid_o(unused_cmp_valid[2*K+1]), .y_o(y2), .flags_o(unused_fl[5+:5]));
      assign lt_lr[K] = y1[0];
      assign lt_rl[K] = y2[0];
      logic [2*W-3:0] unused_hi;
      assign unused_hi = {y1[W-1:1], y2[W-1:1]};
    end
    assign s0q[i] = lt_lr[3*i] | (~lt_rl[3*i] & (lt_lr[3*i+1] | (~lt_rl[3*i+1] &
                    (lt_lr[3*i+2] | ~lt_rl[3*i+2]))));
  end

  // non-finite operands: decided miss at the end
  logic nonfin_in, nonfin_end;
  always_comb begin
    nonfin_in = 1'b0;
    for (int c = 0; c < 3; c++)
      nonfin_in |= f_nonfin(a_i[c*W+:W]) | f_nonfin(d_i[c*W+:W]) | f_nonfin(p0_i[c*W+:W]) |
                   f_nonfin(p1_i[c*W+:W]) | f_nonfin(p2_i[c*W+:W]);
  end
  ru_pipe #(.Width(1), .Depth(span(0, NLev))) u_wait_nonfin (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[0]), .data_i(nonfin_in), .data_o(nonfin_end));

  logic [V3-1:0] d1;
  ru_pipe #(.Width(V3), .Depth(lat(0))) u_wait0_d (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[1]), .data_i(d_i), .data_o(d1));
  logic [W-1:0] tmin7, tmax7;
  ru_pipe #(.Width(2 * W), .Depth(span(0, 7))) u_wait_bounds (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[2]), .data_i({tmin_i, tmax_i}),
    .data_o({tmin7, tmax7}));

  // per-edge and interval tiny bits of L0: edge k: e_k and a - m_k; interval: e0, e1, p2 - a
  logic [V3-1:0] am0, am1, am2;
  assign am0 = s0q[0] ? ap1 : ap2;
  assign am1 = s0q[1] ? ap2 : ap0;
  assign am2 = s0q[2] ? ap0 : ap1;
  logic [3:0] tiny0, tiny0_5;
  assign tiny0 = {uf0[0] | uf0[1] | uf0[6],
                  uf0[2] | (s0q[2] ? uf0[3] : uf0[4]),
                  uf0[1] | (s0q[1] ? uf0[5] : uf0[3]),
                  uf0[0] | (s0q[0] ? uf0[4] : uf0[5])};
  ru_pipe #(.Width(4), .Depth(span(1, 6))) u_wait_tiny0 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[3]), .data_i(tiny0), .data_o(tiny0_5));

  // ---- L1, L2: four cross products (edges 0..2: (a - m_k) x d; 3: e1 x e0) and their permanents --
  logic [4*V3-1:0] cu, cw, cr, pc;
  assign cu = {e1, am2, am1, am0};
  assign cw = {e0, d1, d1, d1};
  logic [3:0] tiny2, tiny2_5;
  logic [3:0] v2;
  for (genvar x = 0; x < 4; x++) begin : gen_cross
    logic [V3-1:0] l, r;
    logic [5:0]    pv;
    logic [29:0]   fm;
    for (genvar c = 0; c < 3; c++) begin : gen_mul
      localparam int unsigned C1 = (c + 1) % 3;
      localparam int unsigned C2 = (c + 2) % 3;
      ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(1)), .Subnormals(Subnormals), .Round(Round),
                  .CutSel(lcut(1))) u_l (
        .clk_i, .rst_ni, .in_valid_i(v0[0]), .a_i(cu[x*V3+C1*W+:W]), .b_i(cw[x*V3+C2*W+:W]),
        .out_valid_o(pv[2*c]), .y_o(l[c*W+:W]), .flags_o(fm[10*c+:5]));
      ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(1)), .Subnormals(Subnormals), .Round(Round),
                  .CutSel(lcut(1))) u_r (
        .clk_i, .rst_ni, .in_valid_i(v0[0]), .a_i(cu[x*V3+C2*W+:W]), .b_i(cw[x*V3+C1*W+:W]),
        .out_valid_o(pv[2*c+1]), .y_o(r[c*W+:W]), .flags_o(fm[10*c+5+:5]));
    end
    logic uf1, uf1_2;
    assign uf1 = fm[1] | fm[6] | fm[11] | fm[16] | fm[21] | fm[26];
    ru_pipe #(.Width(1), .Depth(lat(2))) u_wait_uf1 (
      .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[4+x]), .data_i(uf1), .data_o(uf1_2));
    logic [29:0] fa;
    logic [5:0]  av;
    for (genvar c = 0; c < 3; c++) begin : gen_add
      ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(2)), .Subnormals(Subnormals), .Round(Round),
                  .CutSel(lcut(2))) u_sub (
        .clk_i, .rst_ni, .in_valid_i(pv[0]), .a_i(l[c*W+:W]), .b_i(r[c*W+:W]), .op_i(1'b1),
        .out_valid_o(av[2*c]), .y_o(cr[x*V3+c*W+:W]), .flags_o(fa[10*c+:5]));
      ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(2)), .Subnormals(Subnormals), .Round(Round),
                  .CutSel(lcut(2))) u_perm (
        .clk_i, .rst_ni, .in_valid_i(pv[0]), .a_i(f_abs(l[c*W+:W])), .b_i(f_abs(r[c*W+:W])), .op_i(1'b0),
        .out_valid_o(av[2*c+1]), .y_o(pc[x*V3+c*W+:W]), .flags_o(fa[10*c+5+:5]));
    end
    assign v2[x] = av[0];
    assign tiny2[x] = uf1_2 | fa[1] | fa[6] | fa[11] | fa[16] | fa[21] | fa[26];
    logic unused_x;
    assign unused_x = ^{pv[5:1], av[5:1], fm[29:27], fm[25:22], fm[20:17], fm[15:12], fm[10:7], fm[5:2], fm[0],
                        fa[29:27], fa[25:22], fa[20:17], fa[15:12], fa[10:7], fa[5:2], fa[0]};
  end
  ru_pipe #(.Width(4), .Depth(span(3, 6))) u_wait_tiny2 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[8]), .data_i(tiny2), .data_o(tiny2_5));

  // e0..e2, p2 - a, d wait for L1 + L2
  logic [V3-1:0] e0_2, e1_2, e2_2, p2a_2, d_2;
  ru_pipe #(.Width(5 * V3), .Depth(span(1, 3))) u_wait12 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[9]), .data_i({e0, e1, e2, p2a, d1}),
    .data_o({e0_2, e1_2, e2_2, p2a_2, d_2}));

  // ---- L3..L5: volumes V0, V1, V2, V, Va and their permanents -----------------------------------
  // dot j: 0..2 c_k . e_k, 3 n . d, 4 n . (p2 - a); permanents the same with pc and |z|
  logic [5*V3-1:0] du, dz;
  assign du = {cr[3*V3+:V3], cr[3*V3+:V3], cr[2*V3+:V3], cr[V3+:V3], cr[0+:V3]};
  assign dz = {p2a_2, d_2, e2_2, e1_2, e0_2};
  logic [5*V3-1:0] pu;
  assign pu = {pc[3*V3+:V3], pc[3*V3+:V3], pc[2*V3+:V3], pc[V3+:V3], pc[0+:V3]};
  logic [5*W-1:0] vol, perm;
  logic [4:0]     tinyd;
  logic [9:0]     v5;
  for (genvar j = 0; j < 5; j++) begin : gen_dot
    logic [4:0] fv, fp;
    ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                     .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                     .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_vol (
      .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(du[j*V3+:V3]), .v_i(dz[j*V3+:V3]), .valid_o(v5[2*j]),
      .y_o(vol[j*W+:W]), .flags_o(fv));
    ru_fp_dot3_core #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .Round(Round),
                     .MulStages(lat(3)), .MulCuts(lcut(3)), .Add1Stages(lat(4)), .Add1Cuts(lcut(4)),
                     .Add2Stages(lat(5)), .Add2Cuts(lcut(5))) u_perm (
      .clk_i, .rst_ni, .valid_i(v2[0]), .u_i(pu[j*V3+:V3]), .v_i(f_vabs(dz[j*V3+:V3])), .valid_o(v5[2*j+1]),
      .y_o(perm[j*W+:W]), .flags_o(fp));
    assign tinyd[j] = fv[1] | fp[1];
    logic [7:0] unused_f;
    assign unused_f = {fv[4:2], fv[0], fp[4:2], fp[0]};
  end

  // ---- L6: divisions; beside them the certification and the interval bound's first steps --------
  logic [W-1:0] vV0, vV1, vV2, vV, vVa, pP0, pP1, pP2, pPV, pPa;
  assign {vVa, vV, vV2, vV1, vV0} = vol;
  assign {pPa, pPV, pP2, pP1, pP0} = perm;
  logic [W-1:0] q_t, q_beta, q_gamma;
  logic [2:0]   v6;
  logic [14:0]  unused_div_flags;
  ru_fp_div #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals), .Round(Round),
              .CutSel(lcut(6))) u_div_t (
    .clk_i, .rst_ni, .in_valid_i(v5[0]), .a_i(vVa), .b_i(vV), .out_valid_o(v6[0]), .y_o(q_t),
    .flags_o(unused_div_flags[0+:5]));
  ru_fp_div #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals), .Round(Round),
              .CutSel(lcut(6))) u_div_beta (
    .clk_i, .rst_ni, .in_valid_i(v5[0]), .a_i(vV1), .b_i(vV), .out_valid_o(v6[1]), .y_o(q_beta),
    .flags_o(unused_div_flags[5+:5]));
  ru_fp_div #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(6)), .Subnormals(Subnormals), .Round(Round),
              .CutSel(lcut(6))) u_div_gamma (
    .clk_i, .rst_ni, .in_valid_i(v5[0]), .a_i(vV2), .b_i(vV), .out_valid_o(v6[2]), .y_o(q_gamma),
    .flags_o(unused_div_flags[10+:5]));

  // edge signs and certification; the interval's V certification and bound pieces
  logic [2:0] pos6, neg6, cert6;
  logic [3:0] tiny5;
  logic       ivok6, nonfin6, bad6;
  logic [W-1:0] aV6, BV6, Ba6;
  logic [W:0]   sBV, sBa, s2BV;
  assign tiny5 = tiny0_5 | tiny2_5 | {tinyd[4] | tinyd[3], tinyd[2:0]};
  always_comb begin
    pos6[0] = ~vV0[W-1] & ~f_zero(vV0) & ~f_nan(vV0);
    pos6[1] = ~vV1[W-1] & ~f_zero(vV1) & ~f_nan(vV1);
    pos6[2] = ~vV2[W-1] & ~f_zero(vV2) & ~f_nan(vV2);
    neg6[0] = vV0[W-1] & ~f_zero(vV0) & ~f_nan(vV0);
    neg6[1] = vV1[W-1] & ~f_zero(vV1) & ~f_nan(vV1);
    neg6[2] = vV2[W-1] & ~f_zero(vV2) & ~f_nan(vV2);
    cert6[0] = ~tiny5[0] & f_cert(vV0, pP0, K7);
    cert6[1] = ~tiny5[1] & f_cert(vV1, pP1, K7);
    cert6[2] = ~tiny5[2] & f_cert(vV2, pP2, K7);
    ivok6 = ~tiny5[3] & f_cert(vV, pPV, K7);
    nonfin6 = f_nonfin(vV) | f_nonfin(pPV) | f_nonfin(vVa) | f_nonfin(pPa);
    aV6 = f_abs(vV);
    sBV = f_s2(pPV, K7);
    sBa = f_s2(pPa, K8);
    BV6 = sBV[W-1:0];
    Ba6 = sBa[W-1:0];
    s2BV = f_s2(BV6, 1);
    // 2 BV < |V| on non-negative values: an unsigned comparison of the bit patterns (V is normal
    // when ivok6; otherwise the result does not matter)
    bad6 = sBV[W] | sBa[W] | s2BV[W] | ~(s2BV[W-1:0] < aV6);
  end
  logic [W-1:0] aV8, BV8, Ba9;
  ru_pipe #(.Width(2 * W), .Depth(span(6, 8))) u_wait6_8 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[10]), .data_i({aV6, BV6}), .data_o({aV8, BV8}));
  ru_pipe #(.Width(W), .Depth(span(6, 9))) u_wait6_9 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[11]), .data_i(Ba6), .data_o(Ba9));
  logic [W-1:0] aV10;
  ru_pipe #(.Width(W), .Depth(span(8, 10))) u_wait8_10 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[23]), .data_i(aV8), .data_o(aV10));
  logic [11:0] info6, info_end;
  assign info6 = {pos6, neg6, cert6, ivok6, nonfin6, bad6};
  ru_pipe #(.Width(12), .Depth(span(6, NLev))) u_wait6_end (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[12]), .data_i(info6), .data_o(info_end));

  // ---- L7: tq, D_lo, D_hi ----------------------------------------------------------------------
  logic [W-1:0] tq8, dlo8, dhi8;
  logic [4:0]   ftq, fdlo, fdhi;
  logic [2:0]   v7;
  ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(7)), .Subnormals(Subnormals), .Round(3),
              .CutSel(lcut(7))) u_tq (
    .clk_i, .rst_ni, .in_valid_i(v6[0]), .a_i(f_abs(q_t)), .b_i(One2u), .out_valid_o(v7[0]), .y_o(tq8),
    .flags_o(ftq));
  ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(7)), .Subnormals(Subnormals), .Round(1)) u_dlo (
    .clk_i, .rst_ni, .in_valid_i(v6[0]), .a_i(q_t), .b_i(tmin7), .op_i(1'b1), .out_valid_o(v7[1]), .y_o(dlo8),
    .flags_o(fdlo));
  ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(7)), .Subnormals(Subnormals), .Round(1)) u_dhi (
    .clk_i, .rst_ni, .in_valid_i(v6[0]), .a_i(tmax7), .b_i(q_t), .op_i(1'b1), .out_valid_o(v7[2]), .y_o(dhi8),
    .flags_o(fdhi));
  // the bounds' classes; t below the normal range (zero or subnormal: z = 2 minnorm |V| in L10)
  logic [4:0] info7, info7_end;
  assign info7 = {f_nan(tmin7) | f_nan(tmax7),
                  f_nonfin(tmin7) & ~f_nan(tmin7), tmin7[W-1],
                  f_nonfin(tmax7) & ~f_nan(tmax7), tmax7[W-1]};
  ru_pipe #(.Width(5), .Depth(span(7, NLev))) u_wait7_end (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[13]), .data_i(info7), .data_o(info7_end));
  logic ttiny7, ttiny9, ttiny10;
  assign ttiny7 = q_t[W-2:FracW] == '0;
  ru_pipe #(.Width(1), .Depth(span(7, 9))) u_wait7_tiny (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[21]), .data_i(ttiny7), .data_o(ttiny9));
  ru_pipe #(.Width(1), .Depth(lat(9))) u_wait9_tiny (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[22]), .data_i(ttiny9), .data_o(ttiny10));
  logic [3*W-1:0] tbg_end;
  ru_pipe #(.Width(3 * W), .Depth(span(7, NLev))) u_wait7_tbg (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[14]), .data_i({q_t, q_beta, q_gamma}),
    .data_o(tbg_end));

  // ---- L8: products of the bound and of the sides ----------------------------------------------
  logic [W-1:0] m1_9, m2_9, mlo9, mhi9;
  logic [4:0]   fm1, fm2, fmlo, fmhi;
  logic [3:0]   v8;
  ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(8)), .Subnormals(Subnormals), .Round(3),
              .CutSel(lcut(8))) u_m1 (
    .clk_i, .rst_ni, .in_valid_i(v7[0]), .a_i(tq8), .b_i(BV8), .out_valid_o(v8[0]), .y_o(m1_9), .flags_o(fm1));
  ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(8)), .Subnormals(Subnormals), .Round(3),
              .CutSel(lcut(8))) u_m2 (
    .clk_i, .rst_ni, .in_valid_i(v7[0]), .a_i(tq8), .b_i(aV8), .out_valid_o(v8[1]), .y_o(m2_9), .flags_o(fm2));
  ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(8)), .Subnormals(Subnormals), .Round(1),
              .CutSel(lcut(8))) u_mlo (
    .clk_i, .rst_ni, .in_valid_i(v7[0]), .a_i(f_abs(dlo8)), .b_i(aV8), .out_valid_o(v8[2]), .y_o(mlo9),
    .flags_o(fmlo));
  ru_fp_mul #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(8)), .Subnormals(Subnormals), .Round(1),
              .CutSel(lcut(8))) u_mhi (
    .clk_i, .rst_ni, .in_valid_i(v7[0]), .a_i(f_abs(dhi8)), .b_i(aV8), .out_valid_o(v8[3]), .y_o(mhi9),
    .flags_o(fmhi));
  // D > 0 (lower: t > t_min; upper: t_max > t) and the RUP flags so far
  logic [2:0] info8, info8_end;
  assign info8 = {~dlo8[W-1] & ~f_zero(dlo8), ~dhi8[W-1] & ~f_zero(dhi8), ftq[1] | ftq[2]};
  ru_pipe #(.Width(3), .Depth(span(8, NLev))) u_wait8_end (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[15]), .data_i(info8), .data_o(info8_end));
  logic [W-1:0] m2_10, mlo11, mhi11;
  ru_pipe #(.Width(W), .Depth(lat(9))) u_wait9_m2 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[16]), .data_i(m2_9), .data_o(m2_10));
  ru_pipe #(.Width(2 * W), .Depth(span(9, 11))) u_wait9_11 (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[17]), .data_i({mlo9, mhi9}),
    .data_o({mlo11, mhi11}));

  // ---- L9: Ba + tq BV ------------------------------------------------------------------------------
  logic [W-1:0] s1_10;
  logic [4:0]   fs1;
  logic         v9;
  ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(9)), .Subnormals(Subnormals), .Round(3),
              .CutSel(lcut(9))) u_s1 (
    .clk_i, .rst_ni, .in_valid_i(v8[0]), .a_i(Ba9), .b_i(m1_9), .op_i(1'b0), .out_valid_o(v9), .y_o(s1_10),
    .flags_o(fs1));
  logic bad9, bad9_end;
  assign bad9 = fm1[1] | fm1[2] | ((fm2[1] | fm2[2]) & ~ttiny9);  // tq |V| unused for a tiny t
  ru_pipe #(.Width(1), .Depth(span(9, NLev))) u_wait9_end (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[18]), .data_i(bad9), .data_o(bad9_end));

  // ---- L10: R = 2 (Ba + tq BV) + z, z = u tq |V| (tiny t: 2 minnorm |V|) ---------------------------
  logic [W:0]   sx, sy;
  assign sx = f_s2(s1_10, 1);
  assign sy = ttiny10 ? f_s2(aV10, EMinP1) : f_s2(m2_10, -Q);
  logic [W-1:0] r11;
  logic [4:0]   fr;
  logic         v10;
  ru_fp_add #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(10)), .Subnormals(Subnormals), .Round(3),
              .CutSel(lcut(10))) u_r (
    .clk_i, .rst_ni, .in_valid_i(v9), .a_i(sx[W-1:0]), .b_i(sy[W-1:0]), .op_i(1'b0), .out_valid_o(v10),
    .y_o(r11), .flags_o(fr));
  logic bad10, bad10_end;
  assign bad10 = fs1[1] | fs1[2] | sx[W] | sy[W];
  ru_pipe #(.Width(1), .Depth(span(10, NLev))) u_wait10_end (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[19]), .data_i(bad10), .data_o(bad10_end));

  // ---- L11: R < |D| |V| for each bound ---------------------------------------------------------
  logic [W-1:0] ylo, yhi;
  logic [9:0]   unused_cmp_fl;
  logic         pipe_valid, unused_v11;
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(11)), .Subnormals(Subnormals), .CutSel(lcut(11))) u_clo (
    .clk_i, .rst_ni, .in_valid_i(v10), .a_i(r11), .b_i(mlo11), .op_i(3'd0), .out_valid_o(pipe_valid), .y_o(ylo),
    .flags_o(unused_cmp_fl[0+:5]));
  ru_fp_cmp #(.ExpW(ExpW), .FracW(FracW), .Stages(lat(11)), .Subnormals(Subnormals), .CutSel(lcut(11))) u_chi (
    .clk_i, .rst_ni, .in_valid_i(v10), .a_i(r11), .b_i(mhi11), .op_i(3'd0), .out_valid_o(unused_v11), .y_o(yhi),
    .flags_o(unused_cmp_fl[5+:5]));
  logic bad11, bad11_end;
  assign bad11 = fr[1] | fr[2] | f_nonfin(r11);
  ru_pipe #(.Width(1), .Depth(lat(11))) u_wait11_end (
    .clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly_valid[20]), .data_i(bad11), .data_o(bad11_end));

  // ---- the fast decision at the end of the pipeline -----------------------------------------------
  // state of a test: {slow, in_dec, in_val, pos[3], neg[3], cert[3], nonfin}
  localparam int unsigned SW = 13;
  logic [SW-1:0] arr_state;
  logic          in_dec, in_val;
  always_comb begin : p_fast
    logic [2:0] pos, neg, cert;
    logic ivok, nonfin5, bad_s2, nanb, inf_lo, neg_lo, inf_hi, neg_hi, dlo_pos, dhi_pos, bad_tq;
    logic lo_p, lo_n, hi_p, hi_n;
    {pos, neg, cert, ivok, nonfin5, bad_s2} = info_end;
    {nanb, inf_lo, neg_lo, inf_hi, neg_hi} = info7_end;
    {dlo_pos, dhi_pos, bad_tq} = info8_end;
    // sides: lo_p t above t_min, lo_n below; hi_n t below t_max, hi_p above
    lo_p = inf_lo ? neg_lo : (ylo[0] & dlo_pos);
    lo_n = inf_lo ? ~neg_lo : (ylo[0] & ~dlo_pos);
    hi_n = inf_hi ? ~neg_hi : (yhi[0] & dhi_pos);
    hi_p = inf_hi ? neg_hi : (yhi[0] & ~dhi_pos);
    in_dec = 1'b0;
    in_val = 1'b0;
    if (!ivok || nonfin5 || f_nonfin(tbg_end[2*W+:W])) begin
      in_dec = 1'b0;
    end else if (nanb) begin
      in_dec = 1'b1;
    end else if (!(bad_s2 || bad_tq || bad9_end || bad10_end || bad11_end)) begin
      if (lo_n || hi_p) in_dec = 1'b1;
      else if (lo_p && hi_n) begin
        in_dec = 1'b1;
        in_val = 1'b1;
      end
    end
    arr_state = {1'b0, in_dec, in_val, pos, neg, cert, nonfin_end};
  end
  logic [W-2:0] unused_ylo_hi;
  assign unused_ylo_hi = {ylo[W-1:1] ^ yhi[W-1:1]};

  // ---- order buffer and the side path ---------------------------------------------------------------
  logic [17*W-1:0] ops_in;  // 17 operands
  assign ops_in = {tmax_i, tmin_i, p2_i, p1_i, p0_i, d_i, a_i};
  logic [17*W-1:0] ops_mem [Cap];
  logic [SW-1:0]   st_mem [Cap];
  logic [3*W-1:0]  tbg_mem [Cap];
  logic [Cap-1:0]  arrived_q;
  logic [IW-1:0]   acc_ptr_q, arr_ptr_q, out_ptr_q;
  logic            pending_q;
  logic [1:0]      pend_op_q;

  function automatic logic [IW-1:0] inc(input logic [IW-1:0] p);
    inc = (32'(p) == Cap - 1) ? '0 : p + 1'b1;
  endfunction

  logic head_stored, head_arr, head_valid;
  logic [SW-1:0]  hs;
  logic [3*W-1:0] htbg;
  assign head_stored = arrived_q[out_ptr_q];
  assign head_arr = pipe_valid & (arr_ptr_q == out_ptr_q) & ~head_stored;
  assign head_valid = head_stored | head_arr;
  assign hs = head_stored ? st_mem[out_ptr_q] : arr_state;
  assign htbg = head_stored ? tbg_mem[out_ptr_q] : tbg_end;

  // decision on a state: done (with hit/why) or the next side-path request
  logic       done, need;
  logic [1:0] need_op;
  logic [2:0] why_d;
  always_comb begin : p_decide
    logic [2:0] pos, neg, cert;
    logic mixed;
    pos = hs[9:7];
    neg = hs[6:4];
    cert = hs[3:1];
    mixed = (|(cert & pos)) & (|(cert & neg));
    done = 1'b0;
    need = 1'b0;
    need_op = 2'd0;
    why_d = 3'd1;
    if (hs[0] || (mixed && Plant != 2)) begin
      done = 1'b1;
    end else if (~&cert) begin
      need = 1'b1;
      need_op = ~cert[0] ? 2'd0 : ~cert[1] ? 2'd1 : 2'd2;
    end else if (!((&pos) || (&neg))) begin
      done = 1'b1;
    end else if (hs[11]) begin
      done = 1'b1;
      why_d = hs[10] ? 3'd0 : 3'd4;
    end else begin
      need = 1'b1;
      need_op = 2'd3;
    end
  end

  logic issue, xp_ready, xp_valid;
  logic [1:0] xp_res;
  assign out_fire = head_valid & done & ~pending_q;
  assign issue = head_stored & need & ~pending_q & xp_ready;

  logic [17*W-1:0] hops;
  assign hops = ops_mem[out_ptr_q];
  ru_exact_path #(.ExpW(ExpW), .FracW(FracW), .Subnormals(Subnormals), .DigitW(DigitW)) u_xp (
    .clk_i, .rst_ni, .in_valid_i(issue), .in_ready_o(xp_ready), .op_i(need_op),
    .a_i(hops[0+:V3]), .d_i(hops[V3+:V3]), .p0_i(hops[2*V3+:V3]), .p1_i(hops[3*V3+:V3]),
    .p2_i(hops[4*V3+:V3]), .tmin_i(hops[15*W+:W]), .tmax_i(hops[16*W+:W]), .out_valid_o(xp_valid),
    .res_o(xp_res));

  // operands: written when accepted
  always_ff @(posedge clk_i) begin
    if (accept) ops_mem[acc_ptr_q] <= ops_in;
  end
  // state and t/beta/gamma: written on arrival unless the test leaves at once; the head's state
  // updated by the side path's results
  logic store_arr;
  assign store_arr = pipe_valid & ~(head_arr & out_fire);
  always_ff @(posedge clk_i) begin
    if (store_arr) begin
      st_mem[arr_ptr_q] <= arr_state;
      tbg_mem[arr_ptr_q] <= tbg_end;
    end
    if (issue) st_mem[out_ptr_q][12] <= 1'b1;
    if (xp_valid) begin
      if (pend_op_q == 2'd3) begin
        st_mem[out_ptr_q][11:10] <= {1'b1, xp_res[0]};
      end else begin
        st_mem[out_ptr_q][1 + 32'(pend_op_q)] <= 1'b1;                       // cert
        st_mem[out_ptr_q][7 + 32'(pend_op_q)] <= xp_res == 2'b01;            // pos
        st_mem[out_ptr_q][4 + 32'(pend_op_q)] <= xp_res == 2'b11;            // neg
      end
    end
  end
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      inside_q <= '0;
      acc_ptr_q <= '0;
      arr_ptr_q <= '0;
      out_ptr_q <= '0;
      arrived_q <= '0;
      pending_q <= 1'b0;
      pend_op_q <= 2'd0;
    end else begin
      inside_q <= inside_q + NW'(accept) - NW'(out_fire);
      if (accept) acc_ptr_q <= inc(acc_ptr_q);
      if (pipe_valid) arr_ptr_q <= inc(arr_ptr_q);
      if (store_arr) arrived_q[arr_ptr_q] <= 1'b1;
      if (out_fire) begin
        out_ptr_q <= inc(out_ptr_q);
        if (head_stored) arrived_q[out_ptr_q] <= 1'b0;
      end
      if (issue) begin
        pending_q <= 1'b1;
        pend_op_q <= need_op;
      end else if (xp_valid) begin
        pending_q <= 1'b0;
      end
    end
  end

  assign out_valid_o = out_fire;
  assign why_o = why_d;
  assign hit_o = why_d == 3'd0;
  assign {t_o, beta_o, gamma_o} = htbg;
  assign slow_o = hs[12];

  logic unused_valid;
  assign unused_valid = ^{v0[20:1], v2[3:1], v5[9:1], v6[2:1], v7[2:1], v8[3:1], unused_v11, unused_cmp_valid,
                          unused_dly_valid, unused_div_flags, unused_cmp_fl, ftq[4:3], ftq[0], fdlo, fdhi,
                          fm1[4:3], fm1[0], fm2[4:3], fm2[0], fmlo, fmhi, fs1[4:3], fs1[0], fr[4:3], fr[0]};

endmodule
