// rayunits bvh anim: refit vs refit + rotations vs rebuild on a deforming scene (§5.6).
#include <cstdio>
#include <fstream>
#include <sstream>

#include "cli_util.hpp"
#include "render_common.hpp"
#include "rayunits/render/studies.hpp"

namespace ru::cli {
namespace {

int run_bvh_anim(int argc, char** argv) {
  CLI::App app{"Refit-only vs refit + tree rotations vs full rebuild on a deforming scene (§5.6, Table 5.2 shape)"};
  std::string scene = "balls", csv;
  int frames = 30, cast = 128;
  app.add_option("--scene", scene, "animation: balls | wave");
  app.add_option("--frames", frames, "number of frames")->check(CLI::Range(2, 10000));
  app.add_option("--cast-size", cast, "ray-casting image size per frame (0: skip)")->check(CLI::Range(0, 4096));
  app.add_option("--csv", csv, "write per-frame rows as CSV");
  if (!parse_args(app, argc, argv)) return 0;
  auto rows = render::animation_study(scene, frames, cast, true);
  const size_t tris = scene::make_animation_frame(scene, 0, frames).tris.size();
  std::printf("%s: %zu triangles, %d frames, leaves of 1 triangle, ray casting %dx%d float 1 thread\n", scene.c_str(),
              tris, frames, cast, cast);
  std::printf("%5s | %9s %9s %9s | %9s | %10s %10s %10s | %9s %9s %9s\n", "frame", "SAH refit", "rotate", "rebuild",
              "rotations", "upd refit", "upd rotate", "rebuild s", "cast refit", "rotate", "rebuild");
  render::AnimationFrame sum;
  for (const auto& a : rows) {
    std::printf("%5d | %9.2f %9.2f %9.2f | %9llu | %10.5f %10.5f %10.5f | %9.4f %9.4f %9.4f\n", a.frame, a.cost_refit,
                a.cost_rotate, a.cost_rebuild, (unsigned long long)a.rotations, a.update_refit_s, a.update_rotate_s,
                a.rebuild_s, a.render_refit_s, a.render_rotate_s, a.render_rebuild_s);
    sum.cost_refit += a.cost_refit;
    sum.cost_rotate += a.cost_rotate;
    sum.cost_rebuild += a.cost_rebuild;
    sum.rotations += a.rotations;
    sum.update_refit_s += a.update_refit_s;
    sum.update_rotate_s += a.update_rotate_s;
    sum.rebuild_s += a.rebuild_s;
    sum.render_refit_s += a.render_refit_s;
    sum.render_rotate_s += a.render_rotate_s;
    sum.render_rebuild_s += a.render_rebuild_s;
  }
  const double n = double(rows.size());
  std::printf("%5s | %9.2f %9.2f %9.2f | %9.0f | %10.5f %10.5f %10.5f | %9.4f %9.4f %9.4f\n", "mean", sum.cost_refit / n,
              sum.cost_rotate / n, sum.cost_rebuild / n, double(sum.rotations) / n, sum.update_refit_s / n,
              sum.update_rotate_s / n, sum.rebuild_s / n, sum.render_refit_s / n, sum.render_rotate_s / n,
              sum.render_rebuild_s / n);
  if (!csv.empty()) {
    std::ofstream f(csv);
    if (!f) throw UsageError("cannot write '" + csv + "'");
    f << "scene,frame,cost_refit,cost_rotate,cost_rebuild,rotations,update_refit_s,update_rotate_s,rebuild_s,"
         "cast_refit_s,cast_rotate_s,cast_rebuild_s\n";
    for (const auto& a : rows)
      f << scene << "," << a.frame << "," << a.cost_refit << "," << a.cost_rotate << "," << a.cost_rebuild << ","
        << a.rotations << "," << a.update_refit_s << "," << a.update_rotate_s << "," << a.rebuild_s << ","
        << a.render_refit_s << "," << a.render_rotate_s << "," << a.render_rebuild_s << "\n";
    std::printf("wrote %s\n", csv.c_str());
  }
  return 0;
}

}  // namespace

RU_COMMAND("bvh anim", "refit vs refit+rotations vs rebuild per frame of a deforming scene (5.6)", run_bvh_anim);

}  // namespace ru::cli
