// Report section "trax" (issue 7 section 5): the TRaX model's studies at a small image size,
// each a CSV, a plot and a table, with the command that reproduces it (`rayunits study trax`).
#include <fstream>
#include <string>

#include "rayunits/report/report.hpp"
#include "rayunits/scene/scene.hpp"
#include "rayunits/trax/studies.hpp"

namespace ru::cli {
namespace {

std::string trax_section(ru::report::Context& ctx) {
  const std::string scene_name = ctx.param("trax.scene", "default");
  const std::string size = ctx.param("trax.size", "24");
  trax::StudyOptions o;
  o.width = o.height = std::stoi(size);
  o.log = [&ctx](const std::string& m) { ctx.progress(m); };
  const scene::Scene s = scene::make_scene(scene_name);
  std::string md = "The TRaX-style processor model (docs/TRAX.md) running the renderer's ray tracer on scene `" +
                   scene_name + "` at " + size + "x" + size + " pixels (default chip: 4 TMs x 32 TPs; clock = the STA Fmax of the slowest used unit, areas in mm2 "
                   "of osu018 cells from model/data/trax/areas.json, memories estimated). "
                   "Reproduce a table with `rayunits study trax --kind KIND --scene " + scene_name + " --size " + size +
                   " --out DIR`; larger sizes give steadier numbers. The RTL co-simulation of the box, triangle and "
                   "noise units is `rayunits trax --cosim` (ctest `trax_cosim.*`).\n\n";
  for (const std::string& k : trax::kStudyKinds) {
    ctx.check_cancelled();
    const trax::StudyTable t = trax::run_study(k, s, o);
    const std::string base = "trax_" + k;
    std::ofstream(ctx.path(base + ".csv")) << t.csv();
    if (ctx.opts.plots)
      ctx.run_python("plot_trax_study.py", {k, ctx.path(base + ".csv").string(), ctx.path(base + ".png").string()});
    md += "#### " + t.title + "\n\n" + t.markdown() + "\n" + t.note + " CSV: [" + base + ".csv](" + base + ".csv)\n\n";
    if (ctx.opts.plots) md += "![" + t.title + "](" + base + ".png)\n\n";
  }
  return md;
}

}  // namespace

RU_REPORT_SECTION("trax", "TRaX-style processor model: format trade-off, ray coherence, traversal, noise, unit count",
                  700, trax_section, true);

}  // namespace ru::cli
