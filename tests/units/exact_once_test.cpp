// ray_tri_exact (the exactly-once unit) against the independent exact crossing oracle, per
// triangle and on closed meshes, at e5m10 .. e11m52; and every checker shown to catch a planted
// error (units/ray_tri_exact.hpp ExactPlant, units/crossing_oracle.hpp OraclePlant): each
// *Planted* test runs the same checker with one deliberate bug and requires it to report
// failures, so the checkers are known to be able to fail.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rayunits/num/fp.hpp"
#include "rayunits/units/crossing_oracle.hpp"
#include "rayunits/units/mesh.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/ray_tri_exact.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/units/watertight.hpp"

using namespace ru::units;
using ru::num::Format;
using ru::num::Soft;
using ru::num::SoftScope;

namespace {

const char* kFormats[] = {"e5m10", "e6m12", "e7m16", "e8m23", "e11m52"};

double rnd(const Format& f, double x) { return ru::num::to_double(f, ru::num::from_double(f, x).bits); }
Vec3d rnd(const Format& f, const Vec3d& v) { return {rnd(f, v.x), rnd(f, v.y), rnd(f, v.z)}; }
double uni(Rng& g) { return static_cast<double>(g.below(1u << 30)) / (1u << 29) - 1.0; }  // [-1, 1)
double ulps(const Format& f, double x, int k) {
  int e;
  std::frexp(x, &e);
  const int ex = x == 0 ? f.emin() : std::max(e - 1, f.emin());
  return rnd(f, x + k * std::ldexp(1.0, ex - f.frac_bits));
}

struct Case {
  Vec3d a, d, p0, p1, p2;
  double t_min = 0, t_max = INFINITY;
};

// Adversarial ray/triangle pairs, every value in the format: rays exactly through vertices and
// edge midpoints, within a few ulps of vertices, grazing (d along an edge or in the plane), axis
// aligned on integer grids (many exact zero volumes and zero tie terms), degenerate triangles,
// intervals ending exactly at the hit.
// extreme != 0: coordinates scaled so that the triple products straddle the underflow (-1) or
// the overflow (+1) threshold of the format.
Case make_case(const Format& f, Rng& g, int extreme = 0) {
  Case c;
  const bool grid = g.below(3) == 0;
  const int e0 = extreme < 0 ? f.emin() / 3 : extreme > 0 ? f.emax() / 3 : 0;
  const double s = std::ldexp(1.0, e0 + static_cast<int>(g.below(9)) - 4);
  const double gs = extreme ? s : 1.0;
  auto pt = [&] {
    if (grid) return rnd(f, Vec3d{gs * (double(g.below(5)) - 2), gs * (double(g.below(5)) - 2), gs * (double(g.below(5)) - 2)});
    return rnd(f, Vec3d{s * uni(g), s * uni(g), s * uni(g)});
  };
  c.p0 = pt(), c.p1 = pt(), c.p2 = pt();
  if (g.below(20) == 0) c.p2 = c.p0;  // degenerate
  const Vec3d* P[3] = {&c.p0, &c.p1, &c.p2};
  c.a = grid ? rnd(f, Vec3d{gs * (double(g.below(9)) - 4), gs * (double(g.below(9)) - 4), gs * (double(g.below(9)) - 4)})
             : pt();
  const int i = static_cast<int>(g.below(3)), j = (i + 1 + static_cast<int>(g.below(2))) % 3;
  Vec3d target;
  switch (g.below(7)) {
    case 0: target = *P[i]; break;                                                   // vertex
    case 1: target = rnd(f, Vec3d{(P[i]->x + P[j]->x) / 2, (P[i]->y + P[j]->y) / 2,  // edge
                                   (P[i]->z + P[j]->z) / 2});
      break;
    case 2: target = {ulps(f, P[i]->x, int(g.below(7)) - 3), ulps(f, P[i]->y, int(g.below(7)) - 3),
                      ulps(f, P[i]->z, int(g.below(7)) - 3)};
      break;
    case 3: c.d = rnd(f, Vec3d{P[j]->x - P[i]->x, P[j]->y - P[i]->y, P[j]->z - P[i]->z}); break;  // along an edge
    case 4: c.d = grid ? rnd(f, Vec3d{gs * (double(g.below(3)) - 1), gs * (double(g.below(3)) - 1), gs * (double(g.below(3)) - 1)})
                       : rnd(f, Vec3d{s * uni(g), s * uni(g), s * uni(g)});
      break;
    case 5: c.a = *P[i]; target = *P[j]; break;  // origin on a vertex
    default: target = rnd(f, Vec3d{(c.p0.x + c.p1.x + c.p2.x) / 3, (c.p0.y + c.p1.y + c.p2.y) / 3,
                                   (c.p0.z + c.p1.z + c.p2.z) / 3});
  }
  if (c.d.x == 0 && c.d.y == 0 && c.d.z == 0) c.d = rnd(f, Vec3d{target.x - c.a.x, target.y - c.a.y, target.z - c.a.z});
  switch (g.below(4)) {
    case 0: c.t_max = 1.5; break;
    case 1: c.t_max = 1.0; break;  // ends exactly at the target for exact d
    case 2: c.t_min = -INFINITY; break;
    default: break;
  }
  return c;
}

struct Tally {
  size_t cases = 0, hits = 0, mismatches = 0, slow = 0, fast_hits = 0;
  std::string first;
};

template <class T>
TriExactResult<T> run_exact(const Case& c, const ExactTriOptions& o) {
  return ray_tri_exact(vcast<T>(c.a), vcast<T>(c.d), vcast<T>(c.p0), vcast<T>(c.p1), vcast<T>(c.p2),
                       ru::num::fp_cast<T>(c.t_min), ru::num::fp_cast<T>(c.t_max), o);
}

Tally check_cases(const char* fmt, size_t n, ExactPlant up = ExactPlant::None, OraclePlant op = OraclePlant::None,
                  int extreme = 0, ExactFilter filter = ExactFilter::PermanentFormat) {
  const Format f = Format::parse(fmt);
  SoftScope scope(f);
  Rng g(77 + f.frac_bits);
  Tally t;
  ExactTriOptions o;
  o.plant = up;
  o.filter = filter;
  for (size_t k = 0; k < n; ++k) {
    const Case c = make_case(f, g, extreme);
    const auto r = run_exact<Soft>(c, o);
    const bool want = oracle_crosses(c.a, c.d, c.p0, c.p1, c.p2, c.t_min, c.t_max, op);
    ++t.cases;
    t.hits += want;
    t.slow += r.path.slow();
    t.fast_hits += want && !r.path.slow();
    if (r.hit != want) {
      if (!t.mismatches)
        t.first = std::string(fmt) + " case " + std::to_string(k) + ": unit " + std::to_string(r.hit) +
                  " oracle " + std::to_string(want);
      ++t.mismatches;
    }
  }
  return t;
}

}  // namespace

