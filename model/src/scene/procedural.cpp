// Built-in procedural scenes (no files needed) and the animated scenes of the rotation study.
#include <array>
#include <cmath>
#include <cstdlib>
#include <unordered_map>

#include "rayunits/scene/scene.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Deterministic pseudo-random numbers (a splitmix64 stream) so every scene is the same everywhere.
struct Rng : util::SplitMix64 {
  using util::SplitMix64::SplitMix64;
  double range(double lo, double hi) { return uniform(lo, hi); }
};

struct Builder {
  Scene& s;
  uint32_t material(const Material& m) {
    s.materials.push_back(m);
    return static_cast<uint32_t>(s.materials.size() - 1);
  }
  void tri(const Vec3& a, const Vec3& b, const Vec3& c, uint32_t m) { s.tris.push_back({{a, b, c}, m}); }
  // Quad a-b-c-d (counter-clockwise seen from the front) as two triangles sharing edge a-c.
  void quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, uint32_t m) {
    tri(a, b, c, m);
    tri(a, c, d, m);
  }
  // Tessellated parallelogram origin + i/nu*du + j/nv*dv: every interior edge is shared.
  void grid(const Vec3& o, const Vec3& du, const Vec3& dv, int nu, int nv, uint32_t m) {
    auto at = [&](int i, int j) { return o + du * (double(i) / nu) + dv * (double(j) / nv); };
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), m);
  }
  // Box from its 8 corners c[0..7] (bit 0: +x, bit 1: +y, bit 2: +z), faces outward.
  void box_corners(const Vec3 c[8], uint32_t m) {
    static const int f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : f) quad(c[q[0]], c[q[1]], c[q[2]], c[q[3]], m);
  }
  void box(const Vec3& lo, const Vec3& hi, uint32_t m) { oriented_box((lo + hi) * 0.5, (hi - lo) * 0.5, 0, m); }
  // Box with half extents h around center, rotated by angle (radians) about the z axis.
  void oriented_box(const Vec3& center, const Vec3& h, double angle, uint32_t m) {
    Vec3 c[8];
    const double ca = std::cos(angle), sa = std::sin(angle);
    for (int i = 0; i < 8; ++i) {
      Vec3 l{(i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z};
      c[i] = center + Vec3{ca * l.x - sa * l.y, sa * l.x + ca * l.y, l.z};
    }
    box_corners(c, m);
  }
  // Icosphere: icosahedron subdivided `level` times (20 * 4^level triangles, all edges shared:
  // midpoints are computed once per edge from the same two endpoints in the same order).
  void icosphere(const Vec3& center, double r, int level, uint32_t m) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& p : v) p = normalize(p);
    std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                         {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                         {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                         {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int l = 0; l < level; ++l) {
      std::vector<std::array<int, 3>> g;
      std::unordered_map<uint64_t, int> cache;
      auto mid = [&](int a, int b) {
        uint64_t key = (uint64_t(std::min(a, b)) << 32) | uint64_t(std::max(a, b));
        auto it = cache.find(key);
        if (it != cache.end()) return it->second;
        v.push_back(normalize((v[std::min(a, b)] + v[std::max(a, b)]) * 0.5));
        cache.emplace(key, int(v.size() - 1));
        return int(v.size() - 1);
      };
      for (auto& tr : f) {
        int a = mid(tr[0], tr[1]), b = mid(tr[1], tr[2]), c = mid(tr[2], tr[0]);
        g.push_back({tr[0], a, c});
        g.push_back({tr[1], b, a});
        g.push_back({tr[2], c, b});
        g.push_back({a, b, c});
      }
      f.swap(g);
    }
    for (auto& tr : f) tri(center + v[tr[0]] * r, center + v[tr[1]] * r, center + v[tr[2]] * r, m);
  }
  // Torus around the z axis (major radius R, minor r): nu x nv quads, all edges shared.
  void torus(const Vec3& c, double R, double r, int nu, int nv, uint32_t m) {
    auto at = [&](int i, int j) {
      double u = 2 * kPi * (i % nu) / nu, w = 2 * kPi * (j % nv) / nv;
      return c + Vec3{(R + r * std::cos(w)) * std::cos(u), (R + r * std::cos(w)) * std::sin(u), r * std::sin(w)};
    };
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), m);
  }
  // Closed cylinder along z from base center b, radius r, height h, n segments.
  void cylinder(const Vec3& b, double r, double h, int n, uint32_t m) {
    auto at = [&](int i, double z) {
      double u = 2 * kPi * (i % n) / n;
      return b + Vec3{r * std::cos(u), r * std::sin(u), z};
    };
    Vec3 top = b + Vec3{0, 0, h};
    for (int i = 0; i < n; ++i) {
      quad(at(i, 0), at(i + 1, 0), at(i + 1, h), at(i, h), m);
      tri(b, at(i + 1, 0), at(i, 0), m);
      tri(top, at(i, h), at(i + 1, h), m);
    }
  }
};

