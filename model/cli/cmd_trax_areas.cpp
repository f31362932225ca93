// rayunits trax areas: (re)measures rows of the TRaX model's unit-area table
// (model/data/trax/areas.json) with this project's Yosys flow (`rayunits synth ... --json`).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_util.hpp"
#include "rayunits/num/format.hpp"
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

int run_trax_areas(int argc, char** argv) {
  CLI::App app{"Measure unit areas for the TRaX model's area table (model/data/trax/areas.json) with the Yosys "
               "flow: for each format, the FP units at the chip's latencies and the box / triangle / noise units at "
               "their RTL Stages (rtl_latency); rows already in the file are kept unless re-measured"};
  std::string formats = "e8m23", units = "fp_add,fp_mul,fp_div,fp_cmp,ray_box,noise", config_path, out;
  int timeout = 1800;
  app.add_option("--formats", formats, "comma-separated formats (eXmY[-ftz])");
  app.add_option("--units", units,
                 "comma-separated: fp_add, fp_mul, fp_div, fp_cmp, ray_box, ray_tri_robust, ray_tri_mt, noise");
  app.add_option("--config", config_path, "TRaX configuration whose FP latencies set the Stages (default: built-in)");
  app.add_option("--out", out, "the table to update (JSON)")->required();
  app.add_option("--timeout", timeout, "seconds per synthesis run");
  if (!parse_args(app, argc, argv)) return 0;
  synth::install_interrupt_handler();

  trax::Config cfg;
  try {
    cfg = config_path.empty() ? trax::default_config() : trax::load_config(config_path);
  } catch (const trax::ConfigError& e) {
    throw UsageError(e.what());
  }
  nlohmann::json table = {{"description",
                           "Unit areas (NAND2-equivalents, Yosys generic gates) for the TRaX model "
                           "(docs/TRAX.md 'Area model'); each row has the command that measured it"},
                          {"rows", nlohmann::json::array()}};
  if (std::filesystem::exists(out)) {
    std::ifstream in(out);
    try {
      table = nlohmann::json::parse(in);
    } catch (const std::exception& e) {
      throw UsageError("cannot read '" + out + "': " + e.what());
    }
  }
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  synth::TempDir tmp("ru-trax-areas");
  for (const std::string& f : split(formats)) {
    const num::Format F = num::Format::parse(f);
    F.validate();
    trax::Config c = cfg;
    c.format = F.name();
    for (const std::string& u : split(units)) {
      const synth::UnitSpec& spec = synth::find_unit(u);  // throws on an unknown unit
      int lat;
      if (u == "fp_add") lat = c.unit(trax::Unit::FpAdd).latency;
      else if (u == "fp_mul") lat = c.unit(trax::Unit::FpMul).latency;
      else if (u == "fp_div") lat = c.unit(trax::Unit::FpDiv).latency;
      else if (u == "fp_cmp") lat = c.unit(trax::Unit::FpCmp).latency;
      else if (u == "ray_box") lat = trax::rtl_latency(c, trax::Unit::Box);
      else if (u == "noise") lat = trax::rtl_latency(c, trax::Unit::Noise);
      else {
        c.tri = u == "ray_tri_mt" ? "mt" : "robust";
        lat = trax::rtl_latency(c, trax::Unit::Tri);
      }
      synth::UnitConfig uc;
      uc.fmt = F;
      const int stages = std::min(lat, spec.max_stages(uc));
      const bool fmtless = u == "noise";
      if (fmtless && f != split(formats).front()) continue;  // once
      std::vector<std::string> args = {self, "synth", u};
      if (!fmtless) {
        args.push_back("--format");
        args.push_back(F.name());
      }
      const std::string json_path = tmp.path() + "/" + u + "_" + F.name() + ".json";
      for (const std::string& a : {std::string("--stages"), std::to_string(stages), std::string("--generic-only"),
                                   std::string("--json"), json_path})
        args.push_back(a);
      std::string cmd = "rayunits";
      for (size_t i = 1; i < args.size(); ++i) cmd += " " + (args[i] == json_path ? std::string("-") : args[i]);
      std::fprintf(stderr, "trax areas: %s\n", cmd.c_str());
      // One log per run: an error names this run's last line, not the runs before it.
      const std::string log_path = tmp.path() + "/" + u + "_" + F.name() + ".log";
      const synth::ProcResult pr = synth::run_process(args, tmp.path(), log_path, timeout);
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
      std::ifstream jin(json_path);
      const nlohmann::json r = nlohmann::json::parse(jin);
      nlohmann::json row = {{"unit", u},
                            {"format", fmtless ? "-" : F.name()},
                            {"stages", stages},
                            {"area_nand2", r.at("area_nand2")},
                            {"reg_bits", r.value("reg_bits", 0)},
                            {"fmax_est_mhz", r.value("fmax_est_mhz", 0.0)},
                            {"seconds", pr.seconds},
                            {"command", cmd}};
      auto& rows = table["rows"];
      bool replaced = false;
      for (auto& old : rows)
        if (old.at("unit") == row.at("unit") && old.at("format") == row.at("format") &&
            old.at("stages") == row.at("stages")) {
          old = row;
          replaced = true;
        }
      if (!replaced) rows.push_back(row);
      std::sort(rows.begin(), rows.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
        return std::make_tuple(a.at("unit").get<std::string>(), a.at("format").get<std::string>(),
                               a.at("stages").get<int>()) < std::make_tuple(b.at("unit").get<std::string>(),
                                                                            b.at("format").get<std::string>(),
                                                                            b.at("stages").get<int>());
      });
      std::ofstream o(out);  // written after every row: a long run keeps what it measured
      o << table.dump(1) << "\n";
      std::printf("%s %s Stages %d: %.0f NAND2-eq (%.1f s)\n", u.c_str(), fmtless ? "-" : F.name().c_str(), stages,
                  r.at("area_nand2").get<double>(), pr.seconds);
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace

RU_COMMAND("trax areas", "measure unit areas for the TRaX model's area table (Yosys; model/data/trax/areas.json)",
           run_trax_areas);

}  // namespace ru::cli