// Outputs other than hit are ray_tri_robust's, bit for bit (the same datapath); float == e8m23
// and double == e11m52 Soft, hit and path included.
TEST(UnitsExactOnce, SameDatapathAsRobust) {
  for (const char* fmt : kFormats) {
    const Format f = Format::parse(fmt);
    SoftScope scope(f);
    Rng g(5);
    for (int k = 0; k < 400; ++k) {
      const Case c = make_case(f, g);
      const auto e = run_exact<Soft>(c, {});
      const auto r = ray_tri_robust(vcast<Soft>(c.a), vcast<Soft>(c.d), vcast<Soft>(c.p0), vcast<Soft>(c.p1),
                                    vcast<Soft>(c.p2), Soft::from_double(c.t_min), Soft::from_double(c.t_max));
      for (auto [x, y] : {std::pair{e.t, r.t}, {e.beta, r.beta}, {e.gamma, r.gamma}, {e.V, r.V}, {e.Va, r.Va},
                          {e.V0, r.V0}, {e.V1, r.V1}, {e.V2, r.V2}})
        ASSERT_EQ(x.bits, y.bits) << fmt << " case " << k;
      if (f.frac_bits == 23 || f.frac_bits == 52) {
        const auto n = f.frac_bits == 23 ? run_exact<float>(c, {}).hit : run_exact<double>(c, {}).hit;
        const auto ns = f.frac_bits == 23 ? run_exact<float>(c, {}).path.slow() : run_exact<double>(c, {}).path.slow();
        ASSERT_EQ(n, e.hit) << fmt << " case " << k;
        ASSERT_EQ(ns, e.path.slow()) << fmt << " case " << k;
      }
    }
  }
}

