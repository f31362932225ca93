// Tests of the datapath IR (rayunits/dp, issue 18 §1): today's ray-triangle units written as IR
// graphs evaluate bit for bit like the hand-written golden models (units/ray_tri.hpp) in float,
// double and several Soft formats, on synthetic, integer-grid (exact zero volumes, degenerate
// triangles) and special-value inputs; the exact evaluator equals the exact references
// (units/exact.hpp); the text form round-trips; bad graphs and bad text are one-line errors; and a
// planted change of one operation is caught by the same comparison.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <limits>
#include <string>
#include <vector>

#include "rayunits/dp/formulas.hpp"
#include "rayunits/dp/ir.hpp"
#include "rayunits/num/fp.hpp"
#include "rayunits/units/exact.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/ray_tri_cheap.hpp"
#include "rayunits/units/synthetic.hpp"

namespace {

using namespace ru::dp;
using ru::num::Format;
using ru::num::Soft;
using ru::num::SoftScope;
using ru::units::TriRecord;

// Synthetic records over many binades, integer-grid records (exact zeros, shared edges and
// vertices, degenerate triangles) and records with INF, NaN, signed zeros and huge values.
std::vector<TriRecord> workload(uint64_t seed) {
  ru::units::SynthTriOptions o;
  o.seed = seed;
  o.triangles = 300;
  o.rays_per_packet = 4;
  o.log2_spread = 24;
  std::vector<TriRecord> w = ru::units::synth_tri(o);
  ru::units::Rng rng(seed * 7 + 1);
  auto small = [&] { return static_cast<double>(static_cast<int>(rng.below(7)) - 3); };
  for (int i = 0; i < 1500; ++i) {
    TriRecord r;
    for (auto* v : {&r.a, &r.d, &r.p0, &r.p1, &r.p2}) *v = {small(), small(), small()};
    r.t_min = rng.below(2) ? 0.0 : -INFINITY;
    r.t_max = rng.below(3) ? INFINITY : small() + 4;
    w.push_back(r);
  }
  const double specials[] = {INFINITY, -INFINITY, NAN, 0.0, -0.0, 1e30, -1e30, 1e-30, 65504.0, 3.0e38};
  const size_t n = w.size();
  for (size_t i = 0; i < 800; ++i) {
    TriRecord r = w[rng.below(n)];
    double* fields[] = {&r.a.x, &r.a.y, &r.a.z, &r.d.x, &r.d.y, &r.d.z, &r.p0.x, &r.p0.y, &r.p0.z,
                        &r.p1.x, &r.p1.y, &r.p1.z, &r.p2.x, &r.p2.y, &r.p2.z, &r.t_min, &r.t_max};
    *fields[rng.below(17)] = specials[rng.below(10)];
    w.push_back(r);
  }
  return w;
}

template <class T>
uint64_t bits(T x) {
  return ru::num::fp_bits(ru::num::fp_canon(x));
}

// Number of records on which the graph differs from the hand-written model in any output bit.
enum class Model { Robust, RobustRecip, Mt };

template <class T>
size_t mismatches(const Graph& g, Model model, bool tie_break, const std::vector<TriRecord>& w, std::string* first) {
  const bool robust = model != Model::Mt;
  using ru::num::fp_cast;
  const int o_hit = g.output_node("hit"), o_t = g.output_node("t"), o_b = g.output_node("beta"),
            o_g = g.output_node("gamma"), o_V = g.output_node("V"), o_Va = g.output_node("Va"),
            o_V1 = g.output_node("V1"), o_V2 = g.output_node("V2");
  const int o_V0 = robust ? g.output_node("V0") : -1;
  size_t bad = 0;
  ru::units::TriOptions opt;
  opt.tie_break = tie_break;
  for (const TriRecord& r : w) {
    std::vector<T> in;
    for (double x : tri_inputs(r)) in.push_back(fp_cast<T>(x));
    const auto v = evaluate<T>(g, in);
    const ru::units::Vec3<T> a{in[0], in[1], in[2]}, d{in[3], in[4], in[5]}, p0{in[6], in[7], in[8]},
        p1{in[9], in[10], in[11]}, p2{in[12], in[13], in[14]};
    const auto m = model == Model::Robust        ? ru::units::ray_tri_robust(a, d, p0, p1, p2, in[15], in[16], opt)
                   : model == Model::RobustRecip ? ru::units::ray_tri_robust_recip(a, d, p0, p1, p2, in[15], in[16], opt)
                                                 : ru::units::ray_tri_mt(a, d, p0, p1, p2, in[15], in[16], opt);
    const bool same = v[o_hit].b == m.hit && bits(v[o_t].v) == bits(m.t) && bits(v[o_b].v) == bits(m.beta) &&
                      bits(v[o_g].v) == bits(m.gamma) && bits(v[o_V].v) == bits(m.V) &&
                      bits(v[o_Va].v) == bits(m.Va) && bits(v[o_V1].v) == bits(m.V1) &&
                      bits(v[o_V2].v) == bits(m.V2) && (!robust || bits(v[o_V0].v) == bits(m.V0));
    if (!same && bad++ == 0 && first)
      *first = "a=(" + std::to_string(r.a.x) + "," + std::to_string(r.a.y) + "," + std::to_string(r.a.z) +
               ") hit graph " + std::to_string(v[o_hit].b) + " model " + std::to_string(m.hit);
  }
  return bad;
}

struct Case {
  const char* name;
  Model model;
  bool tie;
  bool robust() const { return model != Model::Mt; }
};
const Case kCases[] = {{"robust", Model::Robust, false},
                       {"robust+tie", Model::Robust, true},
                       {"robust recip", Model::RobustRecip, false},
                       {"robust recip+tie", Model::RobustRecip, true},
                       {"mt", Model::Mt, false}};

Graph graph_of(const Case& c) {
  return c.robust() ? ray_tri_robust_graph(c.tie, c.model == Model::RobustRecip) : ray_tri_mt_graph();
}

TEST(DpIr, TriangleGraphsEqualTheHandWrittenModelsBitForBit) {
  const auto w = workload(3);
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.name);
    const Graph g = graph_of(c);
    std::string first;
    EXPECT_EQ(mismatches<float>(g, c.model, c.tie, w, &first), 0u) << "float: " << first;
    EXPECT_EQ(mismatches<double>(g, c.model, c.tie, w, &first), 0u) << "double: " << first;
    for (const char* f : {"e5m10", "e5m10-ftz", "e6m12", "e7m16", "e8m23", "e11m52"}) {
      SoftScope s(Format::parse(f));
      EXPECT_EQ(mismatches<Soft>(g, c.model, c.tie, w, &first), 0u) << f << ": " << first;
    }
    Format rtz = Format::parse("e7m16");
    rtz.round = ru::num::Round::RTZ;
    SoftScope s(rtz);
    EXPECT_EQ(mismatches<Soft>(g, c.model, c.tie, w, &first), 0u) << "e7m16 RTZ: " << first;
  }
}

