// Tests of the formulation search (rayunits/dp/search.hpp, issue 18 §2): every genome is the same
// exact function as the exact reference (the moves are equivalences; a planted wrong operation is
// caught), genome names, the cost model's row choice and schedule on planted rows, determinism
// (threads, resume) and the sanity check: from a deliberately worse start the search finds a design
// within 5 % of Fig. 3.6's area at no more error (and the check fails on the start population).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "../common/files.hpp"
#include "../common/run_rayunits.hpp"
#include "../common/temp_dir.hpp"
#include "rayunits/dp/formulas.hpp"
#include "rayunits/dp/search.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/units/exact.hpp"
#include "rayunits/units/synthetic.hpp"

namespace {

using namespace ru::dp;
using ru::num::Format;
namespace fs = std::filesystem;

std::vector<ru::units::TriRecord> records(uint64_t seed, size_t n) {
  ru::units::SynthTriOptions o;
  o.seed = seed;
  o.rays_per_packet = 4;
  o.triangles = (n + 3) / 4;
  auto r = ru::units::synth_tri(o);
  r.resize(n);
  for (auto& x : r)
    if (!std::isfinite(x.t_max)) x.t_max = 1e6;  // the exact evaluator needs finite inputs
  return r;
}

// Outputs of g's exact evaluation that differ from units::exact_tri on the record's inputs
// (V, Va, V0 (if any), V1, V2, t, beta, gamma and the hit decision).
int exact_mismatches(const Graph& g, const std::vector<ru::units::TriRecord>& recs) {
  int bad = 0;
  for (const auto& r : recs) {
    const auto in = tri_inputs(r);
    const ExactValues x = evaluate_exact(g, in);
    const auto e = ru::units::exact_tri(r.a, r.d, r.p0, r.p1, r.p2, r.t_min, r.t_max);
    auto q = [&](const char* name) { return x.q[g.output_node(name)]; };
    bad += q("V") != e.vol.V;
    bad += q("Va") != e.vol.Va;
    bad += q("V1") != e.vol.V1;
    bad += q("V2") != e.vol.V2;
    bool has_v0 = false;
    for (const auto& [n, node] : g.outputs()) has_v0 |= n == "V0";
    if (has_v0) bad += q("V0") != e.vol.V0;
    if (e.has_t) bad += q("t") != e.t || q("beta") != e.beta || q("gamma") != e.gamma;
    bad += x.b[g.output_node("hit")] != e.hit;
  }
  return bad;
}

std::vector<TriGenome> all_canonical_genomes() {
  std::vector<TriGenome> out;
  std::set<std::string> seen;
  std::vector<int> v(kTriGenes, 0);
  for (;;) {
    TriGenome g = canonical(tri_genome(v));
    g.wide_de = 1, g.wide_dm = 7;  // mixed precision (the wide gene): e.g. e7m16 with e8m23 inside
    if (seen.insert(genome_name(g)).second) out.push_back(g);
    int i = 0;
    while (i < kTriGenes && ++v[i] == kTriGeneCount[i]) v[i++] = 0;
    if (i == kTriGenes) break;
  }
  return out;
}

TEST(SearchGenome, EveryGenomeIsTheExactReferenceFunction) {
  const auto gs = all_canonical_genomes();
  // (form x origin (form 3: none), denom, va, ... + Moller-Trumbore's q, i, p) x the three fuse values
  // x the four wide values
  EXPECT_EQ(gs.size(), 4u * 3u * (10u * 4 * 4 * 2 * 2 * 2 * 3 + 2 * 2 * 3));
  const auto recs = records(5, 2);
  for (const auto& g : gs) ASSERT_EQ(exact_mismatches(tri_graph(g), recs), 0) << genome_name(g);
}

TEST(SearchGenome, PlantedWrongOperationIsCaught) {
  // The checker above must see one changed operation: the last `sub` of the text form made an `add`.
  const std::string text = tri_graph(start_genome("sv-f3-o0-d3-a3-q1-i1-t0-p2")).print();
  const size_t at = text.find("sub ", text.size() / 3);
  ASSERT_NE(at, std::string::npos);
  std::string planted = text;
  planted.replace(at, 3, "add");
  EXPECT_GT(exact_mismatches(Graph::parse(planted), records(5, 8)), 0);
}

TEST(SearchGenome, NamesRoundTripAndBadNamesAreOneLineErrors) {
  for (const auto& g : all_canonical_genomes()) ASSERT_EQ(genome_name(parse_genome_name(genome_name(g))), genome_name(g));
  EXPECT_EQ(genome_name(fig36_genome()), "sv-f0-o0-d0-a0-q0-i0-t0-p0");
  EXPECT_EQ(genome_name(mt_genome()), "mt-q1-i0-p0");
  for (const char* bad : {"", "sv", "sv-f4-o0-d0-a0-q0-i0-t0-p0", "mt-q1-i0", "xx-q1-i0-p0", "sv-f0-o0-d0-a0-q0-i0-t0-p0-",
                          "sv-f0-o0-d0-a0-q0-i0-t0-p0-u0", "sv-f0-o0-d0-a0-q0-i0-t0-p0-u3", "mt-q1-i0-p0-x1",
                          "mt-q1-i0-p0-u1-u1"}) {
    try {
      parse_genome_name(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const IrError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos);
      EXPECT_NE(m.find("accepted"), std::string::npos) << m;
    }
  }
  EXPECT_THROW(start_genome("best"), IrError);
}

// The wide gene (mixed precision): where the conversions go, counted by hand from Fig. 3.6's
// dataflow (four cross products: 6 mul + 3 sub each; five dot products: 3 mul + 2 add each).
TEST(SearchGenome, MixedGenomesConvertWhereTheGeneSays) {
  auto ops = [](const std::string& name) {
    TriGenome g = parse_genome_name(name);
    g.wide_de = 1, g.wide_dm = 7;
    return tri_graph(g).op_counts();
  };
  // w1: the dot products wide; up: the four cross products' 12 components, the three edges' 9, d's 3
  // and p2 - a's 3 (Va); down: V0, V1, V2, V, Va
  auto w1 = ops("sv-f0-o0-d0-a0-q0-i0-t0-p0-w1");
  EXPECT_EQ(w1["mul_w"], 15);
  EXPECT_EQ(w1["add_w"], 10);
  EXPECT_EQ(w1["mul"], 24);
  EXPECT_EQ(w1["add"], 43 - 10);
  EXPECT_EQ(w1["cvt_up"], 12 + 9 + 3 + 3);
  EXPECT_EQ(w1["cvt_down"], 5);
  // w2: the cross products too; up: the three selected a - m_i (9), d (3), the edges (9), p2 - a (3)
  auto w2 = ops("sv-f0-o0-d0-a0-q0-i0-t0-p0-w2");
  EXPECT_EQ(w2["mul_w"], 39);
  EXPECT_EQ(w2.count("mul"), 0u);
  EXPECT_EQ(w2["add_w"], 10 + 12);
  EXPECT_EQ(w2["add"], 43 - 22);
  EXPECT_EQ(w2["cvt_up"], 9 + 3 + 9 + 3);
  EXPECT_EQ(w2["cvt_down"], 5);
  EXPECT_EQ(w2["div"], 3);
  // w3: every input up (17), every FP output down (t, beta, gamma, V, Va, V0, V1, V2), nothing narrow
  auto w3 = ops("sv-f0-o0-d0-a0-q0-i0-t0-p0-w3");
  EXPECT_EQ(w3["cvt_up"], 17);
  EXPECT_EQ(w3["cvt_down"], 8);
  EXPECT_EQ(w3["add_w"], 43);
  EXPECT_EQ(w3["div_w"], 3);
  for (const char* k : {"add", "mul", "div", "cmp"}) EXPECT_EQ(w3.count(k), 0u) << k;
  // Moller-Trumbore w1: four dot products (V, V1, V2, Va), down four
  auto mt1 = ops("mt-q1-i0-p0-w1");
  EXPECT_EQ(mt1["mul_w"], 12);
  EXPECT_EQ(mt1["cvt_down"], 4);
  // names, records, and the wide format required
  TriGenome g = fig36_genome();
  g.wide = 2;
  g.fuse = 1;
  EXPECT_EQ(genome_name(g), "sv-f0-o0-d0-a0-q0-i0-t0-p0-u1-w2");
  EXPECT_EQ(genes_record(g).size(), 11u);
  EXPECT_EQ(genome_name(parse_genome_name("sv-f0-o0-d0-a0-q0-i0-t0-p0-w2")), "sv-f0-o0-d0-a0-q0-i0-t0-p0-w2");
  EXPECT_EQ(genes_record(parse_genome_name("mt-q1-i0-p0-w3")).size(), 11u);
  for (const char* bad : {"sv-f0-o0-d0-a0-q0-i0-t0-p0-w0", "sv-f0-o0-d0-a0-q0-i0-t0-p0-w4", "mt-q1-i0-p0-w1-u1"})
    EXPECT_THROW(parse_genome_name(bad), IrError) << bad;
  try {
    tri_graph(parse_genome_name("mt-q1-i0-p0-w1"));
    ADD_FAILURE() << "a mixed genome without a wide format accepted";
  } catch (const IrError& e) {
    EXPECT_STREQ(e.what(), "genome mt-q1-i0-p0-w1: mixed precision needs the wide format (rayunits search tri --mixed)");
  }
}

// The fuse gene (fused multiply-adds): counted by hand from the dataflow, names of unfused genomes
// as before (and genomes written with nine genes read as unfused).
TEST(SearchGenome, FusedGenomesCountTheirFmasAndOldNamesStay) {
  auto ops = [](const std::string& name) { return tri_graph(parse_genome_name(name)).op_counts(); };
  // Fig. 3.6: 43 add/sub, 39 mul, 3 div; five dot products (V0, V1, V2, V, Va: 2 adds + 3 muls each,
  // fused 1 mul + 2 fmas) and four cross products (three edge volumes and the normal: 3 subs + 6 muls,
  // fused 3 muls + 3 fmas)
  auto f36 = ops("sv-f0-o0-d0-a0-q0-i0-t0-p0");
  EXPECT_EQ(f36["add"], 43);
  EXPECT_EQ(f36["mul"], 39);
  EXPECT_EQ(f36.count("fma"), 0u);
  auto u1 = ops("sv-f0-o0-d0-a0-q0-i0-t0-p0-u1"), u2 = ops("sv-f0-o0-d0-a0-q0-i0-t0-p0-u2");
  EXPECT_EQ(u1["add"], 43 - 10);
  EXPECT_EQ(u1["mul"], 39 - 10);
  EXPECT_EQ(u1["fma"], 10);
  EXPECT_EQ(u2["add"], 43 - 10 - 12);
  EXPECT_EQ(u2["mul"], 39 - 10 - 12);
  EXPECT_EQ(u2["fma"], 10 + 12);
  EXPECT_EQ(u2["div"], 3);
  // Moller-Trumbore: 24 add/sub, 27 mul; four dot products, two cross products
  auto mt2 = ops("mt-q1-i0-p0-u2");
  EXPECT_EQ(mt2["add"], 24 - 8 - 6);
  EXPECT_EQ(mt2["mul"], 27 - 8 - 6);
  EXPECT_EQ(mt2["fma"], 8 + 6);
  // names and records of unfused genomes are what they were before the gene
  TriGenome g = fig36_genome();
  EXPECT_EQ(genes_record(g).size(), 9u);
  g.fuse = 2;
  EXPECT_EQ(genome_name(g), "sv-f0-o0-d0-a0-q0-i0-t0-p0-u2");
  EXPECT_EQ(genes_record(g).size(), 10u);
  EXPECT_EQ(genome_name(tri_genome(genes_record(g))), genome_name(g));
  EXPECT_EQ(tri_genome(std::vector<int>(9, 0)).fuse, 0);
  EXPECT_THROW(tri_genome(std::vector<int>(8, 0)), IrError);
}

// A fused graph is a golden model like any other: evaluated in Soft at e8m23 / e11m52 it equals the
// same graph in float / double with std::fma, bit for bit; the comparison sees a fusion left out
// (the unfused graph in Soft against the fused one in native arithmetic).
template <class T>
size_t native_mismatches(const Graph& native, const Graph& soft, const Format& f,
                         const std::vector<ru::units::TriRecord>& recs) {
  ru::num::SoftScope scope(f);
  size_t bad = 0;
  for (const auto& r : recs) {
    const auto in = tri_inputs(r);
    std::vector<T> x;
    std::vector<ru::num::Soft> xs;
    for (double v : in) x.push_back(static_cast<T>(v)), xs.push_back(ru::num::Soft::from_double(static_cast<T>(v)));
    const auto a = evaluate<T>(native, x);
    const auto b = evaluate<ru::num::Soft>(soft, xs);
    bool same = true;
    for (const auto& [name, n] : native.outputs()) {
      const int m = soft.output_node(name);
      if (op_is_bool(native.nodes()[n].op)) {
        same &= a[n].b == b[m].b;
      } else {
        const double u = static_cast<double>(a[n].v), v = b[m].v.to_double();
        same &= (std::isnan(u) && std::isnan(v)) || std::memcmp(&u, &v, sizeof u) == 0;
      }
    }
    bad += !same;
  }
  return bad;
}

TEST(SearchGenome, FusedGraphsEqualNativeFmaBitForBit) {
  const auto recs = records(9, 400);
  for (const char* name : {"sv-f0-o0-d0-a0-q0-i0-t0-p0-u1", "sv-f0-o0-d0-a0-q0-i0-t1-p1-u2", "sv-f2-o1-d3-a3-q1-i1-t0-p2-u2",
                           "mt-q1-i0-p0-u2", "mt-q0-i1-p1-u1"}) {
    const Graph g = tri_graph(parse_genome_name(name));
    EXPECT_EQ(native_mismatches<float>(g, g, Format::parse("e8m23"), recs), 0u) << name;
    EXPECT_EQ(native_mismatches<double>(g, g, Format::parse("e11m52"), recs), 0u) << name;
  }
  // planted: the fusion left out on one side
  const Graph fused = tri_graph(parse_genome_name("sv-f0-o0-d0-a0-q0-i0-t0-p0-u2"));
  const Graph plain = tri_graph(parse_genome_name("sv-f0-o0-d0-a0-q0-i0-t0-p0"));
  EXPECT_GT(native_mismatches<float>(fused, plain, Format::parse("e8m23"), recs), 10u);
  EXPECT_GT(native_mismatches<double>(fused, plain, Format::parse("e11m52"), recs), 10u);
}

// Planted rows: each unit with a current rtl_hash, plus a stale row that would be the smallest.
struct Rows {
  ru::test::TempDir tmp{"ru_search_rows"};
  fs::path dir = tmp.p;
  std::string format;
  explicit Rows(std::string fmt = "e7m16") : format(std::move(fmt)) {}
  void add(const std::string& unit, int stages, double period, double area, bool current = true,
           const nlohmann::json& params = nullptr) {
    const auto& spec = ru::synth::find_unit(unit);
    const std::string hash =
        current ? ru::synth::sources_hash(ru::synth::resolve_sources(spec, ru::synth::default_rtl_dir())) : "0000";
    nlohmann::json j = {{"unit", unit},       {"top", "ru_" + unit},       {"flow", "osu018"},
                        {"stages", stages},   {"rtl_hash", hash},          {"format", format},
                        {"round", "rne"},     {"subnormals", true},        {"period_ps", period},
                        {"area_um2", area},   {"fmax_mhz", 1e6 / period},  {"target_clock_ps", period},
                        {"point", unit + "_s" + std::to_string(stages)}};
    if (!params.is_null()) j["params"] = params;
    std::ofstream(dir / "rows.jsonl", std::ios::app) << j.dump() << "\n";
  }
  // Units in the proportions the cell flow measures at e7m16 / 250 MHz (add 55, mul 102, div 217,
  // cmp 6 thousand um2), Stages small enough for a quick Verilator build.
  void realistic() {
    add("fp_add", 1, 3900, 54792);
    add("fp_mul", 1, 3800, 101980);
    add("fp_div", 2, 3980, 217448);
    add("fp_cmp", 0, 2490, 6335);
  }
  // For mixed precision e8m23 inside e7m16: the four kinds at e8m23 and ru_fp_cvt both ways (IntW 2).
  void wide_e8m23() {
    const std::string f = format;
    format = "e8m23";
    add("fp_add", 2, 3900, 80000);
    add("fp_mul", 3, 3950, 170000);
    add("fp_div", 4, 3990, 400000);
    add("fp_cmp", 0, 2800, 8000);
    add("fp_cvt", 0, 3000, 9000, true, {{"InExpW", 7}, {"InFracW", 16}, {"InSubnormals", 1}, {"IntW", 2}});
    format = "e7m16";
    add("fp_cvt", 1, 3500, 7000, true, {{"InExpW", 8}, {"InFracW", 23}, {"InSubnormals", 1}, {"IntW", 2}});
    format = f;
  }
};

TEST(SearchCost, PicksTheSmallestCurrentRowMeetingTheClockAndSchedules) {
  Rows r;
  r.add("fp_add", 1, 3000, 100);
  r.add("fp_add", 2, 1900, 120);
  r.add("fp_add", 3, 1500, 50, false);  // stale: never picked
  r.add("fp_mul", 2, 2000, 400);
  r.add("fp_mul", 4, 1000, 500);
  r.add("fp_div", 5, 2500, 900);  // nothing meets 2000 ps: the fastest is used
  r.add("fp_div", 3, 3500, 700);
  r.add("fp_cmp", 0, 800, 10);
  const auto& lib = ru::synth::cell_library("osu018");
  const Format f = Format::parse("e7m16");
  const CostModel m = CostModel::build({r.dir.string()}, lib, f, 2000);
  EXPECT_EQ(m.units().at("fp_add").stages, 2);
  EXPECT_EQ(m.units().at("fp_mul").stages, 2);
  EXPECT_EQ(m.units().at("fp_div").stages, 5);
  EXPECT_EQ(m.units().at("fp_cmp").stages, 0);
  // x*y + z: the mul (2 stages + its output register) is ready at cycle 3, the add (2 stages) at 6
  const Graph g = Graph::parse("in x\nin y\nin z\nmul 0 1\nadd 3 2\nout f 4\n");
  const CostBreakdown c = m.cost(g);
  const int W = 24;
  EXPECT_EQ(c.latency, 3 + 3);
  // registers: the two unit outputs, and z held from cycle 0 to the add's start at cycle 3
  EXPECT_EQ(c.reg_bits, 2 * W + 3 * W);
  EXPECT_DOUBLE_EQ(c.units_um2, 400 + 120);
  EXPECT_DOUBLE_EQ(c.area_um2, 520 + c.reg_bits * lib.area.at(lib.flop_cell));
  EXPECT_DOUBLE_EQ(c.period_ps, 2000);  // the slower of the two units
  // a division: the fastest fp_div (2500 ps) sets the design's period
  EXPECT_DOUBLE_EQ(m.cost(Graph::parse("in x\nin y\ndiv 0 1\nout q 2\n")).period_ps, 2500);
}

TEST(SearchCost, NoRowOfAUnitIsAOneLineError) {
  Rows r;
  r.add("fp_add", 1, 3000, 100);
  r.add("fp_mul", 1, 3000, 100, false);  // only stale
  try {
    CostModel::build({r.dir.string()}, ru::synth::cell_library("osu018"), Format::parse("e7m16"), 2000);
    FAIL() << "no error";
  } catch (const ru::synth::SynthError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos);
    EXPECT_NE(m.find("no current osu018 row of fp_"), std::string::npos) << m;
  }
}

