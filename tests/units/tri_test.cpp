// ray_tri_robust / ray_tri_mt golden models against the exact rational reference, float ==
// e8m23 bit for bit, and the defined results at the extremes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "rayunits/num/fp.hpp"
#include "rayunits/units/exact.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/synthetic.hpp"

using namespace ru::units;
using ru::num::Format;
using ru::num::Soft;
using ru::num::SoftScope;

namespace {

template <class T>
TriResult<T> run(bool robust, const TriRecord& r, const TriOptions& o = {}) {
  const auto a = vcast<T>(r.a), d = vcast<T>(r.d), p0 = vcast<T>(r.p0), p1 = vcast<T>(r.p1), p2 = vcast<T>(r.p2);
  const T tmin = ru::num::fp_cast<T>(r.t_min), tmax = ru::num::fp_cast<T>(r.t_max);
  return robust ? ray_tri_robust(a, d, p0, p1, p2, tmin, tmax, o) : ray_tri_mt(a, d, p0, p1, p2, tmin, tmax, o);
}

std::vector<TriRecord> workload(uint64_t seed, size_t tris, double scale = 1.0) {
  SynthTriOptions o;
  o.seed = seed;
  o.triangles = tris;
  o.rays_per_packet = 8;
  o.scale = scale;
  return synth_tri(o);
}

TEST(UnitsExact, VolumesSumAndHitPoint) {
  for (const TriRecord& r : workload(11, 50)) {
    const ExactTriHit h = exact_tri(r.a, r.d, r.p0, r.p1, r.p2, r.t_min, r.t_max);
    ASSERT_EQ(h.vol.V0 + h.vol.V1 + h.vol.V2, h.vol.V);
    if (!h.has_t) continue;
    // a + t d = (1 - beta - gamma) p0 + beta p1 + gamma p2, exactly.
    const Vec3q a = to_q(r.a), d = to_q(r.d), p0 = to_q(r.p0), p1 = to_q(r.p1), p2 = to_q(r.p2);
    const mpq_class alpha = 1 - h.beta - h.gamma;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(a[k] + h.t * d[k], alpha * p0[k] + h.beta * p1[k] + h.gamma * p2[k]);
    const bool inside = alpha >= 0 && h.beta >= 0 && h.gamma >= 0;
    ASSERT_EQ(h.hit, inside && h.t > 0);
  }
}

// In double, both algorithms agree with the exact test except within a tiny distance of an
// edge; the hit point and barycentrics are accurate.
TEST(UnitsTri, DoubleAgreesWithExact) {
  const auto recs = workload(5, 400);
  size_t hits = 0, disagree_robust = 0, disagree_mt = 0;
  for (const TriRecord& r : recs) {
    const ExactTriHit h = exact_tri(r.a, r.d, r.p0, r.p1, r.p2, r.t_min, r.t_max);
    const auto rb = run<double>(true, r), mt = run<double>(false, r);
    hits += h.hit;
    disagree_robust += rb.hit != h.hit;
    disagree_mt += mt.hit != h.hit;
    if (h.hit && rb.hit) {
      EXPECT_NEAR(rb.t, h.t.get_d(), 1e-12 * std::fabs(h.t.get_d()));
      EXPECT_NEAR(rb.beta, h.beta.get_d(), 1e-12);
      EXPECT_NEAR(rb.gamma, h.gamma.get_d(), 1e-12);
    }
    if (h.hit && mt.hit) {
      EXPECT_NEAR(mt.t, h.t.get_d(), 1e-12 * std::fabs(h.t.get_d()));
      EXPECT_NEAR(mt.beta, h.beta.get_d(), 1e-12);
    }
  }
  EXPECT_GT(hits, recs.size() / 6);
  EXPECT_EQ(disagree_robust, 0u);
  EXPECT_EQ(disagree_mt, 0u);
}

template <class T>
void expect_same_bits(const TriResult<T>& x, const TriResult<Soft>& s, const char* what) {
  EXPECT_EQ(x.hit, s.hit) << what;
  EXPECT_EQ(x.why, s.why) << what;
  EXPECT_EQ(ru::num::fp_bits(x.t), s.t.bits) << what;
  EXPECT_EQ(ru::num::fp_bits(x.beta), s.beta.bits) << what;
  EXPECT_EQ(ru::num::fp_bits(x.gamma), s.gamma.bits) << what;
  EXPECT_EQ(ru::num::fp_bits(x.V), s.V.bits) << what;
  EXPECT_EQ(ru::num::fp_bits(x.Va), s.Va.bits) << what;
  EXPECT_EQ(ru::num::fp_bits(x.V1), s.V1.bits) << what;
}

// The same template run with float and with Soft e8m23 (and double / e11m52) gives the same
// bits in every output, including the special cases (zero volumes, INF, NaN).
TEST(UnitsTri, NativeEqualsSoftBitForBit) {
  auto recs = workload(8, 60);
  for (const double s : {1e-30, 1e30, 1e-6, 1e6}) {
    auto more = workload(9, 10, s);
    recs.insert(recs.end(), more.begin(), more.end());
  }
  // Degenerate and special records.
  TriRecord deg = recs[0];
  deg.p2 = deg.p1;
  recs.push_back(deg);
  TriRecord nan = recs[1];
  nan.d.y = NAN;
  recs.push_back(nan);
  TriRecord inf = recs[2];
  inf.p0.x = INFINITY;
  recs.push_back(inf);
  TriOptions opts[2];
  opts[1].tie_break = true;
  opts[1].eps_test = true;
  opts[1].eps = 1e-3;
  for (const TriOptions& o : opts) {
    for (const TriRecord& r : recs) {
      {
        SoftScope sc(Format::parse("e8m23"));
        expect_same_bits(run<float>(true, r, o), run<Soft>(true, r, o), "robust float");
        expect_same_bits(run<float>(false, r, o), run<Soft>(false, r, o), "mt float");
      }
      {
        SoftScope sc(Format::parse("e11m52"));
        expect_same_bits(run<double>(true, r, o), run<Soft>(true, r, o), "robust double");
        expect_same_bits(run<double>(false, r, o), run<Soft>(false, r, o), "mt double");
      }
    }
  }
}

// ------------------------------------------------------------------ extremes
TriRecord simple_hit() {
  TriRecord r;
  r.p0 = {0, 0, 0};
  r.p1 = {1, 0, 0};
  r.p2 = {0, 1, 0};
  r.a = {0.25, 0.25, 1};
  r.d = {0, 0, -1};
  return r;
}

TEST(UnitsTriExtremes, AxisParallelAndScales) {
  for (bool robust : {true, false}) {
    for (double s : {1e-6, 1.0, 1e6}) {
      TriRecord r = simple_hit();
      for (Vec3d* v : {&r.p0, &r.p1, &r.p2, &r.a})
        for (int k = 0; k < 3; ++k) (*v)[k] *= s;
      for (const char* fmt : {"e5m10", "e7m16", "e8m23"}) {
        SoftScope sc(Format::parse(fmt));
        const auto h = run<Soft>(robust, r);
        // e5m10 cannot hold 1e6 or 1e-6 squared volumes: defined miss (INF/underflow), not a crash.
        if (std::string(fmt) == "e5m10" && s != 1.0) {
          EXPECT_FALSE(h.hit) << fmt << " scale " << s;
          continue;
        }
        EXPECT_TRUE(h.hit) << fmt << " scale " << s << " robust " << robust;
        // Against the exact values of the format-rounded inputs: a few ulps.
        const ExactTriHit x = exact_tri(vdouble(vcast<Soft>(r.a)), vdouble(vcast<Soft>(r.d)),
                                        vdouble(vcast<Soft>(r.p0)), vdouble(vcast<Soft>(r.p1)),
                                        vdouble(vcast<Soft>(r.p2)), 0.0, INFINITY);
        ASSERT_TRUE(x.hit);
        const double ulp = std::ldexp(1.0, -Format::parse(fmt).frac_bits);
        EXPECT_NEAR(h.t.to_double(), x.t.get_d(), 8 * ulp * x.t.get_d()) << fmt;
        EXPECT_NEAR(h.beta.to_double(), x.beta.get_d(), 8 * ulp) << fmt;
        EXPECT_NEAR(h.gamma.to_double(), x.gamma.get_d(), 8 * ulp) << fmt;
      }
    }
  }
}

TEST(UnitsTriExtremes, DegenerateSliverGrazingOnPlane) {
  for (bool robust : {true, false}) {
    // Zero-area triangle (collinear points): always a miss.
    TriRecord r = simple_hit();
    r.p2 = {2, 0, 0};
    EXPECT_FALSE(run<double>(robust, r).hit);
    EXPECT_FALSE(run<float>(robust, r).hit);
    r.p2 = r.p1;  // two equal vertices
    EXPECT_FALSE(run<double>(robust, r).hit);
    // Ray in the triangle's plane (grazing, V = 0): miss, t is INF or NaN.
    r = simple_hit();
    r.a = {-1, 0.25, 0};
    r.d = {1, 0, 0};
    const auto g = run<double>(robust, r);
    EXPECT_FALSE(g.hit);
    EXPECT_EQ(g.V, 0.0);
    // Ray starting on the plane, inside the triangle: t = 0 is not in (0, t_max): miss...
    r = simple_hit();
    r.a = {0.25, 0.25, 0};
    const auto on = run<double>(robust, r);
    EXPECT_FALSE(on.hit);
    EXPECT_EQ(on.t, 0.0);
    EXPECT_EQ(on.why, TriMiss::Interval);
    // ... and a hit with t_min below zero.
    r.t_min = -1;
    EXPECT_TRUE(run<double>(robust, r).hit);
    // Sliver: 1e-7 wide, hit inside and missed just outside, exactly as the exact test says.
    r = simple_hit();
    r.p2 = {0, 1e-7, 0};
    r.a = {0.5, 2.5e-8, 1};
    EXPECT_TRUE(run<double>(robust, r).hit);
    EXPECT_TRUE(exact_tri(r.a, r.d, r.p0, r.p1, r.p2, r.t_min, r.t_max).hit);
    r.a = {0.5, 6e-8, 1};
    EXPECT_FALSE(run<double>(robust, r).hit);
    EXPECT_FALSE(exact_tri(r.a, r.d, r.p0, r.p1, r.p2, r.t_min, r.t_max).hit);
    // Strict interval: t == t_max is a miss.
    r = simple_hit();
    r.t_max = 1.0;
    EXPECT_FALSE(run<double>(robust, r).hit);
    r.t_max = std::nextafter(1.0, 2.0);
    EXPECT_TRUE(run<double>(robust, r).hit);
    // NaN inputs: miss with NaN t.
    r = simple_hit();
    r.a.x = NAN;
    const auto n = run<float>(robust, r);
    EXPECT_FALSE(n.hit);
    EXPECT_TRUE(std::isnan(n.t));
    EXPECT_EQ(ru::num::fp_bits(n.t), 0x7fc00000u);  // canonical NaN
    // INF input: miss.
    r = simple_hit();
    r.p1.x = INFINITY;
    EXPECT_FALSE(run<float>(robust, r).hit);
  }
}

TEST(UnitsTriExtremes, EpsOption) {
  TriRecord r = simple_hit();
  r.d = {1e-3, 0, -1e-3};  // |V| = 1e-3 * area-ish
  r.a = {0.25, 0.25, 1e-3};
  r.a.x -= 1e-3;
  TriOptions o;
  EXPECT_TRUE(run<double>(true, r, o).hit);
  o.eps_test = true;
  o.eps = 1e-2;
  const auto x = run<double>(true, r, o);
  EXPECT_FALSE(x.hit);
  EXPECT_EQ(x.why, TriMiss::Eps);
  EXPECT_EQ(run<double>(false, r, o).why, TriMiss::Eps);
}

// Two triangles sharing the edge (1,0,0)-(0,1,0); a ray exactly through a point of the edge.
TEST(UnitsTriExtremes, SharedEdgeTieBreak) {
  const Vec3d u{1, 0, 0}, w{0, 1, 0}, A{0, 0, 0}, B{1, 1, 0};
  TriRecord t1, t2;
  t1.p0 = A, t1.p1 = u, t1.p2 = w;  // CCW seen from +z
  t2.p0 = B, t2.p1 = w, t2.p2 = u;  // shares (u, w) in the opposite direction
  t1.a = t2.a = {0.5, 0.5, 1};      // (0.5, 0.5, 0) is on the edge, exactly
  t1.d = t2.d = {0, 0, -1};
  const auto h1 = run<double>(true, t1), h2 = run<double>(true, t2);
  EXPECT_EQ(h1.V0, 0.0);  // the edge volume is exactly zero
  EXPECT_TRUE(h1.hit && h2.hit) << "without the tie-break both take the edge";
  TriOptions o;
  o.tie_break = true;
  const auto k1 = run<double>(true, t1, o), k2 = run<double>(true, t2, o);
  EXPECT_NE(k1.hit, k2.hit) << "with the tie-break exactly one triangle takes the edge";
  EXPECT_EQ((k1.hit ? k2 : k1).why, TriMiss::TieBreak);
  // Off the edge by one ulp either way: exactly one triangle, no tie-break needed.
  for (double dx : {-1e-16, 1e-16}) {
    t1.a.x = t2.a.x = 0.5 + dx;
    EXPECT_NE(run<double>(true, t1).hit, run<double>(true, t2).hit);
  }
}

}  // namespace
