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
         "                    [--param Name=V]... --out DIR [--force] [--no-synth] [flow options]\n\n"
         "Writes DIR with a wrapper module (e.g. ru_fp_mul_e7m16_s3.sv, suffix _rtz/_rdn/_rup/_ftz\n"
         "when not default) with the parameters fixed, copies of every source, files.f, synth.ys\n"
         "(passes `check -assert`) and datasheet.md/.json (ports, latency, area and depth from the\n"
         "flow). DIR must be empty or missing unless --force. Output is deterministic.\n\n"
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
  const synth::UnitConfig c = make_config(u, app, ca);
  if (go.out_dir.empty()) throw UsageError("--out DIR is required");
  synth::install_interrupt_handler();
  const synth::GenReport rep = synth::generate(u, c, go);
  std::printf("wrote %s/ (%s):", rep.dir.c_str(), rep.top.c_str());
  for (const auto& f : rep.files) std::printf(" %s", f.c_str());
  std::printf("\n");
  if (rep.synth)
    std::printf("%s: %.1f NAND2-eq, worst stage %d gate levels, est. Fmax %.0f MHz, latency %d\n",
                rep.top.c_str(), rep.synth->generic.area_nand2, rep.synth->generic.depth,
                rep.synth->generic.fmax_mhz, c.stages);
  return 0;
}

}  // namespace

RU_COMMAND("gen", "generate a synthesis-ready directory for one unit (wrapper, sources, datasheet)",
           run_gen_cmd);

}  // namespace ru::cli