// fp_fma joins the model only when asked (searches with fused moves); a fused graph without it is an
// error, with it each fma costs the fp_fma row (planted areas: by hand).
TEST(SearchCost, FmaRowsOnlyForFusedSearches) {
  Rows r;
  r.realistic();
  r.add("fp_fma", 1, 3950, 150000);
  const auto& lib = ru::synth::cell_library("osu018");
  const Format f = Format::parse("e7m16");
  const CostModel plain = CostModel::build({r.dir.string()}, lib, f, 4000);
  EXPECT_EQ(plain.units().count("fp_fma"), 0u);
  EXPECT_THROW(plain.cost(tri_graph(parse_genome_name("mt-q1-i0-p0-u1"))), IrError);
  const CostModel m = CostModel::build({r.dir.string()}, lib, f, 4000, "", {}, true);
  ASSERT_EQ(m.units().count("fp_fma"), 1u);
  EXPECT_EQ(m.units().at("fp_fma").stages, 1);
  const double base = m.cost(tri_graph(parse_genome_name("mt-q1-i0-p0"))).units_um2;
  const double u1 = m.cost(tri_graph(parse_genome_name("mt-q1-i0-p0-u1"))).units_um2;
  EXPECT_DOUBLE_EQ(u1 - base, 8 * (150000.0 - 54792 - 101980));  // 8 fmas for 8 adds and 8 muls
  Rows none;
  none.realistic();
  EXPECT_THROW(CostModel::build({none.dir.string()}, lib, f, 4000, "", {}, true), ru::synth::SynthError);
  // rows through the maximum useful Stages, none meeting the clock: the fastest is taken and the unit
  // is not characterized again (no synthesis, nothing appended to the measure file)
  Rows slow;
  slow.realistic();
  ru::synth::UnitConfig cfg;
  cfg.fmt = f;
  const int smax = ru::synth::find_unit("fp_fma").max_stages(cfg);
  slow.add("fp_fma", smax, 6460, 285874);
  slow.add("fp_fma", 3, 6969, 152907);
  const fs::path measure = slow.dir / "measured.jsonl";
  const CostModel s = CostModel::build({slow.dir.string()}, lib, f, 4000, measure.string(), {}, true);
  EXPECT_EQ(s.units().at("fp_fma").stages, smax);
  EXPECT_DOUBLE_EQ(s.cost(tri_graph(parse_genome_name("mt-q1-i0-p0-u1"))).period_ps, 6460);
  EXPECT_FALSE(fs::exists(measure));
}

