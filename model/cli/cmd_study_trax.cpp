// rayunits study trax: the TRaX model's studies (issue 7 section 5), each a CSV, a Markdown table
// and a PNG plot (scripts/plot_trax_study.py).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "cli_util.hpp"
#include "render_common.hpp"
#include "rayunits/report/report.hpp"
#include "rayunits/trax/studies.hpp"
#include "rayunits/util/process.hpp"

namespace ru::cli {
namespace {

int run_study_trax(int argc, char** argv) {
  CLI::App app{"TRaX model studies: formats (the whole-chip speed/accuracy trade), rays (coherent vs incoherent), "
               "traversal (stack vs stackless), noise (hardware unit vs software), units (FP unit count sweep); "
               "each writes trax_<kind>.csv, .md and .png into --out"};
  SceneArgs sa;
  sa.add(app, "default");
  std::string kind = "all", size = "32x32", config_path, formats, out;
  bool no_plot = false, quiet = false;
  app.add_option("--kind", kind, "formats | rays | traversal | noise | units | texture | all");
  app.add_option("--size", size, "image size WxH (or N)");
  app.add_option("--config", config_path, "TRaX configuration (TOML) the studies start from");
  app.add_option("--formats", formats, "formats study: comma-separated formats (default e5m8 ... e8m23)");
  app.add_option("--out", out, "output directory")->required();
  app.add_flag("--no-plot", no_plot, "CSV and Markdown only");
  app.add_flag("--quiet", quiet, "no progress lines");
  if (!parse_args(app, argc, argv)) return 0;

  std::vector<std::string> kinds;
  if (kind == "all")
    kinds = trax::kStudyKinds;
  else {
    bool ok = false;
    for (const auto& k : trax::kStudyKinds) ok = ok || k == kind;
    if (!ok) throw UsageError("unknown --kind '" + kind + "' (accepted: formats, rays, traversal, noise, units, texture, all)");
    kinds = {kind};
  }
  trax::StudyOptions o;
  parse_size(size, &o.width, &o.height);
  try {
    if (!config_path.empty()) o.base = trax::load_config(config_path);
    if (!formats.empty()) {
      std::stringstream ss(formats);
      for (std::string t; std::getline(ss, t, ',');)
        if (!t.empty()) {
          if (t != "float") num::Format::parse(t).validate();
          o.formats.push_back(t);
        }
    }
  } catch (const trax::ConfigError& e) {
    throw UsageError(e.what());
  }
  const scene::Scene s = sa.load();
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) throw UsageError("cannot create output directory '" + out + "': " + ec.message());
  const auto t0 = std::chrono::steady_clock::now();
  if (!quiet)
    o.log = [t0](const std::string& m) {
      std::fprintf(stderr, "study trax: %s (%.1f s)\n", m.c_str(),
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    };
  const std::string command = command_line("rayunits study trax", argc, argv);
  for (const std::string& k : kinds) {
    trax::StudyTable t;
    try {
      t = trax::run_study(k, s, o);
    } catch (const trax::ConfigError& e) {
      throw UsageError(e.what());
    }
    const std::string base = out + "/trax_" + k;
    std::ofstream(base + ".csv") << t.csv();
    std::ofstream(base + ".md") << "### " << t.title << "\n\n`" << command << "`\n\n" << t.markdown() << "\n" << t.note
                                << "\n";
    std::printf("%s\n\n%s\n", t.title.c_str(), t.markdown().c_str());
    if (!no_plot) {
      const std::string py = report::find_python();
      const std::string script = (report::scripts_dir() / "plot_trax_study.py").string();
      const std::string cmd = py + " '" + script + "' " + k + " '" + base + ".csv' '" + base + ".png'";
      if (util::run_foreground({py, script, k, base + ".csv", base + ".png"}) != 0)
        throw UsageError("plot failed: " + cmd);
      std::printf("wrote %s.csv, %s.md, %s.png\n", base.c_str(), base.c_str(), base.c_str());
    } else {
      std::printf("wrote %s.csv, %s.md\n", base.c_str(), base.c_str());
    }
  }
  return 0;
}

}  // namespace

RU_COMMAND("study trax",
           "TRaX model studies: format speed/accuracy trade, coherent vs incoherent rays, stack vs stackless, "
           "noise unit vs software, FP unit count (CSV + Markdown + PNG)",
           run_study_trax);

}  // namespace ru::cli