Material constant(const char* name, Vec3 c) {
  Material m;
  m.name = name;
  m.color = c;
  return m;
}
Material procedural(const char* name, MaterialKind k, Vec3 c1, Vec3 c2, double freq) {
  Material m;
  m.name = name;
  m.kind = k;
  m.color = c1;
  m.color2 = c2;
  m.frequency = freq;
  return m;
}

// The default scene's objects, camera and light with the given materials (and, for `noisy`, a back
// wall after the floor: the triangles in this order).
void default_objects(Builder& b, uint32_t floor, uint32_t sphere, uint32_t box, uint32_t torus,
                     const uint32_t* wall = nullptr) {
  b.grid({-4, -4, 0}, {8, 0, 0}, {0, 8, 0}, 8, 8, floor);
  if (wall) b.grid({-4, 3, 0}, {8, 0, 0}, {0, 0, 5}, 8, 5, *wall);
  b.icosphere({-1.3, 0.2, 1.0}, 1.0, 3, sphere);
  b.oriented_box({1.4, 0.6, 0.7}, {0.7, 0.7, 0.7}, 0.5, box);
  b.torus({0.3, -1.6, 0.35}, 0.7, 0.3, 48, 24, torus);
  b.s.camera = {{0.0, -7.0, 3.2}, {0.0, 0.0, 0.6}, {0, 0, 1}, 40.0};
  b.s.light = {4.0, -5.0, 8.0};
}

// The main job's scene: a marble sphere, a wooden box, a granite floor (noise materials,
// like Fig. 4.3 / 4.1) and a tessellated torus with shared edges.
Scene default_scene() {
  Scene s;
  s.name = "default";
  Builder b{s};
  uint32_t floor = b.material(procedural("granite", MaterialKind::Turbulence, {0.75, 0.72, 0.66},
                                         {0.35, 0.33, 0.30}, 2.0));
  uint32_t marble = b.material(procedural("marble", MaterialKind::Marble, {0.92, 0.92, 0.95},
                                          {0.25, 0.30, 0.45}, 1.5));
  uint32_t wood = b.material(procedural("wood", MaterialKind::Wood, {0.80, 0.55, 0.30},
                                        {0.45, 0.25, 0.10}, 3.0));
  uint32_t teal = b.material(constant("teal", {0.20, 0.65, 0.60}));
  default_objects(b, floor, marble, wood, teal);
  return s;
}

// The noise-heavy scene of issue 15 §2 (after Fig. 4.1: every surface procedural): the default
// scene's objects with eight-octave turbulence on the granite floor, the marble sphere and a
// marble back wall, and a granite torus; the wooden box keeps its one evaluation per sample.
Scene noisy_scene() {
  Scene s;
  s.name = "noisy";
  Builder b{s};
  auto eight = [](Material m) {
    m.octaves = 8;
    return m;
  };
  uint32_t floor = b.material(eight(procedural("granite", MaterialKind::Turbulence, {0.75, 0.72, 0.66},
                                               {0.35, 0.33, 0.30}, 2.0)));
  uint32_t marble = b.material(eight(procedural("marble", MaterialKind::Marble, {0.92, 0.92, 0.95},
                                                {0.25, 0.30, 0.45}, 1.5)));
  uint32_t wall = b.material(eight(procedural("wall marble", MaterialKind::Marble, {0.85, 0.80, 0.70},
                                              {0.45, 0.20, 0.15}, 0.8)));
  uint32_t wood = b.material(procedural("wood", MaterialKind::Wood, {0.80, 0.55, 0.30}, {0.45, 0.25, 0.10}, 3.0));
  uint32_t stone = b.material(eight(procedural("torus granite", MaterialKind::Turbulence, {0.30, 0.60, 0.55},
                                               {0.10, 0.25, 0.25}, 4.0)));
  default_objects(b, floor, marble, wood, stone, &wall);
  return s;
}