Candidate planted(const std::string& genome, double area, double mean, double max, uint64_t leaks, uint64_t dbl) {
  Candidate c;
  c.genome = parse_genome_name(genome);
  c.key = genome;
  c.fit.cost.area_um2 = area;
  c.fit.mean_rel = mean;
  c.fit.max_rel = max;
  c.fit.leaks = leaks;
  c.fit.double_hits = dbl;
  return c;
}

TEST(SearchFront, ParetoAndEpsilonBoxes) {
  const std::vector<Candidate> all = {
      planted("sv-f0-o0-d0-a0-q0-i0-t0-p0", 100, 0.010, 1, 0, 50),  // front
      planted("sv-f0-o0-d0-a0-q0-i0-t0-p1", 101, 0.0099, 1, 0, 50),  // front, same 5 % box as the first
      planted("sv-f0-o0-d0-a0-q0-i0-t0-p2", 102, 0.011, 1, 0, 51),  // dominated by the first
      planted("sv-f0-o0-d0-a0-q0-i0-t1-p0", 120, 0.010, 1, 3, 5),  // front: fewer extras, more misses
      planted("mt-q1-i0-p0", 60, 0.02, 2, 10, 100),                 // front: smallest
  };
  std::vector<std::string> names;
  for (const auto& c : pareto_front(all)) names.push_back(c.key);
  EXPECT_EQ(names, (std::vector<std::string>{"mt-q1-i0-p0", "sv-f0-o0-d0-a0-q0-i0-t0-p0", "sv-f0-o0-d0-a0-q0-i0-t0-p1",
                                             "sv-f0-o0-d0-a0-q0-i0-t1-p0"}));
  names.clear();
  for (const auto& c : epsilon_front(pareto_front(all), 0.05)) names.push_back(c.key);
  EXPECT_EQ(names, (std::vector<std::string>{"mt-q1-i0-p0", "sv-f0-o0-d0-a0-q0-i0-t0-p0", "sv-f0-o0-d0-a0-q0-i0-t1-p0"}));
  EXPECT_EQ(epsilon_front(pareto_front(all), 1e-6).size(), 4u);  // tiny boxes: the whole front
  EXPECT_THROW(epsilon_front(all, 0), IrError);
}

