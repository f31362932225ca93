// `rayunits synth`: the open synthesis flow for one unit configuration (synth/README.md).
#include <cstdio>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/process.hpp"
#include "synth_options.hpp"

namespace ru::cli {
namespace {

std::string synth_help() {
  return "usage: rayunits synth <unit> --format eXmY --stages N [--round rne|rtz|rdn|rup] [--ftz]\n"
         "                      [--param Name=V]... [--json FILE|-] [--flow osu018 [--clock LIST]] [flow options]\n\n"
         "Synthesizes the unit's wrapper with Yosys and reports cell counts, NAND2-equivalent area,\n"
         "transistors (stat -tech cmos), register bits, the gate depth of the worst pipeline stage\n"
         "(ltp -noff) with the fo4-v1 delay estimate, iCE40 LUTs (and nextpnr Fmax with --fpga) and\n"
         "Xilinx 7-series LUT/DSP counts. With --flow osu018 (or osu035/osu050) it maps the unit onto\n"
         "that standard-cell library instead and times it with OpenSTA: area in um2 (combinational\n"
         "and sequential), worst slack, Fmax, the critical path and its pipeline segment; --clock\n"
         "gives target clocks (one mapping and one row each). synth/README.md documents both.\n\n"
         "units: " +
         synth::unit_names() +
         "\n\n"
         "  --format eXmY[-ftz]  number format; --ftz: flush to zero; --round: rounding mode (default rne)\n"
         "  --stages N    latency in cycles, 0..the unit's useful maximum (rtl/README.md)\n"
         "  --param N=V   a unit-specific parameter (e.g. noise: FracBits, IntBits, OutW)\n"
         "  --json FILE   also write the result as JSON, one object per target clock (JSON Lines;\n"
         "                \"-\": on stdout, no table)\n\n" +
         kFlowOptionsHelp;
}

}  // namespace

// `rayunits synth` arguments parsed and checked (unit, configuration, flow options) without running
// anything: false if help was printed. `rayunits sweep` checks every synth job's argv with it.
bool parse_synth_command(int argc, char** argv, SynthCommand& r) {
  CLI::App app{"", "rayunits synth"};
  synth_app(app, synth_help);
  std::string unit;
  ConfigArgs ca;
  FlowArgs fa;
  app.add_option("unit", unit, "the unit");
  add_config_options(app, ca);
  app.add_option("--json", r.json_out, "also write the result as JSON (\"-\": on stdout)");
  add_flow_options(app, r.flow, fa);
  if (!parse_synth_args(app, argc, argv, unit_command_surplus("synth"))) return false;
  check_flow_options(app, r.flow, fa);
  if (unit.empty()) throw UsageError("missing unit (units: " + synth::unit_names() + ")");
  r.unit = &synth::find_unit(unit);
  r.config = make_config(*r.unit, app, ca);
  synth::check_config(*r.unit, r.config);
  return true;
}

namespace {

int run_synth_cmd(int argc, char** argv) {
  SynthCommand sc;
  if (!parse_synth_command(argc, argv, sc)) return 0;
  const synth::UnitSpec& u = *sc.unit;
  const synth::UnitConfig& c = sc.config;
  const synth::FlowOptions& fo = sc.flow;
  const std::string& json_out = sc.json_out;
  synth::install_interrupt_handler();
  const synth::SynthResult r = synth::run_synth(u, c, fo);
  std::string row;  // one object per target clock: JSON Lines
  for (const auto& j : synth::to_json_rows(r)) row += j.dump() + "\n";
  if (json_out == "-") {
    std::fputs(row.c_str(), stdout);
  } else {
    std::fputs(synth::format_table(r).c_str(), stdout);
    if (!json_out.empty()) synth::write_file_atomic(json_out, row);
  }
  return 0;
}

}  // namespace

RU_COMMAND("synth", "synthesize one unit: Yosys gates and FPGA LUTs, or a cell library with OpenSTA timing", run_synth_cmd);

}  // namespace ru::cli
