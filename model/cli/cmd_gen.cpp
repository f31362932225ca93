// `rayunits gen`: a self-contained synthesis-ready directory for one unit configuration.
#include <cstdio>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/synth/gen.hpp"
#include "rayunits/synth/process.hpp"
#include "synth_options.hpp"

namespace ru::cli {
namespace {

std::string gen_help() {
  return "usage: rayunits gen <unit> --format eXmY --stages N [--round rne|rtz|rdn|rup] [--ftz]\n"
         "                    [--param Name=V]... --out DIR [--force] [--no-synth] [flow options]\n"
         "       rayunits gen <unit> --format eXmY --clock 400MHz [--flow osu018] --out DIR ...\n\n"
         "Writes DIR with a wrapper module (e.g. ru_fp_mul_e7m16_s3.sv, suffix _rtz/_rdn/_rup/_ftz\n"
         "when not default) with the parameters fixed, copies of every source, files.f, synth.ys\n"
         "(passes `check -assert`) and datasheet.md/.json (ports, latency, area and depth from the\n"
         "flow). DIR must be empty or missing unless --force. Output is deterministic.\n"
         "With --clock and without --stages it finds the smallest Stages whose OpenSTA timing in the\n"
         "cell library (--flow, default osu018) meets the clock -- or fails, naming the most the unit\n"
         "reaches at its maximum useful Stages -- and the datasheet records clock, slack, Stages, area\n"
         "and every Stages count tried.\n\n"
         "units: " +
         synth::unit_names() +
         "\n\n"
         "  --out DIR     output directory\n"
         "  --force       replace a non-empty DIR (only one an earlier gen wrote)\n"
         "  --no-synth    do not run the flow (datasheet without area/depth; fast, for build steps)\n\n" +
         kFlowOptionsHelp;
}

int run_gen_cmd(int argc, char** argv) {
  CLI::App app{"", "rayunits gen"};
  synth_app(app, gen_help);
  std::string unit;
  ConfigArgs ca;
  synth::GenOptions go;
  FlowArgs fa;
  app.add_option("unit", unit, "the unit");
  add_config_options(app, ca);
  app.add_option("--out", go.out_dir, "output directory");
  app.add_flag("--force", go.force, "replace a non-empty DIR");
  app.add_flag_callback("--no-synth", [&go] { go.run_flow = false; }, "do not run the flow");
  add_flow_options(app, go.flow, fa);
  if (!parse_synth_args(app, argc, argv, unit_command_surplus("gen"))) return 0;
  check_flow_options(app, go.flow, fa);
  if (unit.empty()) throw UsageError("missing unit (units: " + synth::unit_names() + ")");
  const synth::UnitSpec& u = synth::find_unit(unit);
  const bool search = app.count("--clock") && !app.count("--stages");
  if (search) ca.stages = std::to_string(u.min_stages);  // found below
  synth::UnitConfig c = make_config(u, app, ca);
  if (go.out_dir.empty()) throw UsageError("--out DIR is required");
  if (go.flow.clocks_ps.size() > 1) throw UsageError("gen takes one --clock (got a list of " +
                                                     std::to_string(go.flow.clocks_ps.size()) + ")");
  if (search && !go.run_flow) throw UsageError("--clock without --stages searches by synthesis: drop --no-synth");
  synth::install_interrupt_handler();
  if (search) {
    const synth::ClockSearch cs = synth::find_stages_for_clock(
        u, c, go.flow.clocks_ps.front(), go.flow, [](const std::string& m) { std::fprintf(stderr, "%s\n", m.c_str()); });
    c.stages = cs.stages;
    go.reuse = cs.result;
    go.clock_search = {{"clock_ps", go.flow.clocks_ps.front()}, {"probes", cs.probes}};
  }
  const synth::GenReport rep = synth::generate(u, c, go);
  std::printf("wrote %s/ (%s):", rep.dir.c_str(), rep.top.c_str());
  for (const auto& f : rep.files) std::printf(" %s", f.c_str());
  std::printf("\n");
  if (rep.synth && rep.synth->cell.run) {
    const synth::CellRun& run = rep.synth->cell.runs.front();
    std::printf("%s: %.0f um2 (%s), Fmax %.1f MHz (OpenSTA), slack %.0f ps%s, latency %d\n", rep.top.c_str(),
                run.area.total, rep.synth->cell.library.c_str(), run.fmax_mhz, run.sta.slack_ps,
                run.target_ps > 0 ? (run.sta.slack_ps >= 0 ? " (clock met)" : " (clock NOT met)") : "", c.stages);
  } else if (rep.synth) {
    std::printf("%s: %.1f NAND2-eq, worst stage %d gate levels (%s estimate %.0f ps), latency %d\n",
                rep.top.c_str(), rep.synth->generic.area_nand2, rep.synth->generic.depth,
                synth::DelayModel::kName, rep.synth->generic.stage_ps, c.stages);
  }
  return 0;
}

}  // namespace

RU_COMMAND("gen", "generate a synthesis-ready directory for one unit (wrapper, sources, datasheet)",
           run_gen_cmd);

}  // namespace ru::cli
