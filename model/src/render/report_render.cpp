// `rayunits report` section "render": the default scene at several widths with both triangle
// algorithms (error table + plot + side-by-side images), its profile and recommendation, and
// the BVH rotation results. Registered in model/cli/cmd_render.cpp.
#include <cmath>
#include <cstdio>
#include <fstream>

#include "rayunits/render/studies.hpp"
#include "rayunits/report/report.hpp"

namespace ru::render {

std::string report_render_section(ru::report::Context& ctx) {
  const std::string scene_name = ctx.param("render.scene", "default");
  const int size = std::atoi(ctx.param("render.size", "128").c_str());
  const int sa_iters = std::atoi(ctx.param("render.sa_iters", "300").c_str());
  if (size < 8 || size > 4096) throw ru::report::ReportError("render: size must be 8..4096");
  const scene::Scene s = scene::make_scene(scene_name);
  std::string md;
  char buf[512];

  // 1. Image-error study (Tables 3.5 / 3.6 shape).
  ctx.progress("image-error study on " + scene_name);
  ImageStudyOptions io;
  io.width = io.height = size;
  io.threads = static_cast<int>(ctx.threads());
  io.image_dir = ctx.dir.string();
  io.image_prefix = "render_";
  io.exp_bits = {7};  // the dissertation's exponent width
  auto rows = image_study(s, io);
  {
    std::ofstream f(ctx.path("render_image_errors.csv"));
    f << "scene,exp_bits,frac_bits,algorithm,errors,pixels,psnr,seconds,overflow_ops,underflow_ops,invalid_ops\n";
    for (const auto& r : rows)
      f << s.name << "," << r.exp_bits << "," << r.frac_bits << "," << tri_name(r.algo) << "," << r.diff.errors << ","
        << r.diff.pixels << "," << (std::isinf(r.diff.psnr) ? std::string("inf") : std::to_string(r.diff.psnr)) << ","
        << r.seconds << "," << r.overflows << "," << r.underflows << "," << r.invalids << "\n";
  }
  std::vector<std::vector<std::string>> table;
  for (int m : io.frac_bits) {
    std::vector<std::string> row{"e7m" + std::to_string(m)};
    for (TriAlgo a : {TriAlgo::MT, TriAlgo::Robust})
      for (const auto& r : rows)
        if (r.frac_bits == m && r.algo == a) {
          row.push_back(std::to_string(r.diff.errors));
          std::snprintf(buf, sizeof buf, "%.1f", r.diff.psnr);
          row.push_back(std::isinf(r.diff.psnr) ? "inf" : buf);
        }
    row.push_back("![](render_side_e7m" + std::to_string(m) + ".png)");
    table.push_back(row);
  }
  std::snprintf(buf, sizeof buf,
                "Scene `%s`, %dx%d, median-split BVH built in the format, plain ray-box test; errors = pixels with a "
                "channel more than 10%% off the double render (`render_reference_double.png`). Images: robust render, its "
                "error map (red: > 10 %% off), MT render, its error map, reference.\n\n",
                s.name.c_str(), size, size);
  md += buf;
  md += ru::report::md_table({"format", "MT errors", "MT PSNR", "robust errors", "robust PSNR", "side by side"}, table);
  if (ctx.opts.plots) {
    ctx.run_python("plot_render_study.py", {ctx.path("render_image_errors.csv").string(), ctx.path("render_image_errors.png").string()});
    md += "\n![error vs fraction bits](render_image_errors.png)\n";
  }

  // 2. Profile and recommendation.
  ctx.progress("profile of " + scene_name);
  ProfileOptions po;
  po.width = po.height = size;
  po.threads = static_cast<int>(ctx.threads());
  const Profile p = profile_scene(s, po);
  {
    std::ofstream f(ctx.path("render_profile.json"));
    f << profile_json(p, po);
  }
  md += "\n### Scene profile\n\n```\n" + profile_text(p, po) + "```\n";

  // 3. Tree rotations (Table 5.1 shape) on the architectural scene and the default scene.
  ctx.progress("tree rotations");
  std::vector<std::vector<std::string>> bt;
  for (const char* n : {"arch", "default"}) {
    RotationOptions ro;
    ro.sa_iterations = sa_iters;
    ro.cast_size = size;
    RotationRow r = rotation_study(scene::make_scene(n), ro);
    auto f2 = [&](double v) {
      std::snprintf(buf, sizeof buf, "%.2f", v);
      return std::string(buf);
    };
    auto pc = [&](double v, double b) {
      std::snprintf(buf, sizeof buf, "%.1f%%", 100.0 * v / b);
      return std::string(buf);
    };
    bt.push_back({r.scene, std::to_string(r.triangles), f2(r.hill_s), f2(r.sa_s), f2(r.cost_none),
                  f2(r.cost_hill) + " (" + pc(r.cost_hill, r.cost_none) + ")",
                  f2(r.cost_sa) + " (" + pc(r.cost_sa, r.cost_none) + ")", f2(r.boxes_none), f2(r.boxes_hill),
                  f2(r.boxes_sa)});
  }
  std::snprintf(buf, sizeof buf,
                "\n### BVH tree rotations\n\nBinned-SAH build (leaves <= 4), hill climbing, simulated annealing "
                "(N = %d, f = 50, h = 0.15); ray-box tests per primary ray at %dx%d.\n\n",
                sa_iters, size, size);
  md += buf;
  md += ru::report::md_table({"scene", "triangles", "hill s", "anneal s", "SAH cost", "hill", "anneal", "box/ray",
                              "hill", "anneal"},
                             bt);
  md += "\nCommands: `rayunits study image`, `rayunits profile`, `rayunits bvh` (docs/RENDER.md).\n";
  return md;
}

}  // namespace ru::render
