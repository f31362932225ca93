// The cheaper robust variants (units/ray_tri_cheap.hpp, issue 14 §3): Fig. 3.6's volumes and
// sign decisions unchanged; recip's outputs within two roundings of the exact quotient of the
// unit's own volumes; deferred's interval test exact away from the bounds, for both signs of V;
// the defined results at the extremes; and the output study against exact rationals.
#include <gtest/gtest.h>

#include <cmath>

#include "rayunits/num/fp.hpp"
#include "rayunits/units/exact.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/ray_tri_cheap.hpp"
#include "rayunits/units/study.hpp"
#include "rayunits/units/study_outputs.hpp"
#include "rayunits/units/synthetic.hpp"

using namespace ru::units;
using ru::num::Format;
using ru::num::Soft;
using ru::num::SoftScope;

namespace {

enum Which { Lit, Recip, Deferred };

template <class T>
TriResult<T> run(Which w, const TriRecord& r, const TriOptions& o = {}) {
  const auto a = vcast<T>(r.a), d = vcast<T>(r.d), p0 = vcast<T>(r.p0), p1 = vcast<T>(r.p1), p2 = vcast<T>(r.p2);
  const T tmin = ru::num::fp_cast<T>(r.t_min), tmax = ru::num::fp_cast<T>(r.t_max);
  if (w == Recip) return ray_tri_robust_recip(a, d, p0, p1, p2, tmin, tmax, o);
  if (w == Deferred) return ray_tri_robust_deferred(a, d, p0, p1, p2, tmin, tmax, o);
  return ray_tri_robust(a, d, p0, p1, p2, tmin, tmax, o);
}

std::vector<TriRecord> workload(uint64_t seed, size_t tris) {
  SynthTriOptions o;
  o.seed = seed;
  o.triangles = tris;
  o.rays_per_packet = 8;
  return synth_tri(o);
}

// Half the triangles flipped (p1 <-> p2), so both signs of V occur.
std::vector<TriRecord> both_orientations(uint64_t seed, size_t tris) {
  auto recs = workload(seed, tris);
  for (size_t i = 0; i < recs.size(); i += 2) std::swap(recs[i].p1, recs[i].p2);
  return recs;
}

mpq_class q_of(const Soft& s) { return to_q(s.to_double()); }

TEST(UnitsTriCheap, VolumesAndSignDecisionsAreFig36s) {
  const auto recs = both_orientations(21, 80);
  TriOptions opts[2];
  opts[1].tie_break = true;
  for (const char* f : {"e5m10", "e7m16", "e8m23"}) {
    SoftScope sc(Format::parse(f));
    for (const TriOptions& o : opts)
      for (const TriRecord& r : recs) {
        const auto l = run<Soft>(Lit, r, o), rc = run<Soft>(Recip, r, o), df = run<Soft>(Deferred, r, o);
        for (const TriResult<Soft>* x : {&rc, &df}) {
          ASSERT_EQ(x->V.bits, l.V.bits) << f;
          ASSERT_EQ(x->Va.bits, l.Va.bits) << f;
          ASSERT_EQ(x->V0.bits, l.V0.bits) << f;
          ASSERT_EQ(x->V1.bits, l.V1.bits) << f;
          ASSERT_EQ(x->V2.bits, l.V2.bits) << f;
          if (l.why == TriMiss::Sign || l.why == TriMiss::TieBreak) {
            ASSERT_EQ(x->why, l.why) << f;
          }
        }
        // deferred's outputs are Fig. 3.6's divisions
        ASSERT_EQ(df.t.bits, l.t.bits) << f;
        ASSERT_EQ(df.beta.bits, l.beta.bits) << f;
        ASSERT_EQ(df.gamma.bits, l.gamma.bits) << f;
      }
  }
}

// RN(Va * RN(1/V)) is within (1+u)^2 - 1 of Va/V (u = 2^-(M+1)) without over/underflow; the
// literal RN(Va/V) within u. The quotient is that of the unit's own rounded V and Va (exact).
TEST(UnitsTriCheap, RecipWithinTwoRoundings) {
  const auto recs = both_orientations(22, 150);
  for (const char* f : {"e7m16", "e8m23", "e11m52"}) {
    const Format fmt = Format::parse(f);
    SoftScope sc(fmt);
    const mpq_class uq(std::ldexp(1.0, -(fmt.frac_bits + 1)));  // exact power of two
    size_t checked = 0, differ = 0;
    for (const TriRecord& r : recs) {
      const auto l = run<Soft>(Lit, r), rc = run<Soft>(Recip, r);
      if (l.V.to_double() == 0 || !std::isfinite(l.V.to_double())) continue;
      const mpq_class V = q_of(l.V);
      const mpq_class num[3] = {q_of(l.Va), q_of(l.V1), q_of(l.V2)};
      const Soft* lit[3] = {&l.t, &l.beta, &l.gamma};
      const Soft* rec[3] = {&rc.t, &rc.beta, &rc.gamma};
      for (int k = 0; k < 3; ++k) {
        if (num[k] == 0) continue;
        const mpq_class q = num[k] / V;
        const mpq_class aq = abs(q);
        const mpq_class er = abs(q_of(*rec[k]) - q), el = abs(q_of(*lit[k]) - q);
        EXPECT_LE(er, aq * (2 * uq + uq * uq)) << f << " k=" << k;
        EXPECT_LE(el, aq * uq) << f << " k=" << k;
        ++checked;
        differ += rec[k]->bits != lit[k]->bits;
      }
    }
    EXPECT_GT(checked, recs.size()) << f;
    EXPECT_GT(differ, checked / 20) << f;  // recip is a different rounding, not the literal one
  }
}

// Deferred decides t_min < Va/V < t_max by products; away from the bounds (relative distance
// > 4 ulps) it must agree with the exact quotient of its own V and Va, for V > 0 and V < 0.
TEST(UnitsTriCheap, DeferredIntervalExactAwayFromBounds) {
  auto recs = both_orientations(23, 200);
  // Put t_max near the hit t for half the records (either side), t_min near it for a quarter.
  {
    for (size_t i = 0; i < recs.size(); ++i) {
      const ExactTriHit h = exact_tri(recs[i].a, recs[i].d, recs[i].p0, recs[i].p1, recs[i].p2, 0, INFINITY);
      if (!h.has_t) continue;
      const double t = h.t.get_d();
      if (i % 2 == 0) recs[i].t_max = t * (1 + ((i / 2) % 2 ? 1e-3 : -1e-3));
      if (i % 4 == 1) recs[i].t_min = t * (1 + ((i / 4) % 2 ? 1e-3 : -1e-3));
    }
  }
  const Format fmt = Format::parse("e7m16");
  SoftScope sc(fmt);
  const double tol = std::ldexp(1.0, -(fmt.frac_bits - 2));
  size_t in = 0, out = 0, pos = 0, neg = 0;
  for (const TriRecord& r : recs) {
    const auto df = run<Soft>(Deferred, r);
    if (df.why == TriMiss::Sign) continue;
    const double V = df.V.to_double();
    if (V == 0 || !std::isfinite(V)) continue;
    const mpq_class q = q_of(df.Va) / q_of(df.V);
    const double lo = Soft::from_double(r.t_min).to_double(), hi = Soft::from_double(r.t_max).to_double();
    const double qd = q.get_d();
    const bool near = std::fabs(qd - lo) <= tol * std::fabs(qd) ||
                      (std::isfinite(hi) && std::fabs(qd - hi) <= tol * std::fabs(qd));
    if (near) continue;
    const bool exact_in = to_q(lo) < q && (!std::isfinite(hi) || q < to_q(hi));
    EXPECT_EQ(df.why == TriMiss::None, exact_in) << "t " << qd << " in (" << lo << ", " << hi << "), V " << V;
    in += exact_in;
    out += !exact_in;
    pos += exact_in && V > 0;
    neg += exact_in && V < 0;
  }
  EXPECT_GT(in, 20u);
  EXPECT_GT(out, 20u);
  EXPECT_GT(pos, 5u);
  EXPECT_GT(neg, 5u);
}

TEST(UnitsTriCheap, Extremes) {
  auto recs = both_orientations(24, 40);
  size_t hits[3] = {0, 0, 0};
  for (const char* f : {"e5m10", "e8m23"}) {
    SoftScope sc(Format::parse(f));
    for (TriRecord r : recs) {
      for (int w = 0; w < 3; ++w) hits[w] += run<Soft>(static_cast<Which>(w), r).hit;
      TriRecord deg = r;
      deg.p2 = deg.p1;  // V = 0
      TriRecord nan = r;
      nan.d.y = NAN;
      TriRecord nan_t = r;
      nan_t.t_max = NAN;
      for (const TriRecord* x : {&deg, &nan, &nan_t})
        for (int w = 0; w < 3; ++w) EXPECT_FALSE(run<Soft>(static_cast<Which>(w), *x).hit) << f << " " << w;
    }
  }
  // t_max = +INF (the default of the synthetic records): the variants hit as often as Fig. 3.6.
  EXPECT_GT(hits[0], recs.size() / 4);
  EXPECT_NEAR(static_cast<double>(hits[1]), static_cast<double>(hits[0]), 2.0);
  EXPECT_NEAR(static_cast<double>(hits[2]), static_cast<double>(hits[0]), 2.0);
}

// The study: errors shrink with the fraction width, recip's t error is between 1x and 3x the
// literal one's, deferred's outputs equal the literal ones, and in e11m52 no decision is wrong.
TEST(UnitsTriCheap, OutputStudySmall) {
  const auto recs = workload(25, 64);
  OutStudyOptions o;
  o.formats = format_grid(7, 7, 10, 10, 64, true);
  o.formats.push_back(Format::parse("e7m20"));
  o.formats.push_back(Format::parse("e11m52"));
  o.threads = 2;
  const OutStudy st = study_tri_outputs(recs, o);
  ASSERT_EQ(st.records, recs.size());
  ASSERT_GT(st.exact_hits, recs.size() / 6);
  for (int u : {0, 1, 3})
    for (int k = 0; k < 3; ++k) {
      EXPECT_GT(st.cells[0].err[u][k].avg(), 1e-5) << u << k;
      EXPECT_LT(st.cells[1].err[u][k].avg(), st.cells[0].err[u][k].avg() / 100) << u << k;
      EXPECT_LT(st.cells[2].err[u][k].avg(), 1e-13) << u << k;
    }
  for (const OutCell& c : st.cells) {
    EXPECT_EQ(c.deferred_outputs_differ, 0u);
    EXPECT_GE(c.err[1][0].avg(), 0.9 * c.err[0][0].avg()) << c.fmt.name();
    EXPECT_LE(c.err[1][0].avg(), 3.0 * c.err[0][0].avg()) << c.fmt.name();
  }
  for (int u = 0; u < kOutUnits; ++u) {
    EXPECT_EQ(st.cells[2].false_hit[u], 0u) << u;
    EXPECT_EQ(st.cells[2].false_miss[u], 0u) << u;
  }
}

}  // namespace