// A small cost model with realistic unit proportions (planted rows).
// Mixed precision: the wide format's rows and ru_fp_cvt's both ways (their source format and IntW
// 2 as the emitter instantiates it), wide registers at the wide width.
TEST(SearchCost, MixedGraphsTakeTheWideRowsAndConversions) {
  Rows r;
  r.realistic();
  r.wide_e8m23();
  r.format = "e8m23";  // a faster, smaller row with another IntW: not the emitter's conversion
  r.add("fp_cvt", 0, 2000, 5000, true, {{"InExpW", 7}, {"InFracW", 16}, {"InSubnormals", 1}, {"IntW", 32}});
  const auto& lib = ru::synth::cell_library("osu018");
  const Format f = Format::parse("e7m16");
  const CostModel m = CostModel::build({r.dir.string()}, lib, f, 4000, "", {}, false, Format::parse("e8m23"));
  EXPECT_EQ(m.units().at("fp_mul@wide").area_um2, 170000);
  EXPECT_EQ(m.units().at("fp_mul").area_um2, 101980);
  EXPECT_EQ(m.units().at("fp_cvt@up").area_um2, 9000);  // not the IntW 32 row
  EXPECT_EQ(m.units().at("fp_cvt@down").stages, 1);
  EXPECT_EQ(m.to_json().at("wide_format"), "e8m23");
  // x*y in e8m23 from two e7m16 values: both up (Stages 0: ready at 1), the wide mul (3 + 1: ready
  // at 5), down (1 + 1: ready at 7); registers: two 32-bit conversions, the 32-bit product, the
  // 24-bit result
  const Graph g = Graph::parse("wide 1 7\nin x\nin y\ncvt 0\ncvt 1\nmul 2 3\ncvt 4\nout f 5\n");
  const CostBreakdown c = m.cost(g);
  EXPECT_EQ(c.latency, 7);
  EXPECT_EQ(c.reg_bits, 32 + 32 + 32 + 24);
  EXPECT_DOUBLE_EQ(c.units_um2, 2 * 9000 + 170000 + 7000);
  // without the wide rows a mixed graph is refused
  Rows plain;
  plain.realistic();
  const CostModel m0 = CostModel::build({plain.dir.string()}, lib, f, 4000);
  EXPECT_THROW(m0.cost(g), IrError);
  // a cost model asked for a wide format without its rows names what is missing
  try {
    CostModel::build({plain.dir.string()}, lib, f, 4000, "", {}, false, Format::parse("e8m23"));
    ADD_FAILURE() << "no e8m23 rows, accepted";
  } catch (const ru::synth::SynthError& e) {
    EXPECT_NE(std::string(e.what()).find("no current osu018 row of fp_add e8m23"), std::string::npos) << e.what();
  }
}

