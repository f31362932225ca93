// rayunits registry: the unit registry (model/src/synth/units.cpp) as a table, as JSON for CMake
// (model/data/registry.json), and checked against the RTL's own stage facts.
#include <cstdio>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/synth/units.hpp"

namespace ru::cli {
namespace {

using namespace ru::synth;

int run_registry(int argc, char** argv) {
  CLI::App app{
      "The unit registry: every hardware unit's parameters, ports (widths as expressions of the "
      "format and parameters), maximum useful Stages and sources. --json writes what CMake reads "
      "(model/data/registry.json); --check-rtl elaborates each unit with Verilator at the registry's "
      "maximum useful Stages and one past it and compares with the RTL's localparams MaxUsefulStages "
      "and OutRegs (exit 1 on a disagreement, one line per unit and format).",
      "rayunits registry"};
  std::string json_out, units_arg, formats_arg = "e5m10,e7m16,e8m23";
  bool check = false;
  app.add_option("--json", json_out, "write the registry as JSON to this file ('-' = stdout)");
  app.add_flag("--check-rtl", check, "compare the maximum useful Stages with the RTL (needs verilator)");
  app.add_option("--units", units_arg, "units to check, comma separated (default: all)");
  app.add_option("--formats", formats_arg, "formats to check for units with a format (default e5m10,e7m16,e8m23)");
  if (!parse_args(app, argc, argv)) return 0;

  std::vector<const UnitSpec*> sel;
  if (units_arg.empty()) {
    for (const auto& u : units()) sel.push_back(&u);
  } else {
    for (const auto& n : split_list(units_arg)) sel.push_back(&find_unit(n));  // SynthError: one line
  }
  std::vector<num::Format> fmts;
  for (const auto& f : split_list(formats_arg)) fmts.push_back(num::Format::parse(f));
  if (fmts.empty()) throw UsageError("--formats: no format given (e.g. e5m10,e7m16,e8m23)");

  if (!json_out.empty()) {
    const std::string text = registry_json(units());
    if (json_out == "-") std::fputs(text.c_str(), stdout);
    else write_file_atomic(json_out, text);
  }
  if (check) {
    int bad = 0;
    for (const UnitSpec* u : sel) {
      std::vector<UnitConfig> cfgs;
      if (u->uses_format) {
        for (const auto& f : fmts) cfgs.push_back(UnitConfig{f, 0, {}, {}});
      } else {
        cfgs.push_back(UnitConfig{});
      }
      const auto errs = check_against_rtl(*u, cfgs, default_rtl_dir());
      for (const auto& e : errs) std::printf("MISMATCH %s\n", e.c_str());
      if (errs.empty()) std::printf("ok %s (max Stages %s)\n", u->name.c_str(), u->max_stages_expr.c_str());
      bad += static_cast<int>(errs.size());
    }
    std::fflush(stdout);
    return bad ? 1 : 0;
  }
  if (json_out.empty()) {
    std::printf("%-15s %-18s %-10s %s\n", "unit", "top", "max Stages", "ports (width)");
    for (const UnitSpec* u : sel) {
      std::string ports;
      for (const auto& p : u->ports) ports += (ports.empty() ? "" : " ") + p.name + ":" + p.width;
      std::printf("%-15s %-18s %-10s %s\n", u->name.c_str(), u->top.c_str(), u->max_stages_expr.c_str(),
                  ports.c_str());
    }
    std::printf("\nE = ExpW, M = FracW, W = 1+E+M, L = csa_levels(M+1) (rtl/README.md).\n");
  }
  return 0;
}

}  // namespace

RU_COMMAND("registry", "the unit registry: table, JSON for CMake, check against the RTL", run_registry);

}  // namespace ru::cli
