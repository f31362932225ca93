// `rayunits gen`: a self-contained synthesis-ready directory for one unit configuration.
#include <cstdio>
#include <string>

#include "command.hpp"
#include "rayunits/synth/args.hpp"
#include "rayunits/synth/gen.hpp"
#include "rayunits/synth/process.hpp"

namespace {

using namespace ru::synth;

void gen_help() {
  std::printf(
      "usage: rayunits gen <unit> --format eXmY --stages N [--round rne|rtz|rdn|rup] [--ftz]\n"
      "                    [--param Name=V]... --out DIR [--force] [--no-synth] [flow options]\n\n"
      "Writes DIR with a wrapper module (e.g. ru_fp_mul_e7m16_s3.sv, suffix _rtz/_rdn/_rup/_ftz\n"
      "when not default) with the parameters fixed, copies of every source, files.f, synth.ys\n"
      "(passes `check -assert`) and datasheet.md/.json (ports, latency, area and depth from the\n"
      "flow). DIR must be empty or missing unless --force. Output is deterministic.\n\n"
      "units: %s\n\n"
      "  --out DIR     output directory\n"
      "  --force       replace a non-empty DIR (only one an earlier gen wrote)\n"
      "  --no-synth    do not run the flow (datasheet without area/depth; fast, for build steps)\n\n%s",
      unit_names().c_str(), kFlowOptionsHelp);
}

int run_gen_cmd(int argc, char** argv) {
  std::string unit;
  ConfigArgs ca;
  GenOptions go;
  for (int i = 1; i < argc; ++i) {
    ArgCursor a{argc, argv, i, argv[i]};
    if (size_t eq = a.opt.find('='); a.opt.rfind("--", 0) == 0 && eq != std::string::npos) a.opt.resize(eq);
    if (a.opt == "--help" || a.opt == "-h") {
      gen_help();
      return 0;
    }
    if (a.opt == "--out")
      go.out_dir = a.value();
    else if (a.opt == "--force")
      go.force = true;
    else if (a.opt == "--no-synth")
      go.run_flow = false;
    else if (parse_config_option(a, ca) || parse_flow_option(a, go.flow)) {
    } else if (a.opt[0] == '-') {
      throw ru::cli::UsageError("unknown option '" + a.opt + "' (see rayunits gen --help)");
    } else if (unit.empty()) {
      unit = a.opt;
    } else {
      throw ru::cli::UsageError("unexpected argument '" + a.opt + "' (one unit per run)");
    }
    i = a.i;
  }
  if (unit.empty()) throw ru::cli::UsageError("missing unit (units: " + unit_names() + ")");
  const UnitSpec& u = find_unit(unit);
  const UnitConfig c = make_config(u, ca);
  if (go.out_dir.empty()) throw ru::cli::UsageError("--out DIR is required");
  install_interrupt_handler();
  const GenReport rep = generate(u, c, go);
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
