// `rayunits gen`: a self-contained synthesis-ready directory for one unit configuration.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/synth/gen.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/trax/config.hpp"
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
         "and every Stages count tried.\n"
         "       rayunits gen --from-profile PROFILE.json --out DIR [--config CHIP.toml] [--clock C]\n"
         "                    [--format eXmY] [--no-synth] [flow options]\n"
         "generates exactly the units the profiled scene needs (its `units`; no noise unit without\n"
         "procedural materials), at its recommended format, one directory each (DIR/<unit>/, as\n"
         "above), and DIR/chip.md + chip.json: per unit the count on the chip (TRaX configuration:\n"
         "per-TM count x TMs), Stages (the configuration's latency; with --clock the fewest Stages\n"
         "whose cell-flow STA meets it), area and clock from the flow, and the totals.\n\n"
         "units: " +
         synth::unit_names() +
         "\n\n"
         "  --out DIR     output directory\n"
         "  --force       replace a non-empty DIR (only one an earlier gen wrote)\n"
         "  --no-synth    do not run the flow (datasheet without area/depth; fast, for build steps)\n\n" +
         kFlowOptionsHelp;
}

namespace fs = std::filesystem;

// `gen --from-profile`: the units a scene profile names, at its format, and one chip datasheet.
int run_gen_from_profile(int argc, char** argv) {
  CLI::App app{"", "rayunits gen"};
  synth_app(app, gen_help);
  std::string profile_path, config_path, format, out;
  bool force = false, no_synth = false;
  synth::FlowOptions flow;
  FlowArgs fa;
  app.add_option("--from-profile", profile_path, "a `rayunits profile --json` file");
  app.add_option("--config", config_path, "TRaX chip configuration (default: the built-in one)");
  app.add_option("--format", format, "override the profile's recommended format");
  app.add_option("--out", out, "output directory");
  app.add_flag("--force", force, "replace DIR (only one an earlier gen --from-profile wrote)");
  app.add_flag("--no-synth", no_synth, "do not run the flow");
  add_flow_options(app, flow, fa);
  if (!parse_synth_args(app, argc, argv, unit_command_surplus("gen --from-profile"))) return 0;
  check_flow_options(app, flow, fa);
  if (out.empty()) throw UsageError("--out DIR is required");
  if (flow.clocks_ps.size() > 1) throw UsageError("gen takes one --clock (got a list)");
  const bool search = !flow.clocks_ps.empty();
  if (search && no_synth) throw UsageError("--clock searches the Stages by synthesis: drop --no-synth");
  if (search && flow.flow == "generic") flow.flow = "osu018";

  nlohmann::json prof;
  std::vector<std::string> units;
  {
    std::ifstream pf(profile_path);
    if (!pf) throw UsageError("--from-profile: cannot open '" + profile_path + "'");
    try {
      prof = nlohmann::json::parse(pf);
      if (format.empty()) {
        const auto& rf = prof.at("recommended_format");
        if (rf.is_null())
          throw UsageError("--from-profile " + profile_path + ": the profile recommends no format (give --format)");
        format = rf.get<std::string>();
      }
      units = prof.at("units").get<std::vector<std::string>>();
    } catch (const nlohmann::json::exception& e) {
      throw UsageError("--from-profile " + profile_path + ": not a `rayunits profile --json` file (" + e.what() + ")");
    }
  }
  if (units.empty()) throw UsageError("--from-profile " + profile_path + ": the profile names no units");
  num::Format fmt;
  try {
    fmt = num::Format::parse(format);
    fmt.validate();
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
  trax::Config cfg;
  try {
    cfg = config_path.empty() ? trax::default_config() : trax::load_config(config_path);
    cfg.validate(config_path.empty() ? "built-in defaults" : config_path);
  } catch (const trax::ConfigError& e) {
    throw UsageError(e.what());
  }
  // Check every unit before anything is written.
  for (const auto& name : units) {
    try {
      synth::find_unit(name);
      trax::area_table_unit(name);
    } catch (const std::exception& e) {
      throw UsageError("--from-profile " + profile_path + ": " + e.what());
    }
  }
  const fs::path dst = fs::absolute(out).lexically_normal();
  std::error_code ec;
  if (fs::exists(dst, ec) && !fs::is_empty(dst, ec)) {
    if (!force) throw UsageError("output directory '" + out + "' is not empty (--force replaces it)");
    if (!fs::exists(dst / "chip.json", ec))
      throw UsageError("--force: '" + out + "' was not written by gen --from-profile (no chip.json); not replaced");
  }
  fs::create_directories(dst.parent_path(), ec);
  std::string tmpl = (dst.parent_path() / ("." + dst.filename().string() + ".tmp-XXXXXX")).string();
  if (!mkdtemp(tmpl.data())) throw UsageError("cannot write '" + out + "': " + std::strerror(errno));
  const fs::path tmp = tmpl;
  struct Cleanup {
    fs::path p;
    bool keep = false;
    ~Cleanup() {
      std::error_code e;
      if (!keep) fs::remove_all(p, e);
    }
  } cleanup{tmp};
  synth::install_interrupt_handler();

  nlohmann::ordered_json chip;
  chip["profile"] = profile_path;
  chip["scene"] = prof.value("scene", "");
  chip["format"] = format;
  chip["config"] = config_path.empty() ? "built-in defaults (model/data/trax/default.toml)" : config_path;
  chip["flow"] = no_synth ? "none (--no-synth)" : flow.flow;
  if (search) chip["clock_ps"] = flow.clocks_ps.front();
  chip["units"] = nlohmann::json::array();
  double total_area = 0, min_fmax = 0;
  std::string area_unit = no_synth ? "" : (flow.flow == "generic" ? "nand2" : "um2");
  std::string md = "# Chip datasheet: units for scene `" + chip["scene"].get<std::string>() + "`\n\n`" +
                   command_line("rayunits gen", argc, argv) + "`\n\nFormat " + format + " (profile " +
                   profile_path + "); chip configuration " + chip["config"].get<std::string>() +
                   "; counts = per-TM count x " + std::to_string(cfg.tms) + " TMs.\n\n"
                   "| unit | top | count | Stages (latency) | chip latency | area per unit | " +
                   std::string(no_synth ? "Fmax MHz" : flow.flow == "generic" ? "Fmax MHz (fo4-v1 estimate)"
                                                                               : "Fmax MHz (OpenSTA)") +
                   " | area x count |\n"
                   "|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& name : units) {
    const synth::UnitSpec& u = synth::find_unit(name);
    synth::UnitConfig c;
    if (u.uses_format) c.fmt = fmt;
    trax::Config cc = cfg;
    const int chip_latency = trax::area_table_latency(cc, name);
    // A chip latency above the unit's useful maximum (fp_sqrt 16 at e5m12: at most M+3 = 15) is
    // the maximum plus delay registers outside the unit (recorded as chip_latency).
    c.stages = std::min(chip_latency, u.max_stages(c));
    if (name == "ray_box" && cfg.box == "conservative") c.params["OptConservative"] = 1;
    synth::GenOptions go;
    go.out_dir = (tmp / name).string();
    go.run_flow = !no_synth;
    go.flow = flow;
    std::fprintf(stderr, "gen: %s %s ...\n", name.c_str(), u.uses_format ? format.c_str() : "");
    if (search) {
      const synth::ClockSearch cs = synth::find_stages_for_clock(
          u, c, flow.clocks_ps.front(), flow, [](const std::string& m) { std::fprintf(stderr, "%s\n", m.c_str()); });
      c.stages = cs.stages;
      go.reuse = cs.result;
      go.clock_search = {{"clock_ps", flow.clocks_ps.front()}, {"probes", cs.probes}};
    }
    const synth::GenReport rep = synth::generate(u, c, go);
    const int count = cfg.unit(trax::area_table_unit(name)).count * cfg.tms;
    // Area and clock as the unit's own datasheet states them (one source for both sheets).
    double area = 0, fmax = 0;
    if (rep.synth) {
      const nlohmann::json ds = nlohmann::json::parse(synth::read_file((tmp / name / "datasheet.json").string()));
      const char* ak = rep.synth->cell.run ? "area_um2" : "area_nand2";
      const char* fk = rep.synth->cell.run ? "fmax_mhz" : "fmax_est_mhz";
      if (!ds.contains(ak) || !ds[ak].is_number() || !ds.contains(fk) || !ds[fk].is_number())
        throw UsageError(name + ": its datasheet has no " + ak + " / " + fk);
      area = ds[ak].get<double>();
      fmax = ds[fk].get<double>();
    }
    nlohmann::ordered_json row = {{"unit", name}, {"top", rep.top}, {"dir", name}, {"count", count},
                                  {"stages", c.stages}, {"latency", u.latency(c)}, {"chip_latency", chip_latency}};
    if (rep.synth) {
      row["area_" + area_unit] = area;
      row["fmax_mhz"] = fmax;
      row["fmax_source"] = rep.synth->cell.run ? "OpenSTA on the cell netlist (before placement)"
                                                : "estimate (fo4-v1 gate-depth model)";
      total_area += area * count;
      if (min_fmax == 0 || fmax < min_fmax) min_fmax = fmax;
    }
    chip["units"].push_back(row);
    char buf[256];
    if (rep.synth)
      std::snprintf(buf, sizeof buf, "| %s | %s | %d | %d | %d | %.0f %s | %.1f | %.0f %s |\n", name.c_str(),
                    rep.top.c_str(), count, c.stages, chip_latency, area, area_unit.c_str(), fmax, area * count,
                    area_unit.c_str());
    else
      std::snprintf(buf, sizeof buf, "| %s | %s | %d | %d | %d | not run | | |\n", name.c_str(), rep.top.c_str(),
                    count, c.stages, chip_latency);
    md += buf;
  }
  if (!no_synth) {
    chip["total_area_" + area_unit] = total_area;
    chip["chip_clock_mhz"] = min_fmax;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "\nTotal functional-unit area %.0f %s; chip clock = the slowest unit's Fmax, %.1f MHz (%s). "
                  "Memories and the thread processors' own logic are not included.\n",
                  total_area, area_unit.c_str(), min_fmax,
                  flow.flow == "generic" ? "estimate: generic flow" : "OpenSTA, before placement");
    md += buf;
  }
  synth::write_file_atomic((tmp / "chip.json").string(), chip.dump(1) + "\n");
  synth::write_file_atomic((tmp / "chip.md").string(), md);
  if (fs::exists(dst, ec)) fs::remove_all(dst, ec);
  fs::rename(tmp, dst, ec);
  if (ec) throw UsageError("cannot move the result into '" + out + "': " + ec.message());
  cleanup.keep = true;
  std::fputs(md.c_str(), stdout);
  std::printf("wrote %s/ (%zu units, chip.md, chip.json)\n", dst.c_str(), units.size());
  return 0;
}

int run_gen_cmd(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--from-profile") == 0 || std::strncmp(argv[i], "--from-profile=", 15) == 0)
      return run_gen_from_profile(argc, argv);
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
