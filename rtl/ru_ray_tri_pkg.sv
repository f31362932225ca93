// ru_ray_tri_pkg: pipeline-register placement for the ray-triangle units (ru_ray_tri_robust,
// ru_ray_tri_mt). The datapath of such a unit is a sequence of "levels"; every level is one
// FP operation deep on the critical path (a level of subtractions, of multiplications, ...):
//
//   level kind  KAdd (ru_fp_add)  KMul (ru_fp_mul)  KDiv (ru_fp_div)  KCmp (ru_fp_cmp)
//
// The critical path is the chain of the levels' segments (the segments of each FP unit, with
// the depth estimates of ru_fp_pkg::*_seg_w). Stages = the unit's latency in cycles: the Stages
// registers are placed on that chain exactly as ru_fp_pkg::cut_mask places them inside one FP
// unit (binary search on the deepest stage + greedy packing), only with room for 255 segments
// (ru_fp_pkg handles 63; robust e8m23 has 73). A cut at the last segment of a level is the
// output register of that level's instances; Stages beyond the number of cuts used become
// output registers of the last level. Each instance of level k then gets
//   CutSel = level_cuts(...)    (its internal cut positions; bit 63 clear = explicit)
//   Stages = level_stages(...)  (internal cuts + its output register(s)),
// and instances that sit in a level without being on the chain (compares beside a division,
// ...) get the level's latency with automatic placement. Every value that skips a level waits
// in an ru_fp_pipe of that level's latency, so the unit's latency is exactly Stages.
//
// Levels are given as a packed vector of 4-bit kinds, level 0 in the low bits. The segment
// counts and weights of the four FP units come from ru_fp_pkg and are handed in by the unit
// (op_shape()): Yosys 0.23 cannot refer to one package from another.
// Yosys 0.23 note: functions assign their name instead of using `return`.
package ru_ray_tri_pkg;

  localparam int unsigned MaxSeg = 255;      // segments of a whole unit
  localparam int unsigned SegWW = 8;         // = ru_fp_pkg::SegWW
  localparam int unsigned FpMaxSeg = 63;     // = ru_fp_pkg::MaxSeg (segments of one FP unit)
  localparam int unsigned FpWW = FpMaxSeg * SegWW;
  localparam int unsigned MaxLev = 16;

  localparam logic [3:0] KAdd = 4'd0;
  localparam logic [3:0] KMul = 4'd1;
  localparam logic [3:0] KDiv = 4'd2;
  localparam logic [3:0] KCmp = 4'd3;

  // The shape of the four FP units: nsegs[8k +: 8] segments and weights wts[FpWW*k +: FpWW]
  // (ru_fp_pkg::*_seg_w) of kind k. Built by every unit as
  //   {cmp_nseg(), div_nseg(FracW), mul_nseg(FracW), add_nseg()} and
  //   {cmp_seg_w(..), div_seg_w(..), mul_seg_w(..), add_seg_w(..)}.

  function automatic logic [3:0] kind_of(input logic [4*MaxLev-1:0] kinds, input int unsigned k);
    kind_of = kinds[k*4+:4];
  endfunction

  function automatic logic known_kind(input logic [3:0] k);
    known_kind = (k == KAdd) || (k == KMul) || (k == KDiv) || (k == KCmp);
  endfunction

  function automatic int unsigned op_nseg(input logic [31:0] nsegs, input logic [3:0] k);
    op_nseg = known_kind(k) ? 32'(nsegs[32'(k)*8+:8]) : 0;
  endfunction

  // First chain segment of level `lev`.
  function automatic int unsigned level_base(input logic [4*MaxLev-1:0] kinds,
                                             input logic [31:0] nsegs, input int unsigned lev);
    int unsigned b;
    b = 0;
    for (int unsigned i = 0; i < MaxLev; i++) if (i < lev) b += op_nseg(nsegs, kind_of(kinds, i));
    level_base = b;
  endfunction

  // Packed segment weights of the whole chain (segment i at [i*SegWW +: SegWW]).
  function automatic logic [MaxSeg*SegWW-1:0] chain_w(input logic [4*MaxLev-1:0] kinds,
                                                      input int unsigned nlev,
                                                      input logic [31:0] nsegs,
                                                      input logic [4*FpWW-1:0] wts);
    logic [MaxSeg*SegWW-1:0] v;
    int unsigned b, n, k;
    v = '0;
    b = 0;
    for (int unsigned l = 0; l < MaxLev; l++) begin
      if (l < nlev) begin
        k = 32'(kind_of(kinds, l));
        n = op_nseg(nsegs, kind_of(kinds, l));
        for (int unsigned i = 0; i < FpMaxSeg; i++)
          if (i < n && b + i < MaxSeg) v[(b+i)*SegWW+:SegWW] = wts[k*FpWW+i*SegWW+:SegWW];
        b += n;
      end
    end
    chain_w = v;
  endfunction

  // Greedy packing under the stage depth bound `cap` (bit MaxSeg set: infeasible): the packing
  // of ru_fp_pkg::pack_cuts over whole-unit masks (Yosys 0.23 cannot call across packages).
  function automatic logic [MaxSeg:0] pack_cuts(input logic [MaxSeg*SegWW-1:0] w,
                                                input int unsigned nseg,
                                                input int unsigned stages,
                                                input int unsigned cap);
    logic [MaxSeg:0] m;
    int unsigned acc, cnt, wi;
    m = '0;
    acc = 0;
    cnt = 0;
    for (int unsigned i = 0; i < MaxSeg; i++) begin
      if (i < nseg) begin
        wi = 32'(w[i*SegWW+:SegWW]);
        if (wi > cap) m[MaxSeg] = 1'b1;
        if (i > 0 && acc + wi > cap) begin
          m[i-1] = 1'b1;
          cnt++;
          acc = wi;
        end else begin
          acc += wi;
        end
      end
    end
    if (cnt > stages) m[MaxSeg] = 1'b1;
    pack_cuts = m;
  endfunction

  function automatic int unsigned popcount(input logic [MaxSeg:0] m);
    int unsigned c;
    c = 0;
    for (int unsigned i = 0; i < MaxSeg; i++) c += 32'(m[i]);
    popcount = c;
  endfunction

  // ru_fp_pkg::split_heaviest over whole-unit masks: one more cut in the heaviest stage that
  // still has an unused cut position, at its most balanced position.
  function automatic logic [MaxSeg:0] split_heaviest(input logic [MaxSeg*SegWW-1:0] w,
                                                     input int unsigned nseg,
                                                     input logic [MaxSeg:0] m);
    int unsigned start, acc, best_w, best_start, best_end, left, cost, best_cost;
    logic [7:0] best_pos;
    logic [MaxSeg:0] r;
    r = m;
    best_w = 0;
    best_start = 0;
    best_end = 0;
    start = 0;
    acc = 0;
    for (int unsigned i = 0; i < MaxSeg; i++) begin
      if (i < nseg) begin
        acc += 32'(w[i*SegWW+:SegWW]);
        if (i + 1 == nseg || m[i]) begin
          if (i > start && acc > best_w) begin
            best_w = acc;
            best_start = start;
            best_end = i;
          end
          start = i + 1;
          acc = 0;
        end
      end
    end
    if (best_w > 0) begin
      left = 0;
      best_cost = best_w + 1;
      best_pos = 8'(best_start);
      for (int unsigned i = 0; i < MaxSeg; i++) begin
        if (i >= best_start && i < best_end) begin
          left += 32'(w[i*SegWW+:SegWW]);
          cost = (left > best_w - left) ? left : best_w - left;
          if (cost < best_cost) begin
            best_cost = cost;
            best_pos = 8'(i);
          end
        end
      end
      r[best_pos] = 1'b1;
    end
    split_heaviest = r;
  endfunction

  // Cut positions 0 .. nseg-2 (bit MaxSeg always clear in the result).
  function automatic logic [MaxSeg:0] cut_mask(input logic [MaxSeg*SegWW-1:0] w,
                                               input int unsigned nseg,
                                               input int unsigned stages);
    int unsigned lo, hi, mid, tot;
    logic [MaxSeg:0] m;
    tot = 0;
    for (int unsigned i = 0; i < MaxSeg; i++) if (i < nseg) tot += 32'(w[i*SegWW+:SegWW]);
    lo = 1;
    hi = tot;
    while (lo < hi) begin
      mid = (lo + hi) / 2;
      m = pack_cuts(w, nseg, stages, mid);
      if (m[MaxSeg]) lo = mid + 1;
      else hi = mid;
    end
    m = pack_cuts(w, nseg, stages, lo);
    m[MaxSeg] = 1'b0;
    // registers left over: split the heaviest stage that still has an unused cut (as
    // ru_fp_pkg::cut_mask), so only Stages beyond nseg-1 reach the output
    for (int unsigned extra = popcount(m); extra < stages; extra++) m = split_heaviest(w, nseg, m);
    cut_mask = (stages == 0) ? '0 : m;
  endfunction

  function automatic int unsigned popcount64(input logic [63:0] m);
    int unsigned c;
    c = 0;
    for (int unsigned i = 0; i < 63; i++) c += 32'(m[i]);
    popcount64 = c;
  endfunction

  // Useful maximum of Stages of a unit: the number of cut positions of its level chain.
  function automatic int unsigned unit_max_useful(input logic [4*MaxLev-1:0] kinds,
                                                  input int unsigned nlev,
                                                  input logic [31:0] nsegs);
    int unsigned n;
    n = level_base(kinds, nsegs, nlev);
    unit_max_useful = (n > 0) ? n - 1 : 0;
  endfunction

  // Registers at the output of the last level: those no cut position is left for.
  function automatic int unsigned unit_out_regs(input logic [MaxSeg:0] cuts,
                                                input int unsigned stages);
    unit_out_regs = (stages > popcount(cuts)) ? stages - popcount(cuts) : 0;
  endfunction

  // The unit's cut mask for Stages.
  function automatic logic [MaxSeg:0] unit_cuts(input logic [4*MaxLev-1:0] kinds,
                                                input int unsigned nlev,
                                                input logic [31:0] nsegs,
                                                input logic [4*FpWW-1:0] wts,
                                                input int unsigned stages);
    unit_cuts = cut_mask(chain_w(kinds, nlev, nsegs, wts), level_base(kinds, nsegs, nlev), stages);
  endfunction

  // CutSel of the instances of level `lev`: its internal cut positions (bit 63 clear).
  function automatic logic [63:0] level_cuts(input logic [MaxSeg:0] cuts,
                                             input logic [4*MaxLev-1:0] kinds,
                                             input logic [31:0] nsegs, input int unsigned lev);
    logic [63:0] r;
    int unsigned b, n;
    b = level_base(kinds, nsegs, lev);
    n = op_nseg(nsegs, kind_of(kinds, lev));
    r = '0;
    for (int unsigned i = 0; i < 63; i++) if (i + 1 < n && b + i < MaxSeg) r[i] = cuts[b+i];
    level_cuts = r;
  endfunction

  // Latency of level `lev`: its internal cuts plus its output register; the last level also
  // takes every register that no cut needs (Stages - popcount(cuts)).
  function automatic int unsigned level_stages(input logic [MaxSeg:0] cuts,
                                               input logic [4*MaxLev-1:0] kinds,
                                               input int unsigned nlev,
                                               input logic [31:0] nsegs,
                                               input int unsigned lev,
                                               input int unsigned stages);
    int unsigned b, n, s;
    b = level_base(kinds, nsegs, lev);
    n = op_nseg(nsegs, kind_of(kinds, lev));
    s = popcount64(level_cuts(cuts, kinds, nsegs, lev));
    if (lev + 1 == nlev) s += (stages > popcount(cuts)) ? stages - popcount(cuts) : 0;
    else if (b + n - 1 < MaxSeg) s += 32'(cuts[b+n-1]);
    level_stages = s;
  endfunction

endpackage
