// Mixed precision in the datapath IR (issue 18 §2, "per-operation precision"): a graph with a wide
// format and cvt nodes evaluates bit for bit like float code that widens to double and rounds back
// (an independent oracle: the hardware's float and double), the exact evaluator sees through cvt,
// the text form round-trips, and malformed graphs are refused with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "rayunits/dp/ir.hpp"
#include "rayunits/num/fp.hpp"
#include "rayunits/util/rng.hpp"

namespace {

using namespace ru::dp;
using ru::num::Format;
using ru::num::Soft;
using ru::num::SoftScope;

uint64_t fbits(float x) { return ru::num::fp_bits(x); }
float from_fbits(uint64_t b) { return ru::num::fp_from_bits<float>(b); }

// d = a*b - c*e (a 2x2 determinant, the shape of a cross-product component), first computed in
// the wide format and rounded back; then the larger of d and a, in the unit's format; a wide
// comparison and select; a wide constant. With wide = false the same dataflow in one format.
Graph det_graph(bool wide) {
  Graph g;
  if (wide) g.set_wide(3, 29);  // e8m23 -> e11m52: float -> double
  const int a = g.input("a"), b = g.input("b"), c = g.input("c"), e = g.input("e");
  auto up = [&](int x) { return wide ? g.cvt(x) : x; };
  const int A = up(a), B = up(b), C = up(c), E = up(e);
  const int d = g.sub(g.mul(A, B), g.mul(C, E));
  const int half = g.mul(d, g.constant(0.5, wide));
  const int pos = g.gt(d, half);              // d > d/2: d > 0 (wide compare when wide)
  const int sel = g.select(pos, d, g.neg(half));
  const int dn = wide ? g.cvt(d) : d;
  const int seln = wide ? g.cvt(sel) : sel;
  g.output("d", dn);
  g.output("m", g.max(dn, a));
  g.output("s", seln);
  g.output("pos", pos);
  return g;
}

// The oracle: float inputs, double arithmetic, one rounding back to float per output.
struct Native {
  float d, m, s;
  bool pos;
};
Native native(float a, float b, float c, float e) {
  const double D = static_cast<double>(a) * b - static_cast<double>(c) * e;
  const double half = D * 0.5;
  const bool pos = D > half;
  const double sel = pos ? D : -half;
  const float d = static_cast<float>(D);
  return {d, std::isnan(d) ? a : std::isnan(a) ? d : std::fmax(d, a), static_cast<float>(sel), pos};
}

float random_float(ru::util::SplitMix64& r) {
  const uint64_t x = r.next();
  switch (x % 8) {
    case 0: return from_fbits(static_cast<uint32_t>(x >> 32) & 0x807fffffu);  // subnormal or zero
    case 1: return std::ldexp(1.0f, static_cast<int>((x >> 8) % 40) - 20);   // powers of two: exact cancellations
    default: {
      // exponents near each other, so that products cancel
      const uint32_t exp = 127 - 12 + static_cast<uint32_t>((x >> 40) % 24);
      return from_fbits(static_cast<uint32_t>((x >> 63) << 31) | (exp << 23) | static_cast<uint32_t>(x & 0x7fffff));
    }
  }
}

TEST(DpMixed, FloatWithDoubleStepsEqualsNativeBitForBit) {
  SoftScope s(Format::parse("e8m23"));
  const Graph g = det_graph(true), plain = det_graph(false);
  ASSERT_TRUE(g.mixed());
  ASSERT_FALSE(plain.mixed());
  ru::util::SplitMix64 r(7);
  const auto& ns = g.nodes();
  size_t caught = 0;
  for (int i = 0; i < 200000; ++i) {
    float x[4];
    for (float& v : x) v = random_float(r);
    std::vector<Soft> in;
    for (float v : x) in.push_back(Soft::from_bits(fbits(v)));
    const auto v = evaluate(g, in);
    const Native n = native(x[0], x[1], x[2], x[3]);
    auto out = [&](const char* name) { return v[g.output_node(name)]; };
    ASSERT_EQ(out("d").v.bits, fbits(n.d)) << x[0] << " " << x[1] << " " << x[2] << " " << x[3];
    ASSERT_EQ(out("m").v.bits, fbits(n.m));
    ASSERT_EQ(out("s").v.bits, fbits(n.s));
    ASSERT_EQ(out("pos").b, n.pos);
    // the wide nodes hold double bits
    const int d = ns[g.output_node("d")].a;
    const double D = ru::num::fp_from_bits<double>(v[d].v.bits);
    ASSERT_TRUE(std::isnan(D) || D == static_cast<double>(x[0]) * x[1] - static_cast<double>(x[2]) * x[3]);
    // the planted error, one format throughout, is caught by the same comparison
    if (evaluate(plain, in)[plain.output_node("d")].v.bits != fbits(n.d)) ++caught;
  }
  EXPECT_GT(caught, 1000u);
}

TEST(DpMixed, ExactSeesThroughConversionsAndTextRoundTrips) {
  const Graph g = det_graph(true), plain = det_graph(false);
  const std::vector<double> in = {1.5, -3.25, 0.125, 7};
  const ExactValues x = evaluate_exact(g, in), y = evaluate_exact(plain, in);
  for (const char* o : {"d", "m", "s"}) EXPECT_EQ(x.q[g.output_node(o)], y.q[plain.output_node(o)]) << o;
  const std::string text = g.print();
  EXPECT_EQ(text.rfind("wide 3 29\n", 0), 0u) << text;
  EXPECT_NE(text.find("const 0.5 w"), std::string::npos);
  EXPECT_EQ(Graph::parse(text).print(), text);
  EXPECT_EQ(plain.print().find("wide"), std::string::npos);  // a one-format graph's text is unchanged
  const auto c = g.op_counts();
  EXPECT_EQ(c.at("mul_w"), 3);
  EXPECT_EQ(c.at("add_w"), 1);
  EXPECT_EQ(c.at("cmp_w"), 1);
  EXPECT_EQ(c.at("cmp"), 1);
  EXPECT_EQ(c.at("cvt_up"), 4);
  EXPECT_EQ(c.at("cvt_down"), 2);
  EXPECT_EQ(c.count("mul"), 0u);
}

TEST(DpMixed, MalformedGraphsAreRefusedWithOneLine) {
  auto err = [](const std::string& text) {
    try {
      Graph::parse(text);
    } catch (const IrError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(err("in a\ncvt 0\n"), "line 2: cvt: the graph has no wide format (a 'wide DE DM' line first)");
  EXPECT_EQ(err("wide 1 7\nin a\ncvt 0\nadd 0 1\n"),
            "line 4: add: operands 0..1 are in different formats (convert one with cvt)");
  EXPECT_EQ(err("in a\nwide 1 7\n"), "line 2: wide: before any node");
  EXPECT_EQ(err("wide 0 0\n"), "line 1: wide: 0 0: exponent and fraction bits to add, each >= 0, not both 0");
  EXPECT_EQ(err("wide 1\n"), "line 1: wide: needs two numbers, exponent and fraction bits to add (e.g. wide 1 7)");
  EXPECT_EQ(err("const 1 w\n"), "line 1: const: a wide constant in a graph without a wide format");
  EXPECT_EQ(err("wide 1 1\nconst 1 x\n"), "line 2: const: 'x' after the value (only 'w', a wide constant)");
  // a mixed graph runs in Soft only; a wide format beyond the model's range is named
  const Graph g = det_graph(true);
  EXPECT_THROW(evaluate<float>(g, {1, 2, 3, 4}), IrError);
  SoftScope s(Format::parse("e9m30"));
  try {
    evaluate<Soft>(g, std::vector<Soft>(4));
    ADD_FAILURE() << "e9m30 widened by 3 29 accepted";
  } catch (const IrError& e) {
    EXPECT_STREQ(e.what(), "wide format of e9m30 widened by 3 29 is e12m59: beyond e11m52");
  }
}

}  // namespace
