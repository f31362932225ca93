// rayunits trax areas: (re)measures rows of the TRaX model's unit-area table
// (model/data/trax/areas.json) with this project's synthesis flows (`rayunits synth ... --json`):
// by default the osu018 cell-library flow (area in um2, OpenSTA Fmax), or the generic flow
// (NAND2-equivalent estimates). Each row is the row `rayunits synth --json` writes (the synthesis
// row schema, synth/README.md) plus the command that made it. docs/TRAX.md "Area model".
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "cli_util.hpp"
#include "rayunits/util/process.hpp"
#include "rayunits/num/format.hpp"
#include "rayunits/synth/cell.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/trax/config.hpp"

namespace ru::cli {
namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  for (std::string t; std::getline(ss, t, ',');)
    if (!t.empty()) v.push_back(t);
  return v;
}

// The mapping target of the cell flow: far above every unit's delay, so ABC maps for area
// (the "relaxed" end of synth/cell/run.py); the chip clock is then the slowest unit's STA Fmax.
constexpr long kRelaxedTargetPs = 1000000;

std::string row_format(const nlohmann::json& r) {
  return r.contains("format") && r["format"].is_string() ? r["format"].get<std::string>() : "-";
}
std::string row_flow(const nlohmann::json& r) { return r.value("flow", std::string("generic")); }

