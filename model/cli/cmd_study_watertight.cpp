// rayunits study watertight: leaks and double hits of ray_tri_robust / ray_tri_mt for rays
// aimed exactly at shared edges and vertices of a closed mesh (units/watertight.hpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "studies.hpp"
#include "rayunits/units/mesh.hpp"
#include "rayunits/units/watertight.hpp"

namespace ru::cli {
namespace {

using namespace ru::units;

double per_million(size_t n, size_t rays) { return rays ? 1e6 * static_cast<double>(n) / static_cast<double>(rays) : 0; }

int run_watertight_cmd(int argc, char** argv) {
  CLI::App app{
      "Watertightness of the ray-triangle units: rays from inside a closed mesh aimed exactly at shared "
      "edges and shared vertices (points representable in the format), counting leaks (no triangle hit) "
      "and double hits (two or more triangles hit). Edge and vertex rays are reported separately. The "
      "last line is 'leaks=L double_hits=D rays=N'.",
      "rayunits study watertight"};
  WatertightArgs a;
  auto* g = app.add_option_group("mesh", "one of");
  g->add_option("--scene", a.scene, std::string("built-in closed mesh: ") + builtin_mesh_names());
  g->add_option("--mesh", a.mesh_file, "closed mesh file (OBJ, OFF, PLY, STL, ...)");
  g->require_option(1);
  app.add_option("--format", a.format, "number format eXmY[-ftz] (e8m23 runs as native float, e11m52 as double)")
      ->capture_default_str();
  app.add_option("--tri", a.tri,
                 "robust (Kensler Fig. 3.6), mt (Moller-Trumbore) or exact (ray_tri_exact: exact edge signs, "
                 "symbolic perturbation of the ray; exactly once)")
      ->check(CLI::IsMember({"robust", "mt", "exact"}))
      ->capture_default_str();
  app.add_option("--rays", a.rays, "number of rays (half edge, half vertex rays)")
      ->capture_default_str()
      ->check(CLI::Range(size_t{2}, size_t{1} << 40));
  app.add_option("--near-vertex", a.near_vertex,
                 "additional rays aimed within -3..3 ulps (per coordinate) of a random vertex")
      ->capture_default_str()
      ->check(CLI::Range(size_t{0}, size_t{1} << 40));
  app.add_option("--scale", a.scale,
                 "multiply the mesh's coordinates by this (before rounding into the format), e.g. 64 to bring "
                 "a mesh normalised to |x| <= 0.5 out of e5m10's underflow range")
      ->capture_default_str();
  app.add_option("--seed", a.seed, "random seed")->capture_default_str();
  app.add_option("--threads", a.threads, "worker threads")->capture_default_str()->check(CLI::Range(1, 64));
  app.add_flag("--tie-break", a.tie_break, "robust: enable Fig. 3.6's optional zero-volume tie-break");
  app.add_option("--csv", a.csv, "append one result row to this CSV file (header written if new)");
  app.add_flag("--quiet", a.quiet, "no progress on stderr");
  if (!parse_args(app, argc, argv)) return 0;
  run_watertight_study(a, stdout, stderr);
  return 0;
}

}  // namespace

WatertightRun run_watertight_study(const WatertightArgs& args, std::FILE* out, std::FILE* err) {
  const std::string &scene = args.scene, &mesh_file = args.mesh_file, &format = args.format, &tri = args.tri,
                    &csv = args.csv;
  const size_t rays = args.rays;
  const uint64_t seed = args.seed;
  const int threads = args.threads;
  const bool tie_break = args.tie_break, quiet = args.quiet;
  if (rays < 2) throw UsageError("--rays must be at least 2");

  WatertightOptions opt;
  opt.fmt = ru::num::Format::parse(format);
  opt.robust = tri == "robust";
  opt.exact = tri == "exact";
  opt.near_vertex_rays = args.near_vertex;
  if (opt.exact && tie_break) throw UsageError("--tie-break applies to --tri robust only");
  opt.tri.tie_break = tie_break;
  opt.rays = rays;
  opt.seed = seed;
  opt.threads = threads;
  const auto t0 = std::chrono::steady_clock::now();
  size_t last = 0;
  if (!quiet)
    opt.progress = [&](size_t done, size_t total) {
      if (done * 10 / total != last * 10 / total || done == total) {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::fprintf(err, "[study watertight] %zu/%zu rays  %.1f s\n", done, total, s);
      }
      last = done;
    };
  if (!(args.scale > 0) || !std::isfinite(args.scale))
    throw UsageError("--scale must be a positive finite number, got " + std::to_string(args.scale));
  Mesh mesh = scene.empty() ? load_mesh(mesh_file) : builtin_mesh(scene);
  if (args.scale != 1.0)
    for (Vec3d& v : mesh.verts) v = {v.x * args.scale, v.y * args.scale, v.z * args.scale};
  const WatertightResult r = run_watertight(mesh, opt);
  const auto tot = r.total();

  std::fprintf(out, "scene %s: %zu vertices, %zu triangles, closed; format %s; ray_tri_%s%s; seed %llu%s\n",
              mesh.name.c_str(), r.vertices, r.triangles, opt.fmt.name().c_str(), tri.c_str(),
              tie_break ? " (tie-break)" : "", static_cast<unsigned long long>(seed),
              args.scale != 1.0 ? ("; coordinates x " + std::to_string(args.scale)).c_str() : "");
  std::fprintf(out, "rays: %zu through shared edges (%zu exactly on the edge, %zu within rounding of it), "
              "%zu through shared vertices, %zu within a few ulps of a vertex\n",
              r.edge.rays, r.edge.rays - r.near_edge_rays, r.near_edge_rays, r.vertex.rays, r.near_vertex.rays);
  std::fprintf(out, "leak: fewer triangles hit than the exact oracle's crossings of the perturbed ray; double: more\n");
  std::fprintf(out, "%-11s %10s %8s %12s %12s %12s %14s", "", "rays", "leaks", "double_hits", "leaks/Mray",
               "double/Mray", "oracle_not_1");
  if (opt.exact) std::fprintf(out, " %10s %10s %9s", "tests", "slow", "slow_%");
  std::fprintf(out, "\n");
  auto row = [&](const char* name, const WatertightCounts& c) {
    std::fprintf(out, "%-11s %10zu %8zu %12zu %12.0f %12.0f %14zu", name, c.rays, c.leaks, c.double_hits,
                per_million(c.leaks, c.rays), per_million(c.double_hits, c.rays), c.oracle_not_one);
    if (opt.exact)
      std::fprintf(out, " %10zu %10zu %9.3f", c.tests, c.slow_tests,
                   c.tests ? 100.0 * static_cast<double>(c.slow_tests) / static_cast<double>(c.tests) : 0.0);
    std::fprintf(out, "\n");
  };
  row("edge", r.edge);
  row("vertex", r.vertex);
  if (r.near_vertex.rays) row("near-vertex", r.near_vertex);
  row("all", tot);
  std::fprintf(out, "exact check: %zu rays hit nothing in exact arithmetic (must be 0); %zu rays aimed only "
              "within rounding; candidates/ray %.1f; rays with overflow: %zu\n",
              r.exact_misses, r.inexact_aim, r.candidates_per_ray, r.overflow_rays);
  if (!csv.empty()) {
    std::FILE* probe = std::fopen(csv.c_str(), "r");
    const bool is_new = !probe;
    if (probe) std::fclose(probe);
    std::FILE* f = std::fopen(csv.c_str(), "a");
    if (!f) throw UsageError("cannot write " + csv);
    if (is_new)
      std::fprintf(f, "scene,format,tri,tie_break,seed,edge_rays,edge_leaks,edge_double_hits,vertex_rays,"
                      "vertex_leaks,vertex_double_hits,near_edge_rays,exact_misses,overflow_rays,"
                      "near_vertex_rays,near_vertex_leaks,near_vertex_double_hits,oracle_not_one,tests,slow_tests,scale\n");
    std::fprintf(f, "%s,%s,%s,%d,%llu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%g\n", mesh.name.c_str(),
                 opt.fmt.name().c_str(), tri.c_str(), tie_break ? 1 : 0, static_cast<unsigned long long>(seed),
                 r.edge.rays, r.edge.leaks, r.edge.double_hits, r.vertex.rays, r.vertex.leaks,
                 r.vertex.double_hits, r.near_edge_rays, r.exact_misses, r.overflow_rays, r.near_vertex.rays,
                 r.near_vertex.leaks, r.near_vertex.double_hits, tot.oracle_not_one, tot.tests, tot.slow_tests,
                 args.scale);
    std::fclose(f);
  }
  std::fprintf(out, "leaks=%zu double_hits=%zu rays=%zu\n", tot.leaks, tot.double_hits, tot.rays);
  return {mesh.name, opt.fmt.name(), r};
}


RU_COMMAND("study watertight", "leaks / double hits of the ray-triangle units on closed meshes", run_watertight_cmd);

}  // namespace ru::cli
