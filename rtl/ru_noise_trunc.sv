// ru_noise_trunc: the smaller gradient noise unit (issue 15 §1): Kensler's half-resolution noise
// (same tables, same ports, same output convention as ru_noise) on a cheaper datapath:
//   - one exact squarer per axis; (1 - f)^2 = f^2 + 1 - 2f by an adder (same bits as ru_noise),
//   - the kernel weight w = t^4 (4t - 3), t = 1 - d, from a 2^B-entry table indexed by the squared
//     distance d: the exact value rounded to nearest in B + 1 signed bits (saturated at 1 - 2^-B
//     for d = 0), computed at elaboration. It replaces ru_noise's t^2, t^4, t^5 products (at B = 8
//     the table maps to a fifth of their cells); FracBits is therefore limited to 5..12,
//   - gradients with B - 3 fraction bits (clamped to +-(1 - 2^-(B-3))), the dot products with
//     B fraction bits (as ru_noise: fewer made the noise 4x coarser near lattice points, docs/
//     NOISE.md) from truncated unsigned arrays f x g's low bits plus exact sign rows; the arrays
//     keep the partial-product bits of the columns >= R - 2 (two guard columns below the last
//     bit of the result, R = the shift) and add a constant correction (half an ulp plus the
//     expected value of the dropped bits rounded to the lowest kept column),
//   - the eight w * dot summed exactly (products, pairs, total).
//
// The tables are ru_noise's (the generated ru_noise_tables.svh; its ru_noise_gq is defined here
// with this unit's gradient width). Bit for bit equal to ru::noise::FixedNoise with
// NoiseDatapath::kTrunc (model/src/noise/fixed.cpp, eval_trunc); the steps are described in
// docs/NOISE.md ("The truncated datapath").
// Fully pipelined: one result per clock, latency = Stages cycles (0 = combinational).
//
//   x_i, y_i, z_i  signed two's complement, IntBits integer bits (incl. sign) and FracBits
//                  fraction bits: u = x_i / 2^FracBits in half-resolution cells.
//   value_o        signed OutW bits, value_o / 2^(OutW+1) ~= N(u) (as ru_noise).
module ru_noise_trunc #(
  parameter int unsigned FracBits = 8,   // B, 5..12
  parameter int unsigned IntBits  = 8,   // 1..24
  parameter int unsigned OutW     = 10,  // 2..2*FracBits+6
  parameter int unsigned Stages   = 4    // pipeline registers (latency), 0..
) (
  input  logic                        clk_i,
  input  logic                        rst_ni,
  input  logic                        in_valid_i,
  input  logic [IntBits+FracBits-1:0] x_i,
  input  logic [IntBits+FracBits-1:0] y_i,
  input  logic [IntBits+FracBits-1:0] z_i,
  output logic                        out_valid_o,
  output logic [OutW-1:0]             value_o
);

  localparam int unsigned B     = FracBits;
  localparam int unsigned InW   = IntBits + FracBits;
  localparam int unsigned Gb    = B - 3;          // gradient fraction bits
  localparam int unsigned GradW = Gb + 1;         // gradient component: signed, |g| < 2^Gb
  localparam int unsigned QW    = B + 1;          // sq1 = (1 - f)^2 in [0, 2^B]
  localparam int unsigned DW    = B + 2;          // squared distance: unsigned, <= 3 * 2^B
  localparam int unsigned WW    = B + 1;          // kernel weight: signed, |w| < 2^B
  // dot product (DotF = B fraction bits): signed, |dot| < 2 in DotF + 2 bits from B = 8 on
  // (Cauchy-Schwarz with the table's largest narrowed norm and the truncation's slack:
  // tests/noise), else DotF + 3
  localparam int unsigned DotF  = B;
  localparam int unsigned DotW  = (B >= 8) ? DotF + 2 : DotF + 3;
  localparam int unsigned AccW  = 2 * B + 1;      // dot accumulator (B + Gb fraction bits), modulo
  localparam int unsigned PairW = WW + DotW;      // sum of two contributions w * dot: signed
  localparam int unsigned SumW  = WW + DotW + 2;  // sum of the eight: signed (B + DotF fraction bits)
  localparam int          Sh    = B + DotF - 1 - OutW;  // output shift (right if > 0)
  localparam int unsigned VW    = SumW - Sh;      // scaled sum

  // Gradient narrowing: round(q16 / 2^(16-Gb)) (ties up), clamped to +-(2^Gb - 1).
  localparam int GradShift = 16 - Gb;
  localparam int GradMax   = (1 << Gb) - 1;

  // Constant corrections (the model computes the same by the same formula: scoreboard). K = the
  // lowest kept column, R = the shift, E4 = 4 x the expected value of the dropped bits.
  function automatic logic [63:0] ru_corr(input int r, input int k, input logic [63:0] e4);
    ru_corr = 64'd1 << (r - 1);
    if (k > 0) ru_corr = ru_corr + ((64'd1 << k) * ((e4 + (64'd1 << (k + 1))) >> (k + 2)));
  endfunction
  function automatic logic [63:0] ru_e4_array(input int na, input int nb, input int k, input int copies);
    ru_e4_array = '0;
    for (int i = 0; i < na; i++)
      for (int j = 0; j < nb; j++) if (i + j < k) ru_e4_array = ru_e4_array + (64'(copies) << (i + j));
  endfunction
  localparam int RDot = B + Gb - DotF;  // dot: R = B - 3
  localparam int KDot = RDot - 2;
  localparam logic [63:0] CorrDot = ru_corr(RDot, KDot, ru_e4_array(B, Gb, KDot, 3));

  // Kernel weight table entry d: round(t^4 (4t - 3) 2^B) with t = 1 - d 2^-B (half up; B <= 12 so
  // the product fits 63 bits), saturated at 2^B - 1 (d = 0). Entry 2^B - 1 is 0.
  function automatic logic [WW-1:0] ru_weight(input int unsigned d);
    logic signed [63:0] t, num, v;
    t   = 64'(1 << B) - 64'(d);
    num = t * t * t * t * (4 * t - 3 * 64'(1 << B));
    v   = (num + (64'sd1 <<< (4 * B - 1))) >>> (4 * B);
    if (v > 64'((1 << B) - 1)) v = 64'((1 << B) - 1);
    ru_weight = WW'(v);
  endfunction

  // Folded squarer of x (exact): x_i at column 2i and x_i x_j (i < j) at column i + j + 1.
  function automatic logic [2*B-1:0] ru_square(input logic [B-1:0] x);
    logic [2*B-1:0] row;
    ru_square = '0;
    for (int i = 0; i < B; i++) begin
      row = '0;
      row[2*i] = x[i];
      for (int j = i + 1; j < B; j++) row[i+j+1] = x[i] & x[j];
      ru_square = ru_square + row;
    end
  endfunction
  // Unsigned B x B array a * b, partial-product bits of the columns >= k only (one row per b_j).
  function automatic logic [2*B-1:0] ru_mul_sum(input logic [B-1:0] a, input logic [B-1:0] b, input int k);
    logic [2*B-1:0] row;
    ru_mul_sum = '0;
    for (int j = 0; j < B; j++) begin
      row = '0;
      for (int i = 0; i < B; i++) if (i + j >= k) row[i+j] = a[i] & b[j];
      ru_mul_sum = ru_mul_sum + row;
    end
  endfunction

  // Pipelining (ru_pipe_pkg, the mechanism of every unit): seven levels, output register first.
  //   1 split + hash lookup + squarer + sq1       2 xor + gradient lookup + distance, table index
  //   3 weight table + dot product terms          4 dot product sum
  //   5 w * dot                                   6 summed in pairs
  //   7 total, scaling, saturation (output)
  // Level weights (units of 100 ps): the levels' logic delays in osu018 at the default widths, from
  // OpenSTA's stage periods minus 0.8 ns of clock-to-Q and setup (`rayunits synth noise_trunc
  // --stages S --flow osu018 --clock 200ps --stage-periods`). Alone (Stages 7): levels 1-7 take
  // 26, 22, 35, 16, 30, 23, 25. Merged, some pairs take less than the sum (their critical paths
  // are different paths: 1+2 37, 3+4 45, 6+7 40) and 4+5 the sum (47); the weights below are the
  // marginal delays that reproduce the merged pairs the placement chooses between (level 2 = 37 -
  // 26, level 4 = 45 - 35, level 5 = 47 - 10, level 7 = 40 - 23), so that every Stages gets the
  // partition with the shortest measured cycle (docs/NOISE.md, "The truncated datapath").
  localparam int unsigned NLevels = 7;
  localparam logic [ru_pipe_pkg::WW-1:0] LevelDepth = {{(ru_pipe_pkg::WW - 8 * NLevels){1'b0}},
      8'd17, 8'd23, 8'd37, 8'd10, 8'd35, 8'd11, 8'd26};  // level 7 .. level 1
  localparam logic [ru_pipe_pkg::MaxSeg:0] PipeCuts =
      ru_pipe_pkg::cut_mask_reg_out(LevelDepth, NLevels, Stages);
  localparam logic [NLevels-1:0] Cuts = PipeCuts[NLevels-1:0];
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(NLevels) + 1;
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(PipeCuts, Stages);
  if (OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_noise_trunc: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  if (FracBits < 5 || FracBits > 12) begin : gen_frac_check
    $error("ru_noise_trunc: FracBits must be 5..12 (the kernel weight table has 2^FracBits entries), got %0d", FracBits);
  end
  logic [ru_pipe_pkg::MaxSeg-NLevels:0] unused_pipe_cuts;
  assign unused_pipe_cuts = PipeCuts[ru_pipe_pkg::MaxSeg:NLevels];

  // One stored Q1.16 gradient component narrowed to GradW bits (folded at elaboration).
  function automatic logic [GradW-1:0] ru_noise_gq(input logic signed [17:0] q16);
    logic signed [31:0] v;
    v = 32'(q16);
    v = (v + (1 << (GradShift - 1))) >>> GradShift;
    if (v > GradMax) v = GradMax;
    if (v < -GradMax) v = -GradMax;
    ru_noise_gq = GradW'(v);
  endfunction

  `include "ru_noise_tables.svh"

  // ------------------------------------------------------------------------------------------
  // Level 1: (1) split, (2) hash lookup, (3) sq0 = floor(f^2 / 2^B), sq1 = sq0 + 2^B - 2f.
  localparam int unsigned L1W = 3 * B + 3 * 12 + 3 * B + 3 * QW;
  logic [L1W-1:0] l1_d, l1_q;
  logic           l1_valid_q;
  logic [3*B-1:0]  a_fr;
  logic [3*12-1:0] a_hash;
  logic [3*B-1:0]  a_sq0;
  logic [3*QW-1:0] a_sq1;

  for (genvar a = 0; a < 3; a++) begin : g_axis
    logic [InW-1:0] coord;
    logic [7:0]     cell_idx;
    logic [B-1:0]   fr;
    logic [2*B-1:0] sq_full;
    logic [B-1:0]   sq0;
    logic [11:0]    hash;

    if (a == 0) begin : g_x
      assign coord = x_i;
      assign hash = ru_noise_hash_x(cell_idx);
    end else if (a == 1) begin : g_y
      assign coord = y_i;
      assign hash = ru_noise_hash_y(cell_idx);
    end else begin : g_z
      assign coord = z_i;
      assign hash = ru_noise_hash_z(cell_idx);
    end

    if (IntBits >= 8) begin : g_cell_low
      assign cell_idx = coord[B+7:B];
      if (IntBits > 8) begin : g_unused_hi
        logic unused_hi;
        assign unused_hi = ^coord[InW-1:B+8];
      end
    end else begin : g_cell_sext
      assign cell_idx = {{(8 - IntBits){coord[InW-1]}}, coord[InW-1:B]};
    end

    assign fr      = coord[B-1:0];
    assign sq_full = ru_square(fr);
    assign sq0     = sq_full[2*B-1:B];
    assign a_fr[a*B+:B]     = fr;
    assign a_hash[a*12+:12] = hash;
    assign a_sq0[a*B+:B]    = sq0;
    assign a_sq1[a*QW+:QW]  = QW'({1'b0, sq0} + {1'b1, {B{1'b0}}} - {fr, 1'b0});
    logic unused_sq;
    assign unused_sq = ^sq_full[B-1:0];
  end

  assign l1_d = {a_sq1, a_sq0, a_hash, a_fr};

  ru_pipe #(.Width(L1W), .Depth(Cuts[0] ? 1 : 0)) u_cut1 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .data_i(l1_d), .valid_o(l1_valid_q), .data_o(l1_q));

  // ------------------------------------------------------------------------------------------
  // Level 2: (4) d and the table index min(d, 2^B - 1); (9) xor hash, gradients.
  localparam int unsigned L2W = 3 * B + 8 * 3 * GradW + 8 * B;
  logic [L2W-1:0] l2_d, l2_q;
  logic           l2_valid_q;
  logic [3*B-1:0]       b_fr;
  logic [3*12-1:0]      b_hash;
  logic [3*B-1:0]       b_sq0;
  logic [3*QW-1:0]      b_sq1;
  logic [8*3*GradW-1:0] b_g;
  logic [8*B-1:0]       b_idx;

  assign {b_sq1, b_sq0, b_hash, b_fr} = l1_q;

  for (genvar c = 0; c < 8; c++) begin : g_corner_b
    localparam int unsigned Cx = c % 2, Cy = (c / 2) % 2, Cz = c / 4;
    logic [5:0]    h;
    logic [QW-1:0] sx, sy, sz;
    logic [DW-1:0] d;
    assign h  = b_hash[0*12+6*Cx+:6] ^ b_hash[1*12+6*Cy+:6] ^ b_hash[2*12+6*Cz+:6];
    assign sx = (Cx != 0) ? b_sq1[0*QW+:QW] : {1'b0, b_sq0[0*B+:B]};
    assign sy = (Cy != 0) ? b_sq1[1*QW+:QW] : {1'b0, b_sq0[1*B+:B]};
    assign sz = (Cz != 0) ? b_sq1[2*QW+:QW] : {1'b0, b_sq0[2*B+:B]};
    assign b_g[c*3*GradW+:3*GradW] = ru_noise_grad(h);
    assign d = DW'(sx) + DW'(sy) + DW'(sz);
    assign b_idx[c*B+:B] = (d[DW-1:B] != '0) ? {B{1'b1}} : d[B-1:0];
  end

  assign l2_d = {b_idx, b_g, b_fr};

  ru_pipe #(.Width(L2W), .Depth(Cuts[1] ? 1 : 0)) u_cut2 (
    .clk_i, .rst_ni, .valid_i(l1_valid_q), .data_i(l2_d), .valid_o(l2_valid_q), .data_o(l2_q));

  // ------------------------------------------------------------------------------------------
  // Level 3: (5)-(8) kernel weight w = table[index]; (10) the dot product's three terms per corner
  // (truncated unsigned array f x low(g), minus the sign row f 2^Gb where g < 0, minus the corner
  // row g 2^B where c = 1; modulo 2^AccW, summed with the correction in level 4).
  localparam int unsigned L3W = 8 * WW + 8 * 3 * AccW;
  logic [L3W-1:0] l3_d, l3_q;
  logic           l3_valid_q;
  logic [3*B-1:0]       c_fr;
  logic [8*3*GradW-1:0] c_g;
  logic [8*B-1:0]       c_idx;
  logic [8*WW-1:0]      c_w;
  logic [8*3*AccW-1:0]  c_term;

  assign {c_idx, c_g, c_fr} = l2_q;

  // The table (a constant-initialized ROM: Yosys maps it to logic, one read port per corner).
  logic [WW-1:0] weight_rom [1 << B];
  initial begin
    for (int unsigned i = 0; i < (1 << B); i++) weight_rom[i] = ru_weight(i);
  end

  for (genvar c = 0; c < 8; c++) begin : g_corner_c
    localparam logic [2:0] Cb = 3'(c);  // corner bits {cz, cy, cx}
    assign c_w[c*WW+:WW] = weight_rom[c_idx[c*B+:B]];
    for (genvar a = 0; a < 3; a++) begin : g_term
      logic [GradW-1:0] g;
      logic [B-1:0]     f;
      logic [AccW-1:0]  m, sr, kr;
      assign g  = c_g[(3*c+a)*GradW+:GradW];
      assign f  = c_fr[a*B+:B];
      assign m  = AccW'(ru_mul_sum(f, B'(g[Gb-1:0]), KDot));
      assign sr = {AccW{g[Gb]}} & (AccW'(f) << Gb);
      if (Cb[a]) begin : g_corner_row
        assign kr = AccW'({{(AccW-GradW){g[Gb]}}, g}) << B;
      end else begin : g_no_corner_row
        assign kr = '0;
      end
      assign c_term[(3*c+a)*AccW+:AccW] = m - sr - kr;
    end
  end

  assign l3_d = {c_term, c_w};

  ru_pipe #(.Width(L3W), .Depth(Cuts[2] ? 1 : 0)) u_cut3 (
    .clk_i, .rst_ni, .valid_i(l2_valid_q), .data_i(l3_d), .valid_o(l3_valid_q), .data_o(l3_q));

  // ------------------------------------------------------------------------------------------
  // Level 4: (10) dot = floor((correction + the three terms) / 2^R), B fraction bits.
  localparam int unsigned L4W = 8 * WW + 8 * DotW;
  logic [L4W-1:0] l4_d, l4_q;
  logic           l4_valid_q;
  logic [8*WW-1:0]     d_w;
  logic [8*3*AccW-1:0] d_term;
  logic [8*DotW-1:0]   d_dot;

  assign {d_term, d_w} = l3_q;

  for (genvar c = 0; c < 8; c++) begin : g_corner_d
    logic [AccW-1:0] acc;
    assign acc = AccW'(CorrDot) + d_term[(3*c+0)*AccW+:AccW] + d_term[(3*c+1)*AccW+:AccW]
               + d_term[(3*c+2)*AccW+:AccW];
    assign d_dot[c*DotW+:DotW] = acc[RDot+:DotW];
    logic unused_acc;
    assign unused_acc = (^acc[RDot-1:0]) ^ (^acc[AccW-1:RDot+DotW]);
  end

  assign l4_d = {d_dot, d_w};

  ru_pipe #(.Width(L4W), .Depth(Cuts[3] ? 1 : 0)) u_cut4 (
    .clk_i, .rst_ni, .valid_i(l3_valid_q), .data_i(l4_d), .valid_o(l4_valid_q), .data_o(l4_q));

  // ------------------------------------------------------------------------------------------
  // Level 5: (11) the contributions w * dot (exact; |w * dot| < 2^(WW+DotW-2)).
  localparam int unsigned L5W = 8 * PairW;
  logic [L5W-1:0]    l5_d, l5_q;
  logic              l5_valid_q;
  logic [8*DotW-1:0] e_dot;
  logic [8*WW-1:0]   e_w;

  assign {e_dot, e_w} = l4_q;

  for (genvar c = 0; c < 8; c++) begin : g_contrib
    logic signed [WW-1:0]    w;
    logic signed [DotW-1:0]  dt;
    logic signed [PairW-1:0] p;
    assign w  = e_w[c*WW+:WW];
    assign dt = e_dot[c*DotW+:DotW];
    assign p  = PairW'(w) * PairW'(dt);
    assign l5_d[c*PairW+:PairW] = p;
  end

  ru_pipe #(.Width(L5W), .Depth(Cuts[4] ? 1 : 0)) u_cut5 (
    .clk_i, .rst_ni, .valid_i(l4_valid_q), .data_i(l5_d), .valid_o(l5_valid_q), .data_o(l5_q));

  // ------------------------------------------------------------------------------------------
  // Level 6: (12) the contributions summed in pairs.
  localparam int unsigned L6W = 4 * PairW;
  logic [L6W-1:0] l6_d, l6_q;
  logic           l6_valid_q;

  for (genvar k = 0; k < 4; k++) begin : g_pair
    assign l6_d[k*PairW+:PairW] = l5_q[(2*k)*PairW+:PairW] + l5_q[(2*k+1)*PairW+:PairW];
  end

  ru_pipe #(.Width(L6W), .Depth(Cuts[5] ? 1 : 0)) u_cut6 (
    .clk_i, .rst_ni, .valid_i(l5_valid_q), .data_i(l6_d), .valid_o(l6_valid_q), .data_o(l6_q));

  // ------------------------------------------------------------------------------------------
  // Level 7: (12) total of the four pair sums, (13) scaling (floor) and saturation.
  logic [OutW-1:0]        l7_d, l7_q;
  logic                   l7_valid_q;
  logic signed [SumW-1:0] g_sum;
  logic signed [VW-1:0]   g_v;
  logic                   g_ovf;

  always_comb begin
    g_sum = '0;
    for (int k = 0; k < 4; k++) begin
      g_sum = g_sum + SumW'($signed(l6_q[k*PairW+:PairW]));
    end
  end

  if (Sh >= 0) begin : g_shift_right
    assign g_v = VW'(g_sum >>> Sh);
    if (Sh > 0) begin : g_unused_low
      logic unused_low;
      assign unused_low = ^g_sum[(Sh > 0 ? Sh - 1 : 0):0];
    end
  end else begin : g_shift_left
    assign g_v = {g_sum, {(-Sh){1'b0}}};
  end

  assign g_ovf = !((&g_v[VW-1:OutW-1]) || !(|g_v[VW-1:OutW-1]));
  assign l7_d  = g_ovf ? {g_v[VW-1], {(OutW - 1){~g_v[VW-1]}}} : g_v[OutW-1:0];

  ru_pipe #(.Width(OutW), .Depth(Cuts[6] ? 1 : 0)) u_cut7 (
    .clk_i, .rst_ni, .valid_i(l6_valid_q), .data_i(l7_d), .valid_o(l7_valid_q), .data_o(l7_q));

  // Output registers for Stages > MaxUsefulStages.
  ru_pipe #(.Width(OutW), .Depth(OutRegs)) u_out (
    .clk_i, .rst_ni, .valid_i(l7_valid_q), .data_i(l7_q), .valid_o(out_valid_o), .data_o(value_o));

endmodule