// The checker sees a one-operation change: the text form with one subtraction's operands swapped
// (the first edge of the unit), and the tie-break left out of a graph compared with a model that
// has it.
TEST(DpIr, PlantedChangesAreCaught) {
  const auto w = workload(4);
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.name);
    std::string text = graph_of(c).print();
    const size_t p = text.find("\nsub ");
    ASSERT_NE(p, std::string::npos);
    const size_t e = text.find('\n', p + 1);
    std::istringstream ls(text.substr(p + 5, e - p - 5));
    int x = 0, y = 0;
    ls >> x >> y;
    text.replace(p + 1, e - p - 1, "sub " + std::to_string(y) + " " + std::to_string(x));
    const Graph planted = Graph::parse(text);
    SoftScope s(Format::parse("e8m23"));
    EXPECT_GT(mismatches<Soft>(planted, c.model, c.tie, w, nullptr), 100u);
  }
  SoftScope s(Format::parse("e5m10"));
  EXPECT_GT(mismatches<Soft>(ray_tri_robust_graph(false), Model::Robust, true, workload(5), nullptr), 10u);
  // and the two ways of dividing are told apart
  EXPECT_GT(mismatches<Soft>(ray_tri_robust_graph(false, true), Model::Robust, false, workload(5), nullptr), 100u);
}

