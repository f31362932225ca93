// rayunits bvh: tree rotations on static scenes (Table 5.1 shape);
// rayunits bvh anim: refit vs refit + rotations vs rebuild on a deforming scene (§5.6).
#include <cstdio>
#include <fstream>
#include <sstream>

#include "cli_util.hpp"
#include "render_common.hpp"
#include "rayunits/render/studies.hpp"

namespace ru::cli {
namespace {

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

double pct(double a, double b) { return b != 0 ? 100.0 * a / b : 0.0; }

int run_bvh(int argc, char** argv) {
  CLI::App app{"BVH tree rotations (Kensler ch. 5): SAH cost and ray-casting time before and after hill climbing "
               "and simulated annealing (the shape of Table 5.1)"};
  std::string scenes = "arch", csv, costs_csv, mesh;
  render::RotationOptions o;
  app.add_option("--scene", scenes, "comma-separated scene names (" + scene::scene_name_help() + ")");
  app.add_option("--mesh", mesh, "a mesh file instead of --scene");
  app.add_option("--leaf", o.leaf_size, "max triangles per leaf of the SAH build")->check(CLI::Range(1, 64));
  app.add_option("--sa-iters", o.sa_iterations, "simulated annealing schedule length N (dissertation: 1250)")
      ->check(CLI::Range(0, 100000));
  app.add_option("--heat", o.heat, "hottest temperature h (dissertation: 0.8 .. 2.2 with other cost constants; here 0.1 .. 0.2)")->check(CLI::Range(0.0, 100.0));
  app.add_option("--seed", o.seed, "random seed of the annealing");
  app.add_option("--cast-size", o.cast_size, "ray-casting image size for the timing (0: skip)")->check(CLI::Range(0, 4096));
  app.add_option("--csv", csv, "write the table as CSV");
  app.add_option("--costs-csv", costs_csv, "write the SAH cost after every annealing pass (Fig. 5.4) as CSV");
  if (!parse_args(app, argc, argv)) return 0;
  o.progress = true;
  std::vector<scene::Scene> list;
  if (!mesh.empty()) list.push_back(scene::load_mesh(mesh));
  else
    for (const auto& n : split_commas(scenes)) list.push_back(scene::make_scene(n));
  if (list.empty()) throw UsageError("no scene given");
  std::vector<render::RotationRow> rows;
  for (const auto& s : list) rows.push_back(render::rotation_study(s, o));
  std::printf("Tree rotations (SAH Ct = Ci = 1, leaves <= %d, annealing N = %d, f = 50, h = %g, seed %llu; "
              "ray casting %dx%d float, primary rays, 1 thread)\n",
              o.leaf_size, o.sa_iterations, o.heat, (unsigned long long)o.seed, o.cast_size, o.cast_size);
  std::printf("%-14s %9s | %8s %8s | %8s %8s %8s | %14s %14s | %7s %7s %7s | %7s %7s %7s\n", "scene", "triangles",
              "hill s", "anneal s", "cost", "hill", "anneal", "hill %", "anneal %", "cast s", "hill", "anneal",
              "box/ray", "hill", "anneal");
  for (const auto& r : rows)
    std::printf("%-14s %9zu | %8.2f %8.2f | %8.2f %8.2f %8.2f | %13.1f%% %13.1f%% | %7.3f %7.3f %7.3f | %7.1f %7.1f %7.1f\n",
                r.scene.c_str(), r.triangles, r.hill_s, r.sa_s, r.cost_none, r.cost_hill, r.cost_sa,
                pct(r.cost_hill, r.cost_none), pct(r.cost_sa, r.cost_none), r.cast_none, r.cast_hill, r.cast_sa,
                r.boxes_none, r.boxes_hill, r.boxes_sa);
  if (!csv.empty()) {
    std::ofstream f(csv);
    if (!f) throw UsageError("cannot write '" + csv + "'");
    f << "scene,triangles,build_s,hill_s,anneal_s,cost_none,cost_hill,cost_anneal,cast_none_s,cast_hill_s,"
         "cast_anneal_s,boxes_per_ray_none,boxes_per_ray_hill,boxes_per_ray_anneal,hill_passes,anneal_passes,"
         "hill_rotations,anneal_rotations\n";
    for (const auto& r : rows)
      f << r.scene << "," << r.triangles << "," << r.build_s << "," << r.hill_s << "," << r.sa_s << "," << r.cost_none
        << "," << r.cost_hill << "," << r.cost_sa << "," << r.cast_none << "," << r.cast_hill << "," << r.cast_sa << ","
        << r.boxes_none << "," << r.boxes_hill << "," << r.boxes_sa << "," << r.hill_passes << "," << r.sa_passes << ","
        << r.hill_rotations << "," << r.sa_rotations << "\n";
    std::printf("wrote %s\n", csv.c_str());
  }
  if (!costs_csv.empty()) {
    std::ofstream f(costs_csv);
    if (!f) throw UsageError("cannot write '" + costs_csv + "'");
    f << "scene,pass,sah_cost\n";
    for (const auto& r : rows)
      for (size_t i = 0; i < r.sa_cost_per_pass.size(); ++i) f << r.scene << "," << i + 1 << "," << r.sa_cost_per_pass[i] << "\n";
    std::printf("wrote %s\n", costs_csv.c_str());
  }
  return 0;
}

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

RU_COMMAND("bvh", "BVH tree rotations: SAH cost / ray-cast time before and after (Table 5.1 shape)", run_bvh);
RU_COMMAND("bvh anim", "refit vs refit+rotations vs rebuild per frame of a deforming scene (5.6)", run_bvh_anim);

}  // namespace ru::cli
