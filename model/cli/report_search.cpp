// Report section "search" (issue 18 §3): the formulation searches checked in under
// sweeps/results/search/<name>/ (`rayunits search tri --out DIR`, hours each): per search its
// command, the reported designs beside the hand designs, the cost model against the designs
// synthesized in full, and the front's plot. Tables and plot come from scripts/search_table.py,
// the same script that makes the README's tables (one table writer).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayunits/report/report.hpp"

namespace ru::cli {
namespace {

namespace fs = std::filesystem;

#ifdef RU_SOURCE_DIR
const std::string kSource = RU_SOURCE_DIR;
#else
const std::string kSource = ".";
#endif

std::string search_section(ru::report::Context& ctx) {
  // --param search.dir=DIR: another results directory (one subdirectory per search), e.g. a test's
  const fs::path root = ctx.param("search.dir", (fs::path(kSource) / "sweeps" / "results" / "search").string());
  std::vector<fs::path> dirs;
  if (fs::is_directory(root))
    for (const auto& e : fs::directory_iterator(root))
      if (fs::exists(e.path() / "front.csv")) dirs.push_back(e.path());
  std::sort(dirs.begin(), dirs.end());
  std::string md =
      "Searches over equivalent ray-triangle formulations (docs/DATAPATH.md, \"The search\"): NSGA-II on "
      "area (cost model from cell-flow rows: an estimate), error of t, β, γ against exact rationals on a "
      "captured render trace, watertightness misses and extra hits. These are the **checked-in results** "
      "under `sweeps/results/search/` (each search takes hours); every reported design passed the "
      "cycle-by-cycle scoreboard (`rtl` column) before it was reported.\n\n";
  if (dirs.empty()) return md + "No search results found under `" + root.string() + "`.\n";
  for (const auto& d : dirs) {
    ctx.check_cancelled();
    const std::string name = d.filename().string();
    std::string command = "(not recorded)";
    std::ifstream fj(d / "front.json");
    if (fj) {
      const auto j = nlohmann::json::parse(fj, nullptr, false);
      if (!j.is_discarded() && j.contains("command")) command = j["command"].get<std::string>();
    }
    md += "### " + name + "\n\nCommand: `" + command + "`; files: `" + (ctx.opts.params.count("search.dir") ? d.string() : "sweeps/results/search/" + name) + "/`.\n\n";
    if (!ctx.opts.plots) {
      md += "(The table and plot are made by scripts/search_table.py, which needs python: run the report "
            "without --no-plots, or `scripts/search_table.py sweeps/results/search/" + name + "`.)\n\n";
      continue;
    }
    const std::string base = "search_" + name;
    ctx.run_python("search_table.py",
                   {d.string(), "--md", ctx.path(base + ".md").string(), "--plot", ctx.path(base + ".png").string()});
    std::ifstream t(ctx.path(base + ".md"));
    std::stringstream ss;
    ss << t.rdbuf();
    md += ss.str() + "\n![" + name + "](" + base + ".png)\n\n";
  }
  return md;
}

}  // namespace

RU_REPORT_SECTION("search", "Formulation search: smaller ray-triangle hardware (from the checked-in results)", 760,
                  search_section, true);

}  // namespace ru::cli