// Per triangle: the unit's hit == the oracle's crossing, on adversarial pairs at every width.
// The tally also shows the cases exercise both paths and both answers.
TEST(UnitsExactOnce, AgreesWithOracle) {
  for (const char* fmt : {"e5m10", "e6m12", "e7m16", "e8m23", "e11m52", "e5m10-ftz", "e8m23-ftz"}) {
    const Tally t = check_cases(fmt, 6000);
    std::printf("%s: %zu cases, %zu hits (%zu decided by the fast path), %zu took the exact path\n", fmt, t.cases,
                t.hits, t.fast_hits, t.slow);
    EXPECT_EQ(t.mismatches, 0u) << t.first;
    EXPECT_GT(t.hits, 300u) << fmt;
    EXPECT_GT(t.slow, 300u) << fmt << ": the exact path must be exercised";
    EXPECT_GT(t.fast_hits, 100u) << fmt << ": the fast path must decide hits";
  }
}

// At the extremes: coordinates scaled so that the volumes' products underflow or overflow (the
// filter must send those to the exact path: subnormal/flushed results, INF/NaN). Planted: without
// the underflow check the checker fails.
TEST(UnitsExactOnce, AgreesWithOracleAtExtremes) {
  for (const char* fmt : {"e5m10", "e6m12", "e7m16", "e8m23", "e11m52", "e5m10-ftz", "e8m23-ftz"}) {
    for (int ex : {-1, 1}) {
      const Tally t = check_cases(fmt, 3000, ExactPlant::None, OraclePlant::None, ex);
      std::printf("%s extreme %+d: %zu cases, %zu hits (%zu by the fast path), %zu took the exact path\n", fmt, ex,
                  t.cases, t.hits, t.fast_hits, t.slow);
      EXPECT_EQ(t.mismatches, 0u) << t.first;
      EXPECT_GT(t.hits, 100u) << fmt << " " << ex;
    }
  }
  size_t planted = 0;
  for (const char* fmt : {"e5m10", "e8m23", "e5m10-ftz", "e8m23-ftz"}) {
    const size_t m = check_cases(fmt, 3000, ExactPlant::NoTinyCheck, OraclePlant::None, -1).mismatches;
    std::printf("%s extreme -1, plant NoTinyCheck: %zu mismatches\n", fmt, m);
    planted += m;
  }
  EXPECT_GT(planted, 0u);
}