// Fig. 4.1's other half: the noise-heavy scene with a box of smoke in front of the objects, its
// density eight-octave fBm sampled 64 times along every primary ray through it (512 noise
// evaluations per such ray, Kensler's 552 per shading sample).
Scene smoke_scene() {
  Scene s = noisy_scene();
  s.name = "smoke";
  Volume v;
  v.lo = {-3.5, -3.0, 0.0};
  v.hi = {3.5, 2.5, 3.0};
  v.color = {0.78, 0.78, 0.80};
  v.frequency = 1.2;
  v.density = 1.6;
  v.bias = 0.05;
  v.steps = 64;
  v.octaves = 8;
  s.volume = v;
  return s;
}

Scene sphere_scene() {
  Scene s;
  s.name = "sphere";
  Builder b{s};
  uint32_t m = b.material(constant("orange", {0.9, 0.5, 0.2}));
  b.icosphere({0, 0, 0}, 1.0, 4, m);
  s.camera = {{0.0, -3.6, 1.0}, {0, 0, 0}, {0, 0, 1}, 40.0};
  s.light = {3.0, -4.0, 5.0};
  return s;
}

// Cornell box (5.55 units wide, after the original's 555 mm), lit by a point light below the
// ceiling; walls tessellated 4x4 so that their edges are shared.
Scene cornell_scene() {
  Scene s;
  s.name = "cornell";
  Builder b{s};
  uint32_t white = b.material(constant("white", {0.75, 0.75, 0.75}));
  uint32_t red = b.material(constant("red", {0.75, 0.15, 0.15}));
  uint32_t green = b.material(constant("green", {0.15, 0.75, 0.15}));
  const double L = 5.55;
  b.grid({0, 0, 0}, {L, 0, 0}, {0, L, 0}, 4, 4, white);       // floor
  b.grid({0, 0, L}, {0, L, 0}, {L, 0, 0}, 4, 4, white);       // ceiling
  b.grid({0, L, 0}, {L, 0, 0}, {0, 0, L}, 4, 4, white);       // back
  b.grid({0, 0, 0}, {0, L, 0}, {0, 0, L}, 4, 4, red);         // left
  b.grid({L, 0, 0}, {0, 0, L}, {0, L, 0}, 4, 4, green);       // right
  b.oriented_box({1.85, 1.69, 0.825}, {0.825, 0.825, 0.825}, -0.29, white);  // short block
  b.oriented_box({3.68, 3.51, 1.65}, {0.825, 0.825, 1.65}, 0.29, white);     // tall block
  s.camera = {{2.775, -8.0, 2.775}, {2.775, 2.775, 2.775}, {0, 0, 1}, 39.3};
  s.light = {2.775, 2.3, 5.3};
  return s;
}