struct Fixture {
  Rows rows;
  CostModel cm;
  Workload w;
  Fixture() {
    rows.realistic();
    const Format f = Format::parse("e7m16");
    cm = CostModel::build({rows.dir.string()}, ru::synth::cell_library("osu018"), f, 4000);
    w = make_workload(records(3, 384), f, ru::units::builtin_mesh("icosphere"), 120, 3);
  }
};

// Two generations of eight from Fig. 3.6, seed 5, into out.
SearchOptions tiny_search(const fs::path& out) {
  SearchOptions o;
  o.start = fig36_genome();
  o.population = 8;
  o.seed = 5;
  o.generations = 2;
  o.threads = 2;
  o.out_dir = out.string();
  return o;
}

std::vector<std::string> front_names(const SearchResult& r) {
  std::vector<std::string> v;
  for (const auto& c : r.front) v.push_back(genome_name(c.genome) + "@" + c.key);
  return v;
}

using ru::test::slurp;

TEST(Search, SameSeedSameFrontWhateverTheThreadsOrAResume) {
  Fixture fx;
  const fs::path base = fs::temp_directory_path() / "ru-search-det";
  fs::remove_all(base);
  const nlohmann::json ctx = {{"test", 1}};
  SearchOptions o;
  o.start = start_genome("worst");
  o.population = 8;
  o.seed = 11;
  o.generations = 3;
  o.threads = 1;
  o.out_dir = (base / "a").string();
  const SearchResult a = run_search(o, fx.w, fx.cm, ctx);
  o.threads = 2;
  o.out_dir = (base / "b").string();
  o.generations = 1;
  run_search(o, fx.w, fx.cm, ctx);
  o.generations = 3;  // resumed: continues from generation 1
  const SearchResult b = run_search(o, fx.w, fx.cm, ctx);
  EXPECT_EQ(b.generations_run, 2);
  EXPECT_EQ(front_names(a), front_names(b));
  EXPECT_EQ(slurp(base / "a" / "state.json"), slurp(base / "b" / "state.json"));
  // a finished search reruns from its cache: nothing new evaluated, the same front
  const SearchResult c = run_search(o, fx.w, fx.cm, ctx);
  EXPECT_EQ(c.generations_run, 0);
  EXPECT_EQ(c.evaluations, 0u);
  EXPECT_EQ(front_names(c), front_names(a));
  // another seed in the same directory: refused, the state left as it was
  const std::string before = slurp(base / "b" / "state.json");
  o.seed = 12;
  EXPECT_THROW(run_search(o, fx.w, fx.cm, ctx), IrError);
  EXPECT_EQ(slurp(base / "b" / "state.json"), before);
  // another seed elsewhere: another search (the check above is not vacuous)
  o.out_dir = (base / "c").string();
  EXPECT_NE(slurp(base / "a" / "state.json"), (run_search(o, fx.w, fx.cm, ctx), slurp(base / "c" / "state.json")));
  fs::remove_all(base);
}

// Fused moves only when asked: without them every evaluated genome is unfused and state.json holds
// nine genes per design (the files of searches before the gene); with them the search visits fused
// genomes; a fused start without them is refused.
TEST(Search, FusedMovesOnlyWhenAsked) {
  Fixture fx;
  Rows rows;
  rows.realistic();
  rows.add("fp_fma", 1, 3950, 150000);
  const CostModel cm = CostModel::build({rows.dir.string()}, ru::synth::cell_library("osu018"), Format::parse("e7m16"),
                                        4000, "", {}, true);
  const fs::path base = fs::temp_directory_path() / "ru-search-fused";
  fs::remove_all(base);
  SearchOptions o = tiny_search(base / "plain");
  run_search(o, fx.w, cm, {{"test", 3}});
  auto fused_evaluated = [&](const fs::path& dir) {
    std::ifstream in(dir / "evaluations.jsonl");
    int n = 0;
    for (std::string line; std::getline(in, line);) n += line.find("-u") != std::string::npos;
    return n;
  };
  EXPECT_EQ(fused_evaluated(base / "plain"), 0);
  for (const auto& v : nlohmann::json::parse(slurp(base / "plain" / "state.json")).at("population"))
    EXPECT_EQ(v.size(), 9u);
  o.fused = true;
  o.out_dir = (base / "fused").string();
  run_search(o, fx.w, cm, {{"test", 3}});
  EXPECT_GT(fused_evaluated(base / "fused"), 0);
  o.fused = false;
  o.start.fuse = 1;
  o.out_dir = (base / "refused").string();
  EXPECT_THROW(run_search(o, fx.w, cm, {{"test", 3}}), IrError);
  fs::remove_all(base);
}