// The other filters (the default is PermanentFormat, the RTL's): Exponent (the error bound from
// exponent fields, the cheap one for hardware) and Permanent (the interval's error evaluated in
// double arithmetic): the same hits as the oracle on the adversarial pairs and at the extremes
// (a filter changes only which path decides); with the bound 2^24 too small (ShrunkBound) the
// checker fails.
TEST(UnitsExactOnce, OtherFiltersAgreeWithOracle) {
  for (ExactFilter fl : {ExactFilter::Exponent, ExactFilter::Permanent}) {
    const char* name = fl == ExactFilter::Exponent ? "exponent" : "permanent";
    for (const char* fmt : {"e5m10", "e6m12", "e7m16", "e8m23", "e11m52", "e5m10-ftz", "e8m23-ftz"}) {
      for (int ex : {0, -1, 1}) {
        const Tally t = check_cases(fmt, ex ? 1500 : 3000, ExactPlant::None, OraclePlant::None, ex, fl);
        std::printf("%s extreme %+d, %s filter: %zu cases, %zu hits (%zu by the fast path), %zu exact path\n", fmt,
                    ex, name, t.cases, t.hits, t.fast_hits, t.slow);
        EXPECT_EQ(t.mismatches, 0u) << name << ": " << t.first;
        if (ex == 0) {
          EXPECT_GT(t.fast_hits, 50u) << fmt << ": the fast path must decide hits";
        }
      }
    }
    size_t planted = 0;
    for (const char* fmt : {"e5m10", "e8m23"})
      planted += check_cases(fmt, 6000, ExactPlant::ShrunkBound, OraclePlant::None, 0, fl).mismatches;
    std::printf("%s filter, plant ShrunkBound: %zu mismatches\n", name, planted);
    EXPECT_GT(planted, 0u) << name;
  }
}

// The same checker with each planted error in the unit, or in the oracle, must fail.
TEST(UnitsExactOnce, PlantedErrorsCaughtPerTriangle) {
  for (const char* fmt : {"e5m10", "e8m23"}) {
    for (ExactPlant p : {ExactPlant::NoExactPath, ExactPlant::VertexOrderTie, ExactPlant::ShrunkBound}) {
      const size_t m = check_cases(fmt, 6000, p).mismatches;
      std::printf("%s unit plant %d: %zu of 6000 mismatches\n", fmt, int(p), m);
      EXPECT_GT(m, 0u) << fmt << " plant " << int(p);
    }
    for (OraclePlant p : {OraclePlant::NoPerturbation, OraclePlant::ReversedOrder}) {
      const size_t m = check_cases(fmt, 6000, ExactPlant::None, p).mismatches;
      std::printf("%s oracle plant %d: %zu of 6000 mismatches\n", fmt, int(p), m);
      EXPECT_GT(m, 0u) << fmt << " oracle plant " << int(p);
    }
  }
}

// The claim on closed, consistently oriented meshes: #triangles hit == #oracle crossings for every
// ray exactly through a shared edge, exactly through a shared vertex, and within a few ulps of a
// vertex; on the convex meshes the oracle itself counts exactly one crossing for every ray.
namespace {
WatertightResult wt_exact(const char* scene, const char* fmt, size_t rays, size_t near,
                          ExactPlant up = ExactPlant::None, OraclePlant op = OraclePlant::None) {
  WatertightOptions o;
  o.fmt = Format::parse(fmt);
  o.exact = true;
  o.exact_opt.plant = up;
  o.oracle_plant = op;
  o.rays = rays;
  o.near_vertex_rays = near;
  o.seed = 9;
  return run_watertight(builtin_mesh(scene), o);
}
}  // namespace

TEST(UnitsExactOnce, ExactlyOnceOnClosedMeshes) {
  for (const char* fmt : kFormats) {
    for (const char* scene : {"icosphere", "torus", "cube", "uvsphere"}) {
      const WatertightResult r = wt_exact(scene, fmt, 300, 150);
      const std::string at = std::string(scene) + " " + fmt;
      EXPECT_EQ(r.exact_misses, 0u) << at;
      EXPECT_EQ(r.edge.rays, 150u) << at;
      EXPECT_EQ(r.near_vertex.rays, 150u) << at;
      for (const WatertightCounts* c : {&r.edge, &r.vertex, &r.near_vertex}) {
        EXPECT_EQ(c->leaks, 0u) << at;
        EXPECT_EQ(c->double_hits, 0u) << at;
      }
      // Smooth convex meshes: every origin is inside, the oracle counts one crossing. (The torus is
      // not convex; the cube's corners and creases are sharper than the origins' tilt cone, so some
      // origins lie outside and the oracle rightly counts 0 or 2.)
      if (std::string(scene) == "icosphere" || std::string(scene) == "uvsphere") {
        EXPECT_EQ(r.total().oracle_not_one, 0u) << at << ": convex";
      }
      EXPECT_GT(r.vertex.slow_tests, 0u) << at;
    }
  }
}

