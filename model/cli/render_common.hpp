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
  ru::scene::Scene load() const {
    if (!mesh.empty() && !scene.empty() && scene != "default")
      throw UsageError("give either --scene or --mesh, not both");
    if (!mesh.empty()) return ru::scene::load_mesh(mesh, up[0]);
    if (scene.empty()) throw UsageError("give --scene NAME or --mesh FILE");
    return ru::scene::make_scene(scene);
  }
};

// "512x384" or "256" (square).
inline void parse_size(const std::string& s, int* w, int* h) {
  char* end = nullptr;
  long a = std::strtol(s.c_str(), &end, 10);
  long b = a;
  if (end && *end == 'x') {
    const char* p = end + 1;
    b = std::strtol(p, &end, 10);
    if (end == p) end = nullptr;
  }
  if (!end || *end != '\0' || a < 1 || b < 1 || a > 16384 || b > 16384)
    throw UsageError("bad --size '" + s + "' (expected WxH or N, 1..16384, e.g. 512x512)");
  *w = static_cast<int>(a);
  *h = static_cast<int>(b);
}

// Wraps std::invalid_argument from the parse_* helpers as usage errors.
template <class F>
auto parse_or_usage(F f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

}  // namespace ru::cli
