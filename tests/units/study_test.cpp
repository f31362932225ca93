// Meshes, the watertightness study and the error study (small runs).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "rayunits/units/mesh.hpp"
#include "rayunits/units/study.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/units/watertight.hpp"

using namespace ru::units;
using ru::num::Format;

namespace {

double signed_volume(const Mesh& m) {
  double v = 0;
  for (const auto& t : m.tris) {
    const Vec3d &a = m.verts[t[0]], &b = m.verts[t[1]], &c = m.verts[t[2]];
    v += a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x);
  }
  return v / 6;
}

TEST(UnitsMesh, BuiltinsAreClosedAndOutward) {
  for (const char* name : {"icosphere", "uvsphere", "torus", "cube"}) {
    const Mesh m = builtin_mesh(name);
    const auto edges = closed_mesh_edges(m);
    EXPECT_EQ(edges.size() * 2, m.tris.size() * 3) << name;
    // Euler characteristic: 2 for the spheres and the cube, 0 for the torus.
    const long chi = static_cast<long>(m.verts.size()) - static_cast<long>(edges.size()) + static_cast<long>(m.tris.size());
    EXPECT_EQ(chi, std::string(name) == "torus" ? 0 : 2) << name;
    EXPECT_GT(signed_volume(m), 0) << name << ": normals must point outward";
  }
  EXPECT_NEAR(signed_volume(builtin_mesh("cube")), 8.0, 1e-12);
  EXPECT_THROW(builtin_mesh("teapot"), MeshError);
}

TEST(UnitsMesh, ClosednessCheckerCatchesHolesAndFlips) {
  Mesh m = make_icosphere(1);
  Mesh hole = m;
  hole.tris.pop_back();
  EXPECT_THROW(closed_mesh_edges(hole), MeshError);
  Mesh flip = m;
  std::swap(flip.tris[3][0], flip.tris[3][1]);
  EXPECT_THROW(closed_mesh_edges(flip), MeshError);
}