int run_trax_areas(int argc, char** argv) {
  CLI::App app{"Measure unit areas (and, in the cell-library flow, STA Fmax) for the TRaX model's area table "
               "(model/data/trax/areas.json): for each format, the FP units at the chip's latencies and the box / "
               "triangle / noise units at their RTL Stages (rtl_latency); rows already in the file are kept unless "
               "re-measured"};
  std::string formats, units = "fp_add,fp_mul,fp_div,fp_sqrt,fp_cmp,ray_box,noise_trunc", config_path, out, flow = "osu018";
  int timeout = 1800;
  bool skip_present = false;
  app.add_option("--formats", formats,
                 "comma-separated formats (eXmY[-ftz]; default: every format the table's rows have, else e8m23)");
  std::string accepted;
  for (const auto& u : trax::area_table_units()) accepted += (accepted.empty() ? "" : ", ") + u;
  app.add_option("--units", units, "comma-separated: " + accepted);
  app.add_option("--config", config_path, "TRaX configuration whose FP latencies set the Stages (default: built-in)");
  app.add_option("--flow", flow,
                 "osu018 (default: cell library, area-oriented mapping at a 1000 ns target, OpenSTA Fmax), osu035, "
                 "osu050, or generic (NAND2-eq estimates, no clock)");
  app.add_option("--out", out, "the table to update (JSON)")->required();
  app.add_option("--timeout", timeout, "seconds per synthesis run");
  app.add_flag("--skip-present", skip_present,
               "do not re-measure a row the table already has for this flow (resume an interrupted run)");
  if (!parse_args(app, argc, argv)) return 0;
  synth::install_interrupt_handler();
  try {
    synth::check_flow_name(flow);
  } catch (const std::exception& e) {
    throw UsageError(std::string("--flow: ") + e.what());
  }
  if (timeout < 1) throw UsageError("--timeout: must be >= 1 second (got " + std::to_string(timeout) + ")");
  const bool cell = synth::is_cell_flow(flow);
  const auto& trax_units = trax::area_table_units();
  for (const std::string& u : split(units))  // all checked before the first (long) run
    if (std::find(trax_units.begin(), trax_units.end(), u) == trax_units.end())
      throw UsageError("--units: '" + u + "' is not a TRaX unit (accepted: " + accepted + ")");
  for (const std::string& f : split(formats)) num::Format::parse(f).validate();

  trax::Config cfg;
  try {
    cfg = config_path.empty() ? trax::default_config() : trax::load_config(config_path);
  } catch (const trax::ConfigError& e) {
    throw UsageError(e.what());
  }
  nlohmann::json table = {{"rows", nlohmann::json::array()}};
  if (std::filesystem::exists(out)) {
    std::ifstream in(out);
    try {
      table = nlohmann::json::parse(in);
      if (!table.is_object() || !table.contains("rows") || !table["rows"].is_array())
        throw std::runtime_error("no \"rows\" array");
    } catch (const std::exception& e) {
      throw UsageError("cannot read '" + out + "': " + e.what());
    }
  }
  table["description"] =
      "Unit areas for the TRaX model (docs/TRAX.md 'Area model'). Each row is the synthesis row of "
      "`rayunits synth --json` (schema: synth/README.md) with the command that measured it, made by "
      "`rayunits trax areas`. Cell-flow rows (flow osu018): area_um2 of the area-oriented mapping at a "
      "1000 ns target and the OpenSTA Fmax that netlist reaches (fmax_mhz, before placement); the chip "
      "clock is the slowest used unit's fmax_mhz. nand2_cell: the NAND2X1 area read from the liberty, "
      "used only to convert NAND2-eq estimates (a configured units.NAME.area_nand2) to um2; the memories have their own model (docs/TRAX.md \"Memories\").";
  {
    // generic rows too are charged in um2 by the model (NAND2-eq x NAND2X1 of osu018: estimates)
    const synth::CellLibrary& lib = synth::cell_library(cell ? flow : "osu018");  // throws naming the package
    auto it = lib.area.find("NAND2X1");
    if (it == lib.area.end()) throw UsageError("liberty " + lib.liberty + " has no cell NAND2X1");
    table["nand2_cell"] = {{"cell", "NAND2X1"}, {"area_um2", it->second}, {"library", lib.name},
                           {"liberty", lib.liberty}};
  }
  std::vector<std::string> fmts = split(formats);
  if (fmts.empty()) {
    std::set<std::string> have;
    for (const auto& r : table["rows"])
      if (row_format(r) != "-") have.insert(row_format(r));
    fmts.assign(have.begin(), have.end());
    if (fmts.empty()) fmts = {"e8m23"};
  }
  const std::string self = util::self_exe();
  if (self.empty()) throw UsageError("cannot find the rayunits executable (/proc/self/exe)");
  synth::TempDir tmp("ru-trax-areas");
  std::set<std::string> fmtless_done;  // units without a format: measured once
  for (const std::string& f : fmts) {
    const num::Format F = num::Format::parse(f);
    F.validate();
    trax::Config c = cfg;
    c.format = F.name();
    for (const std::string& u : split(units)) {
      const synth::UnitSpec& spec = synth::find_unit(u);  // throws on an unknown unit
      const int lat = trax::area_table_latency(c, u);
      synth::UnitConfig uc;
      uc.fmt = F;
      const int stages = std::min(lat, spec.max_stages(uc));
      const bool fmtless = !spec.uses_format;
      if (fmtless && !fmtless_done.insert(u).second) continue;  // once
      const std::string rfmt = fmtless ? "-" : F.name();
      auto& rows = table["rows"];
      auto same = [&](const nlohmann::json& old) {
        return old.value("unit", "") == u && row_format(old) == rfmt && old.value("stages", -1) == stages &&
               row_flow(old) == flow;
      };
      if (skip_present && std::any_of(rows.begin(), rows.end(), same)) {
        std::printf("%s %s Stages %d: in the table (--skip-present)\n", u.c_str(), rfmt.c_str(), stages);
        continue;
      }
      std::vector<std::string> args = {self, "synth", u};
      if (!fmtless) {
        args.push_back("--format");
        args.push_back(F.name());
      }
      args.push_back("--stages");
      args.push_back(std::to_string(stages));
      if (cell) {
        for (const std::string& a : {std::string("--flow"), flow, std::string("--clock"),
                                     std::to_string(kRelaxedTargetPs) + "ps"})
          args.push_back(a);
      } else {
        args.push_back("--generic-only");
      }
      const std::string json_path = tmp.path() + "/" + u + "_" + F.name() + ".json";
      for (const std::string& a : {std::string("--timeout"), std::to_string(timeout), std::string("--json"), json_path})
        args.push_back(a);
      std::string cmd = "rayunits";
      for (size_t i = 1; i < args.size(); ++i) cmd += " " + (args[i] == json_path ? std::string("-") : args[i]);
      std::fprintf(stderr, "trax areas: %s\n", cmd.c_str());
      // One log per run: an error names this run's last line, not the runs before it.
      const std::string log_path = tmp.path() + "/" + u + "_" + F.name() + ".log";
      const synth::ProcResult pr = synth::run_process(args, tmp.path(), log_path, timeout + 60);
      if (pr.timed_out)
        throw UsageError("'" + cmd + "' timed out after " + std::to_string(timeout) + " s (raise --timeout)");
      if (pr.exit_code != 0) {
        std::ifstream lg(log_path);
        std::string line, last;
        while (std::getline(lg, line))
          if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
        throw UsageError("'" + cmd + "' failed (exit " + std::to_string(pr.exit_code) + "): " +
                         (last.empty() ? std::string("no output") : last));
      }
      // The row exactly as `rayunits synth --json` wrote it (one line: one target clock), + command.
      std::ifstream jin(json_path);
      std::vector<nlohmann::json> got;
      for (std::string line; std::getline(jin, line);)
        if (line.find_first_not_of(" \t\r") != std::string::npos) got.push_back(nlohmann::json::parse(line));
      if (got.size() != 1)
        throw UsageError("'" + cmd + "' wrote " + std::to_string(got.size()) + " rows (expected 1)");
      nlohmann::json row = got.front();
      row["command"] = cmd;
      bool replaced = false;
      for (auto& old : rows)
        if (same(old)) {
          old = row;
          replaced = true;
        }
      if (!replaced) rows.push_back(row);
      std::sort(rows.begin(), rows.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
        return std::make_tuple(a.value("unit", ""), row_format(a), a.value("stages", 0), row_flow(a)) <
               std::make_tuple(b.value("unit", ""), row_format(b), b.value("stages", 0), row_flow(b));
      });
      // Written after every row (to a temp name, then renamed): a long run keeps what it measured.
      const std::string part = out + ".part";
      {
        std::ofstream o(part);
        o << table.dump(1) << "\n";
        if (!o) throw UsageError("cannot write '" + part + "'");
      }
      std::filesystem::rename(part, out);
      if (cell)
        std::printf("%s %s Stages %d: %.0f um2 (comb %.0f, seq %.0f), STA Fmax %.1f MHz (%.1f s)\n", u.c_str(),
                    rfmt.c_str(), stages, row.at("area_um2").get<double>(), row.at("area_comb_um2").get<double>(),
                    row.at("area_seq_um2").get<double>(), row.at("fmax_mhz").get<double>(), pr.seconds);
      else
        std::printf("%s %s Stages %d: %.0f NAND2-eq (estimate, %.1f s)\n", u.c_str(), rfmt.c_str(), stages,
                    row.at("area_nand2").get<double>(), pr.seconds);
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace

RU_COMMAND("trax areas",
           "measure unit areas and STA clocks for the TRaX model's area table (osu018 cell flow; "
           "model/data/trax/areas.json)",
           run_trax_areas);

}  // namespace ru::cli
