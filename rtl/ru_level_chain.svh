// ru_level_chain.svh: the register placement of a unit built as a chain of FP levels
// (ru_fp_dot3, ru_ray_box, ru_ray_tri_robust, ru_ray_tri_mt), written once and `include`d in the
// body of each such unit after it declares
//   localparam int unsigned NLev                               number of levels
//   localparam logic [4*ru_pipe_pkg::MaxLev-1:0] Kinds          level kinds (ru_fp_pkg::KAdd ...),
//                                                               level 0 in the low nibble
// and its parameters ExpW, FracW, Subnormals, Stages. It declares the placement (Cuts), every
// level's CutSel and latency (LevCuts, LevStages), the unit's MaxUsefulStages and OutRegs (read
// by the registry check, rtl/README.md), the accessors lcut(k) (CutSel of level k), lat(k)
// (latency of level k) and span(a, b) (latency of levels a .. b-1, for values that skip levels),
// and the elaboration checks that OutRegs is what the placement promises and that the levels'
// latencies add up to Stages. (An include, not a module or a package function: these are
// localparams and functions of the including module, computed from its own parameters.)
  localparam logic [8*ru_pipe_pkg::MaxKind-1:0] NSegs = ru_fp_pkg::op_nsegs(FracW);
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::unit_cuts(
      Kinds, NLev, NSegs, ru_fp_pkg::op_wts(ExpW, FracW, Subnormals), Stages);
  localparam logic [ru_pipe_pkg::MaxLev*ru_pipe_pkg::MW-1:0] LevCuts =
      ru_pipe_pkg::level_cuts_all(Cuts, Kinds, NLev, NSegs);
  localparam logic [ru_pipe_pkg::MaxLev*32-1:0] LevStages =
      ru_pipe_pkg::level_stages_all(Cuts, Kinds, NLev, NSegs, Stages);
  // Useful maximum of Stages (a register at every cut position of the level chain) and the
  // registers placed at the output of the last level (those beyond MaxUsefulStages).
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::unit_max_useful(Kinds, NLev, NSegs);
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("level chain: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end
  function automatic logic [ru_pipe_pkg::MaxSeg:0] lcut(input int unsigned k);
    lcut = LevCuts[k*ru_pipe_pkg::MW+:ru_pipe_pkg::MW];
  endfunction
  function automatic int unsigned lat(input int unsigned k);
    lat = LevStages[k*32+:32];
  endfunction
  function automatic int unsigned span(input int unsigned first, input int unsigned last);
    span = ru_pipe_pkg::level_span(LevStages, first, last);
  endfunction
  // The unit's latency: Stages by construction (checked here at elaboration).
  if (span(0, NLev) != Stages) begin : gen_latency_check
    $error("level chain: internal error: latency %0d != Stages %0d", span(0, NLev), Stages);
  end
