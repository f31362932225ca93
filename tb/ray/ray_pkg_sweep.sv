// Property test of the level-chain register placement of ru_pipe_pkg (ctest ray_pkg.latency_sweep,
// built with verilator --binary from rtl/ru_pipe_pkg.sv, rtl/ru_fp_pkg.sv and this file): for the
// level sequences of ru_ray_tri_robust, ru_ray_tri_mt, ru_ray_box and ru_fp_dot3, 8 formats, with
// and without subnormals, and every Stages in 0..160:
//   * the per-level latencies sum to Stages (the units' latency is Stages),
//   * no level's CutSel names a cut position outside that FP unit (>= its segment count - 1),
//   * every cut position is taken before a register goes to the output: up to the useful
//     maximum (unit_max_useful) no output register, beyond it exactly Stages - maximum.
// A planted error (the last level's latency left out of the sum) must be reported, so the
// checker is shown to fail. Exits with $fatal on any violation.
module ray_pkg_sweep;
  function automatic int check(input int e, input int m, input int sub,
                               input logic [4*ru_pipe_pkg::MaxLev-1:0] kinds, input int nlev,
                               input bit planted);
    logic [8*ru_pipe_pkg::MaxKind-1:0] nsegs;
    logic [ru_pipe_pkg::MaxKind*ru_pipe_pkg::WW-1:0] wts;
    int bad, max_u;
    bad = 0;
    nsegs = ru_fp_pkg::op_nsegs(m);
    wts = ru_fp_pkg::op_wts(e, m, sub);
    max_u = ru_pipe_pkg::unit_max_useful(kinds, nlev, nsegs);
    for (int st = 0; st <= 160; st++) begin
      automatic logic [ru_pipe_pkg::MaxSeg:0] cuts = ru_pipe_pkg::unit_cuts(kinds, nlev, nsegs, wts, st);
      automatic int sum = 0;
      automatic int outr = ru_pipe_pkg::out_regs(cuts, st);
      for (int l = 0; l < nlev; l++) begin
        automatic logic [ru_pipe_pkg::MaxSeg:0] c = ru_pipe_pkg::level_cuts(cuts, kinds, nsegs, l);
        automatic int n = ru_pipe_pkg::level_nseg(kinds, nsegs, l);
        if (!(planted && l == nlev - 1))
          sum += ru_pipe_pkg::level_stages(cuts, kinds, nlev, nsegs, l, st);
        if ((c >> (n - 1)) != 0) bad++;
      end
      if (sum != st) bad++;
      if (outr != ((st > max_u) ? st - max_u : 0)) bad++;
    end
    check = bad;
  endfunction

  initial begin
    automatic int bad = 0, planted = 0;
    automatic int fm[8][2] = '{'{3, 4}, '{4, 3}, '{5, 10}, '{6, 12}, '{7, 16}, '{8, 7}, '{8, 23}, '{11, 52}};
    // level kinds (4 bits each, level 0 in the low bits): 0 add, 1 mul, 2 div, 3 cmp
    automatic logic [4*ru_pipe_pkg::MaxLev-1:0] kinds[4] = '{64'h32001010, 64'h3012001010, 64'h33310,
                                                            64'h001};
    automatic int nlev[4] = '{8, 10, 5, 3};
    for (int i = 0; i < 8; i++)
      for (int sub = 0; sub < 2; sub++)
        for (int u = 0; u < 4; u++) bad += check(fm[i][0], fm[i][1], sub, kinds[u], nlev[u], 1'b0);
    planted = check(8, 23, 1, kinds[0], nlev[0], 1'b1);
    $display("ray_pkg_sweep: %0d violations (8 formats x 2 subnormal settings x 4 units x Stages 0..160); planted error: %0d violations",
             bad, planted);
    if (bad != 0) $fatal(1, "ray_pkg_sweep: the level latencies do not add up to Stages");
    if (planted == 0) $fatal(1, "ray_pkg_sweep: the planted error was not detected");
    $finish;
  end
endmodule