// "Architectural": a conference room with triangles of very different sizes — two-triangle
// walls, floor and ceiling, tables and chairs from thin boxes, tessellated columns and small
// detailed lamps — the case where tree rotations help most (§5.5).
Scene arch_scene() {
  Scene s;
  s.name = "arch";
  Builder b{s};
  uint32_t wall = b.material(constant("wall", {0.80, 0.78, 0.72}));
  uint32_t carpet = b.material(constant("carpet", {0.35, 0.25, 0.40}));
  uint32_t table = b.material(constant("table", {0.55, 0.35, 0.20}));
  uint32_t chair = b.material(constant("chair", {0.20, 0.25, 0.55}));
  uint32_t metal = b.material(constant("metal", {0.70, 0.70, 0.75}));
  uint32_t lamp = b.material(constant("lamp", {0.95, 0.90, 0.60}));
  const double W = 20, D = 12, H = 4;
  b.quad({0, 0, 0}, {W, 0, 0}, {W, D, 0}, {0, D, 0}, carpet);
  b.quad({0, 0, H}, {0, D, H}, {W, D, H}, {W, 0, H}, wall);
  b.quad({0, D, 0}, {W, D, 0}, {W, D, H}, {0, D, H}, wall);
  b.quad({0, 0, 0}, {0, D, 0}, {0, D, H}, {0, 0, H}, wall);
  b.quad({W, 0, 0}, {W, 0, H}, {W, D, H}, {W, D, 0}, wall);
  Rng rng(42);
  for (int ty = 0; ty < 2; ++ty)
    for (int tx = 0; tx < 3; ++tx) {
      Vec3 c{4.0 + 6.0 * tx, 3.5 + 5.0 * ty, 0};
      b.box(c + Vec3{-2.0, -0.9, 0.72}, c + Vec3{2.0, 0.9, 0.78}, table);  // top
      for (int lx = -1; lx <= 1; lx += 2)
        for (int ly = -1; ly <= 1; ly += 2) b.cylinder(c + Vec3{1.8 * lx, 0.7 * ly, 0}, 0.04, 0.72, 8, metal);
      for (int k = 0; k < 8; ++k) {  // chairs around the table
        double side = k < 4 ? -1.0 : 1.0;
        Vec3 p = c + Vec3{-1.5 + (k % 4) * 1.0, side * 1.35, 0};
        double ang = rng.range(-0.25, 0.25);
        b.oriented_box(p + Vec3{0, 0, 0.45}, {0.24, 0.24, 0.03}, ang, chair);                  // seat
        b.oriented_box(p + Vec3{0, side * 0.22, 0.75}, {0.24, 0.02, 0.28}, ang, chair);        // back
        for (int leg = 0; leg < 4; ++leg)
          b.cylinder(p + Vec3{(leg & 1) ? 0.2 : -0.2, (leg & 2) ? 0.2 : -0.2, 0}, 0.015, 0.42, 6, metal);
      }
      b.icosphere(c + Vec3{0.0, 0.0, 0.95}, 0.15, 3, lamp);  // a detailed lamp on every table
      b.cylinder(c + Vec3{0.0, 0.0, 0.78}, 0.02, 0.05, 12, metal);
    }
  for (int i = 0; i < 4; ++i) b.cylinder({2.0 + 5.33 * i, 0.5, 0}, 0.25, H, 32, wall);  // columns
  s.camera = {{1.0, 0.6, 2.6}, {11.0, 7.0, 0.6}, {0, 0, 1}, 60.0};
  s.light = {10.0, 6.0, 3.7};
  return s;
}

bool parse_scale(const std::string& text, double* out) {
  if (text.empty()) return false;
  char* end = nullptr;
  double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v) || !(v > 0)) return false;
  *out = v;
  return true;
}

}  // namespace

const char* material_kind_name(MaterialKind k) {
  switch (k) {
    case MaterialKind::Constant: return "constant";
    case MaterialKind::Marble: return "marble";
    case MaterialKind::Wood: return "wood";
    case MaterialKind::Turbulence: return "turbulence";
  }
  return "?";
}

bool Scene::has_procedural_materials() const {
  if (volume) return true;  // its density is noise
  std::vector<bool> used(materials.size(), false);
  for (const auto& t : tris)
    if (t.material < used.size()) used[t.material] = true;
  for (size_t i = 0; i < materials.size(); ++i)
    if (used[i] && is_procedural(materials[i].kind)) return true;
  return false;
}

Vec3 Scene::bounds_lo() const {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL};
  for (const auto& t : tris)
    for (const auto& p : t.p) lo = vmin(lo, p);
  return lo;
}
Vec3 Scene::bounds_hi() const {
  Vec3 hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const auto& t : tris)
    for (const auto& p : t.p) hi = vmax(hi, p);
  return hi;
}

void scale_scene(Scene& s, double f) {
  if (!std::isfinite(f) || !(f > 0)) throw SceneError("scale factor must be a positive finite number");
  for (auto& t : s.tris)
    for (auto& p : t.p) p = p * f;
  s.camera.eye = s.camera.eye * f;
  s.camera.look_at = s.camera.look_at * f;
  s.light = s.light * f;
  if (s.volume) {
    s.volume->lo = s.volume->lo * f;
    s.volume->hi = s.volume->hi * f;
    s.volume->density /= f;  // per unit length
  }
  s.unit *= f;
}

std::vector<std::string> builtin_scene_names() {
  return {"default", "noisy", "smoke", "sphere", "cornell", "arch", "balls", "wave", "bunny", "dragon", "armadillo"};
}