TEST(UnitsExactOnce, PlantedErrorsCaughtOnMeshes) {
  for (const char* fmt : {"e5m10", "e8m23"}) {
    // Plain rounded signs: vertex rays double-hit (exact zeros, closed triangles).
    const auto a = wt_exact("icosphere", fmt, 300, 150, ExactPlant::NoExactPath).total();
    EXPECT_GT(a.leaks + a.double_hits, 0u) << fmt;
    // Zeros broken by vertex order instead of the ray: edge rays leak or double-hit.
    const auto b = wt_exact("icosphere", fmt, 300, 0, ExactPlant::VertexOrderTie);
    EXPECT_GT(b.edge.leaks + b.edge.double_hits, 0u) << fmt;
    // Oracle without perturbation: a convex mesh's vertex rays cross "several" triangles.
    const auto c = wt_exact("icosphere", fmt, 300, 0, ExactPlant::None, OraclePlant::NoPerturbation);
    EXPECT_GT(c.total().oracle_not_one, 0u) << fmt;
    EXPECT_GT(c.total().leaks, 0u) << fmt;
  }
  // The same counters on the plain unit see its known vertex failures.
  WatertightOptions o;
  o.fmt = Format::parse("e8m23");
  o.tri.tie_break = true;
  o.rays = 2000;
  const auto r = run_watertight(builtin_mesh("icosphere"), o);
  EXPECT_GT(r.vertex.leaks, 0u);
}

// Long: the claim on real closed meshes from Debian's CGAL demo data (libcgal-demo, installed by
// scripts/install-deps.sh --long): non-convex elephant (genus 3), knot1 (genus 1), eight (genus
// 2), 3torus (genus 3, coarse: many rays cross 2-3 times), at e5m10 and e8m23, scaled x64 / x16
// like scripts/watertight_exact.sh.
TEST(LongUnitsExactOnce, CgalMeshes) {
  std::string tarball;
  for (const char* t : {"/usr/share/doc/libcgal-demo/data.tar.gz", "/usr/share/doc/libcgal-dev/data.tar.gz"}) {
    std::FILE* f = std::fopen(t, "rb");
    if (f) {
      std::fclose(f);
      tarball = t;
      break;
    }
  }
  if (tarball.empty()) GTEST_SKIP() << "libcgal-demo not installed (scripts/install-deps.sh --long)";
  const std::string dir = std::string(RU_BINARY_DIR) + "/exact_once_cgal";
  const std::string cmd = "mkdir -p '" + dir + "' && tar -xzf " + tarball + " -C '" + dir +
                          "' data/meshes/elephant.off data/meshes/knot1.off data/meshes/eight.off data/meshes/3torus.off";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  for (auto [name, scale] : {std::pair{"elephant", 64.0}, {"knot1", 64.0}, {"eight", 64.0}, {"3torus", 16.0}}) {
    Mesh m = load_mesh(dir + "/data/meshes/" + name + ".off");
    for (Vec3d& v : m.verts) v = {v.x * scale, v.y * scale, v.z * scale};
    for (const char* fmt : {"e5m10", "e8m23"}) {
      WatertightOptions o;
      o.fmt = Format::parse(fmt);
      o.exact = true;
      o.rays = 1000;
      o.near_vertex_rays = 500;
      o.seed = 4;
      const WatertightResult r = run_watertight(m, o);
      const std::string at = std::string(name) + " " + fmt;
      for (const WatertightCounts* c : {&r.edge, &r.vertex, &r.near_vertex}) {
        EXPECT_EQ(c->leaks, 0u) << at;
        EXPECT_EQ(c->double_hits, 0u) << at;
      }
      if (std::string(name) == "3torus") {
        EXPECT_GT(r.total().oracle_not_one, 0u) << at << ": multiple crossings expected";
      }
    }
  }
}
