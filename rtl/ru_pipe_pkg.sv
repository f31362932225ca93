// ru_pipe_pkg: pipeline-register placement, the one mechanism of every rayunits unit.
//
// A unit's datapath is a chain of nseg combinational segments with a depth estimate each
// (packed weights: segment i at w[i*SegWW +: SegWW]); between segment i and i+1 lies cut
// position i (0 .. nseg-2). cut_mask() turns a requested latency (Stages) into the set of cut
// positions that get a register: binary search on the depth bound of the deepest stage + greedy
// packing (pack_cuts), then registers left over split the heaviest remaining stage that still
// has an unused cut position (split_heaviest). So every cut position is taken before a register
// goes to the unit's output: the useful maximum is nseg-1 (max_useful), and only the
// Stages - (nseg-1) registers beyond it are output registers (extra_regs / out_regs).
//
// Units built of other units (ru_fp_dot3, the ray units) describe their datapath as a chain of
// levels, each level one operation of a "kind" (a table of kinds: segment count and weights of
// each, e.g. ru_fp_pkg::op_nsegs / op_wts for the four FP units). The level chain is placed as
// one chain (unit_cuts); level k's instances get their slice as CutSel (level_cuts) and their
// latency as Stages (level_stages: internal cuts + the cut on the level boundary, which is the
// instances' output register; the last level also takes the output registers). level_cuts_all
// and level_stages_all give every level at once (a table the unit reads with a small function),
// level_span the latency of a range of levels (delay lines of values that skip them).
//
// A unit whose output register is part of its design (ru_noise) uses cut_mask_reg_out: the
// first register goes after the last segment (bit nseg-1), the others are placed by cut_mask.
//
// Mask width: one width for every unit, MaxSeg+1 bits (bit MaxSeg: the "automatic" sentinel of
// the units' CutSel parameter / "infeasible" inside pack_cuts; never a cut position). MaxSeg =
// 255 holds the longest chain (ru_ray_tri_mt e11m52: 133 segments). The loops run to nseg, not
// MaxSeg, so the width costs little elaboration time.
//
// Yosys 0.23 notes: functions assign their name instead of using `return`. Yosys resolves
// `other_pkg::name` inside function bodies and function signatures (they are elaborated where
// they are called), but not in package-level declarations (a localparam or `import` naming
// another package is an error). So ru_fp_pkg uses ru_pipe_pkg only inside its functions, and
// this package knows nothing of the FP units (their shapes come in as arguments).
package ru_pipe_pkg;

  localparam int unsigned MaxSeg = 255;            // segments of one chain
  localparam int unsigned SegWW = 8;               // bits per segment weight
  localparam int unsigned WW = MaxSeg * SegWW;     // packed weights of one chain
  localparam int unsigned MW = MaxSeg + 1;         // cut mask width
  localparam logic [MaxSeg:0] AutoCuts = {1'b1, {MaxSeg{1'b0}}};  // CutSel: automatic placement
  localparam int unsigned MaxLev = 16;             // levels of a level chain
  localparam int unsigned MaxKind = 4;             // kinds of level (4-bit codes 0..MaxKind-1)

  // ---------------------------------------------------------------------------------------
  // Packed segment weights.
  function automatic logic [WW-1:0] put_w(input logic [WW-1:0] v, input int unsigned idx,
                                          input int unsigned w);
    logic [WW-1:0] r;
    r = v;
    r[idx*SegWW+:SegWW] = SegWW'((w > 255) ? 255 : w);
    put_w = r;
  endfunction

  function automatic int unsigned popcount(input logic [MaxSeg:0] m);
    int unsigned c;
    c = 0;
    for (int unsigned i = 0; i < MaxSeg; i++) c += 32'(m[i]);
    popcount = c;
  endfunction

  // ---------------------------------------------------------------------------------------
  // Cut placement of one chain.

  // Greedy packing with stage depth bound `cap`: the cut mask; bit MaxSeg set when the bound
  // cannot be met with at most `stages` cuts.
  function automatic logic [MaxSeg:0] pack_cuts(input logic [WW-1:0] w, input int unsigned nseg,
                                                input int unsigned stages, input int unsigned cap);
    logic [MaxSeg:0] m;
    int unsigned acc, cnt, wi;
    m = '0;
    acc = 0;
    cnt = 0;
    for (int unsigned i = 0; i < nseg; i++) begin
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
    if (cnt > stages) m[MaxSeg] = 1'b1;
    pack_cuts = m;
  endfunction

  // One more cut: in the heaviest stage that still has an unused cut position, at its most
  // balanced position.
  function automatic logic [MaxSeg:0] split_heaviest(input logic [WW-1:0] w,
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
    // the heaviest stage [start, i] that contains at least one unused cut position
    for (int unsigned i = 0; i < nseg; i++) begin
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
    if (best_w > 0) begin
      left = 0;
      best_cost = best_w + 1;
      best_pos = 8'(best_start);
      for (int unsigned i = best_start; i < best_end; i++) begin
        left += 32'(w[i*SegWW+:SegWW]);
        cost = (left > best_w - left) ? left : best_w - left;
        if (cost < best_cost) begin
          best_cost = cost;
          best_pos = 8'(i);
        end
      end
      r[best_pos] = 1'b1;
    end
    split_heaviest = r;
  endfunction

  // The cut positions (0 .. nseg-2) that get a register for `stages` (bit MaxSeg clear).
  function automatic logic [MaxSeg:0] cut_mask(input logic [WW-1:0] w, input int unsigned nseg,
                                               input int unsigned stages);
    int unsigned lo, hi, mid, tot;
    logic [MaxSeg:0] m;
    m = '0;
    if (stages + 1 >= nseg) begin
      // every cut position: what the search and splitting below end with (much faster)
      for (int unsigned i = 0; i + 1 < nseg; i++) m[i] = 1'b1;
    end else begin
      tot = 0;
      for (int unsigned i = 0; i < nseg; i++) tot += 32'(w[i*SegWW+:SegWW]);
      // smallest feasible depth bound in [1, tot]
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
      // registers left over (the bound cannot improve further): split the heaviest stages
      for (int unsigned extra = popcount(m); extra < stages; extra++)
        m = split_heaviest(w, nseg, m);
    end
    cut_mask = (stages == 0) ? '0 : m;
  endfunction

  // Cut mask actually used by a unit: the automatic one unless CutSel (bit MaxSeg clear)
  // overrides it.
  function automatic logic [MaxSeg:0] sel_mask(input logic [MaxSeg:0] cut_sel,
                                               input logic [WW-1:0] w, input int unsigned nseg,
                                               input int unsigned stages);
    sel_mask = ((cut_sel & AutoCuts) != '0) ? cut_mask(w, nseg, stages) : cut_sel;
  endfunction

  // Segment weights of a unit's automatic placement: its SegW parameter if set (packed SegWW-bit
  // weights, e.g. delays measured in a cell library: `rayunits synth --placement delay`), else the
  // unit's own depth estimates.
  function automatic logic [WW-1:0] pick_w(input logic [WW-1:0] seg_w, input logic [WW-1:0] depth_w);
    pick_w = (seg_w != '0) ? seg_w : depth_w;
  endfunction

  // Useful maximum of Stages of a chain of nseg segments: one register per cut position.
  function automatic int unsigned max_useful(input int unsigned nseg);
    max_useful = (nseg > 0) ? nseg - 1 : 0;
  endfunction

  // Registers placed at the output: Stages minus the cuts used inside.
  function automatic int unsigned out_regs(input logic [MaxSeg:0] mask, input int unsigned stages);
    out_regs = (stages > popcount(mask)) ? stages - popcount(mask) : 0;
  endfunction

  // Registers that no cut position is left for: Stages - MaxUsefulStages beyond the maximum,
  // else 0 (= out_regs(cut_mask(..), Stages); the units check it at elaboration).
  function automatic int unsigned extra_regs(input int unsigned stages, input int unsigned max_u);
    extra_regs = (stages > max_u) ? stages - max_u : 0;
  endfunction

  // A unit with a registered output (ru_noise): bit nseg-1 is the register after the last
  // segment and is the first one placed; the other stages-1 go to cut positions by cut_mask.
  // Useful maximum: nseg (max_useful(nseg) + 1).
  function automatic logic [MaxSeg:0] cut_mask_reg_out(input logic [WW-1:0] w,
                                                       input int unsigned nseg,
                                                       input int unsigned stages);
    logic [MaxSeg:0] m;
    // Not `(stages > 1) ? cut_mask(w, nseg, stages - 1) : '0`: Yosys 0.23 evaluates both arms of
    // a conditional in a constant function, and at Stages 0 the unsigned stages - 1 made
    // cut_mask's splitting loop run 2^32 times (ru_noise Stages 0 never finished elaborating).
    m = cut_mask(w, nseg, (stages > 1) ? stages - 1 : 0);
    if (stages > 0) m[nseg-1] = 1'b1;
    cut_mask_reg_out = m;
  endfunction

  // ---------------------------------------------------------------------------------------
  // Level chains. kinds: 4-bit kind code per level, level 0 in the low bits. Kind table:
  // nsegs[8k +: 8] segments and wts[WW*k +: WW] weights of kind k.

  function automatic logic [3:0] kind_of(input logic [4*MaxLev-1:0] kinds, input int unsigned k);
    kind_of = kinds[k*4+:4];
  endfunction

  function automatic int unsigned kind_nseg(input logic [8*MaxKind-1:0] nsegs,
                                            input logic [3:0] k);
    kind_nseg = (32'(k) < MaxKind) ? 32'(nsegs[32'(k)*8+:8]) : 0;
  endfunction

  // Segments of level `lev`.
  function automatic int unsigned level_nseg(input logic [4*MaxLev-1:0] kinds,
                                             input logic [8*MaxKind-1:0] nsegs,
                                             input int unsigned lev);
    level_nseg = kind_nseg(nsegs, kind_of(kinds, lev));
  endfunction

  // First chain segment of level `lev` (= the chain's segment count for lev = nlev).
  function automatic int unsigned level_base(input logic [4*MaxLev-1:0] kinds,
                                             input logic [8*MaxKind-1:0] nsegs,
                                             input int unsigned lev);
    int unsigned b;
    b = 0;
    for (int unsigned i = 0; i < lev; i++) b += level_nseg(kinds, nsegs, i);
    level_base = b;
  endfunction

  // Packed segment weights of the whole chain.
  function automatic logic [WW-1:0] chain_w(input logic [4*MaxLev-1:0] kinds,
                                            input int unsigned nlev,
                                            input logic [8*MaxKind-1:0] nsegs,
                                            input logic [MaxKind*WW-1:0] wts);
    logic [WW-1:0] v;
    int unsigned b, n, k;
    v = '0;
    b = 0;
    for (int unsigned l = 0; l < nlev; l++) begin
      k = 32'(kind_of(kinds, l));
      n = level_nseg(kinds, nsegs, l);
      for (int unsigned i = 0; i < n; i++)
        if (b + i < MaxSeg) v[(b+i)*SegWW+:SegWW] = wts[k*WW+i*SegWW+:SegWW];
      b += n;
    end
    chain_w = v;
  endfunction

  // The unit's cut mask for Stages, and its useful maximum.
  function automatic logic [MaxSeg:0] unit_cuts(input logic [4*MaxLev-1:0] kinds,
                                                input int unsigned nlev,
                                                input logic [8*MaxKind-1:0] nsegs,
                                                input logic [MaxKind*WW-1:0] wts,
                                                input int unsigned stages);
    unit_cuts = cut_mask(chain_w(kinds, nlev, nsegs, wts), level_base(kinds, nsegs, nlev), stages);
  endfunction

  function automatic int unsigned unit_max_useful(input logic [4*MaxLev-1:0] kinds,
                                                  input int unsigned nlev,
                                                  input logic [8*MaxKind-1:0] nsegs);
    unit_max_useful = max_useful(level_base(kinds, nsegs, nlev));
  endfunction

  // CutSel of the instances of level `lev`: its internal cut positions (bit MaxSeg clear).
  function automatic logic [MaxSeg:0] level_cuts(input logic [MaxSeg:0] cuts,
                                                 input logic [4*MaxLev-1:0] kinds,
                                                 input logic [8*MaxKind-1:0] nsegs,
                                                 input int unsigned lev);
    logic [MaxSeg:0] r;
    int unsigned b, n;
    b = level_base(kinds, nsegs, lev);
    n = level_nseg(kinds, nsegs, lev);
    r = '0;
    for (int unsigned i = 0; i + 1 < n; i++) if (b + i < MaxSeg) r[i] = cuts[b+i];
    level_cuts = r;
  endfunction

  // Latency of level `lev`: its internal cuts plus its output register; the last level also
  // takes the output registers (Stages - popcount(cuts)).
  function automatic int unsigned level_stages(input logic [MaxSeg:0] cuts,
                                               input logic [4*MaxLev-1:0] kinds,
                                               input int unsigned nlev,
                                               input logic [8*MaxKind-1:0] nsegs,
                                               input int unsigned lev,
                                               input int unsigned stages);
    int unsigned b, n, s;
    b = level_base(kinds, nsegs, lev);
    n = level_nseg(kinds, nsegs, lev);
    s = popcount(level_cuts(cuts, kinds, nsegs, lev));
    if (lev + 1 == nlev) s += out_regs(cuts, stages);
    else if (b + n >= 1 && b + n - 1 < MaxSeg) s += 32'(cuts[b+n-1]);
    level_stages = s;
  endfunction

  // Every level at once: level k's CutSel at [k*MW +: MW], its latency at [k*32 +: 32].
  function automatic logic [MaxLev*MW-1:0] level_cuts_all(input logic [MaxSeg:0] cuts,
                                                          input logic [4*MaxLev-1:0] kinds,
                                                          input int unsigned nlev,
                                                          input logic [8*MaxKind-1:0] nsegs);
    logic [MaxLev*MW-1:0] r;
    r = '0;
    for (int unsigned l = 0; l < nlev; l++) r[l*MW+:MW] = level_cuts(cuts, kinds, nsegs, l);
    level_cuts_all = r;
  endfunction

  function automatic logic [MaxLev*32-1:0] level_stages_all(input logic [MaxSeg:0] cuts,
                                                            input logic [4*MaxLev-1:0] kinds,
                                                            input int unsigned nlev,
                                                            input logic [8*MaxKind-1:0] nsegs,
                                                            input int unsigned stages);
    logic [MaxLev*32-1:0] r;
    r = '0;
    for (int unsigned l = 0; l < nlev; l++)
      r[l*32+:32] = level_stages(cuts, kinds, nlev, nsegs, l, stages);
    level_stages_all = r;
  endfunction

  // Latency of the levels first .. last-1 (a table from level_stages_all).
  function automatic int unsigned level_span(input logic [MaxLev*32-1:0] lat,
                                             input int unsigned first, input int unsigned last);
    int unsigned s;
    s = 0;
    for (int unsigned l = first; l < last; l++) s += lat[l*32+:32];
    level_span = s;
  endfunction

endpackage
