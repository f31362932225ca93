// The ray-box unit in the datapath IR (issue 18 §2, "the same for the ray-box unit"): the hand
// designs' genomes equal the golden model units::ray_box_reference bit for bit (plain and
// conservative), every move is an equivalence in exact rationals (against units::exact_slab), the
// conservative genomes never miss a box the exact slab test hits (adversarial rays), and the new IR
// pieces (bit tests, +-inf constants, per-node rounding) print, parse and emit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../common/temp_dir.hpp"
#include "rayunits/dp/emit.hpp"
#include "rayunits/dp/formulas.hpp"
#include "rayunits/num/fp.hpp"
#include "rayunits/synth/unit_models.hpp"
#include "rayunits/units/exact.hpp"
#include "rayunits/units/ray_box.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/util/process.hpp"

namespace {

using namespace ru::dp;
using ru::num::Format;
using ru::num::Soft;
using ru::num::SoftScope;
using ru::units::BoxMode;

// Records of the registry's ray-box stimulus (synthetic boxes at random scales, 1 % special values)
// in format f: 14 fields each, in the graphs' input order.
std::vector<std::vector<uint64_t>> stimulus(const Format& f, size_t n, uint64_t seed) {
  ru::synth::UnitConfig c;
  c.fmt = f;
  auto gen = ru::synth::models::ray_box_inputs(c, seed);
  std::vector<std::vector<uint64_t>> v(n, std::vector<uint64_t>(14));
  for (auto& r : v) gen(r.data());
  return v;
}

// Records where graph g (in Soft, format f) and ray_box_reference (mode m) differ in hit, t_enter
// or t_exit bits.
size_t mismatches(const Graph& g, BoxMode m, const Format& f, const std::vector<std::vector<uint64_t>>& recs) {
  SoftScope scope(f);
  const int hit = g.output_node("hit"), te = g.output_node("t_enter"), tx = g.output_node("t_exit");
  size_t bad = 0;
  for (const auto& r : recs) {
    std::vector<Soft> x(14);
    for (int k = 0; k < 14; ++k) x[k] = Soft::from_bits(r[k]);
    const auto v = evaluate<Soft>(g, x);
    const ru::units::Vec3<Soft> o{x[0], x[1], x[2]}, inv{x[3], x[4], x[5]}, lo{x[8], x[9], x[10]},
        hi{x[11], x[12], x[13]};
    const auto ref = ru::units::ray_box_reference(o, inv, lo, hi, x[6], x[7], m);
    bad += v[hit].b != ref.hit || v[te].v.bits != ref.t_enter.bits || v[tx].v.bits != ref.t_exit.bits;
  }
  return bad;
}

TEST(DpBox, HandGenomesEqualTheGoldenModelBitForBit) {
  const Graph plain = box_graph(box_plain_genome()), cons = box_graph(box_conservative_genome());
  for (const char* fs : {"e5m10", "e6m12", "e7m16", "e8m23", "e11m52", "e5m10-ftz"}) {
    const Format f = Format::parse(fs);
    const auto recs = stimulus(f, 3000, 7);
    EXPECT_EQ(mismatches(plain, BoxMode::Plain, f, recs), 0u) << fs;
    // the balanced tree and the chain give the same bits (maxNum / minNum are associative)
    BoxGenome chain = box_plain_genome();
    chain.tree = 1;
    EXPECT_EQ(mismatches(box_graph(chain), BoxMode::Plain, f, recs), 0u) << fs;
    // conservative: formats with subnormals (with FTZ the unit's bound replacement is not in the graph)
    if (f.subnormals) {
      EXPECT_EQ(mismatches(cons, BoxMode::Conservative, f, recs), 0u) << fs;
    }
  }
  Format rtz = Format::parse("e7m16");
  rtz.round = ru::num::Round::RTZ;
  EXPECT_EQ(mismatches(plain, BoxMode::Plain, rtz, stimulus(rtz, 2000, 3)), 0u);
  // the checker sees a change: the conservative graph against the plain model and vice versa, and
  // one directed rounding left out (the difference rounded as the format)
  const Format f = Format::parse("e7m16");
  const auto recs = stimulus(f, 3000, 9);
  EXPECT_GT(mismatches(cons, BoxMode::Plain, f, recs), 100u);
  EXPECT_GT(mismatches(plain, BoxMode::Conservative, f, recs), 100u);
  BoxGenome half = box_conservative_genome();
  half.round = 2;  // the product only
  EXPECT_GT(mismatches(box_graph(half), BoxMode::Conservative, f, recs), 10u);
}

// Every move is the same function in exact arithmetic: the exact evaluation of each genome's graph
// equals units::exact_slab (hit, t_enter, t_exit) on records with finite inputs.
TEST(DpBox, EveryGenomeIsTheExactSlabTest) {
  ru::units::SynthBoxOptions o;
  o.seed = 4;
  o.boxes = 64;
  o.axis_parallel_fraction = 0;  // finite reciprocals (the exact evaluator takes finite inputs)
  o.finite_tmax_fraction = 1;
  auto recs = ru::units::synth_box(o);
  ASSERT_GT(recs.size(), 500u);
  EXPECT_EQ(all_box_genomes().size(), 16u);
  for (const BoxGenome& G : all_box_genomes()) {
    const Graph g = box_graph(G);
    const int hit = g.output_node("hit"), te = g.output_node("t_enter"), tx = g.output_node("t_exit");
    size_t bad = 0, hits = 0;
    for (const auto& r : recs) {
      const auto x = evaluate_exact(g, box_inputs(r));
      const auto e = ru::units::exact_slab(r.o, r.inv, r.lo, r.hi, r.t_min, r.t_max);
      ASSERT_EQ(e.t_enter.kind, ru::units::XQ::Finite);
      bad += x.b[hit] != e.hit || x.q[te] != e.t_enter.q || x.q[tx] != e.t_exit.q;
      hits += e.hit;
    }
    EXPECT_EQ(bad, 0u) << box_genome_name(G);
    EXPECT_GT(hits, 50u);
  }
  // planted: far and near swapped on one axis is caught
  std::string text = box_graph(box_plain_genome()).print();
  const size_t at = text.find("sel ");
  ASSERT_NE(at, std::string::npos);
  const size_t eol = text.find('\n', at);
  std::string line = text.substr(at, eol - at);  // "sel P H L   # n"
  std::istringstream ls(line);
  std::string w, p, a, b;
  ls >> w >> p >> a >> b;
  text.replace(at, eol - at, "sel " + p + " " + b + " " + a);
  const Graph planted = Graph::parse(text);
  size_t bad = 0;
  for (const auto& r : recs) bad += evaluate_exact(planted, box_inputs(r)).b[planted.output_node("hit")] !=
                                    ru::units::exact_slab(r.o, r.inv, r.lo, r.hi, r.t_min, r.t_max).hit;
  EXPECT_GT(bad, 0u);
}

// Directed rounding of the difference and the product (r1, either form) never misses a box the exact
// slab test hits; the format's rounding (r0) does (adversarial rays on box corners, edges and faces).
TEST(DpBox, ConservativeGenomesNeverMiss) {
  const Format f = Format::parse("e5m10");
  SoftScope scope(f);
  ru::units::AdversarialBoxGen gen(f, 21);
  std::vector<ru::units::BoxRecord> recs;
  const int n = std::getenv("RU_BOX_RAYS") ? std::atoi(std::getenv("RU_BOX_RAYS")) : 4000;
  for (int i = 0; i < n; ++i) recs.push_back(gen.next());
  for (const BoxGenome& G : all_box_genomes()) {
    if (G.tree != 0) continue;  // the same bits as tree 0
    const Graph g = box_graph(G);
    const int hit = g.output_node("hit");
    size_t misses = 0;
    for (const auto& r : recs) {
      std::vector<Soft> x;
      for (double v : box_inputs(r)) x.push_back(Soft::from_double(v));
      const auto e = ru::units::exact_slab(r.o, r.inv, r.lo, r.hi, r.t_min, r.t_max);
      misses += e.hit && !evaluate<Soft>(g, x)[hit].b;
    }
    if (std::getenv("RU_BOX_RAYS")) std::printf("%s: %zu misses of %zu\n", box_genome_name(G).c_str(), misses, recs.size());
    if (G.round == 1) {
      EXPECT_EQ(misses, 0u) << box_genome_name(G);
    } else if (G.round == 0) {
      EXPECT_GT(misses, 0u) << box_genome_name(G);  // the check can fail
    }
    // (one directed rounding alone, r2 / r3, is no bound in general; measured by the search)
  }
}

TEST(DpBox, NewIrPiecesPrintParseAndEmit) {
  const Graph g = box_graph(box_conservative_genome());
  EXPECT_EQ(Graph::parse(g.print()).print(), g.print());
  EXPECT_NE(g.print().find(" rdn"), std::string::npos);
  Graph h;
  const int x = h.input("x");
  h.output("p", h.isinf(h.max(x, h.constant(-INFINITY))));
  EXPECT_NE(h.print().find("const -inf"), std::string::npos);
  EXPECT_EQ(Graph::parse(h.print()).print(), h.print());
  EXPECT_THROW(Graph::parse("in x\nin y\nadd 0 1 up\n"), IrError);
  EXPECT_THROW(Graph::parse("in x\nneg 0 rdn\n"), IrError);  // only add sub mul div fma round
  EXPECT_THROW(h.rounded(x, ru::num::Round::RDN), IrError);
  EXPECT_THROW(h.constant(NAN), IrError);
  // in exact arithmetic the bit tests are of finite values
  Graph e;
  const int a = e.input("a");
  e.output("s", e.signbit(a));
  EXPECT_TRUE(evaluate_exact(e, {-2.0}).b[1]);
  EXPECT_FALSE(evaluate_exact(e, {0.0}).b[1]);
  // emitted: the mode as the instance's Round, the bit tests, the constant
  const std::string sv = emit_sv(g, "ru_dp_box");
  EXPECT_NE(sv.find(".Round(2)"), std::string::npos);
  EXPECT_NE(sv.find(".Round(3)"), std::string::npos);
  EXPECT_NE(sv.find("[W-1]"), std::string::npos);
  EXPECT_NE(emit_sv(h, "ru_dp_h").find("{ExpW{1'b1}}"), std::string::npos);
}

// The emitted box units are lint clean (plain and conservative, both forms, Stages 0 and mid).
TEST(DpBox, EmittedUnitsAreLintClean) {
  if (ru::util::find_program("verilator").empty()) GTEST_SKIP() << "verilator not installed";
  ru::test::TempDir t("ru_dp_box_lint");
  const std::string rtl = std::string(RU_SOURCE_DIR) + "/rtl/";
  for (const char* name : {"box-r0-f0-m0", "box-r1-f1-m1"}) {
    const Graph g = box_graph(parse_box_genome_name(name));
    const std::string sv = (t.p / "ru_dp_box.sv").string();
    std::ofstream(sv) << emit_sv(g, "ru_dp_box");
    for (int stages : {0, 7}) {
      std::vector<std::string> argv = {"verilator", "--lint-only", "-Wall", "-I" + rtl, "--top-module", "ru_dp_box",
                                       "-GExpW=5", "-GFracW=10", "-GStages=" + std::to_string(stages)};
      for (const auto& f : emit_sources(g)) argv.push_back(rtl + f);
      argv.push_back(sv);
      ru::util::ProcessOptions po;
      po.out = ru::util::Redirect::capture();
      po.err = ru::util::Redirect::capture();
      po.timeout_s = 300;
      const auto r = ru::util::run_process(argv, po);
      EXPECT_EQ(r.status(), 0) << name << " Stages " << stages << ":\n" << r.err;
      EXPECT_EQ(r.err.find("%Warning"), std::string::npos) << r.err;
    }
  }
}

}  // namespace
