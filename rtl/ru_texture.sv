// ru_texture: procedural texture unit (issue 15 §2; Kensler sec. 6.2 future work): spectral
// sums of noise octaves (fBm, turbulence) and the renderer's material transfer functions
// (granite, marble, wood), around Units noise units (ru_noise_trunc, or ru_noise with Trunc = 0).
//
// Bit for bit equal to the C++ model ru::noise::FixedTexture (model/src/noise/texture.cpp; the
// steps and scales are documented in model/include/rayunits/noise/texture.hpp and docs/NOISE.md
// "The procedural texture unit").
//
// A request (x_i, y_i, z_i, mode_i, oct_i) is accepted in a cycle with in_valid_i && in_ready_o.
// It takes n = clamp(oct_i, 1, Octaves) octaves in K = ceil(n / Units) groups: group j goes to
// the noise units in the j-th cycle from acceptance (group 0 in the acceptance cycle itself),
// lane u evaluating octave o = j Units + u (lanes with o >= n idle). in_ready_o is low while
// groups are pending, so one request is accepted every K cycles at most. The noise results of
// group j leave the noise units Stages cycles later and are summed into the accumulator; after the
// last group the transfer function is applied and the result is registered:
//   latency = K + Stages + RootStages cycles from acceptance; results leave in acceptance order.
// Units = Octaves gives one result per clock for every n (K = 1); Units = 1 reuses one noise unit
// for n cycles. The square root of the wood texture runs in a pipeline of its own, Stages +
// RootStages deep, from the acceptance cycle (cuts placed by ru_pipe_pkg); the last group's sum
// waits RootStages cycles for it (RootStages registers before the transfer functions), and the
// root is held until that sum arrives.
//
//   x_i, y_i, z_i  signed, IntBits integer and FracBits + E fraction bits, E = LacShift (Octaves-1):
//                  u = x_i / 2^(FracBits+E) in half-resolution cells (the noise unit's coordinate
//                  with E more bits for the octaves: octave o's noise input is x_i >>> (E - LacShift o))
//   mode_i         0 fbm, 1 turbulence, 2 granite, 3 marble, 4 wood (5..7: as fbm)
//   oct_i          octaves of this request (clamped to 1..Octaves)
//   value_o        signed OutF+2 bits, value_o / 2^OutF
module ru_texture #(
  parameter int unsigned FracBits  = 8,   // B of the noise units
  parameter int unsigned IntBits   = 8,
  parameter int unsigned OutW      = 10,  // the noise units' output width
  parameter int unsigned Trunc     = 1,   // 1: ru_noise_trunc, 0: ru_noise
  parameter int unsigned Octaves   = 8,   // 1..8
  parameter int unsigned Units     = 4,   // noise units: 1, 2, 4 or 8
  parameter int unsigned LacShift  = 1,   // lacunarity 2^LacShift, 1..2
  parameter int unsigned GainShift = 1,   // gain 2^-GainShift, 1..2
  parameter int unsigned OutF      = 12,  // output fraction bits, 4..20
  parameter int unsigned RootStages = 2,  // extra cycles for the square root, 0..8
  parameter int unsigned Stages    = 4    // the noise units' Stages
) (
  input  logic                                         clk_i,
  input  logic                                         rst_ni,
  input  logic                                         in_valid_i,
  output logic                                         in_ready_o,
  input  logic [IntBits+FracBits+LacShift*(Octaves-1)-1:0] x_i,
  input  logic [IntBits+FracBits+LacShift*(Octaves-1)-1:0] y_i,
  input  logic [IntBits+FracBits+LacShift*(Octaves-1)-1:0] z_i,
  input  logic [2:0]                                   mode_i,
  input  logic [3:0]                                   oct_i,
  output logic                                         out_valid_o,
  output logic [OutF+1:0]                              value_o
);

  localparam int unsigned B    = FracBits;
  localparam int unsigned NW   = IntBits + FracBits;               // noise input words
  localparam int unsigned E    = LacShift * (Octaves - 1);
  localparam int unsigned InW  = NW + E;
  localparam int unsigned InF  = B + E;                            // fraction bits of the inputs
  localparam int unsigned SF   = OutW + GainShift * (Octaves - 1);  // fraction bits of the sums
  localparam int unsigned AccW = SF + 2;                           // signed, |sum| < 2
  localparam int unsigned OW   = OutF + 2;
  localparam int unsigned JW   = 4;                                // group index / count (<= 8)
  localparam int unsigned MF   = (InF > SF + 1) ? InF : SF + 1;    // marble: fraction bits
  localparam int unsigned WF   = (InF - 2 > SF) ? InF - 2 : SF;    // wood: fraction bits
  localparam int unsigned RW   = InW;                              // square root width

  // The noise units' useful maximum (their seven levels, ru_noise_trunc / ru_noise); the registry
  // entry equals it and equals the noise units' (ctest Registry.*); registers beyond it are the
  // noise units' output registers.
  localparam int unsigned MaxUsefulStages = 7;
  /* verilator lint_off UNUSEDPARAM */  // read by the registry check (verilator --xml-only)
  localparam int unsigned OutRegs = (Stages > MaxUsefulStages) ? Stages - MaxUsefulStages : 0;
  /* verilator lint_on UNUSEDPARAM */

  if (Octaves < 1 || Octaves > 8) begin : gen_oct_check
    $error("ru_texture: Octaves must be 1..8, got %0d", Octaves);
  end
  if (Units != 1 && Units != 2 && Units != 4 && Units != 8) begin : gen_units_check
    $error("ru_texture: Units must be 1, 2, 4 or 8, got %0d", Units);
  end
  if (LacShift < 1 || LacShift > 2 || GainShift < 1 || GainShift > 2) begin : gen_shift_check
    $error("ru_texture: LacShift and GainShift must be 1..2");
  end
  if (OutF < 4 || OutF > 20) begin : gen_outf_check
    $error("ru_texture: OutF must be 4..20, got %0d", OutF);
  end
  if (InW > 31 || SF > 30) begin : gen_width_check
    $error("ru_texture: input words of %0d bits (max 31) or sums of %0d fraction bits (max 30)", InW, SF);
  end

  // ------------------------------------------------------------------------------------------
  // Sequencer: the request is held while its groups are issued.
  logic [InW-1:0] x_q, y_q, z_q;
  logic [2:0]     mode_q;
  logic [3:0]     n_q;
  logic [JW-1:0]  j_q;      // next group to issue (busy when j_q != 0)
  logic [JW-1:0]  k_q;      // groups of the held request
  logic           busy_q;
  logic           accept;
  logic [3:0]     n_in;
  logic [JW-1:0]  k_in;

  assign in_ready_o = !busy_q;
  assign accept     = in_valid_i && in_ready_o;
  assign n_in       = (oct_i == 4'd0) ? 4'd1 : (32'(oct_i) > Octaves) ? 4'(Octaves) : oct_i;
  // ceil(n / Units) with Units a power of two
  assign k_in       = JW'((32'(n_in) + Units - 1) / Units);

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      busy_q <= 1'b0;
      j_q    <= '0;
    end else if (accept) begin
      busy_q <= k_in > 1;
      j_q    <= JW'(1);
    end else if (busy_q) begin
      busy_q <= (j_q + 1'b1) < k_q;
      j_q    <= j_q + 1'b1;
    end
  end
  always_ff @(posedge clk_i) begin
    if (accept) begin
      x_q    <= x_i;
      y_q    <= y_i;
      z_q    <= z_i;
      mode_q <= mode_i;
      n_q    <= n_in;
      k_q    <= k_in;
    end
  end

  // The group issued in this cycle.
  logic           g_valid;
  logic [InW-1:0] g_x, g_y, g_z;
  logic [2:0]     g_mode;
  logic [3:0]     g_n;
  logic [JW-1:0]  g_j, g_k;
  assign g_valid = accept || busy_q;
  assign g_x     = accept ? x_i : x_q;
  assign g_y     = accept ? y_i : y_q;
  assign g_z     = accept ? z_i : z_q;
  assign g_mode  = accept ? mode_i : mode_q;
  assign g_n     = accept ? n_in : n_q;
  assign g_j     = accept ? '0 : j_q;
  assign g_k     = accept ? k_in : k_q;

  // ------------------------------------------------------------------------------------------
  // Noise lanes: octave o = j Units + u, input word = coordinate >>> (E - LacShift o), low NW bits.
  logic [Units-1:0]      lane_on;
  logic [Units*OutW-1:0] lane_v;
  logic [Units-1:0]      lane_vld;

  for (genvar u = 0; u < Units; u++) begin : g_lane
    logic [JW+3:0] o;
    logic [NW-1:0] nx, ny, nz;
    assign o = (JW+4)'(g_j) * (JW+4)'(Units) + (JW+4)'(u);
    assign lane_on[u] = 32'(o) < 32'(g_n);
    always_comb begin
      nx = g_x[E+:NW];
      ny = g_y[E+:NW];
      nz = g_z[E+:NW];
      for (int k = 1; k < Octaves; k++) begin
        if (32'(o) == k) begin
          nx = NW'(g_x >> (E - LacShift * k));
          ny = NW'(g_y >> (E - LacShift * k));
          nz = NW'(g_z >> (E - LacShift * k));
        end
      end
    end
    if (Trunc != 0) begin : g_trunc
      ru_noise_trunc #(.FracBits(FracBits), .IntBits(IntBits), .OutW(OutW), .Stages(Stages)) u_noise (
        .clk_i, .rst_ni, .in_valid_i(g_valid), .x_i(nx), .y_i(ny), .z_i(nz),
        .out_valid_o(lane_vld[u]), .value_o(lane_v[u*OutW+:OutW]));
    end else begin : g_full
      ru_noise #(.FracBits(FracBits), .IntBits(IntBits), .OutW(OutW), .Stages(Stages)) u_noise (
        .clk_i, .rst_ni, .in_valid_i(g_valid), .x_i(nx), .y_i(ny), .z_i(nz),
        .out_valid_o(lane_vld[u]), .value_o(lane_v[u*OutW+:OutW]));
    end
  end

  // The group's control travels beside the noise units (same latency).
  localparam int unsigned MetaW = 1 + 3 + JW + Units;
  logic             m_valid;
  logic [MetaW-1:0] m_q;
  logic             m_last;
  logic [2:0]       m_mode;
  logic [JW-1:0]    m_j;
  logic [Units-1:0] m_on;
  ru_pipe #(.Width(MetaW), .Depth(Stages)) u_meta (
    .clk_i, .rst_ni, .valid_i(g_valid), .data_i({g_j == g_k - 1'b1, g_mode, g_j, lane_on}),
    .valid_o(m_valid), .data_o(m_q));
  assign {m_last, m_mode, m_j, m_on} = m_q;
  logic unused_lane_vld;
  assign unused_lane_vld = ^lane_vld;

  // ------------------------------------------------------------------------------------------
  // Square root of X^2 + Y^2 (wood) from the acceptance cycle, Stages deep: a restoring
  // recurrence (one root bit per step from the top), the cuts placed by ru_pipe_pkg over the
  // segments {squares, step RW-1, ..., step 0}; X travels along (marble).
  localparam int unsigned SqSeg = RW + 1;
  function automatic logic [ru_pipe_pkg::WW-1:0] sq_weights();
    logic [ru_pipe_pkg::WW-1:0] w;
    w = '0;
    w = ru_pipe_pkg::put_w(w, 0, 8);  // the two squares and their sum (estimate, 100 ps units)
    for (int i = 1; i < SqSeg; i++) w = ru_pipe_pkg::put_w(w, i, 4);  // one compare-subtract
    sq_weights = w;
  endfunction
  localparam int unsigned SqLat = Stages + RootStages;
  localparam logic [ru_pipe_pkg::MaxSeg:0] SqCuts = ru_pipe_pkg::cut_mask(sq_weights(), SqSeg, SqLat);
  localparam int unsigned SqOutRegs = ru_pipe_pkg::out_regs(SqCuts, SqLat);
  logic unused_sq_cuts;
  assign unused_sq_cuts = ^SqCuts[ru_pipe_pkg::MaxSeg:SqSeg-1];

  localparam int unsigned SqDW = 2 * RW + RW + InW;  // remainder, root, X
  logic [SqSeg*SqDW-1:0] sq_d, sq_q;
  logic [SqSeg-1:0]      sq_vd, sq_vq;

  // segment 0: X^2 + Y^2
  logic signed [2*RW-1:0] sq_ex, sq_ey;
  assign sq_ex = (2*RW)'($signed(x_i));
  assign sq_ey = (2*RW)'($signed(y_i));
  assign sq_d[0+:SqDW] = {(2*RW)'(sq_ex * sq_ex) + (2*RW)'(sq_ey * sq_ey), RW'(0), x_i};
  assign sq_vd[0] = accept;
  for (genvar s = 0; s < SqSeg; s++) begin : g_sq
    if (s > 0) begin : g_step
      localparam int unsigned I = RW - s;  // root bit decided in this step
      // Only rem >> 2I takes part: it is < 4 (root >> I) + 4 < 2^(RW-I+2) before this step (the
      // recurrence's invariant), so HW bits hold it; the bits below 2I are the radicand's.
      localparam int unsigned HW = (RW - I + 3 < 2 * RW - 2 * I) ? RW - I + 3 : 2 * RW - 2 * I;
      logic [2*RW-1:0] rem, rem_n;
      logic [HW-1:0]   hi, trial;
      logic [RW-1:0]   root;
      logic [InW-1:0]  xx;
      assign {rem, root, xx} = sq_q[(s-1)*SqDW+:SqDW];
      assign hi    = rem[2*I+:HW];
      assign trial = HW'({(root >> (I + 1)), 2'b01});  // (2 root_hi + 2^I) 2^I / 2^(2I)
      always_comb begin : p_step
        rem_n = rem;
        if (trial <= hi) rem_n[2*I+:HW] = hi - trial;
      end
      assign sq_d[s*SqDW+:SqDW] = {rem_n, (trial <= hi) ? (root | (RW'(1) << I)) : root, xx};
      assign sq_vd[s] = sq_vq[s-1];
    end
    ru_pipe #(.Width(SqDW), .Depth((s + 1 < SqSeg && SqCuts[s]) ? 1 : 0)) u_cut (
      .clk_i, .rst_ni, .valid_i(sq_vd[s]), .data_i(sq_d[s*SqDW+:SqDW]), .valid_o(sq_vq[s]),
      .data_o(sq_q[s*SqDW+:SqDW]));
  end
  logic            geo_valid;
  logic [SqDW-1:0] geo_out;
  ru_pipe #(.Width(SqDW), .Depth(SqOutRegs)) u_sq_out (
    .clk_i, .rst_ni, .valid_i(sq_vq[SqSeg-1]), .data_i(sq_q[(SqSeg-1)*SqDW+:SqDW]), .valid_o(geo_valid),
    .data_o(geo_out));
  // held until the request's last group arrives (the next request's root arrives later)
  logic [RW+InW-1:0] geo_q, geo;
  always_ff @(posedge clk_i) if (geo_valid) geo_q <= geo_out[RW+InW-1:0];
  assign geo = geo_valid ? geo_out[RW+InW-1:0] : geo_q;
  logic unused_rem;
  assign unused_rem = ^geo_out[SqDW-1:RW+InW];
  logic [RW-1:0]  t_root;
  logic [InW-1:0] t_x;
  assign {t_root, t_x} = geo;
  logic unused_geo;  // the transfer functions use the low bits (frac of the sums)
  assign unused_geo = ^{t_root, t_x};

  // ------------------------------------------------------------------------------------------
  // Accumulate: lane u of group j is octave o = j Units + u, weight 2^(GainShift (Octaves-1-o)).
  logic             absolute;
  logic [AccW-1:0]  acc_q, acc_in, acc_d;
  assign absolute = (m_mode == 3'd1) || (m_mode == 3'd2) || (m_mode == 3'd3);
  always_comb begin : p_acc
    logic signed [OutW:0] v;
    logic [AccW-1:0]      term;
    logic [7:0]           o;
    acc_in = '0;
    v = '0;
    term = '0;
    o = '0;
    for (int u = 0; u < Units; u++) begin
      v = {lane_v[u*OutW+OutW-1], lane_v[u*OutW+:OutW]};
      if (absolute && v < 0) v = -v;
      o = 8'(m_j) * 8'(Units) + 8'(u);
      term = '0;
      for (int k = 0; k < Octaves; k++)
        if (o == 8'(k)) term = AccW'($signed(v)) << (GainShift * (Octaves - 1 - k));
      if (m_on[u]) acc_in = acc_in + term;
    end
  end
  assign acc_d = (m_j == '0) ? acc_in : acc_q + acc_in;
  always_ff @(posedge clk_i) if (m_valid) acc_q <= acc_d;

  // The complete sum waits RootStages cycles for the square root.
  logic            f_valid;
  logic [2:0]      f_mode;
  logic [AccW-1:0] f_sum;
  ru_pipe #(.Width(AccW + 3), .Depth(RootStages)) u_final (
    .clk_i, .rst_ni, .valid_i(m_valid && m_last), .data_i({m_mode, acc_d}), .valid_o(f_valid),
    .data_o({f_mode, f_sum}));

  // ------------------------------------------------------------------------------------------
  // Transfer functions on the complete sum (exact), then the floor to OutF fraction bits.
  function automatic logic [OW-1:0] floor_to(input logic [63:0] r, input int unsigned frac);
    floor_to = (frac >= OutF) ? OW'(r >> (frac - OutF)) : OW'(r << (OutF - frac));
  endfunction
  logic [OW-1:0] t_val;
  always_comb begin : p_transfer
    logic signed [AccW+1:0] t15;
    logic [63:0]            r;
    logic [MF:0]            ms;
    logic [WF-1:0]          wg;
    logic signed [63:0]     sacc;
    sacc = 64'($signed(f_sum));
    r  = '0;
    ms = '0;
    wg = '0;
    t15 = '0;
    case (f_mode)
      3'd2: begin  // granite: min(1, 1.5 T)
        t15 = (AccW+2)'($signed(f_sum)) * 3;
        r = (64'(t15) > (64'd1 << (SF + 1))) ? (64'd1 << (SF + 1)) : 64'(t15);
        t_val = floor_to(r, SF + 1);
      end
      3'd3: begin  // marble: |2 frac(u_x + 1.5 T) - 1|
        ms = (MF+1)'(((MF+1)'(t_x) << (MF - InF)) + ((MF+1)'(sacc * 3) << (MF - SF - 1)));
        ms[MF] = 1'b0;  // frac: MF fraction bits
        r = 64'(ms) << 1;
        r = (r >= (64'd1 << MF)) ? r - (64'd1 << MF) : (64'd1 << MF) - r;
        t_val = floor_to(r, MF);
      end
      3'd4: begin  // wood: frac(4 root + S)^2
        wg = WF'((WF'(t_root) << (WF - (InF - 2))) + (WF'(sacc) << (WF - SF)));
        r = 64'(wg) * 64'(wg);
        t_val = floor_to(r, 2 * WF);
      end
      default: begin  // fbm, turbulence: the sum (arithmetic shift = floor)
        t_val = (SF >= OutF) ? OW'(sacc >>> (SF - OutF)) : OW'(sacc <<< (OutF - SF));
      end
    endcase
  end

  ru_pipe #(.Width(OW), .Depth(1)) u_out (
    .clk_i, .rst_ni, .valid_i(f_valid), .data_i(t_val), .valid_o(out_valid_o), .data_o(value_o));

endmodule
