// CLI11 options shared by `synth`, `gen` and `synth-sweep` (cmd_synth.cpp, cmd_gen.cpp,
// cmd_synth_sweep.cpp): the flow options, the unit configuration options, their hand-laid help
// texts and the error lines these commands have always printed ("unknown option '--x'",
// "--stages expects an integer in 0..1000, got 'x'", ...).
#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/num/format.hpp"
#include "rayunits/rtl/cache.hpp"
#include "rayunits/synth/args.hpp"
#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/units.hpp"

namespace ru::cli {

inline const char* const kFlowOptionsHelp =
    "flow options:\n"
    "  --flow NAME         generic (default: Yosys gates, NAND2-eq, FPGA LUTs) or a cell library:\n"
    "                      osu018, osu035, osu050 (liberty mapping + OpenSTA: um2, slack, Fmax)\n"
    "  --clock LIST        target clocks of the cell flow, e.g. 400MHz or 2.5ns,2ns,1500ps: one\n"
    "                      mapping (abc -D) and one STA each (default: no target)\n"
    "  --sta PATH          OpenSTA binary (default: sta on PATH)\n"
    "  --netlist FILE      cell flow: write the mapped unit module (of the first --clock) to FILE\n"
    "  --placement depth|delay  register placement: the RTL's depth estimates (default) or, in a\n"
    "                      cell flow, the delays STA measures with every cut registered\n"
    "  --stage-periods     cell flow: report the period every pipeline stage needs (OpenSTA)\n"
    "  --fpga              also place and route on iCE40 with nextpnr-ice40 (Fmax; slow)\n"
    "  --device hx8k|up5k  iCE40 device (default hx8k)\n"
    "  --no-ice40          skip synth_ice40 LUT counts\n"
    "  --no-xilinx         skip synth_xilinx LUT/DSP counts\n"
    "  --generic-only      skip both FPGA flows (generic gates only)\n"
    "  --no-share          synth -noshare: no resource sharing (the ray-triangle units always)\n"
    "  --rtl DIR           RTL source directory (default <repo>/rtl or $RU_RTL_DIR)\n"
    "  --yosys PATH        yosys binary (default: yosys on PATH)\n"
    "  --nextpnr PATH      nextpnr-ice40 binary (default: on PATH)\n"
    "  --timeout S         kill a tool run after S seconds (default: no limit)\n"
    "  --keep              keep the temp directory with scripts and logs\n";

// Values checked after parsing (with the messages above), as typed.
struct FlowArgs {
  std::string device, timeout, flow, clock, placement;
};

// Sets up `app` the way these three commands parse: the given help text (instead of CLI11's
// layout), a repeated option keeps its last value, unknown arguments are collected and reported
// by parse_synth_args. Call before adding options.
inline void synth_app(CLI::App& app, std::function<std::string()> help) {
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.allow_extras();
  app.formatter_fn([help](const CLI::App* a, std::string, CLI::AppFormatMode) {
    std::string text = help();
    // An option missing from the hand-laid text is still listed, from its CLI11 description.
    for (const CLI::Option* o : a->get_options()) {
      if (o == a->get_help_ptr() || (o->get_lnames().empty() && o->get_snames().empty())) continue;
      bool named = false;
      for (const auto& n : o->get_lnames()) named = named || text.find("--" + n) != std::string::npos;
      for (const auto& n : o->get_snames()) named = named || text.find("-" + n) != std::string::npos;
      if (!named) text += "  " + o->get_name() + "  " + o->get_description() + "\n";
    }
    return text;
  });
}

// The flow options (`kFlowOptionsHelp`). Flags take effect in command-line order, so
// `--generic-only --fpga` runs iCE40 place and route and `--fpga --no-ice40` does not.
inline void add_flow_options(CLI::App& app, synth::FlowOptions& o, FlowArgs& a) {
  app.add_option("--rtl", o.rtl_dir, "RTL source directory");
  app.add_option("--yosys", o.yosys, "yosys binary");
  app.add_option("--nextpnr", o.nextpnr, "nextpnr-ice40 binary");
  app.add_option("--device", a.device, "iCE40 device: hx8k or up5k");
  app.add_option("--timeout", a.timeout, "kill a tool run after S seconds");
  app.add_option("--flow", a.flow, "generic or a cell library (osu018, osu035, osu050)");
  app.add_option("--clock", a.clock, "target clocks of the cell flow");
  app.add_option("--sta", o.sta, "OpenSTA binary");
  app.add_option("--netlist", o.netlist_out, "write the mapped netlist");
  app.add_option("--placement", a.placement, "register placement: depth or delay");
  auto flag = [&app](const char* name, std::function<void()> f, const char* what) {
    app.add_flag_callback(name, std::move(f), what)->trigger_on_parse();
  };
  flag("--fpga", [&o] { o.pnr = o.ice40 = true; }, "also place and route on iCE40");
  flag("--no-ice40", [&o] { o.ice40 = o.pnr = false; }, "skip synth_ice40");
  flag("--no-xilinx", [&o] { o.xilinx = false; }, "skip synth_xilinx");
  flag("--generic-only", [&o] { o.ice40 = o.pnr = o.xilinx = false; }, "skip both FPGA flows");
  flag("--no-share", [&o] { o.share = false; }, "synth -noshare");
  flag("--keep", [&o] { o.keep_temp = true; }, "keep the temp directory");
  flag("--stage-periods", [&o] { o.stage_periods = true; }, "report every pipeline stage's period");
}

inline void check_flow_options(const CLI::App& app, synth::FlowOptions& o, const FlowArgs& a) {
  if (app.count("--device")) {
    if (a.device != "hx8k" && a.device != "up5k")
      throw UsageError("--device expects hx8k or up5k, got '" + a.device + "'");
    o.ice40_device = a.device;
  }
  if (app.count("--timeout")) o.timeout_s = synth::parse_int("--timeout", a.timeout, 1, 1000000);
  if (app.count("--flow")) {
    synth::check_flow_name(a.flow);
    o.flow = a.flow;
  }
  if (app.count("--netlist") && !synth::is_cell_flow(o.flow) && !app.count("--clock"))
    throw UsageError("--netlist needs a cell-library flow (--flow osu018, osu035 or osu050)");
  if (!o.netlist_out.empty()) o.netlist_out = std::filesystem::absolute(o.netlist_out).string();
  if (app.count("--placement")) {
    if (a.placement != "depth" && a.placement != "delay")
      throw UsageError("--placement expects depth or delay, got '" + a.placement + "'");
    o.placement = a.placement;
  }
  if (synth::is_cell_flow(o.flow) || app.count("--clock"))
    for (const char* f : {"--fpga", "--device"})
      if (app.count(f))
        throw UsageError(std::string(f) + " applies to the generic flow, not to a cell-library flow (--flow " +
                         (synth::is_cell_flow(o.flow) ? o.flow : std::string("osu018")) + ")");
  if (app.count("--clock")) {
    o.clocks_ps = synth::parse_clock_list("--clock", a.clock);
    if (!app.count("--flow")) o.flow = "osu018";  // a clock means a timed flow
    if (!synth::is_cell_flow(o.flow))
      throw UsageError("--clock needs a cell-library flow (--flow osu018, osu035 or osu050), not --flow generic");
  }
  for (const char* f : {"--placement", "--stage-periods"})
    if (app.count(f) && !synth::is_cell_flow(o.flow) && (std::string(f) == "--stage-periods" || o.placement != "depth"))
      throw UsageError(std::string(f) + " needs a cell-library flow (--flow osu018, osu035 or osu050)");
}

// Unit configuration options: --format eXmY[-ftz], --stages N, --round MODE, --ftz,
// --param Name=Value (repeatable; unit-specific parameters).
struct ConfigArgs {
  std::string format;  // empty until given
  std::string stages;  // empty until given
  std::string round;   // empty: rne
  bool ftz = false;
  std::vector<std::string> params;
};

inline void add_config_options(CLI::App& app, ConfigArgs& c) {
  app.add_option("--format", c.format, "number format eXmY[-ftz]");
  app.add_option("--stages", c.stages, "latency in cycles");
  app.add_option("--round", c.round, "rounding mode: rne, rtz, rdn, rup");
  app.add_flag("--ftz", c.ftz, "flush to zero");
  app.add_option("--param", c.params, "a unit-specific parameter Name=Value (repeatable)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->allow_extra_args(false);
}

// Checks that --format (for units with a format) and --stages were given and builds the
// UnitConfig (FormatError on a bad format). Range checks are check_config()'s.
inline synth::UnitConfig make_config(const synth::UnitSpec& u, const CLI::App& app, const ConfigArgs& a) {
  synth::UnitConfig c;
  std::map<std::string, long long> params;
  for (const std::string& v : a.params) {
    const size_t eq = v.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError("--param expects Name=Value, got '" + v + "'");
    params[v.substr(0, eq)] =
        synth::parse_int("--param " + v.substr(0, eq), v.substr(eq + 1), -1000000, 1000000);
  }
  const int stages =
      app.count("--stages") || !a.stages.empty() ? synth::parse_int("--stages", a.stages, 0, 1000) : -1;
  if (u.uses_format) {
    if (a.format.empty()) throw UsageError("--format eXmY is required (e.g. --format e7m16)");
    c.fmt = num::Format::parse(a.format);
    if (a.ftz) c.fmt.subnormals = false;
    if (!a.round.empty()) c.fmt.round = num::parse_round(a.round);
  } else if (!a.format.empty() || a.ftz || !a.round.empty()) {
    throw UsageError(u.name + " has no floating-point format: --format/--round/--ftz do not apply (use --param)");
  }
  if (stages < 0) throw UsageError("--stages N is required (0 = combinational)");
  c.stages = stages;
  c.params = params;
  return c;
}

// "--bogus=3" -> "--bogus"
inline std::string option_name(const std::string& arg) {
  return arg.rfind("--", 0) == 0 ? arg.substr(0, arg.find('=')) : arg;
}

// What `synth` and `gen` say about an argument they do not take: an unknown option, or a
// second unit.
inline std::function<std::string(const std::string&)> unit_command_surplus(const std::string& cmd) {
  return [cmd](const std::string& a) {
    if (a.size() > 1 && a[0] == '-')
      return "unknown option '" + option_name(a) + "' (see rayunits " + cmd + " --help)";
    return "unexpected argument '" + a + "' (one unit per run)";
  };
}

// parse_args() with these commands' error lines: an option without its value is
// "--x needs a value"; the first argument no option took is the error `surplus(arg)`.
inline bool parse_synth_args(CLI::App& app, int argc, char** argv,
                             const std::function<std::string(const std::string&)>& surplus) {
  try {
    if (!parse_args(app, argc, argv)) return false;
  } catch (const UsageError& e) {
    // CLI11 says "--format: 1 required TEXT missing (see --help)".
    const std::string m = e.what();
    const size_t colon = m.find(": ");
    if (m.rfind("-", 0) == 0 && colon != std::string::npos && m.find(" missing", colon) != std::string::npos)
      throw UsageError(m.substr(0, colon) + " needs a value");
    throw;
  }
  const std::vector<std::string> rest = app.remaining();
  if (!rest.empty()) throw UsageError(surplus(rest.front()));
  return true;
}

// A `rayunits synth` command line, parsed and checked (cmd_synth.cpp; `rayunits sweep` checks
// every synth job with it).
struct SynthCommand {
  const synth::UnitSpec* unit = nullptr;
  synth::UnitConfig config;
  synth::FlowOptions flow;
  std::string json_out;
};
bool parse_synth_command(int argc, char** argv, SynthCommand& r);  // false: help was printed

// A `rayunits rtl` command line, parsed and checked (cmd_rtl.cpp; `rayunits sweep` checks every
// rtl job with it).
struct RtlCommand {
  rtl::Request req;
  std::string json_out;
  bool quiet = false;
};
bool parse_rtl_command(int argc, char** argv, RtlCommand& r);  // false: help was printed

}  // namespace ru::cli