// Mixed moves only when asked; with them the wide gene moves and the fuse gene stays 0 (no --fused).
TEST(Search, MixedMovesOnlyWhenAsked) {
  Fixture fx;
  Rows rows;
  rows.realistic();
  rows.wide_e8m23();
  const CostModel cm = CostModel::build({rows.dir.string()}, ru::synth::cell_library("osu018"), Format::parse("e7m16"),
                                        4000, "", {}, false, Format::parse("e8m23"));
  const fs::path base = fs::temp_directory_path() / "ru-search-mixed";
  fs::remove_all(base);
  SearchOptions o = tiny_search(base / "mixed");
  o.wide_de = 1, o.wide_dm = 7;
  run_search(o, fx.w, cm, {{"test", 4}});
  int mixed = 0, fused = 0;
  {
    std::ifstream in(base / "mixed" / "evaluations.jsonl");
    for (std::string line; std::getline(in, line);)
      mixed += line.find("-w") != std::string::npos, fused += line.find("-u") != std::string::npos;
  }
  EXPECT_GT(mixed, 0);
  EXPECT_EQ(fused, 0);
  EXPECT_EQ(nlohmann::json::parse(slurp(base / "mixed" / "state.json")).at("settings").at("mixed"),
            nlohmann::json({1, 7}));
  // a mixed start without mixed moves is refused
  o.wide_de = o.wide_dm = 0;
  o.start.wide = 1;
  o.out_dir = (base / "refused").string();
  EXPECT_THROW(run_search(o, fx.w, cm, {{"test", 4}}), IrError);
  fs::remove_all(base);
}

// True when the front has a design within 5 % of the reference's area at no more mean and max
// error and no more misses or extras.
bool recovers(const std::vector<Candidate>& front, const Fitness& ref) {
  for (const auto& c : front)
    if (c.fit.cost.area_um2 <= 1.05 * ref.cost.area_um2 && c.fit.mean_rel <= ref.mean_rel &&
        c.fit.max_rel <= ref.max_rel && c.fit.misses() <= ref.misses() && c.fit.extras() <= ref.extras())
      return true;
  return false;
}

TEST(Search, FromAWorseStartFindsFig36OrBetter) {
  Fixture fx;
  const Fitness fig36 = evaluate_fitness(tri_graph(fig36_genome()), fx.w, fx.cm);
  const Fitness worst = evaluate_fitness(tri_graph(start_genome("worst")), fx.w, fx.cm);
  EXPECT_GT(worst.cost.area_um2, 1.05 * fig36.cost.area_um2);  // the start really is worse
  const fs::path dir = fs::temp_directory_path() / "ru-search-recover";
  fs::remove_all(dir);
  SearchOptions o;
  o.start = start_genome("worst");
  o.population = 16;
  o.seed = 1;
  o.threads = 2;
  o.out_dir = dir.string();
  o.generations = 0;  // the start population alone does not pass the check (it can fail)
  EXPECT_FALSE(recovers(run_search(o, fx.w, fx.cm, {{"test", 2}}).front, fig36));
  o.generations = 12;
  const SearchResult r = run_search(o, fx.w, fx.cm, {{"test", 2}});
  EXPECT_TRUE(recovers(r.front, fig36)) << "front of " << r.front.size();
  fs::remove_all(dir);
}

// ---- the command --------------------------------------------------------------------------

using ru::test::run_rayunits;

std::vector<std::string> small_search(const Rows& rows, const fs::path& out, const std::string& fmt) {
  return {"search", "tri", "--format", fmt, "--clock", "4ns", "--budget", "24", "--population", "8", "--records",
          "128", "--mesh-rays", "40", "--rows", rows.dir.string(), "--no-characterize", "--out", out.string(),
          "--epsilon", "10", "--quiet"};
}

TEST(SearchCli, WritesTheFrontAndRefusesBadInputInOneLine) {
  Rows rows;
  rows.realistic();
  ru::test::TempDir t("ru_search_cli");
  auto args = small_search(rows, t.p / "s", "e7m16");
  args.push_back("--no-verify");
  const auto r = run_rayunits(args, 300);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("references:"), std::string::npos) << r.out;
  for (const char* f : {"front.json", "front.csv", "pareto_all.csv", "state.json", "evaluations.jsonl"})
    EXPECT_TRUE(fs::exists(t.p / "s" / f)) << f;
  const auto doc = nlohmann::json::parse(slurp(t.p / "s" / "front.json"));
  ASSERT_GE(doc.at("front").size(), 1u);
  EXPECT_EQ(doc["front"][0].at("rtl"), "not verified");
  for (const auto& d : doc["front"]) EXPECT_TRUE(fs::exists(t.p / "s" / "designs" / (d.at("unit").get<std::string>().substr(3) + ".dp")));
  // bad input: one line on stderr, exit 2, no output directory made
  const std::vector<std::vector<std::string>> bad = {
      {"--start", "best"}, {"--population", "6"}, {"--epsilon", "0"}, {"--format", "e1m2"}, {"--clock", "fast"}};
  for (const auto& extra : bad) {
    auto a = small_search(rows, t.p / "bad", "e7m16");
    a.insert(a.end(), extra.begin(), extra.end());
    const auto b = run_rayunits(a, 120);
    EXPECT_EQ(b.code, 2) << extra[0] << ": " << b.err;
    EXPECT_EQ(std::count(b.err.begin(), b.err.end(), '\n'), 1) << b.err;
    EXPECT_FALSE(fs::exists(t.p / "bad")) << extra[0];
  }
  // no current row for a unit and no characterization: one line naming the unit
  Rows few;
  few.add("fp_add", 1, 3900, 54792);
  const auto n = run_rayunits(small_search(few, t.p / "few", "e7m16"), 120);
  EXPECT_NE(n.code, 0);
  EXPECT_NE(n.err.find("no current osu018 row of fp_"), std::string::npos) << n.err;
  EXPECT_FALSE(fs::exists(t.p / "few"));
}

