// `rayunits synth-sweep`: a grid of (unit, format, stages) points synthesized in parallel
// (synth/README.md).
#include <cstdio>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/synth/sweep.hpp"
#include "synth_options.hpp"

namespace ru::cli {
namespace {

std::string sweep_help() {
  return std::string(
             "usage: rayunits synth-sweep --out DIR [--units a,b] [--formats eXmY,...] [--stages 0,1,2,max]\n"
             "                            [--round MODE] [-j N] [--resume] [--no-plot] [--python PATH]\n"
             "                            [flow options]\n\n"
             "Synthesizes every (unit, format, stages) point as one grid of the sweep engine (`rayunits\n"
             "synth` jobs on -j workers, progress on stderr; job list, logs and rows in DIR/sweep/) and\n"
             "writes DIR/synth_sweep.csv, DIR/synth_sweep.json (meta + one row per point, as `synth\n"
             "--json`) and DIR/synth_sweep.png (area vs fraction bits, Fmax vs stages).\n"
             "Stage counts above a unit's maximum are skipped; \"max\" is each unit's maximum.\n\n"
             "defaults: --units fp_add,fp_mul,fp_div --formats e5m10,e6m12,e7m16,e8m23\n"
             "          --stages 0,1,2,3,4,max -j 2\n"
             "  --resume      reuse the points in DIR/sweep/ with the same content hash (parameters, flow\n"
             "                options, RTL sources, tool versions); without it every point runs again\n\n") +
         kFlowOptionsHelp;
}

int run_sweep_cmd(int argc, char** argv) {
  CLI::App app{"", "rayunits synth-sweep"};
  synth_app(app, sweep_help);
  synth::SweepOptions so;
  std::string cmd = "rayunits synth-sweep";
  for (int i = 1; i < argc; ++i) cmd += std::string(" ") + argv[i];
  so.command = cmd;
  std::string units, formats, stages, jobs;
  FlowArgs fa;
  app.add_option("--units", units, "comma-separated units");
  app.add_option("--formats", formats, "comma-separated formats eXmY[-ftz]");
  app.add_option("--stages", stages, "comma-separated stage counts, \"max\": each unit's maximum");
  app.add_option("--round", so.round, "rounding mode");
  app.add_option("-j,--jobs", jobs, "parallel synthesis runs");
  app.add_option("--out", so.out_dir, "output directory");
  app.add_flag("--resume", so.resume, "reuse the points of an earlier run");
  app.add_flag_callback("--no-plot", [&so] { so.plot = false; }, "no plot");
  app.add_option("--python", so.python, "python with matplotlib for the plot");
  add_flow_options(app, so.flow, fa);
  const auto surplus = [](const std::string& a) {
    return "unknown argument '" + option_name(a) + "' (see rayunits synth-sweep --help)";
  };
  if (!parse_synth_args(app, argc, argv, surplus)) return 0;
  if (app.count("--units")) so.units = split_list(units);
  if (app.count("--formats")) so.formats = split_list(formats);
  if (app.count("--stages")) so.stages = split_list(stages);
  if (app.count("--jobs")) so.jobs = synth::parse_int("-j", jobs, 1, 256);
  check_flow_options(app, so.flow, fa);
  if (synth::is_cell_flow(so.flow.flow))
    throw UsageError("synth-sweep runs the generic flow only; for " + so.flow.flow +
                     " run `rayunits synth ... --flow " + so.flow.flow + " --clock LIST` per point (synth/cell/)");
  if (app.count("--netlist")) throw UsageError("--netlist applies to one unit (rayunits synth), not to a sweep");
  if (so.out_dir.empty()) throw UsageError("--out DIR is required");
  synth::install_interrupt_handler();
  const int failed = synth::run_sweep(so, [](const std::string& s) {
    std::fprintf(stderr, "%s\n", s.c_str());
    std::fflush(stderr);
  });
  if (failed > 0) {
    std::fprintf(stderr, "rayunits synth-sweep: error: %d point(s) failed (rows with \"error\" in %s)\n",
                 failed, (so.out_dir + "/synth_sweep.json").c_str());
    return 1;
  }
  return 0;
}

}  // namespace

RU_COMMAND("synth-sweep", "synthesize a grid of units/formats/stages in parallel: CSV, JSON, plot",
           run_sweep_cmd);

}  // namespace ru::cli
