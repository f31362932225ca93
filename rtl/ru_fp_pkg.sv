// ru_fp_pkg: the one source of truth shared by every rayunits floating-point unit.
//
// Formats are given to each unit by the parameters ExpW (2..11) and FracW (1..52); the
// encoding, rounding and flag semantics are docs/FORMAT.md. This package holds what the
// units derive from those parameters:
//   * exp_iw()      width of the signed internal exponent,
//   * round_up()    the rounding truth table (the one implementation of it),
//   * csa_*()       the shape of the carry-save multiplier tree (ru_umul),
//   * *_seg_w()     per-unit segment depth estimates and cut_mask(), which turns a
//                   requested latency (Stages) into pipeline-register positions.
//
// Pipelining model. A unit's datapath is a chain of NSeg combinational segments; between
// segment i and i+1 lies cut position i (0..NSeg-2). cut_mask() picks which cut positions get
// a register for a given Stages so that the deepest stage is as shallow as the segment
// granularity allows (binary search on the stage depth bound + greedy packing, using the
// gate-level depth estimates below); registers left over then split the heaviest remaining
// stages at unused cut positions. Only when every cut position is taken do the remaining
// Stages-popcount(mask) registers go to the unit's output (out_regs()).
//
// Yosys 0.23 note: functions assign their name instead of using `return`.
package ru_fp_pkg;

  // Maximum number of segments a unit may have (cut masks are 64 bits; bit 63 is the
  // "automatic" sentinel of the units' CutSel parameter and is never a real cut position).
  localparam int unsigned MaxSeg = 63;
  localparam int unsigned SegWW = 8;  // bits per segment weight in a packed weight vector

  // Rounding modes (the units' Round parameter): 0 RNE, 1 RTZ, 2 RDN, 3 RUP.

  function automatic int unsigned max2(input int unsigned a, input int unsigned b);
    max2 = (a > b) ? a : b;
  endfunction

  // ceil(log2(x)) for x >= 1, at least 1 (usable as a vector width).
  function automatic int unsigned clog2p(input int unsigned x);
    int unsigned r;
    r = 1;
    while ((32'd1 << r) < x) r++;
    clog2p = r;
  endfunction

  // Width of the signed internal (biased) exponent. It must hold, with a sign bit, every
  // intermediate exponent of mul/div/add: about +-(2^(ExpW+1) + 2*FracW).
  function automatic int unsigned exp_iw(input int unsigned exp_w, input int unsigned frac_w);
    exp_iw = max2(exp_w, clog2p(2 * frac_w + 4)) + 3;
  endfunction

  // Rounding truth table (docs/FORMAT.md), g = first dropped bit, s = OR of the rest,
  // l = kept LSB, neg = sign of the value:
  //
  //   | mode | round the magnitude up when |
  //   |------|-----------------------------|
  //   | RNE  | g & (s | l)                 |
  //   | RTZ  | never                       |
  //   | RDN  | (g | s) &  neg              |
  //   | RUP  | (g | s) & ~neg              |
  function automatic logic round_up(input int unsigned rnd, input logic neg, input logic l,
                                    input logic g, input logic s);
    case (rnd)
      0:       round_up = g & (s | l);  // RNE
      1:       round_up = 1'b0;  // RTZ
      2:       round_up = (g | s) & neg;  // RDN
      default: round_up = (g | s) & ~neg;  // RUP
    endcase
  endfunction

  // On overflow the result is INF (else the largest finite value) when this is true.
  function automatic logic ovf_to_inf(input int unsigned rnd, input logic neg);
    case (rnd)
      0:       ovf_to_inf = 1'b1;  // RNE
      1:       ovf_to_inf = 1'b0;  // RTZ
      2:       ovf_to_inf = neg;  // RDN
      default: ovf_to_inf = ~neg;  // RUP
    endcase
  endfunction

  // ---------------------------------------------------------------------------------------
  // Carry-save (3:2) multiplier tree shape: level 0 holds the N partial products; every
  // level turns each group of three rows into two and passes the 0..2 leftover rows on.
  function automatic int unsigned csa_rows(input int unsigned n, input int unsigned level);
    int unsigned r;
    r = n;
    for (int unsigned k = 0; k < level; k++) r = 2 * (r / 3) + (r % 3);
    csa_rows = r;
  endfunction

  function automatic int unsigned csa_levels(input int unsigned n);
    int unsigned r, l;
    r = n;
    l = 0;
    while (r > 2) begin
      r = 2 * (r / 3) + (r % 3);
      l++;
    end
    csa_levels = l;
  endfunction

  // ---------------------------------------------------------------------------------------
  // Depth estimates in generic gate levels (2-input cells), used only to place cuts.
  function automatic int unsigned d_add(input int unsigned n);  // prefix adder
    d_add = 2 * clog2p(n) + 2;
  endfunction
  function automatic int unsigned d_shift(input int unsigned n);  // barrel shifter
    d_shift = clog2p(n) + 1;
  endfunction
  function automatic int unsigned d_lzc(input int unsigned n);  // leading-zero count tree
    d_lzc = 2 * clog2p(n);
  endfunction
  // ru_fp_round_pack, first half (tininess, denormalization) and second half (increment,
  // overflow, packing; the caller's special-result mux is added by the caller)
  function automatic int unsigned d_round_a(input int unsigned exp_w, input int unsigned frac_w,
                                            input int unsigned sub);
    d_round_a = 4 + ((sub != 0) ? d_add(exp_iw(exp_w, frac_w)) + d_shift(frac_w + 2) +
                                  clog2p(frac_w + 2) : clog2p(frac_w + 2));
  endfunction
  function automatic int unsigned d_round_b(input int unsigned exp_w, input int unsigned frac_w);
    d_round_b = 2 + d_add(exp_iw(exp_w, frac_w) + frac_w) + clog2p(exp_w) + 4;
  endfunction

  function automatic logic [MaxSeg*SegWW-1:0] put_w(input logic [MaxSeg*SegWW-1:0] v,
                                                     input int unsigned idx,
                                                     input int unsigned w);
    logic [MaxSeg*SegWW-1:0] r;
    r = v;
    r[idx*SegWW+:SegWW] = SegWW'((w > 255) ? 255 : w);
    put_w = r;
  endfunction

  // ru_fp_mul: unpack | CSA level 1 .. L | final adder | normalize | round A | round B
  function automatic int unsigned mul_nseg(input int unsigned frac_w);
    mul_nseg = csa_levels(frac_w + 1) + 5;
  endfunction
  function automatic logic [MaxSeg*SegWW-1:0] mul_seg_w(input int unsigned exp_w,
                                                        input int unsigned frac_w,
                                                        input int unsigned sub);
    logic [MaxSeg*SegWW-1:0] v;
    int unsigned l, n;
    n = frac_w + 1;
    l = csa_levels(n);
    v = '0;
    v = put_w(v, 0, d_add(exp_iw(exp_w, frac_w)) + 1);
    for (int unsigned k = 1; k <= MaxSeg; k++) if (k <= l) v = put_w(v, k, (k == 1) ? 3 : 2);
    v = put_w(v, l + 1, d_add(2 * n));
    v = put_w(v, l + 2, (sub != 0) ? d_lzc(2 * n) + d_shift(2 * n) : 2);
    v = put_w(v, l + 3, d_round_a(exp_w, frac_w, sub));
    v = put_w(v, l + 4, d_round_b(exp_w, frac_w) + 2);
    mul_seg_w = v;
  endfunction

  // ru_fp_add: unpack+compare | swap+align | add | normalize | round A | round B
  function automatic int unsigned add_nseg();
    add_nseg = 6;
  endfunction
  function automatic logic [MaxSeg*SegWW-1:0] add_seg_w(input int unsigned exp_w,
                                                        input int unsigned frac_w,
                                                        input int unsigned sub);
    logic [MaxSeg*SegWW-1:0] v;
    v = '0;
    v = put_w(v, 0, d_add(exp_w + frac_w) + 1);
    v = put_w(v, 1, d_shift(frac_w + 5) + clog2p(frac_w + 5) + 2);
    v = put_w(v, 2, d_add(frac_w + 5) + 1);
    v = put_w(v, 3, d_lzc(frac_w + 5) + d_shift(frac_w + 5));
    v = put_w(v, 4, d_round_a(exp_w, frac_w, sub));
    v = put_w(v, 5, d_round_b(exp_w, frac_w) + 2);
    add_seg_w = v;
  endfunction

  // ru_fp_div: unpack(+normalize) | step 0 .. step FracW+2 | select + round A | round B
  function automatic int unsigned div_nseg(input int unsigned frac_w);
    div_nseg = frac_w + 6;
  endfunction
  function automatic logic [MaxSeg*SegWW-1:0] div_seg_w(input int unsigned exp_w,
                                                        input int unsigned frac_w,
                                                        input int unsigned sub);
    logic [MaxSeg*SegWW-1:0] v;
    v = '0;
    v = put_w(v, 0, max2(d_add(exp_iw(exp_w, frac_w)),
                         (sub != 0) ? d_lzc(frac_w + 1) + d_shift(frac_w + 1) : 2) + 2);
    for (int unsigned k = 1; k <= MaxSeg; k++)
      if (k <= frac_w + 3) v = put_w(v, k, d_add(frac_w + 3) + 1);
    v = put_w(v, frac_w + 4, clog2p(frac_w + 3) + 2 + d_round_a(exp_w, frac_w, sub));
    v = put_w(v, frac_w + 5, d_round_b(exp_w, frac_w) + 2);
    div_seg_w = v;
  endfunction

  // ru_fp_dot3: the segments of ru_fp_mul, then two times those of ru_fp_add
  function automatic int unsigned dot3_nseg(input int unsigned frac_w);
    dot3_nseg = mul_nseg(frac_w) + 2 * add_nseg();
  endfunction
  function automatic logic [MaxSeg*SegWW-1:0] dot3_seg_w(input int unsigned exp_w,
                                                         input int unsigned frac_w,
                                                         input int unsigned sub);
    int unsigned lm;
    lm = mul_nseg(frac_w);
    dot3_seg_w = mul_seg_w(exp_w, frac_w, sub) | (add_seg_w(exp_w, frac_w, sub) << (lm * SegWW)) |
                 (add_seg_w(exp_w, frac_w, sub) << ((lm + add_nseg()) * SegWW));
  endfunction

  // ru_fp_cmp: unpack/flush/classify | magnitude compare | operation select
  function automatic int unsigned cmp_nseg();
    cmp_nseg = 3;
  endfunction
  function automatic logic [MaxSeg*SegWW-1:0] cmp_seg_w(input int unsigned exp_w,
                                                        input int unsigned frac_w);
    logic [MaxSeg*SegWW-1:0] v;
    v = '0;
    v = put_w(v, 0, clog2p(max2(exp_w, frac_w)) + 2);
    v = put_w(v, 1, d_add(exp_w + frac_w));
    v = put_w(v, 2, 4);
    cmp_seg_w = v;
  endfunction

  // ---------------------------------------------------------------------------------------
  // Cut placement. w: packed segment weights (segment i at w[i*SegWW +: SegWW]).

  // Greedy packing with stage depth bound `cap`: returns the cut mask; sets bit 63 when the
  // bound cannot be met with at most `stages` cuts.
  function automatic logic [63:0] pack_cuts(input logic [MaxSeg*SegWW-1:0] w,
                                            input int unsigned nseg, input int unsigned stages,
                                            input int unsigned cap);
    logic [63:0] m;
    int unsigned acc, cnt, wi;
    m = '0;
    acc = 0;
    cnt = 0;
    for (int unsigned i = 0; i < MaxSeg; i++) begin
      if (i < nseg) begin
        wi = 32'(w[i*SegWW+:SegWW]);
        if (wi > cap) m[63] = 1'b1;
        if (i > 0 && acc + wi > cap) begin
          m[i-1] = 1'b1;
          cnt++;
          acc = wi;
        end else begin
          acc += wi;
        end
      end
    end
    if (cnt > stages) m[63] = 1'b1;
    pack_cuts = m;
  endfunction

  function automatic int unsigned popcount(input logic [63:0] m);
    int unsigned c;
    c = 0;
    for (int unsigned i = 0; i < 63; i++) c += 32'(m[i]);
    popcount = c;
  endfunction

  function automatic logic [63:0] split_heaviest(input logic [MaxSeg*SegWW-1:0] w,
                                                 input int unsigned nseg, input logic [63:0] m);
    int unsigned start, acc, best_w, best_start, best_end, left, cost, best_cost;
    logic [5:0] best_pos;
    logic [63:0] r;
    r = m;
    best_w = 0;
    best_start = 0;
    best_end = 0;
    start = 0;
    acc = 0;
    // find the heaviest stage [start, i] containing at least one unused cut position
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
      best_pos = 6'(best_start);
      for (int unsigned i = 0; i < MaxSeg; i++) begin
        if (i >= best_start && i < best_end) begin
          left += 32'(w[i*SegWW+:SegWW]);
          cost = (left > best_w - left) ? left : best_w - left;
          if (cost < best_cost) begin
            best_cost = cost;
            best_pos = 6'(i);
          end
        end
      end
      r[best_pos] = 1'b1;
    end
    split_heaviest = r;
  endfunction

  function automatic logic [63:0] cut_mask(input logic [MaxSeg*SegWW-1:0] w,
                                           input int unsigned nseg, input int unsigned stages);
    int unsigned lo, hi, mid, tot;
    logic [63:0] m;
    tot = 0;
    for (int unsigned i = 0; i < MaxSeg; i++) if (i < nseg) tot += 32'(w[i*SegWW+:SegWW]);
    // smallest feasible depth bound in [1, tot]
    lo = 1;
    hi = tot;
    while (lo < hi) begin
      mid = (lo + hi) / 2;
      m = pack_cuts(w, nseg, stages, mid);
      if (m[63]) lo = mid + 1;
      else hi = mid;
    end
    m = pack_cuts(w, nseg, stages, lo);
    // Registers left over (the bound cannot improve further): split the heaviest stage that
    // still has an unused cut, at its most balanced position, while registers remain.
    for (int unsigned extra = popcount(m); extra < stages; extra++) m = split_heaviest(w, nseg, m);
    cut_mask = (stages == 0) ? 64'd0 : m;
  endfunction


  // Cut mask actually used by a unit: the automatic one unless CutSel overrides it.
  function automatic logic [63:0] sel_mask(input logic [63:0] cut_sel,
                                           input logic [MaxSeg*SegWW-1:0] w,
                                           input int unsigned nseg, input int unsigned stages);
    sel_mask = cut_sel[63] ? cut_mask(w, nseg, stages) : cut_sel;
  endfunction

  // Registers that go at the output: Stages minus the cuts used inside.
  function automatic int unsigned out_regs(input logic [63:0] mask, input int unsigned stages);
    out_regs = (stages > popcount(mask)) ? stages - popcount(mask) : 0;
  endfunction

  // Useful maximum of Stages for a chain of nseg segments: one register at each of its nseg-1
  // cut positions (every unit's localparam MaxUsefulStages).
  function automatic int unsigned max_useful(input int unsigned nseg);
    max_useful = (nseg > 0) ? nseg - 1 : 0;
  endfunction

  // Registers that no cut position is left for: Stages - MaxUsefulStages beyond the maximum,
  // else 0. With automatic placement this equals out_regs(cut_mask(..), Stages) (cut_mask fills
  // every cut position before the output gets a register; the units check it).
  function automatic int unsigned extra_regs(input int unsigned stages, input int unsigned max_u);
    extra_regs = (stages > max_u) ? stages - max_u : 0;
  endfunction

endpackage
