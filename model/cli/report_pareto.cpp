// Report section "pareto" (issue 17 §3–4): the Pareto fronts of the FP units (osu018 cell flow)
// and of the TRaX chip per format, from the checked-in results (the cell-flow points take hours
// to remeasure): rows read and fronts computed by the pareto library, one CSV, plot and table each.
#include <fstream>
#include <string>

#include "rayunits/pareto/pareto.hpp"
#include "rayunits/report/report.hpp"

namespace ru::cli {
namespace {

#ifdef RU_SOURCE_DIR
const std::string kSource = RU_SOURCE_DIR;
#else
const std::string kSource = ".";
#endif

struct Front {
  std::string name, title, inputs, refresh;
  std::vector<std::string> axes, targets;
  std::string plot_axes;
};

std::string pareto_section(ru::report::Context& ctx) {
  const std::vector<Front> fronts = {
      {"fp_units", "FP units: unit roundoff x osu018 area x STA Fmax",
       "synth/results/cell/fp_*.curve.jsonl",
       "`/usr/bin/python3 synth/cell/run.py --rayunits build/model/cli/rayunits -j 1` (hours; synth/cell/README.md)",
       {"error", "area", "fmax"}, {}, "3,2"},
      {"chip", "TRaX chip per format: PSNR x area x rays/s", "docs/trax/trax_formats.csv",
       "`rayunits study trax --kind formats --size 64x64 --out docs/trax`",
       {"psnr_db", "area_mm2", "rays_per_s"}, {"psnr_db>=40", "error_pct<=0.1"}, "1,3"},
  };
  std::string md =
      "Non-dominated points (docs/PARETO.md): per group, the points no other point beats on every axis. "
      "These fronts read the **checked-in results** named below (remeasuring them takes hours); the command "
      "after each refreshes its input, `rayunits pareto` then redraws it.\n\n";
  for (const auto& f : fronts) {
    ctx.check_cancelled();
    std::vector<pareto::Row> rows;
    for (const auto& in : pareto::expand_inputs({kSource + "/" + f.inputs})) {
      auto r = pareto::load_rows(in);
      rows.insert(rows.end(), r.begin(), r.end());
    }
    pareto::Options o;
    for (const auto& a : f.axes) o.axes.push_back(pareto::parse_axis(a));
    const pareto::Result res = pareto::compute(rows, o);
    const std::string base = "pareto_" + f.name;
    std::ofstream(ctx.path(base + ".csv")) << pareto::points_csv(res, rows);
    md += "### " + f.title + "\n\nInput: `" + f.inputs + "` (" + std::to_string(rows.size()) +
          " rows), refreshed by " + f.refresh + "; the same front: `rayunits pareto '" + f.inputs + "' --x " +
          f.axes[0] + " --y " + f.axes[1] + " --z " + f.axes[2] + "`. CSV: [" + base + ".csv](" + base + ".csv)\n\n";
    if (ctx.opts.plots) {
      ctx.run_python("plot_pareto.py", {ctx.path(base + ".csv").string(), ctx.path(base + ".png").string(),
                                        "--axes=" + f.plot_axes});
      md += "![" + f.title + "](" + base + ".png)\n\n";
    }
    md += pareto::front_markdown(res, rows, false);
    if (!f.targets.empty()) {
      std::vector<pareto::Target> ts;
      for (const auto& t : f.targets) ts.push_back(pareto::parse_target(t));
      md += pareto::picks_markdown(res, rows, ts, pareto::cheapest(res, rows, ts, 1)) + "\n";
    }
  }
  return md;
}

}  // namespace

RU_REPORT_SECTION("pareto", "Pareto fronts: FP units and the TRaX chip (from the checked-in results)", 750,
                  pareto_section, true);

}  // namespace ru::cli
