// Procedural scenes: contents, scaling, shared edges, names.
#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include "rayunits/scene/scene.hpp"

using namespace ru::scene;

namespace {

// Number of edges used by exactly one triangle / by more than two (0, 0: closed 2-manifold).
std::pair<int, int> open_edges(const std::vector<Triangle>& tris) {
  std::map<std::tuple<double, double, double, double, double, double>, int> count;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      Vec3 a = t.p[k], b = t.p[(k + 1) % 3];
      if (std::make_tuple(b.x, b.y, b.z) < std::make_tuple(a.x, a.y, a.z)) std::swap(a, b);
      ++count[{a.x, a.y, a.z, b.x, b.y, b.z}];
    }
  int once = 0, more = 0;
  for (auto& [e, c] : count) {
    once += c == 1;
    more += c > 2;
  }
  return {once, more};
}

}  // namespace

TEST(Scene, BuiltinsAreWellFormed) {
  for (const char* name : {"default", "sphere", "cornell", "arch", "balls", "wave"}) {
    SCOPED_TRACE(name);
    Scene s = make_scene(name);
    EXPECT_EQ(s.name, name);
    ASSERT_FALSE(s.tris.empty());
    for (const auto& t : s.tris) {
      ASSERT_LT(t.material, s.materials.size());
      for (const auto& p : t.p) ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    }
    EXPECT_EQ(s.unit, 1.0);
    EXPECT_NE(s.camera.eye, s.camera.look_at);
  }
  EXPECT_TRUE(make_scene("default").has_procedural_materials());
  EXPECT_FALSE(make_scene("sphere").has_procedural_materials());
  EXPECT_FALSE(make_scene("cornell").has_procedural_materials());
  EXPECT_EQ(make_scene("sphere").tris.size(), 20u * 256u);  // icosphere level 4
}

TEST(Scene, ArchHasHeterogeneousTriangleSizes) {
  Scene s = make_scene("arch");
  double amin = HUGE_VAL, amax = 0;
  for (const auto& t : s.tris) {
    double a = 0.5 * length(cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
    amin = std::min(amin, a);
    amax = std::max(amax, a);
  }
  EXPECT_GT(amax / amin, 1e5);  // walls of 120 m^2 against chair-leg slivers
  EXPECT_GT(s.tris.size(), 10000u);
}

TEST(Scene, ClosedMeshesShareEveryEdge) {
  // The tessellated sphere is closed: every edge belongs to exactly two triangles.
  Scene s = make_scene("sphere");
  EXPECT_EQ(open_edges(s.tris), std::make_pair(0, 0));
  // The checker sees a planted crack: move one vertex of one triangle.
  Scene bad = s;
  bad.tris[17].p[1].x += 1e-9;
  EXPECT_GT(open_edges(bad.tris).first, 0);
  // The default scene's torus (the tessellated object with shared edges) is closed too.
  Scene d = make_scene("default");
  std::vector<Triangle> torus;
  for (const auto& t : d.tris)
    if (d.materials[t.material].name == "teal") torus.push_back(t);
  EXPECT_EQ(torus.size(), 48u * 24u * 2u);
  EXPECT_EQ(open_edges(torus), std::make_pair(0, 0));
}

TEST(Scene, ScaledVariants) {
  Scene a = make_scene("default");
  for (double f : {1e-6, 1e6}) {
    char name[32];
    std::snprintf(name, sizeof name, "default@%g", f);
    SCOPED_TRACE(name);
    Scene b = make_scene(name);
    EXPECT_EQ(b.name, name);
    ASSERT_EQ(a.tris.size(), b.tris.size());
    EXPECT_EQ(b.unit, f);
    for (size_t i = 0; i < a.tris.size(); i += 97)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(b.tris[i].p[k], a.tris[i].p[k] * f);
    EXPECT_EQ(b.camera.eye, a.camera.eye * f);
    EXPECT_EQ(b.light, a.light * f);
    EXPECT_EQ(b.epsilon(), 1e-3 * f);
  }
  EXPECT_EQ(make_scene("sphere@1e+6").unit, 1e6);
  // The smoke's box scales with the scene, its extinction per unit length inversely.
  const Scene s = make_scene("smoke"), s2 = make_scene("smoke@2");
  ASSERT_TRUE(s.volume && s2.volume);
  EXPECT_EQ(s2.volume->lo, s.volume->lo * 2.0);
  EXPECT_EQ(s2.volume->hi, s.volume->hi * 2.0);
  EXPECT_EQ(s2.volume->density, s.volume->density / 2.0);
  EXPECT_TRUE(s.has_procedural_materials());
  EXPECT_FALSE(make_scene("noisy").volume);
}

TEST(Scene, BadNamesGiveOneLineErrors) {
  for (const char* bad : {"nope", "default@", "default@0", "default@-1", "default@abc", "default@1e400",
                          "default@nan", "@1e-6", ""}) {
    SCOPED_TRACE(bad);
    try {
      make_scene(bad);
      ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
      std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos);
      EXPECT_FALSE(m.empty());
    }
  }
  EXPECT_THROW(make_animation_frame("balls", 5, 5), SceneError);
  EXPECT_THROW(make_animation_frame("nope", 0, 2), SceneError);
}

TEST(Scene, AnimationKeepsTrianglesAndMoves) {
  for (const auto& name : animation_names()) {
    SCOPED_TRACE(name);
    Scene f0 = make_animation_frame(name, 0, 10), f9 = make_animation_frame(name, 9, 10);
    ASSERT_EQ(f0.tris.size(), f9.tris.size());
    size_t moved = 0;
    for (size_t i = 0; i < f0.tris.size(); ++i) moved += f0.tris[i].p[0] != f9.tris[i].p[0];
    EXPECT_GT(moved, f0.tris.size() / 2);
  }
}
