// Property test of ru_ray_tri_pkg (ctest ray_pkg.latency_sweep, built with verilator --binary):
// for the level sequences of ru_ray_tri_robust, ru_ray_tri_mt and ru_ray_box, 8 formats, with
// and without subnormals, and every Stages in 0..160:
//   * the per-level latencies sum to Stages (the units' latency is Stages), and
//   * no level's CutSel names a cut position outside that FP unit (>= its segment count - 1).
// A planted error (the last level's latency left out of the sum) must be reported, so the
// checker is shown to fail. Exits with $fatal on any violation.
module ray_pkg_sweep;
  function automatic int check(input int e, input int m, input int sub, input logic [63:0] kinds,
                               input int nlev, input bit planted);
    logic [31:0] nsegs;
    logic [4*ru_ray_tri_pkg::FpWW-1:0] wts;
    int bad;
    bad = 0;
    nsegs = {8'(ru_fp_pkg::cmp_nseg()), 8'(ru_fp_pkg::div_nseg(m)), 8'(ru_fp_pkg::mul_nseg(m)),
             8'(ru_fp_pkg::add_nseg())};
    wts = {ru_fp_pkg::cmp_seg_w(e, m), ru_fp_pkg::div_seg_w(e, m, sub),
           ru_fp_pkg::mul_seg_w(e, m, sub), ru_fp_pkg::add_seg_w(e, m, sub)};
    for (int st = 0; st <= 160; st++) begin
      automatic logic [255:0] cuts = ru_ray_tri_pkg::unit_cuts(kinds, nlev, nsegs, wts, st);
      automatic int sum = 0;
      for (int l = 0; l < nlev; l++) begin
        automatic logic [63:0] c = ru_ray_tri_pkg::level_cuts(cuts, kinds, nsegs, l);
        automatic int n = ru_ray_tri_pkg::op_nseg(nsegs, ru_ray_tri_pkg::kind_of(kinds, l));
        if (!(planted && l == nlev - 1)) sum += ru_ray_tri_pkg::level_stages(cuts, kinds, nlev, nsegs, l, st);
        if ((c >> (n - 1)) != 0) bad++;
      end
      if (sum != st) bad++;
    end
    check = bad;
  endfunction

  initial begin
    automatic int bad = 0, planted = 0;
    automatic int fm[8][2] = '{'{3, 4}, '{4, 3}, '{5, 10}, '{6, 12}, '{7, 16}, '{8, 7}, '{8, 23}, '{11, 52}};
    // level kinds (4 bits each, level 0 in the low bits): 0 add, 1 mul, 2 div, 3 cmp
    automatic logic [63:0] kinds[3] = '{64'h32001010, 64'h3012001010, 64'h33310};
    automatic int nlev[3] = '{8, 10, 5};
    for (int i = 0; i < 8; i++)
      for (int sub = 0; sub < 2; sub++)
        for (int u = 0; u < 3; u++) bad += check(fm[i][0], fm[i][1], sub, kinds[u], nlev[u], 1'b0);
    planted = check(8, 23, 1, kinds[0], nlev[0], 1'b1);
    $display("ray_pkg_sweep: %0d violations (8 formats x 2 subnormal settings x 3 units x Stages 0..160); planted error: %0d violations",
             bad, planted);
    if (bad != 0) $fatal(1, "ray_pkg_sweep: the level latencies do not add up to Stages");
    if (planted == 0) $fatal(1, "ray_pkg_sweep: the planted error was not detected");
    $finish;
  end
endmodule