// rayunits search box: all 16 ray-box designs evaluated, the front written with the hand designs as
// references; bad input is one line and leaves nothing behind.
TEST(SearchCli, BoxWritesTheFrontAndRefusesBadInputInOneLine) {
  Rows rows;
  rows.realistic();
  rows.add("fp_fma", 1, 3950, 150000);
  ru::test::TempDir t("ru_search_box");
  auto box = [&](const fs::path& out) {
    return std::vector<std::string>{"search", "box", "--format", "e7m16", "--clock", "4ns", "--records", "500",
                                    "--adversarial", "3000", "--rows", rows.dir.string(), "--no-characterize",
                                    "--out", out.string(), "--quiet", "--threads", "2"};
  };
  auto args = box(t.p / "b");
  args.push_back("--no-verify");
  const auto r = run_rayunits(args, 300);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("16 designs evaluated"), std::string::npos) << r.out;
  const auto doc = nlohmann::json::parse(slurp(t.p / "b" / "front.json"));
  EXPECT_EQ(doc.at("all").size(), 16u);
  ASSERT_GE(doc.at("front").size(), 1u);
  int hand = 0;
  for (const auto& d : doc["all"]) hand += !d.at("role").get<std::string>().empty();
  EXPECT_EQ(hand, 2);
  // the hand conservative design never misses; the plain one does on the adversarial rays
  for (const auto& d : doc["all"]) {
    if (d.at("design") == "box-r1-f0-m0") {
      EXPECT_EQ(d.at("fitness").at("false_misses"), 0);
    }
    if (d.at("design") == "box-r0-f0-m0") {
      EXPECT_GT(d.at("fitness").at("false_misses"), 0);
    }
  }
  for (const char* f : {"front.csv", "all.csv"}) EXPECT_TRUE(fs::exists(t.p / "b" / f)) << f;
  for (const auto& d : doc["front"])
    EXPECT_TRUE(fs::exists(t.p / "b" / "designs" / (d.at("unit").get<std::string>().substr(3) + ".dp")));
  const std::vector<std::vector<std::string>> bad = {{"--epsilon", "0"}, {"--format", "e1m2"}, {"--clock", "fast"},
                                                     {"--records", "0"}, {"--rows", "/no/such/dir"}};
  for (const auto& extra : bad) {
    auto a = box(t.p / "bad");
    a.insert(a.end(), extra.begin(), extra.end());
    const auto b = run_rayunits(a, 120);
    EXPECT_EQ(b.code, 2) << extra[0] << ": " << b.err;
    EXPECT_EQ(std::count(b.err.begin(), b.err.end(), '\n'), 1) << b.err;
    EXPECT_FALSE(fs::exists(t.p / "bad")) << extra[0];
  }
}

// A search as a sweep job (kind "search"): two seeds, two jobs, their reported designs and the
// references as typed rows of results.jsonl; a rerun skips both (the searches' state is in out/).
TEST(SearchCli, RunsAsSweepJobs) {
  Rows rows;
  rows.realistic();
  ru::test::TempDir t("ru_search_sweep");
  std::ofstream(t.p / "grid.toml") << "kind = \"search\"\nformat = \"e7m16\"\nclock = \"4ns\"\nbudget = 16\n"
                                      "population = 8\nrecords = 64\nmesh_rays = 20\nscene = \"icosphere\"\n"
                                      "no_characterize = true\nno_verify = true\nthreads = 1\nseed = [1, 2]\n"
                                      "rows = \"" << rows.dir.string() << "\"\n";
  const auto r = run_rayunits({"sweep", (t.p / "grid.toml").string(), "--out", (t.p / "sw").string(), "--jobs", "2"}, 600);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  std::ifstream in(t.p / "sw" / "results.jsonl");
  int jobs = 0;
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line);
    EXPECT_EQ(j.at("status"), "ok");
    bool fig36 = false;
    for (const auto& row : j.at("result")) fig36 |= row.at("role") == "reference:fig36";
    EXPECT_TRUE(fig36) << line;
    ++jobs;
  }
  EXPECT_EQ(jobs, 2);
  const auto again = run_rayunits({"sweep", (t.p / "grid.toml").string(), "--out", (t.p / "sw").string()}, 600);
  EXPECT_EQ(again.code, 0) << again.err;
}

// The reported designs are run-time registry units verified cycle by cycle (rayunits rtl); the
// same verification fails on a planted RTL error (one subtraction made an addition).
TEST(LongSearchCli, ReportedDesignsAreVerifiedAndAPlantedRtlErrorIsCaught) {
  Rows rows("e5m10");
  rows.realistic();
  ru::test::TempDir t("ru_search_verify");
  const auto r = run_rayunits(small_search(rows, t.p / "s", "e5m10"), 3000);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto doc = nlohmann::json::parse(slurp(t.p / "s" / "front.json"));
  ASSERT_GE(doc.at("front").size(), 1u);
  for (const auto& d : doc["front"]) EXPECT_EQ(d.at("rtl"), "pass") << d.at("genome");
  const std::string unit = doc["front"][0].at("unit");
  const fs::path sv = t.p / "s" / "rtl" / ("ru_" + unit + ".sv");
  std::string text = slurp(sv);
  const size_t at = text.find(".op_i(1'b1)");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 11, ".op_i(1'b0)");
  std::ofstream(sv) << text;
  ::setenv("RU_DP_DESIGNS", (t.p / "s" / "designs").c_str(), 1);
  const auto v = run_rayunits({"rtl", unit, "--format", "e5m10", "--stages", "max", "--rtl", (t.p / "s" / "rtl").string(),
                               "--vectors", "2000", "--quiet"},
                              1800);
  ::unsetenv("RU_DP_DESIGNS");
  EXPECT_EQ(v.code, 1) << v.out << v.err;
  EXPECT_NE(v.out.find("MISMATCH"), std::string::npos);
}

// The reported ray-box designs are verified cycle by cycle too; a planted error (one directed
// rounding of an emitted module made round-to-nearest) fails the same verification.
TEST(LongSearchCli, BoxDesignsAreVerifiedAndAPlantedRtlErrorIsCaught) {
  Rows rows("e5m10");
  rows.realistic();
  rows.add("fp_fma", 1, 3950, 150000);
  ru::test::TempDir t("ru_search_box_verify");
  const auto r = run_rayunits({"search", "box", "--format", "e5m10", "--clock", "4ns", "--records", "300", "--adversarial",
                               "300", "--rows", rows.dir.string(), "--no-characterize", "--epsilon", "1e-6", "--out",
                               (t.p / "b").string(), "--quiet"},
                              3000);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto doc = nlohmann::json::parse(slurp(t.p / "b" / "front.json"));
  std::string directed;
  for (const auto& d : doc.at("front")) {
    EXPECT_EQ(d.at("rtl"), "pass") << d.at("design");
    const std::string u = d.at("unit");
    if (directed.empty() && slurp(t.p / "b" / "rtl" / ("ru_" + u + ".sv")).find(".Round(2)") != std::string::npos) directed = u;
  }
  ASSERT_FALSE(directed.empty()) << "no reported design with a directed rounding";
  const fs::path sv = t.p / "b" / "rtl" / ("ru_" + directed + ".sv");
  std::string text = slurp(sv);
  text.replace(text.find(".Round(2)"), 9, ".Round(0)");
  std::ofstream(sv) << text;
  ::setenv("RU_DP_DESIGNS", (t.p / "b" / "designs").c_str(), 1);
  const auto v = run_rayunits({"rtl", directed, "--format", "e5m10", "--stages", "max", "--rtl", (t.p / "b" / "rtl").string(),
                               "--vectors", "5000", "--quiet"},
                              1800);
  ::unsetenv("RU_DP_DESIGNS");
  EXPECT_EQ(v.code, 1) << v.out << v.err;
  EXPECT_NE(v.out.find("MISMATCH"), std::string::npos);
}