TEST(UnitsMesh, LoadObjAndOff) {
  const std::string dir = RU_BINARY_DIR;
  const std::string obj = dir + "/units_test_tet.obj", off = dir + "/units_test_tet.off", bad = dir + "/units_test_bad.obj";
  {
    std::ofstream f(obj);
    f << "# tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    std::ofstream g(off);
    g << "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";
    std::ofstream h(bad);
    h << "v 0 0 0\nf 1 2 3\n";
  }
  for (const std::string& p : {obj, off}) {
    const Mesh m = load_mesh(p);
    EXPECT_EQ(m.tris.size(), 4u);
    EXPECT_EQ(closed_mesh_edges(m).size(), 6u);
    EXPECT_NEAR(signed_volume(m), 1.0 / 6, 1e-15);
  }
  try {
    load_mesh(bad);
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("units_test_bad.obj:2: vertex index 2 out of range"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_mesh(dir + "/missing.obj"), MeshError);
  EXPECT_THROW(load_mesh(dir + "/x.stl"), MeshError);
  std::remove(obj.c_str());
  std::remove(off.c_str());
  std::remove(bad.c_str());
}

WatertightResult wt(const char* scene, const char* fmt, bool robust, bool tie, size_t rays) {
  WatertightOptions o;
  o.fmt = Format::parse(fmt);
  o.robust = robust;
  o.tri.tie_break = tie;
  o.rays = rays;
  o.seed = 3;
  return run_watertight(builtin_mesh(scene), o);
}

// Kensler's argument: rays through a shared edge never leak with the robust unit (at any width
// without overflow), and with the tie-break never double-hit either. Moller-Trumbore leaks.
TEST(UnitsWatertight, RobustEdgesDoNotLeak) {
  for (const char* fmt : {"e8m23", "e7m16", "e5m10"}) {
    const WatertightResult r = wt("icosphere", fmt, true, true, 2000);
    EXPECT_EQ(r.exact_misses, 0u) << fmt << ": every ray must really hit the surface";
    EXPECT_EQ(r.edge.rays, 1000u);
    EXPECT_EQ(r.edge.leaks, 0u) << fmt;
    EXPECT_EQ(r.edge.double_hits, 0u) << fmt;
    EXPECT_LT(r.near_edge_rays, 50u) << fmt;
    EXPECT_EQ(r.overflow_rays, 0u) << fmt;
  }
  // Without the tie-break, exactly-zero edge volumes give double hits (closed triangles).
  EXPECT_GT(wt("icosphere", "e8m23", true, false, 2000).edge.double_hits, 0u);
}

TEST(UnitsWatertight, MollerTrumboreLeaks) {
  // The leak counter must see leaks where they exist.
  const WatertightResult r = wt("icosphere", "e8m23", false, false, 4000);
  EXPECT_GT(r.edge.leaks + r.vertex.leaks, 0u);
  EXPECT_EQ(r.exact_misses, 0u);
}

TEST(UnitsWatertight, OtherScenes) {
  for (const char* scene : {"torus", "cube", "uvsphere"}) {
    const WatertightResult r = wt(scene, "e7m16", true, true, 1000);
    EXPECT_EQ(r.exact_misses, 0u) << scene;
    EXPECT_EQ(r.edge.leaks, 0u) << scene;
  }
}

TEST(UnitsStudy, TriStudySmall) {
  SynthTriOptions so;
  so.triangles = 24;
  const auto recs = synth_tri(so);
  TriStudyOptions o;
  o.formats = format_grid(7, 11, 10, 10, 64, true);
  o.formats.push_back(Format::parse("e7m20"));
  o.formats.push_back(Format::parse("e11m52"));
  o.formats.push_back(Format::parse("e3m10"));  // overflows on this data
  const TriStudy st = study_tri(recs, o);
  ASSERT_EQ(st.records, recs.size());
  auto best = [](const TriCell& c, int k) {
    double b = 1e300;
    for (const VolStat& v : c.cls[k])
      if (v.nan == 0) b = std::min(b, v.avg());
    return b;
  };
  // The exponent does not matter without overflow (e7..e11 at m10 are identical).
  for (int e = 1; e < 5; ++e)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(best(st.cells[e], k), best(st.cells[0], k));
  for (int k = 0; k < 3; ++k) {
    // 10 more fraction bits: ~1000x smaller error; double: ~1e-16.
    EXPECT_LT(best(st.cells[5], k), best(st.cells[0], k) / 100) << k;
    EXPECT_LT(best(st.cells[6], k), 1e-13) << k;
    EXPECT_GT(best(st.cells[0], k), 1e-5) << k;
  }
  EXPECT_GT(st.cells[7].flags.overflow, 0u);
  // A volume and its sign errors are counted for every record and every k.
  uint64_t n = 0;
  for (const VolStat& v : st.cells[0].cls[2]) n = std::max<uint64_t>(n, v.n + v.nan + v.exact_zero);
  EXPECT_EQ(n, 3 * recs.size());
}

TEST(UnitsStudy, GridAndRanges) {
  int lo, hi;
  parse_range("6:11", "--exp", lo, hi);
  EXPECT_EQ(lo, 6);
  EXPECT_EQ(hi, 11);
  parse_range("7", "--exp", lo, hi);
  EXPECT_EQ(lo + hi, 14);
  EXPECT_THROW(parse_range("9:3", "--exp", lo, hi), ru::num::FormatError);
  EXPECT_THROW(parse_range("a:3", "--exp", lo, hi), ru::num::FormatError);
  EXPECT_EQ(format_grid(6, 11, 8, 25, 32, true).size(), 93u);  // the dissertation's grid
  EXPECT_THROW(format_grid(1, 3, 8, 9, 32, true), ru::num::FormatError);
}

}  // namespace
