// ru_fp_pkg: the one source of truth shared by every rayunits floating-point unit.
//
// Formats are given to each unit by the parameters ExpW (2..11) and FracW (1..52); the
// encoding, rounding and flag semantics are docs/FORMAT.md. This package holds what the
// units derive from those parameters:
//   * exp_iw()      width of the signed internal exponent,
//   * round_up()    the rounding truth table (the one implementation of it),
//   * csa_*()       the shape of the carry-save multiplier tree (ru_umul),
//   * *_nseg(), *_seg_w()  the pipeline segments of each FP unit and their gate-depth
//                   estimates, and op_nsegs()/op_wts(), the same as the kind table (KAdd,
//                   KMul, KDiv, KCmp) of the level chains of ru_fp_dot3 and the ray units.
// Where the registers go is decided by ru_pipe_pkg (cut_mask) from these estimates.
//
// Yosys 0.23 note: functions assign their name instead of using `return`; ru_pipe_pkg is named
// only inside functions (see ru_pipe_pkg: Yosys cannot name another package in package-level
// declarations).
package ru_fp_pkg;

  // Level kinds of the level chains (ru_pipe_pkg): the index of each FP unit in op_nsegs/op_wts.
  localparam logic [3:0] KAdd = 4'd0;
  localparam logic [3:0] KMul = 4'd1;
  localparam logic [3:0] KDiv = 4'd2;
  localparam logic [3:0] KCmp = 4'd3;

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

  // ru_fp_mul: unpack | CSA level 1 .. L | final adder | normalize | round A | round B
  function automatic int unsigned mul_nseg(input int unsigned frac_w);
    mul_nseg = csa_levels(frac_w + 1) + 5;
  endfunction
  function automatic logic [ru_pipe_pkg::WW-1:0] mul_seg_w(input int unsigned exp_w,
                                                              input int unsigned frac_w,
                                                              input int unsigned sub);
    logic [ru_pipe_pkg::WW-1:0] v;
    int unsigned l, n;
    n = frac_w + 1;
    l = csa_levels(n);
    v = '0;
    v = ru_pipe_pkg::put_w(v, 0, d_add(exp_iw(exp_w, frac_w)) + 1);
    for (int unsigned k = 1; k <= l; k++) v = ru_pipe_pkg::put_w(v, k, (k == 1) ? 3 : 2);
    v = ru_pipe_pkg::put_w(v, l + 1, d_add(2 * n));
    v = ru_pipe_pkg::put_w(v, l + 2, (sub != 0) ? d_lzc(2 * n) + d_shift(2 * n) : 2);
    v = ru_pipe_pkg::put_w(v, l + 3, d_round_a(exp_w, frac_w, sub));
    v = ru_pipe_pkg::put_w(v, l + 4, d_round_b(exp_w, frac_w) + 2);
    mul_seg_w = v;
  endfunction

  // ru_fp_add: unpack+compare | swap+align | add | normalize | round A | round B
  function automatic int unsigned add_nseg();
    add_nseg = 6;
  endfunction
  function automatic logic [ru_pipe_pkg::WW-1:0] add_seg_w(input int unsigned exp_w,
                                                              input int unsigned frac_w,
                                                              input int unsigned sub);
    logic [ru_pipe_pkg::WW-1:0] v;
    v = '0;
    v = ru_pipe_pkg::put_w(v, 0, d_add(exp_w + frac_w) + 1);
    v = ru_pipe_pkg::put_w(v, 1, d_shift(frac_w + 5) + clog2p(frac_w + 5) + 2);
    v = ru_pipe_pkg::put_w(v, 2, d_add(frac_w + 5) + 1);
    v = ru_pipe_pkg::put_w(v, 3, d_lzc(frac_w + 5) + d_shift(frac_w + 5));
    v = ru_pipe_pkg::put_w(v, 4, d_round_a(exp_w, frac_w, sub));
    v = ru_pipe_pkg::put_w(v, 5, d_round_b(exp_w, frac_w) + 2);
    add_seg_w = v;
  endfunction

  // ru_fp_div: unpack(+normalize) | step 0 .. step FracW+2 | select + round A | round B
  function automatic int unsigned div_nseg(input int unsigned frac_w);
    div_nseg = frac_w + 6;
  endfunction
  function automatic logic [ru_pipe_pkg::WW-1:0] div_seg_w(input int unsigned exp_w,
                                                              input int unsigned frac_w,
                                                              input int unsigned sub);
    logic [ru_pipe_pkg::WW-1:0] v;
    v = '0;
    v = ru_pipe_pkg::put_w(v, 0, max2(d_add(exp_iw(exp_w, frac_w)),
                                      (sub != 0) ? d_lzc(frac_w + 1) + d_shift(frac_w + 1) : 2) + 2);
    for (int unsigned k = 1; k <= frac_w + 3; k++)
      v = ru_pipe_pkg::put_w(v, k, d_add(frac_w + 3) + 1);
    v = ru_pipe_pkg::put_w(v, frac_w + 4,
                           clog2p(frac_w + 3) + 2 + d_round_a(exp_w, frac_w, sub));
    v = ru_pipe_pkg::put_w(v, frac_w + 5, d_round_b(exp_w, frac_w) + 2);
    div_seg_w = v;
  endfunction

  // ru_fp_sqrt: unpack(+normalize) + exponent halving + root bit 0 | step 1 .. step FracW+1 |
  // round A | round B
  function automatic int unsigned sqrt_nseg(input int unsigned frac_w);
    sqrt_nseg = frac_w + 4;
  endfunction
  function automatic logic [ru_pipe_pkg::WW-1:0] sqrt_seg_w(input int unsigned exp_w,
                                                               input int unsigned frac_w,
                                                               input int unsigned sub);
    logic [ru_pipe_pkg::WW-1:0] v;
    v = '0;
    v = ru_pipe_pkg::put_w(v, 0, max2(d_add(exp_iw(exp_w, frac_w)) + 1,
                                      (sub != 0) ? d_lzc(frac_w + 1) + d_shift(frac_w + 1) : 2) + 2);
    // step k compares a (k+3)-bit partial remainder with the (k+2)-bit trial root
    for (int unsigned k = 1; k <= frac_w + 1; k++)
      v = ru_pipe_pkg::put_w(v, k, d_add(k + 3) + 1);
    v = ru_pipe_pkg::put_w(v, frac_w + 2, clog2p(frac_w + 3) + d_round_a(exp_w, frac_w, sub));
    v = ru_pipe_pkg::put_w(v, frac_w + 3, d_round_b(exp_w, frac_w) + 2);
    sqrt_seg_w = v;
  endfunction

  // ru_fp_fma: unpack + exponents | align c | CSA level 1 .. L | product adder | add/subtract |
  // normalize | round A | round B (L = csa_levels(FracW+1); window of 3(FracW+1)+5 bits + carry)
  function automatic int unsigned fma_nseg(input int unsigned frac_w);
    fma_nseg = csa_levels(frac_w + 1) + 7;
  endfunction
  function automatic logic [ru_pipe_pkg::WW-1:0] fma_seg_w(input int unsigned exp_w,
                                                              input int unsigned frac_w,
                                                              input int unsigned sub);
    logic [ru_pipe_pkg::WW-1:0] v;
    int unsigned l, n, ww;
    n = frac_w + 1;
    l = csa_levels(n);
    ww = 3 * n + 5;
    v = '0;
    // ec - ea - eb (+ constant): a three-input add, then the shift-amount clamp
    v = ru_pipe_pkg::put_w(v, 0, d_add(exp_iw(exp_w, frac_w)) + 4);
    v = ru_pipe_pkg::put_w(v, 1, d_shift(ww) + clog2p(ww) + 1);
    for (int unsigned k = 1; k <= l; k++) v = ru_pipe_pkg::put_w(v, k + 1, (k == 1) ? 3 : 2);
    v = ru_pipe_pkg::put_w(v, l + 2, d_add(2 * n));
    v = ru_pipe_pkg::put_w(v, l + 3, d_add(ww + 1) + 2);
    v = ru_pipe_pkg::put_w(v, l + 4, d_lzc(ww + 1) + d_shift(ww + 1));
    v = ru_pipe_pkg::put_w(v, l + 5, d_round_a(exp_w, frac_w, sub));
    v = ru_pipe_pkg::put_w(v, l + 6, d_round_b(exp_w, frac_w) + 2);
    fma_seg_w = v;
  endfunction

  // ru_fp_cmp: unpack/flush/classify | magnitude compare | operation select
  // ru_fp_dot3_fused: L+8 segments (see the module), window WW = 4N+4, sum 4N+7 bits
  function automatic int unsigned dot3f_nseg(input int unsigned frac_w);
    dot3f_nseg = csa_levels(frac_w + 1) + 8;
  endfunction
  function automatic logic [ru_pipe_pkg::WW-1:0] dot3f_seg_w(input int unsigned exp_w,
                                                                input int unsigned frac_w,
                                                                input int unsigned sub);
    logic [ru_pipe_pkg::WW-1:0] v;
    int unsigned l, n, ww, ew;
    n = frac_w + 1;
    l = csa_levels(n);
    ww = 4 * n + 4;
    ew = exp_iw(exp_w, frac_w) + 1;
    v = '0;
    v = ru_pipe_pkg::put_w(v, 0, ((sub != 0) ? d_lzc(n) + d_shift(n) : 0) + d_add(ew) + 2);
    v = ru_pipe_pkg::put_w(v, 1, 2 * d_add(ew) + 4);
    for (int unsigned k = 1; k <= l; k++) v = ru_pipe_pkg::put_w(v, k + 1, (k == 1) ? 3 : 2);
    v = ru_pipe_pkg::put_w(v, l + 2, d_add(2 * n));
    v = ru_pipe_pkg::put_w(v, l + 3, max2(d_shift(ww) + clog2p(ww) + 1, d_add(2 * n + 1) + 2) + 3);
    v = ru_pipe_pkg::put_w(v, l + 4, 2 * d_add(ww + 3) + 4);
    v = ru_pipe_pkg::put_w(v, l + 5, d_lzc(ww + 2) + d_shift(ww + 2));
    v = ru_pipe_pkg::put_w(v, l + 6, d_round_a(exp_w, frac_w, sub));
    v = ru_pipe_pkg::put_w(v, l + 7, d_round_b(exp_w, frac_w) + 2);
    dot3f_seg_w = v;
  endfunction

  function automatic int unsigned cmp_nseg();
    cmp_nseg = 3;
  endfunction
  function automatic logic [ru_pipe_pkg::WW-1:0] cmp_seg_w(input int unsigned exp_w,
                                                              input int unsigned frac_w);
    logic [ru_pipe_pkg::WW-1:0] v;
    v = '0;
    v = ru_pipe_pkg::put_w(v, 0, clog2p(max2(exp_w, frac_w)) + 2);
    v = ru_pipe_pkg::put_w(v, 1, d_add(exp_w + frac_w));
    v = ru_pipe_pkg::put_w(v, 2, 4);
    cmp_seg_w = v;
  endfunction

  // ru_fp_cvt: unpack (integer magnitude, exponents) | normalize (f2f, i2f) / integer shift (f2i)
  // | round A / integer round increment | round B / range check, negate, result mux
  function automatic int unsigned cvt_nseg();
    cvt_nseg = 4;
  endfunction
  function automatic logic [ru_pipe_pkg::WW-1:0] cvt_seg_w(input int unsigned exp_w,
                                                              input int unsigned frac_w,
                                                              input int unsigned sub,
                                                              input int unsigned in_exp_w,
                                                              input int unsigned in_frac_w,
                                                              input int unsigned int_w);
    logic [ru_pipe_pkg::WW-1:0] v;
    int unsigned sw, cw;
    sw = max2(in_frac_w + 1, int_w);
    cw = max2(max2(exp_w, in_exp_w), clog2p(sw + 2)) + 3;
    v = '0;
    v = ru_pipe_pkg::put_w(v, 0, max2(d_add(int_w), d_add(cw)) + 3);
    v = ru_pipe_pkg::put_w(v, 1, max2(d_lzc(sw) + d_shift(sw) + d_add(cw) + 2,
                                      d_shift(frac_w + int_w + 2) + 1));
    v = ru_pipe_pkg::put_w(v, 2, max2(d_round_a(exp_w, frac_w, sub), d_add(int_w + 1) + 3));
    v = ru_pipe_pkg::put_w(v, 3, max2(d_round_b(exp_w, frac_w), d_add(int_w + 2) + 2) + 3);
    cvt_seg_w = v;
  endfunction

  // ---------------------------------------------------------------------------------------
  // The kind table of the level chains (ru_pipe_pkg::unit_cuts): segment counts (8 bits each)
  // and segment weights (ru_pipe_pkg::WW bits each) of the FP unit of kind k at index k.
  function automatic logic [8*ru_pipe_pkg::MaxKind-1:0] op_nsegs(input int unsigned frac_w);
    logic [8*ru_pipe_pkg::MaxKind-1:0] r;
    r = '0;
    r[32'(KAdd)*8+:8] = 8'(add_nseg());
    r[32'(KMul)*8+:8] = 8'(mul_nseg(frac_w));
    r[32'(KDiv)*8+:8] = 8'(div_nseg(frac_w));
    r[32'(KCmp)*8+:8] = 8'(cmp_nseg());
    op_nsegs = r;
  endfunction

  function automatic logic [ru_pipe_pkg::MaxKind*ru_pipe_pkg::WW-1:0] op_wts(
      input int unsigned exp_w, input int unsigned frac_w, input int unsigned sub);
    logic [ru_pipe_pkg::MaxKind*ru_pipe_pkg::WW-1:0] r;
    r = '0;
    r[32'(KAdd)*ru_pipe_pkg::WW+:ru_pipe_pkg::WW] = add_seg_w(exp_w, frac_w, sub);
    r[32'(KMul)*ru_pipe_pkg::WW+:ru_pipe_pkg::WW] = mul_seg_w(exp_w, frac_w, sub);
    r[32'(KDiv)*ru_pipe_pkg::WW+:ru_pipe_pkg::WW] = div_seg_w(exp_w, frac_w, sub);
    r[32'(KCmp)*ru_pipe_pkg::WW+:ru_pipe_pkg::WW] = cmp_seg_w(exp_w, frac_w);
    op_wts = r;
  endfunction

endpackage
