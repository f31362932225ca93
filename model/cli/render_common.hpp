// Shared option handling of the rendering subcommands (render, study image, profile, bench
// render, bvh): scene selection and image size.
#pragma once
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <string>

#include "command.hpp"
#include "rayunits/render/render.hpp"
#include "rayunits/scene/scene.hpp"

namespace ru::cli {

struct SceneArgs {
  std::string scene, mesh, up = "y";
  void add(CLI::App& app, const std::string& default_scene = "") {
    scene = default_scene;
    app.add_option("--scene", scene, "built-in scene: " + ru::scene::scene_name_help());
    app.add_option("--mesh", mesh, "mesh file (OBJ, PLY, OFF, STL, ... via Assimp)");
    app.add_option("--up", up, "up axis of the mesh file: y or z")->check(CLI::IsMember({"y", "z"}));
  }
  // The choice itself (one of --scene and --mesh), without loading anything.
  void check() const {
    if (!mesh.empty() && !scene.empty() && scene != "default")
      throw UsageError("give either --scene or --mesh, not both");
    if (mesh.empty() && scene.empty()) throw UsageError("give --scene NAME or --mesh FILE");
  }
  ru::scene::Scene load() const {
    check();
    if (!mesh.empty()) return ru::scene::load_mesh(mesh, up[0]);
    return ru::scene::make_scene(scene);
  }
};

// Wraps std::invalid_argument from the parse_* helpers as usage errors.
template <class F>
auto parse_or_usage(F f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

// `rayunits render` arguments, parsed and checked without rendering (cmd_render.cpp; `rayunits
// sweep` checks every render job with it).
struct RenderCommand {
  SceneArgs sa;
  render::RenderOptions opt;
  std::string format = "float", tri = "robust", box = "plain", bvh = "sah", noise = "float", texture = "shader";
  std::string out, trace_out, diff_out, json_out;
  std::string compare_noise;  // --compare-noise: the reference's noise model ("": as --noise)
  render::NoiseMode ref_noise = render::NoiseMode::Float;
  bool compare = false;
};
bool parse_render_command(int argc, char** argv, RenderCommand& c);  // false: help was printed

// "512x384" or "256" (square): render::parse_size as a usage error.
inline void parse_size(const std::string& s, int* w, int* h) {
  parse_or_usage([&] { render::parse_size(s, w, h); });
}

}  // namespace ru::cli