// The exact evaluator of the same graphs gives the exact volumes of units/exact.hpp, and for the
// robust graph an exact zero volume exactly when the reference has one.
TEST(DpIr, ExactEvaluatorEqualsTheExactReferences) {
  const auto w = workload(6);
  size_t checked = 0, zeros = 0;
  for (const Case& c : {kCases[0], kCases[4]}) {
    const Graph g = graph_of(c);
    for (TriRecord r : w) {
      // infinite interval ends (rationals have none) become finite: the volumes do not use them
      if (std::isinf(r.t_min)) r.t_min = std::copysign(1e300, r.t_min);
      if (std::isinf(r.t_max)) r.t_max = std::copysign(1e300, r.t_max);
      const auto in = tri_inputs(r);
      bool finite = true;
      for (double x : in) finite = finite && std::isfinite(x);
      if (!finite) continue;
      const ExactValues ex = evaluate_exact(g, in);
      const auto ref = ru::units::exact_volumes(r.a, r.d, r.p0, r.p1, r.p2);
      // MT's V1, V2 are volumes of other tetrahedra than Fig. 3.6's; V and Va are the same
      // determinant up to orientation.
      if (c.robust()) {
        EXPECT_EQ(ex.q[g.output_node("V0")], ref.V0);
        EXPECT_EQ(ex.q[g.output_node("V1")], ref.V1);
        EXPECT_EQ(ex.q[g.output_node("V2")], ref.V2);
        EXPECT_EQ(ex.q[g.output_node("V")], ref.V);
        EXPECT_EQ(ex.q[g.output_node("Va")], ref.Va);
        zeros += sgn(ref.V0) == 0;
      } else {
        EXPECT_EQ(abs(ex.q[g.output_node("V")]), abs(ref.V));
      }
      EXPECT_EQ(ex.defined[g.output_node("t")], sgn(ref.V) != 0);
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000u);
  EXPECT_GT(zeros, 50u);  // the integer grid gives exact zeros
}

TEST(DpIr, OperationCountsFollowTheDataflow) {
  // From the dataflow comments of units/ray_tri.hpp: robust 9 edge subs, three V_i (3 sub,
  // cross 6 mul 3 sub, dot 3 mul 2 add), N (6 mul 3 sub), V (3 mul 2 add), Va (3 sub, 3 mul
  // 2 add), 3 div; MT 9 subs, two crosses, four dots, 1 div, 3 mul, 1 add.
  auto c = ray_tri_robust_graph().op_counts();
  EXPECT_EQ(c["add"], 9 + 3 * 8 + 3 + 2 + 5);
  EXPECT_EQ(c["mul"], 3 * 9 + 6 + 3 + 3);
  EXPECT_EQ(c["div"], 3);
  c = ray_tri_mt_graph().op_counts();
  EXPECT_EQ(c["add"], 9 + 6 + 8 + 1);
  EXPECT_EQ(c["mul"], 12 + 12 + 3);
  EXPECT_EQ(c["div"], 1);
  c = ray_tri_robust_graph(false, true).op_counts();
  EXPECT_EQ(c["div"], 1);
  EXPECT_EQ(c["mul"], 3 * 9 + 6 + 3 + 3 + 3);
}

// The graphs' levels of FP operations are the RTL's level chains (NLev, read from the RTL:
// ru_ray_tri_mt `NLev = 10`, ru_ray_tri_robust `NLev = 8 + R` with R = OptRecip): an emitter
// that places one level per FP depth gives the same latency structure.
int rtl_levels(const std::string& file, int r) {
  std::ifstream f(std::string(RU_SOURCE_DIR) + "/rtl/" + file);
  std::stringstream ss;
  ss << f.rdbuf();
  std::smatch m;
  const std::string text = ss.str();
  if (!std::regex_search(text, m, std::regex(R"(localparam int unsigned NLev = (\d+)( \+ R)?;)"))) return -1;
  return std::stoi(m[1]) + (m[2].matched ? r : 0);
}

TEST(DpIr, LevelsAreTheRtlLevelChains) {
  EXPECT_EQ(ray_tri_mt_graph().fp_depth(), rtl_levels("ru_ray_tri_mt.sv", 0));
  EXPECT_EQ(ray_tri_robust_graph(false, false).fp_depth(), rtl_levels("ru_ray_tri_robust.sv", 0));
  EXPECT_EQ(ray_tri_robust_graph(true, false).fp_depth(), rtl_levels("ru_ray_tri_robust.sv", 0));
  EXPECT_EQ(ray_tri_robust_graph(false, true).fp_depth(), rtl_levels("ru_ray_tri_robust.sv", 1));
  EXPECT_GT(rtl_levels("ru_ray_tri_mt.sv", 0), 0);  // the pattern is found in both files
  EXPECT_GT(rtl_levels("ru_ray_tri_robust.sv", 0), 0);
}

TEST(DpIr, TextRoundTripsAndEvaluatesTheSame) {
  for (const Case& c : kCases) {
    const Graph g = graph_of(c);
    const Graph h = Graph::parse(g.print());
    EXPECT_EQ(h.print(), g.print());
    SoftScope s(Format::parse("e6m12"));
    EXPECT_EQ(mismatches<Soft>(h, c.model, c.tie, workload(8), nullptr), 0u);
  }
}

TEST(DpIr, BadGraphsAndTextAreOneLineErrors) {
  Graph g;
  const int x = g.input("x");
  const int p = g.lt(x, x);
  EXPECT_THROW(g.add(x, p), IrError);     // a Boolean where an FP value is needed
  EXPECT_THROW(g.land(x, p), IrError);    // an FP value where a Boolean is needed
  EXPECT_THROW(g.add(x, 7), IrError);     // not an earlier node
  EXPECT_THROW(g.input("x"), IrError);    // twice
  EXPECT_THROW(g.constant(NAN), IrError);
  EXPECT_THROW(evaluate<double>(g, {}), IrError);  // one input value missing
  struct Bad {
    const char* text;
    const char* must;
  };
  for (const Bad& b : {Bad{"in x\nfoo 0 0\n", "line 2: unknown operation 'foo'"},
                       Bad{"in x\nadd 0\n", "line 2: add: missing operand"},
                       Bad{"in x\nadd 0 1\n", "line 2: add: operand 1 is not an earlier node"},
                       Bad{"in x\nlt 0 0\nadd 0 1\n", "line 3: add: operand 1 is a Boolean"},
                       Bad{"in x\nconst abc\n", "line 2: const: 'abc' is not a number"},
                       Bad{"in x\nneg 0 0\n", "line 2: unexpected '0'"},
                       Bad{"in x\nout y 5\n", "line 2: out y: no node 5"}}) {
    try {
      Graph::parse(b.text);
      ADD_FAILURE() << "no error for " << b.text;
    } catch (const IrError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(b.must), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
}

}  // namespace
