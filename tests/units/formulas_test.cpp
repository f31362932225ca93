// Scalar-triple-product enumeration: counts, exact equivalence, classes and the study's
// class evaluation against the literal evaluation of all 528 formulations.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <tuple>

#include "rayunits/num/fp.hpp"
#include "rayunits/units/exact.hpp"
#include "rayunits/units/formulas.hpp"
#include "rayunits/units/study.hpp"
#include "rayunits/units/synthetic.hpp"

using namespace ru::units;
using ru::num::Format;
using ru::num::Soft;
using ru::num::SoftScope;

namespace {

TEST(UnitsFormulas, CountsAndDistinct) {
  EXPECT_EQ(stp_formulas(VolKind::V).size(), 36u);
  EXPECT_EQ(stp_formulas(VolKind::Va).size(), 384u);
  EXPECT_EQ(stp_formulas(VolKind::Vk).size(), 36u);
  EXPECT_EQ(stp_class_count(VolKind::V), 9);
  EXPECT_EQ(stp_class_count(VolKind::Va), 48);
  EXPECT_EQ(stp_class_count(VolKind::Vk), 9);
  for (VolKind k : {VolKind::V, VolKind::Va, VolKind::Vk}) {
    std::set<std::string> texts;
    for (const Stp& s : stp_formulas(k)) {
      // No two formulations equal, even with the cross operands swapped.
      Stp sw = s;
      std::swap(sw.u, sw.v);
      EXPECT_TRUE(texts.insert(s.text(k)).second) << s.text(k);
      EXPECT_EQ(texts.count(sw.text(k)), 0u) << s.text(k);
    }
  }
  EXPECT_EQ(stp_formulas(VolKind::Vk)[0].text(VolKind::Vk, 1).find("q"), std::string::npos);
}

// Every formulation (with its sign) equals the canonical exact volume on random rational
// inputs (not the configurations used to derive the signs).
TEST(UnitsFormulas, ExactlyEquivalent) {
  Rng rng(99);
  for (int trial = 0; trial < 20; ++trial) {
    Vec3q p[3], a, d;
    auto rq = [&] {
      mpq_class q(static_cast<long>(rng.below(2001)) - 1000, 1 + static_cast<long>(rng.below(50)));
      q.canonicalize();
      return q;
    };
    for (auto& v : p) v = {rq(), rq(), rq()};
    a = {rq(), rq(), rq()};
    d = {rq(), rq(), rq()};
    const mpq_class V = dot_q(cross_q(sub_q(p[2], p[0]), sub_q(p[1], p[2])), d);
    const mpq_class Va = dot_q(cross_q(sub_q(p[2], p[0]), sub_q(p[2], p[1])), sub_q(a, p[2]));
    for (VolKind kind : {VolKind::V, VolKind::Va, VolKind::Vk}) {
      for (int k = 0; k < (kind == VolKind::Vk ? 3 : 1); ++k) {
        std::vector<Vec3q> pts;
        if (kind == VolKind::V) pts = {p[0], p[1], p[2]};
        if (kind == VolKind::Va) pts = {p[0], p[1], p[2], a};
        if (kind == VolKind::Vk) pts = {a, p[(k + 1) % 3], p[(k + 2) % 3]};
        const mpq_class want = kind == VolKind::V    ? V
                               : kind == VolKind::Va ? Va
                                                     : dot_q(cross_q(sub_q(a, pts[2]), d), sub_q(pts[1], pts[2]));
        for (const Stp& s : stp_formulas(kind)) {
          auto term = [&](const StpTerm& t) { return t.is_d() ? d : sub_q(pts[t.i], pts[t.j]); };
          const mpq_class got = s.sign * dot_q(cross_q(term(s.u), term(s.v)), term(s.w));
          ASSERT_EQ(got, want) << s.text(kind, k);
        }
      }
    }
  }
}

TEST(UnitsFormulas, KnownEquations) {
  const auto& V = stp_formulas(VolKind::V);
  const auto& Va = stp_formulas(VolKind::Va);
  const auto& Vk = stp_formulas(VolKind::Vk);
  auto has = [](const std::vector<Stp>& l, VolKind k, int cls, const std::string& text) {
    for (const Stp& s : l)
      if (s.cls == cls && (s.text(k) == text || s.text(k) == "-" + text)) return true;
    return false;
  };
  EXPECT_TRUE(has(V, VolKind::V, known_formula_class(KnownFormula::Eq33), "[(p2 - p0) x (p1 - p2)] . d"));
  EXPECT_TRUE(has(Va, VolKind::Va, known_formula_class(KnownFormula::Eq34), "[(p2 - p0) x (p2 - p1)] . (a - p2)"));
  // Eq. 3.5 / 3.6 with the cross operands in the canonical order (d first).
  EXPECT_TRUE(has(Vk, VolKind::Vk, known_formula_class(KnownFormula::Eq35), "[d x (a - q2)] . (q1 - q2)"));
  EXPECT_TRUE(has(Vk, VolKind::Vk, known_formula_class(KnownFormula::Eq36), "[d x (a - q1)] . (q1 - q2)"));
  EXPECT_NE(known_formula_class(KnownFormula::Eq35), known_formula_class(KnownFormula::Eq36));
  EXPECT_NE(known_formula_class(KnownFormula::Eq33), known_formula_class(KnownFormula::MtV));
  // Each class has 4 (V, V_k) or 8 (Va) members.
  for (VolKind k : {VolKind::V, VolKind::Va, VolKind::Vk}) {
    std::vector<int> n(stp_class_count(k));
    for (const Stp& s : stp_formulas(k)) ++n[s.cls];
    for (int c : n) EXPECT_EQ(c, k == VolKind::Va ? 8 : 4);
  }
}

// The study evaluates one representative per class with cached cross products; every member
// of the class, evaluated literally in the format, must give the same value up to the sign of
// zero. This also checks that reversing edges only negates (round to nearest).
int compare_classes(const char* fmt, size_t tris, bool plant_error) {
  SoftScope sc(Format::parse(fmt));
  SynthTriOptions o;
  o.triangles = tris;
  o.rays_per_packet = 4;
  o.seed = 17;
  int mismatches = 0;
  std::vector<Soft> out[3];
  for (const TriRecord& r : synth_tri(o)) {
    eval_classes(r, out);
    if (plant_error) out[1][5] = -out[1][5];  // a wrong sign in one class
    for (VolKind kind : {VolKind::V, VolKind::Va, VolKind::Vk}) {
      const int ki = static_cast<int>(kind), n = stp_class_count(kind);
      for (int k = 0; k < (kind == VolKind::Vk ? 3 : 1); ++k)
        for (const Stp& s : stp_formulas(kind)) {
          const Soft lit = eval_formula(r, kind, k, s);
          const Soft cls = out[ki][k * n + s.cls];
          const bool both_zero = lit.to_double() == 0 && cls.to_double() == 0;
          if (!both_zero && lit.bits != cls.bits) ++mismatches;
        }
    }
  }
  return mismatches;
}

TEST(UnitsFormulas, ClassEvaluationMatchesLiteral) {
  for (const char* fmt : {"e5m10", "e7m16", "e8m23", "e6m9-ftz"}) EXPECT_EQ(compare_classes(fmt, 40, false), 0) << fmt;
}

TEST(UnitsFormulas, ClassCheckerCatchesPlantedSign) { EXPECT_GT(compare_classes("e7m16", 10, true), 0); }

}  // namespace