// `rayunits gen` of a run-time design (issue 18 §3): without its emitted module in the RTL directory
// it is one error line naming the `dp emit` command (before, it wrote a directory with the wrapper
// and none of the unit's sources); with a copy of rtl/ holding the module (`rayunits dp emit`) the
// generated directory has the module, its FP units and the wrapper.
TEST(SearchCli, GenOfARunTimeDesignNeedsItsModuleAndSaysHow) {
  ru::test::TempDir t("ru_search_gen");
  const fs::path designs = t.p / "designs", rtl = t.p / "rtl";
  fs::create_directories(designs);
  fs::create_directories(rtl);
  const fs::path src = fs::path(RU_SOURCE_DIR) / "sweeps" / "results" / "search" / "tri_e7m16_250MHz" / "designs";
  fs::copy_file(src / "sv_f1_o0_d3_a1_q1_i0_t0_p0.dp", designs / "best.dp");
  ::setenv("RU_DP_DESIGNS", designs.c_str(), 1);
  const auto bad = run_rayunits({"gen", "dp_best", "--format", "e5m10", "--stages", "3", "--no-synth", "--out",
                                 (t.p / "g1").string()});
  EXPECT_EQ(bad.code, 2) << bad.out << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_NE(bad.err.find("rayunits dp emit"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(t.p / "g1"));
  for (const auto& e : fs::directory_iterator(fs::path(RU_SOURCE_DIR) / "rtl"))
    if (e.is_regular_file()) fs::copy_file(e.path(), rtl / e.path().filename());
  const auto em = run_rayunits({"dp", "emit", (designs / "best.dp").string(), "--module", "ru_dp_best", "--out",
                                rtl.string()});
  ASSERT_EQ(em.code, 0) << em.out << em.err;
  const auto ok = run_rayunits({"gen", "dp_best", "--format", "e5m10", "--stages", "3", "--no-synth", "--rtl",
                                rtl.string(), "--out", (t.p / "g2").string()});
  ::unsetenv("RU_DP_DESIGNS");
  ASSERT_EQ(ok.code, 0) << ok.out << ok.err;
  for (const char* f : {"ru_dp_best.sv", "ru_fp_div.sv", "ru_level_chain.svh", "ru_dp_best_e5m10_s3.sv"})
    EXPECT_TRUE(fs::exists(t.p / "g2" / f)) << f;
}

// `rayunits report --sections search` (issue 18 §3): every search directory's table comes from its
// files — a planted area of Fig. 3.6 in front.csv and a planted synthesis row appear in the report,
// and the cost model's error is computed from the two (7,777,777 against 7,000,000: +11.1 %); a
// directory without front.csv is not a search and is left out.
TEST(SearchReport, TablesAreReadFromTheResultFiles) {
  ru::test::TempDir t("ru_search_report");
  const fs::path src = fs::path(RU_SOURCE_DIR) / "sweeps" / "results" / "search" / "tri_e7m16_250MHz";
  const fs::path d = t.p / "planted";
  fs::create_directories(d);
  fs::create_directories(t.p / "not_a_search");
  for (const char* f : {"front.json", "pareto_all.csv"}) fs::copy_file(src / f, d / f);
  std::string csv = slurp((src / "front.csv").string());
  const std::string fig = "sv-f0-o0-d0-a0-q0-i0-t0-p0,8312570,";
  ASSERT_NE(csv.find(fig), std::string::npos) << "the checked-in front.csv changed: update this test";
  csv.replace(csv.find(fig), fig.size(), "sv-f0-o0-d0-a0-q0-i0-t0-p0,7777777,");
  std::ofstream(d / "front.csv") << csv;
  std::ofstream(d / "synth_dp_ray_tri_robust_s53.jsonl")
      << R"({"unit": "dp_ray_tri_robust", "stages": 53, "area_um2": 7000000.0, "fmax_mhz": 123.4, )"
      << R"("slack_ps": -4104.0, "target_clock_ps": 4000.0})" << "\n";
  const auto r = run_rayunits({"report", "--sections", "search", "--param", "search.dir=" + t.p.string(), "--out",
                               (t.p / "rep").string(), "--quiet"});
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const std::string md = slurp((t.p / "rep" / "search_planted.md").string());
  EXPECT_NE(md.find("| `sv-f0-o0-d0-a0-q0-i0-t0-p0` | hand: fig36 | 7,777,777 | 53 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| `sv-f0-o0-d0-a0-q0-i0-t0-p0` (hand: fig36) | 53 | 7,777,777 | 7,000,000 | +11.1 % |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| 123 MHz (-4104 ps at 4000 ps) |"), std::string::npos) << md;
  EXPECT_TRUE(fs::exists(t.p / "rep" / "search_planted.png"));
  const std::string index = slurp((t.p / "rep" / "index.md").string());
  EXPECT_NE(index.find("### planted"), std::string::npos);
  EXPECT_EQ(index.find("not_a_search"), std::string::npos);
}

// A ray-box search directory gets its own table: a planted area reaches the report.
TEST(SearchReport, BoxTablesAreReadFromTheResultFiles) {
  ru::test::TempDir t("ru_search_report_box");
  const fs::path src = fs::path(RU_SOURCE_DIR) / "sweeps" / "results" / "search" / "box_e7m16_250MHz";
  const fs::path d = t.p / "boxplanted";
  fs::create_directories(d);
  for (const char* f : {"front.json", "all.csv"}) fs::copy_file(src / f, d / f);
  std::string csv = slurp((src / "front.csv").string());
  const std::string row = "box-r1-f0-m0,1154161,";
  ASSERT_NE(csv.find(row), std::string::npos) << "the checked-in front.csv changed: update this test";
  csv.replace(csv.find(row), row.size(), "box-r1-f0-m0,7654321,");
  std::ofstream(d / "front.csv") << csv;
  const auto r = run_rayunits({"report", "--sections", "search", "--param", "search.dir=" + t.p.string(), "--out",
                               (t.p / "rep").string(), "--quiet"});
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const std::string md = slurp((t.p / "rep" / "search_boxplanted.md").string());
  EXPECT_NE(md.find("| `box-r1-f0-m0` | hand: ru_ray_box conservative | 7,654,321 | 13 |"), std::string::npos) << md;
  EXPECT_TRUE(fs::exists(t.p / "rep" / "search_boxplanted.png"));
}

}  // namespace