std::string scene_name_help() {
  return "default, noisy, smoke, sphere, cornell, arch, balls, wave (procedural), bunny, dragon, armadillo "
         "(CGAL demo meshes, scripts/install-deps.sh --long); suffix @FACTOR scales, e.g. default@1e-6";
}

Scene make_scene(const std::string& full) {
  std::string name = full;
  double factor = 1.0;
  const auto at = full.find('@');
  if (at != std::string::npos) {
    name = full.substr(0, at);
    if (!parse_scale(full.substr(at + 1), &factor))
      throw SceneError("bad scale in scene name '" + full + "' (expected NAME@FACTOR with FACTOR > 0, e.g. default@1e-6)");
  }
  Scene s;
  if (name == "default") s = default_scene();
  else if (name == "noisy") s = noisy_scene();
  else if (name == "smoke") s = smoke_scene();
  else if (name == "sphere") s = sphere_scene();
  else if (name == "cornell") s = cornell_scene();
  else if (name == "arch") s = arch_scene();
  else if (name == "balls" || name == "wave") s = make_animation_frame(name, 0, 1);
  else if (name == "bunny" || name == "dragon" || name == "armadillo") {
    std::string path = find_demo_mesh(name);
    if (path.empty())
      throw SceneError("scene '" + name + "' needs the CGAL demo meshes (Debian package libcgal-demo): run scripts/install-deps.sh --long");
    s = load_mesh(path, 'y');
    s.name = name;
  } else {
    throw SceneError("unknown scene '" + full + "' (accepted: " + scene_name_help() + ")");
  }
  if (factor != 1.0) scale_scene(s, factor);
  s.name = full;
  return s;
}

std::vector<std::string> animation_names() { return {"balls", "wave"}; }

Scene make_animation_frame(const std::string& name, int frame, int frames) {
  if (frames < 1 || frame < 0 || frame >= frames)
    throw SceneError("animation frame out of range");
  const double t = frames == 1 ? 0.0 : double(frame) / double(frames - 1);
  Scene s;
  s.name = name;
  Builder b{s};
  if (name == "balls") {
    // 64 balls start in a tight 4x4x4 cluster and fly to random places in a 40-unit box:
    // neighbours in the first frame end far apart, so refitted boxes grow and overlap.
    uint32_t m = b.material(constant("ball", {0.85, 0.35, 0.25}));
    b.grid({-25, -25, -1}, {50, 0, 0}, {0, 50, 0}, 2, 2, b.material(constant("ground", {0.6, 0.6, 0.6})));
    Rng rng(7);
    for (int i = 0; i < 64; ++i) {
      Vec3 start{(i % 4) * 0.5 - 0.75, ((i / 4) % 4) * 0.5 - 0.75, (i / 16) * 0.5 + 0.25};
      Vec3 end{rng.range(-20, 20), rng.range(-20, 20), rng.range(0.2, 15)};
      b.icosphere(start + (end - start) * t, 0.2, 2, m);
    }
    s.camera = {{0, -45, 25}, {0, 0, 4}, {0, 0, 1}, 50.0};
    s.light = {10, -20, 40};
  } else if (name == "wave") {
    // A 64x64 cloth sheet that twists about its centre: the twist angle grows with time and
    // with the distance from the centre, shearing the BVH's spatial coherence.
    uint32_t m = b.material(constant("cloth", {0.3, 0.5, 0.85}));
    const int n = 64;
    auto at = [&](int i, int j) {
      double x = -4 + 8.0 * i / n, y = -4 + 8.0 * j / n;
      double r = std::sqrt(x * x + y * y);
      double a = t * 2.5 * kPi * r / 4.0;
      double z = 0.6 * t * std::sin(1.5 * r - 4 * t);
      return Vec3{x * std::cos(a) - y * std::sin(a), x * std::sin(a) + y * std::cos(a), z};
    };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) b.quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), m);
    s.camera = {{0, -9, 6}, {0, 0, 0}, {0, 0, 1}, 45.0};
    s.light = {3, -4, 8};
  } else {
    throw SceneError("unknown animation '" + name + "' (accepted: balls, wave)");
  }
  return s;
}

}  // namespace ru::scene
