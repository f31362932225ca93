// ru_noise: hardware gradient noise unit (Kensler's dissertation sec. 4.9-4.13, Fig. 4.13).
//
// Half-resolution-grid gradient noise with the xor hash of three per-axis tables, a relaxed
// 64-entry gradient table and the radial kernel 4t^5 - 3t^4 on the squared distance. Fully
// pipelined: one result per clock, latency = Stages cycles (0 = combinational).
//
// Bit for bit equal to the C++ model ru::noise::FixedNoise (model/src/noise/fixed.cpp); the
// numbered steps (1)..(13) below are the same as there and in docs/NOISE.md.
//
//   x_i, y_i, z_i  signed two's complement, IntBits integer bits (incl. sign) and FracBits
//                  fraction bits: u = x_i / 2^FracBits in half-resolution cells; the cell index
//                  is floor(u) mod 256 (coordinates wrap with the tables).
//   value_o        signed OutW bits, value_o / 2^(OutW+1) ~= N(u), the half-resolution noise in
//                  cell units (|N| <= 0.1807, docs/NOISE.md); saturated to OutW bits.
//
// Tables are `case` functions generated into ru_noise_tables.svh (do not edit that file; the
// generator is `rayunits noise tables --write`).
module ru_noise #(
  parameter int unsigned FracBits = 8,   // B, 4..16
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
  localparam int unsigned QW    = B + 1;      // squares, t, t^2, t^4, t^5: unsigned, <= 2^B
  localparam int unsigned DW    = B + 2;      // squared distance: unsigned, <= 3 * 2^B
  localparam int unsigned GradW = B + 2;      // gradient component: signed, |g| <= 2^B
  localparam int unsigned AW    = B + 1;      // offset f - corner bit: signed, [-2^B, 2^B)
  localparam int unsigned PW    = 2 * B + 5;  // dot product before truncation: signed
  localparam int unsigned WW    = B + 2;      // kernel weight 4t^5 - 3t^4: signed
  localparam int unsigned DotW  = B + 2;      // truncated dot product: signed
  localparam int unsigned CW    = WW + DotW;  // w * dot: signed
  localparam int unsigned SumW  = 2 * B + 6;  // sum of the eight w * dot: signed
  localparam int          Sh    = 2 * B - OutW - 1;  // output shift (right if > 0)
  localparam int unsigned VW    = OutW + 7;   // scaled sum (= SumW - Sh)

  // Gradient narrowing (docs/NOISE.md): g = floor((q16 + 2^(15-B)) / 2^(16-B)).
  localparam int GradShift = 16 - B;
  localparam int GradRnd   = (GradShift > 0) ? (1 << (GradShift - 1)) : 0;

  // Pipelining (ru_pipe_pkg, the mechanism of every unit). The seven levels below are the
  // segments of the chain; their weights are the logic depths per level measured with Yosys at
  // the default widths (docs/NOISE.md, "level depths"; used for every width). The output register
  // (after level 7) is the first one placed, the others go where ru_pipe_pkg::cut_mask puts
  // them (cut_mask_reg_out). Bit k-1 of Cuts = register after level k:
  //   1 split + hash lookup + squares   2 xor + gradient lookup + distance, t
  //   3 t^2 + dot products              4 t^4
  //   5 t^5 + kernel weight             6 w * dot
  //   7 sum, scaling, saturation (output)
  // Stages 1..7 give 7 | 4,7 | 3,5,7 | 2,4,5,7 | 1,3,4,5,7 | 1,3,4,5,6,7 | all; Stages > 7 adds
  // Stages - 7 further output registers.
  localparam int unsigned NLevels = 7;
  localparam logic [ru_pipe_pkg::WW-1:0] LevelDepth = {{(ru_pipe_pkg::WW - 8 * NLevels){1'b0}},
      8'd17, 8'd27, 8'd31, 8'd24, 8'd21, 8'd22, 8'd23};  // level 7 .. level 1
  localparam logic [ru_pipe_pkg::MaxSeg:0] PipeCuts =
      ru_pipe_pkg::cut_mask_reg_out(LevelDepth, NLevels, Stages);
  localparam logic [NLevels-1:0] Cuts = PipeCuts[NLevels-1:0];
  // Useful maximum of Stages (every cut point registered) and the registers placed at the
  // output beyond it (Stages - MaxUsefulStages, else 0).
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(NLevels) + 1;
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(PipeCuts, Stages);
  if (OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_noise: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  logic [ru_pipe_pkg::MaxSeg-NLevels:0] unused_pipe_cuts;
  assign unused_pipe_cuts = PipeCuts[ru_pipe_pkg::MaxSeg:NLevels];

  // ru_noise_gq: one stored Q1.16 gradient component narrowed to GradW bits (a constant
  // function: its arguments in ru_noise_grad are literals, so synthesis folds it).
  function automatic logic [GradW-1:0] ru_noise_gq(input logic signed [17:0] q16);
    ru_noise_gq = GradW'((19'(q16) + 19'(GradRnd)) >>> GradShift);
  endfunction

  `include "ru_noise_tables.svh"

  // ------------------------------------------------------------------------------------------
  // Level 1: (1) split, (2) hash lookup, (3) squares of f and 1 - f (floor to B bits).
  localparam int unsigned L1W = 3 * B + 3 * 12 + 6 * QW;
  logic [L1W-1:0] l1_d, l1_q;
  logic           l1_valid_q;
  logic [3*B-1:0]  a_fr;
  logic [3*12-1:0] a_hash;
  logic [6*QW-1:0] a_sq;

  for (genvar a = 0; a < 3; a++) begin : g_axis
    logic [InW-1:0]   coord;
    logic [7:0]       cell_idx;
    logic [B-1:0]     fr;
    logic [B:0]       om;        // 2^B - f, in [1, 2^B]
    logic [2*B-1:0]   sq0_full;
    logic [2*B+1:0]   sq1_full;
    logic [11:0]      hash;

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

    assign fr       = coord[B-1:0];
    assign om       = {1'b1, {B{1'b0}}} - {1'b0, fr};
    assign sq0_full = fr * fr;
    assign sq1_full = {{(B+1){1'b0}}, om} * {{(B+1){1'b0}}, om};

    assign a_fr[a*B+:B]               = fr;
    assign a_hash[a*12+:12]           = hash;
    assign a_sq[(2*a)*QW+:QW]         = {1'b0, sq0_full[2*B-1:B]};
    assign a_sq[(2*a+1)*QW+:QW]       = sq1_full[2*B:B];
    logic unused_sq1;
    assign unused_sq1 = sq1_full[2*B+1] ^ (^sq1_full[B-1:0]) ^ (^sq0_full[B-1:0]);
  end

  assign l1_d = {a_sq, a_hash, a_fr};

  ru_pipe #(.Width(L1W), .Depth(Cuts[0] ? 1 : 0)) u_cut1 (
    .clk_i, .rst_ni, .valid_i(in_valid_i), .data_i(l1_d), .valid_o(l1_valid_q), .data_o(l1_q));

  // ------------------------------------------------------------------------------------------
  // Level 2: (4) squared distance and t = max(0, 1 - d); (9) xor hash and gradient lookup.
  localparam int unsigned L2W = 3 * B + 8 * 3 * GradW + 8 * QW;
  logic [L2W-1:0] l2_d, l2_q;
  logic           l2_valid_q;
  logic [3*B-1:0]        b_fr;
  logic [3*12-1:0]       b_hash;
  logic [6*QW-1:0]       b_sq;
  logic [8*3*GradW-1:0]  b_g;
  logic [8*QW-1:0]       b_t;

  assign {b_sq, b_hash, b_fr} = l1_q;

  for (genvar c = 0; c < 8; c++) begin : g_corner_b
    localparam int unsigned Cx = c % 2, Cy = (c / 2) % 2, Cz = c / 4;
    logic [5:0]    h;
    logic [DW-1:0] d;
    assign h = b_hash[0*12+6*Cx+:6] ^ b_hash[1*12+6*Cy+:6] ^ b_hash[2*12+6*Cz+:6];
    assign b_g[c*3*GradW+:3*GradW] = ru_noise_grad(h);
    assign d = DW'(b_sq[(0+Cx)*QW+:QW]) + DW'(b_sq[(2+Cy)*QW+:QW]) + DW'(b_sq[(4+Cz)*QW+:QW]);
    assign b_t[c*QW+:QW] = (d < DW'(1 << B)) ? QW'(DW'(1 << B) - d) : '0;
  end

  assign l2_d = {b_t, b_g, b_fr};

  ru_pipe #(.Width(L2W), .Depth(Cuts[1] ? 1 : 0)) u_cut2 (
    .clk_i, .rst_ni, .valid_i(l1_valid_q), .data_i(l2_d), .valid_o(l2_valid_q), .data_o(l2_q));

  // ------------------------------------------------------------------------------------------
  // Level 3: (5) t^2; (10) dot product of the offset with the gradient, floor to B bits.
  localparam int unsigned L3W = 8 * QW + 8 * QW + 8 * DotW;
  logic [L3W-1:0] l3_d, l3_q;
  logic           l3_valid_q;
  logic [3*B-1:0]       c_fr;
  logic [8*3*GradW-1:0] c_g;
  logic [8*QW-1:0]      c_t, c_t2;
  logic [8*DotW-1:0]    c_dot;

  assign {c_t, c_g, c_fr} = l2_q;

  for (genvar c = 0; c < 8; c++) begin : g_corner_c
    localparam int unsigned Cx = c % 2, Cy = (c / 2) % 2, Cz = c / 4;
    logic [2*QW-1:0]         tt;
    logic signed [AW-1:0]    ax, ay, az;
    logic signed [GradW-1:0] gx, gy, gz;
    logic signed [PW-1:0]    p;
    assign tt = {{QW{1'b0}}, c_t[c*QW+:QW]} * {{QW{1'b0}}, c_t[c*QW+:QW]};
    assign c_t2[c*QW+:QW] = tt[2*B:B];
    // offset f - corner bit as a signed B+1-bit number: {corner bit, f}
    assign ax = {1'(Cx), c_fr[0*B+:B]};
    assign ay = {1'(Cy), c_fr[1*B+:B]};
    assign az = {1'(Cz), c_fr[2*B+:B]};
    assign gx = c_g[(3*c+0)*GradW+:GradW];
    assign gy = c_g[(3*c+1)*GradW+:GradW];
    assign gz = c_g[(3*c+2)*GradW+:GradW];
    assign p = PW'(ax) * PW'(gx) + PW'(ay) * PW'(gy) + PW'(az) * PW'(gz);
    assign c_dot[c*DotW+:DotW] = p[B+DotW-1:B];
    logic unused_p;
    assign unused_p = (^tt[2*QW-1:2*B+1]) ^ (^tt[B-1:0]) ^ (^p[PW-1:B+DotW]) ^ (^p[B-1:0]);
  end

  assign l3_d = {c_dot, c_t2, c_t};

  ru_pipe #(.Width(L3W), .Depth(Cuts[2] ? 1 : 0)) u_cut3 (
    .clk_i, .rst_ni, .valid_i(l2_valid_q), .data_i(l3_d), .valid_o(l3_valid_q), .data_o(l3_q));

  // ------------------------------------------------------------------------------------------
  // Level 4: (6) t^4 = floor(t^2 * t^2) to B bits.
  localparam int unsigned L4W = L3W;
  logic [L4W-1:0] l4_d, l4_q;
  logic           l4_valid_q;
  logic [8*QW-1:0]   d_t, d_t2, d_t4;
  logic [8*DotW-1:0] d_dot;

  assign {d_dot, d_t2, d_t} = l3_q;

  for (genvar c = 0; c < 8; c++) begin : g_corner_d
    logic [2*QW-1:0] tt;
    assign tt = {{QW{1'b0}}, d_t2[c*QW+:QW]} * {{QW{1'b0}}, d_t2[c*QW+:QW]};
    assign d_t4[c*QW+:QW] = tt[2*B:B];
    logic unused_tt;
    assign unused_tt = (^tt[2*QW-1:2*B+1]) ^ (^tt[B-1:0]);
  end

  assign l4_d = {d_dot, d_t4, d_t};

  ru_pipe #(.Width(L4W), .Depth(Cuts[3] ? 1 : 0)) u_cut4 (
    .clk_i, .rst_ni, .valid_i(l3_valid_q), .data_i(l4_d), .valid_o(l4_valid_q), .data_o(l4_q));

  // ------------------------------------------------------------------------------------------
  // Level 5: (7) t^5 = floor(t^4 * t) to B bits; (8) w = 4 t^5 - 3 t^4 (exact).
  localparam int unsigned L5W = 8 * WW + 8 * DotW;
  logic [L5W-1:0] l5_d, l5_q;
  logic           l5_valid_q;
  logic [8*QW-1:0]   e_t, e_t4;
  logic [8*DotW-1:0] e_dot;
  logic [8*WW-1:0]   e_w;

  assign {e_dot, e_t4, e_t} = l4_q;

  for (genvar c = 0; c < 8; c++) begin : g_corner_e
    logic [2*QW-1:0] tt;
    logic [B:0]      t5;
    logic [B+3:0]    wf;  // 4 t^5 - 3 t^4 modulo 2^(B+4); the value fits WW signed bits
    assign tt = {{QW{1'b0}}, e_t4[c*QW+:QW]} * {{QW{1'b0}}, e_t[c*QW+:QW]};
    assign t5 = tt[2*B:B];
    assign wf = {1'b0, t5, 2'b00} - ({2'b00, e_t4[c*QW+:QW], 1'b0} + {3'b000, e_t4[c*QW+:QW]});
    assign e_w[c*WW+:WW] = wf[WW-1:0];
    logic unused_w;
    assign unused_w = (^tt[2*QW-1:2*B+1]) ^ (^tt[B-1:0]) ^ (^wf[B+3:WW]);
  end

  assign l5_d = {e_dot, e_w};

  ru_pipe #(.Width(L5W), .Depth(Cuts[4] ? 1 : 0)) u_cut5 (
    .clk_i, .rst_ni, .valid_i(l4_valid_q), .data_i(l5_d), .valid_o(l5_valid_q), .data_o(l5_q));

  // ------------------------------------------------------------------------------------------
  // Level 6: (11) contributions w * dot (exact).
  localparam int unsigned L6W = 8 * CW;
  logic [L6W-1:0]    l6_d, l6_q;
  logic              l6_valid_q;
  logic [8*DotW-1:0] f_dot;
  logic [8*WW-1:0]   f_w;

  assign {f_dot, f_w} = l5_q;

  for (genvar c = 0; c < 8; c++) begin : g_corner_f
    logic signed [WW-1:0]   w;
    logic signed [DotW-1:0] dt;
    logic signed [CW-1:0]   prod;
    assign w    = f_w[c*WW+:WW];
    assign dt   = f_dot[c*DotW+:DotW];
    assign prod = CW'(w) * CW'(dt);
    assign l6_d[c*CW+:CW] = prod;
  end

  ru_pipe #(.Width(L6W), .Depth(Cuts[5] ? 1 : 0)) u_cut6 (
    .clk_i, .rst_ni, .valid_i(l5_valid_q), .data_i(l6_d), .valid_o(l6_valid_q), .data_o(l6_q));

  // ------------------------------------------------------------------------------------------
  // Level 7: (12) exact sum of the eight contributions, (13) scaling (floor) and saturation.
  logic [OutW-1:0]        l7_d, l7_q;
  logic                   l7_valid_q;
  logic signed [SumW-1:0] g_sum;
  logic signed [VW-1:0]   g_v;
  logic                   g_ovf;

  always_comb begin
    g_sum = '0;
    for (int c = 0; c < 8; c++) begin
      g_sum = g_sum + SumW'($signed(l6_q[c*CW+:CW]));
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

  // ------------------------------------------------------------------------------------------
  // Output registers for Stages > MaxUsefulStages.
  ru_pipe #(.Width(OutW), .Depth(OutRegs)) u_out (
    .clk_i, .rst_ni, .valid_i(l7_valid_q), .data_i(l7_q), .valid_o(out_valid_o), .data_o(value_o));

endmodule
