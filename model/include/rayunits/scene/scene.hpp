// Scenes: triangle soups with materials, a pinhole camera and one point light (Mirth, §2.1).
//
// Built-in procedural scenes need no files (make_scene); mesh files load through the one
// loader (load_mesh, scene/mesh_file.hpp). Every scene may be scaled by a power of ten with
// the suffix "@<factor>" ("default@1e-6"): geometry, camera, light and the epsilon scale together, while
// procedural textures are evaluated in unscaled object coordinates, so the scaled image is
// the same picture and only the numbers differ (the point of the 1e-6 / 1e+6 variants).
#pragma once
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayunits/scene/vec.hpp"

namespace ru::scene {

// One-line error for unknown scene names, unreadable or malformed mesh files.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class MaterialKind : uint8_t {
  Constant,    // colour only
  Marble,      // bands of sin-free triangle wave perturbed by turbulence (noise)
  Wood,        // rings around the z axis perturbed by noise
  Turbulence,  // colour blend by |noise| summed over octaves (granite-like)
};
const char* material_kind_name(MaterialKind k);
inline bool is_procedural(MaterialKind k) { return k != MaterialKind::Constant; }

struct Material {
  std::string name;
  MaterialKind kind = MaterialKind::Constant;
  Vec3 color{0.8, 0.8, 0.8};   // base colour (rgb in [0,1])
  Vec3 color2{0.2, 0.2, 0.2};  // second colour of procedural patterns
  double frequency = 1.0;      // texture-space frequency (per unscaled scene unit)
  int octaves = 4;             // noise octaves of the turbulence (marble, turbulence), 1..8
};

struct Triangle {
  Vec3 p[3];
  uint32_t material = 0;
};

struct Camera {
  Vec3 eye{0, -4, 1}, look_at{0, 0, 0}, up{0, 0, 1};
  double fov_deg = 40.0;  // vertical field of view
};

// A participating medium (Kensler's Fig. 4.1 smoke): an axis-aligned box whose density is fBm
// noise, ray-marched along the primary rays in a fixed number of steps (render/tracer.hpp,
// Tracer::through_volume). Lengths and frequency in scene units (scaled with the scene).
struct Volume {
  Vec3 lo, hi;                  // the box
  Vec3 color{0.8, 0.8, 0.8};    // the medium's (emitted and scattered) colour
  double frequency = 1.0;       // noise coordinate = point * frequency / unit
  double density = 1.0;         // extinction per unit length = density * max(0, fbm + bias)
  double bias = 0.0;
  int steps = 64;               // samples per ray through the box
  int octaves = 8;              // fBm octaves per sample
};

struct Scene {
  std::string name;
  std::vector<Triangle> tris;
  std::vector<Material> materials;
  std::optional<Volume> volume;
  Camera camera;
  Vec3 light{0, 0, 10};
  double unit = 1.0;  // length of one "scene unit" (the @ scale factor): epsilon = 1e-3 * unit

  double epsilon() const { return 1e-3 * unit; }
  bool has_procedural_materials() const;
  Vec3 bounds_lo() const;
  Vec3 bounds_hi() const;
};

// Names accepted by make_scene (without scale suffix): default, sphere, cornell, arch,
// balls, wave, plus "bunny"/"dragon"/"armadillo" when the CGAL demo meshes are installed.
std::vector<std::string> builtin_scene_names();
std::string scene_name_help();  // "default, sphere, cornell, arch, ... (suffix @1e-6 ...)"

// Builds a named scene; "NAME@FACTOR" scales it. Throws SceneError naming the accepted names.
Scene make_scene(const std::string& name);

// Loads a mesh file through the one loader (scene/mesh_file.hpp: parent-side checks, Assimp in
// a sandboxed child with time and memory limits; OBJ, PLY, OFF, STL, ...). Every triangle gets
// its file's material colour (grey by default); the camera frames the bounding box (up axis:
// 'y' for most scanned meshes, 'z'). Throws SceneError with one line (file name and reason)
// for missing, unreadable, empty, oversized or malformed files, out-of-range indices and
// non-finite or huge coordinates; time limit: 30 s + 2 s per MB (RU_MESH_TIMEOUT overrides),
// memory limit: 2 GiB (RU_MESH_MEMORY_MB overrides).
Scene load_mesh(const std::string& path, char up_axis = 'y');
void set_mesh_load_timeout(double seconds);  // > 0 overrides the default (tests); 0 restores it

// Multiplies geometry, camera, light and unit by s (s > 0, finite).
void scale_scene(Scene& s, double factor);

// Path of a CGAL demo mesh ("bunny" -> .../bunny00.off) or "" when not installed.
std::string find_demo_mesh(const std::string& name);

// Animated (deforming) scenes for the refit / rotation study (§5.6): same triangles in every
// frame, positions change. names: "balls" (spheres scattering from a cluster), "wave"
// (a cloth sheet rolling up). frame in [0, frames).
std::vector<std::string> animation_names();
Scene make_animation_frame(const std::string& name, int frame, int frames);

}  // namespace ru::scene
