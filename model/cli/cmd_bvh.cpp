// rayunits bvh: tree rotations on static scenes (Table 5.1 shape).
#include <cstdio>
#include <fstream>
#include <sstream>

#include "cli_util.hpp"
#include "render_common.hpp"
#include "rayunits/render/studies.hpp"

namespace ru::cli {
namespace {

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
    for (const auto& n : split_list(scenes)) list.push_back(scene::make_scene(n));
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

}  // namespace

RU_COMMAND("bvh", "BVH tree rotations: SAH cost / ray-cast time before and after (Table 5.1 shape)", run_bvh);

}  // namespace ru::cli
