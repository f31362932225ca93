// The datapath IR's SystemVerilog emitter (rayunits/dp/emit.hpp): levels follow the FP depth,
// level kinds are the RTL's, and the emitted Fig. 3.6 and Moller-Trumbore modules are
// `verilator --lint-only -Wall` clean at Stages 0, in the middle and beyond the useful maximum
// (output registers), in two formats. (Simulation of the emitted modules under the scoreboard is
// not done yet: README, issue 18.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "../common/files.hpp"
#include "../common/run_rayunits.hpp"
#include "../common/temp_dir.hpp"
#include "rayunits/dp/emit.hpp"
#include "rayunits/dp/formulas.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/util/process.hpp"

namespace {

using namespace ru::dp;
namespace fs = std::filesystem;

// The level kinds of the hand-written units, read from their RTL (the `Kinds` localparams of
// rtl/ru_ray_tri_mt.sv and rtl/ru_ray_tri_robust.sv: ru_fp_pkg::K* tokens, highest level first).
std::vector<int> kinds_in(const std::string& text) {
  std::vector<int> v;
  const std::regex re(R"(ru_fp_pkg::K(Add|Mul|Div|Cmp))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it) {
    const std::string k = (*it)[1].str();
    v.insert(v.begin(), k == "Add" ? 0 : k == "Mul" ? 1 : k == "Div" ? 2 : 3);  // level 0 is the last token
  }
  return v;
}
std::string statement(const std::string& text, const std::string& head) {
  const size_t p = text.find(head);
  if (p == std::string::npos) return "";
  return text.substr(p, text.find(';', p) - p);
}

TEST(DpEmit, LevelKindsAreTheHandWrittenUnits) {
  const std::string rtl = std::string(RU_SOURCE_DIR) + "/rtl/";
  const std::string mt_text = ru::test::slurp(rtl + "ru_ray_tri_mt.sv"), rb_text = ru::test::slurp(rtl + "ru_ray_tri_robust.sv");
  const std::vector<int> mt = kinds_in(statement(mt_text, "localparam logic [4*ru_pipe_pkg::MaxLev-1:0] Kinds"));
  // robust: Kinds = (R != 0) ? {upper levels with OptRecip, KindsL0to5} : {upper levels, KindsL0to5}
  const std::vector<int> low = kinds_in(statement(rb_text, "localparam logic [31:0] KindsL0to5"));
  const std::string kinds = statement(rb_text, "localparam logic [4*ru_pipe_pkg::MaxLev-1:0] Kinds");
  const size_t q = kinds.find('?'), c = kinds.find(": {", q);  // the else branch (not a [23:0] slice)
  ASSERT_TRUE(q != std::string::npos && c != std::string::npos) << kinds;
  std::vector<int> robust = low, recip = low;
  for (int k : kinds_in(kinds.substr(c))) robust.push_back(k);
  for (int k : kinds_in(kinds.substr(q, c - q))) recip.push_back(k);
  ASSERT_EQ(mt.size(), 10u);  // the statements were found (NLev of each unit: DpIr.LevelsAreTheRtlLevelChains)
  ASSERT_EQ(robust.size(), 8u);
  EXPECT_EQ(levels(ray_tri_mt_graph()).kind, mt);
  EXPECT_EQ(levels(ray_tri_robust_graph()).kind, robust);
  EXPECT_EQ(levels(ray_tri_robust_graph(true)).kind, robust);
  EXPECT_EQ(levels(ray_tri_robust_graph(false, true)).kind, recip);
}

struct LintCase {
  const char* top;
  const char* genome;  // the design (rayunits search tri genome name)
  const char* fmt;  // -G overrides
  int stages;
};

void lint(const std::vector<LintCase>& cases) {
  if (ru::util::find_program("verilator").empty()) GTEST_SKIP() << "verilator not installed";
  ru::test::TempDir t("ru_dp_emit");
  const std::string rtl = std::string(RU_SOURCE_DIR) + "/rtl/";
  for (const LintCase& c : cases) {
    const std::string sv = (t.p / (std::string(c.top) + ".sv")).string();
    TriGenome genome = parse_genome_name(c.genome);
    genome.wide_de = 1, genome.wide_dm = 7;  // mixed-precision genomes (-w): e5m10 with e6m17 inside
    const Graph g = tri_graph(genome);
    std::ofstream(sv) << emit_sv(g, c.top);
    std::vector<std::string> argv = {"verilator", "--lint-only", "-Wall", "-I" + rtl, "--top-module", c.top};
    for (const auto& f : emit_sources(g)) argv.push_back(rtl + f);
    argv.push_back(sv);
    const std::string f = c.fmt;
    argv.push_back(f.substr(0, f.find(' ')));
    argv.push_back(f.substr(f.find(' ') + 1));
    argv.push_back("-GStages=" + std::to_string(c.stages));
    ru::util::ProcessOptions o;
    o.out = ru::util::Redirect::capture();
    o.err = ru::util::Redirect::capture();
    o.timeout_s = 300;
    const auto r = ru::util::run_process(argv, o);
    EXPECT_EQ(r.status(), 0) << c.top << " " << c.fmt << " Stages " << c.stages << ":\n" << r.err;
    EXPECT_EQ(r.err.find("%Warning"), std::string::npos) << r.err;
  }
}

constexpr const char* kMt = "mt-q1-i0-p0";                   // ray_tri_mt
constexpr const char* kRobust = "sv-f0-o0-d0-a0-q0-i0-t1-p0";  // ray_tri_robust_tie
constexpr const char* kFused = "sv-f0-o0-d0-a0-q0-i0-t1-p0-u2";  // the same with fused dot and cross products
constexpr const char* kMixed = "sv-f0-o0-d0-a0-q0-i0-t1-p0-w3";  // all of it in the wide format (cvt both ways)
constexpr const char* kMixedDots = "mt-q1-i0-p0-u1-w1";          // MT, fused dot products in the wide format

// fast: one format, Stages 0 (MT) and beyond the useful maximum (robust: output registers); the
// fused robust unit at Stages 0 and mid; the mixed-precision one (wide instances, ru_fp_cvt) mid
TEST(DpEmit, EmittedUnitsAreLintClean) {
  lint({{"ru_dp_mt", kMt, "-GExpW=5 -GFracW=10", 0},
        {"ru_dp_robust", kRobust, "-GExpW=5 -GFracW=10", 80},
        {"ru_dp_fused", kFused, "-GExpW=5 -GFracW=10", 0},
        {"ru_dp_fused", kFused, "-GExpW=5 -GFracW=10", 23},
        {"ru_dp_mixed", kMixed, "-GExpW=5 -GFracW=10", 9}});
}

// long: the three units, two formats, Stages 0, mid and beyond the maximum
TEST(LongDpEmit, EmittedUnitsAreLintClean) {
  std::vector<LintCase> cases;
  for (const char* genome : {kMt, kRobust, kFused, kMixed, kMixedDots})
    for (const char* fmt : {"-GExpW=5 -GFracW=10", "-GExpW=8 -GFracW=23"})
      for (int stages : {0, 9, 80}) cases.push_back({"ru_dp_unit", genome, fmt, stages});
  lint(cases);
}

// A mixed-precision unit (Fig. 3.6 with its dot products in e6m17 inside e5m10) as a run-time
// registry unit passes the cycle-by-cycle scoreboard (wide instances and ru_fp_cvt against the
// graph's Soft evaluation); the same unit with one down-conversion rounding toward zero fails it.
TEST(LongDpEmit, MixedUnitPassesTheScoreboardAndAPlantedRoundingIsCaught) {
  if (ru::util::find_program("verilator").empty()) GTEST_SKIP() << "verilator not installed";
  ru::test::TempDir t("ru_dp_mixed");
  const fs::path dd = t.p / "designs", rtl = t.p / "rtl";
  fs::create_directories(dd);
  fs::create_directories(rtl);
  for (const auto& e : fs::directory_iterator(std::string(RU_SOURCE_DIR) + "/rtl"))
    if (e.path().extension() == ".sv" || e.path().extension() == ".svh") fs::copy_file(e.path(), rtl / e.path().filename());
  TriGenome genome = parse_genome_name("sv-f0-o0-d0-a0-q0-i0-t1-p0-w1");
  genome.wide_de = 1, genome.wide_dm = 7;
  const Graph g = tri_graph(genome);
  std::string sv = emit_sv(g, "ru_dp_mixed");
  const std::string good = ".Subnormals(Subnormals), .Round(Round), .InExpW(WExpW)";  // a down-conversion
  const size_t at = sv.find(good);
  ASSERT_NE(at, std::string::npos);
  std::string planted = sv;
  planted.replace(at, good.size(), ".Subnormals(Subnormals), .Round(1), .InExpW(WExpW)");
  for (const char* name : {"mixed", "planted"}) {
    std::ofstream(dd / (std::string(name) + ".dp")) << g.print();
    std::string text = std::string(name) == "mixed" ? sv : planted;
    if (std::string(name) == "planted") text = std::regex_replace(text, std::regex("ru_dp_mixed\\b"), "ru_dp_planted");
    std::ofstream(rtl / ("ru_dp_" + std::string(name) + ".sv")) << text;
    std::ofstream(rtl / ("ru_dp_" + std::string(name) + ".f")) << emit_filelist("ru_dp_" + std::string(name), g);
  }
  ::setenv("RU_DP_DESIGNS", dd.c_str(), 1);
  auto rtl_run = [&](const std::string& unit) {
    return ru::test::run_rayunits({"rtl", unit, "--format", "e5m10", "--stages", "max", "--rtl", rtl.string(),
                                   "--vectors", "4000"},
                                  3600);
  };
  const auto ok = rtl_run("dp_mixed");
  const auto bad = rtl_run("dp_planted");
  ::unsetenv("RU_DP_DESIGNS");
  EXPECT_EQ(ok.code, 0) << ok.out << ok.err;
  EXPECT_EQ(bad.code, 1) << bad.out << bad.err;
  EXPECT_NE(bad.out.find("MISMATCH"), std::string::npos) << bad.out;
}

// The registry's dp_* units are the emitter's output, checked in (regenerate: rayunits dp emit
// <design> --out rtl). A stale file (e.g. after an emitter change) fails here.
TEST(DpRtl, CheckedInModulesAreTheEmitterOutput) {
  int n = 0;
  for (const auto& u : ru::synth::units()) {
    if (u.name.rfind("dp_", 0) != 0) continue;
    const std::string design = u.name.substr(3), rtl = std::string(RU_SOURCE_DIR) + "/rtl/";
    EXPECT_EQ(ru::test::slurp(rtl + u.top + ".sv"), emit_sv(find_design(design).make(), u.top, find_design(design).origin()))
        << "rtl/" << u.top << ".sv is stale: rayunits dp emit " << design << " --out rtl";
    EXPECT_EQ(ru::test::slurp(rtl + u.top + ".f"), emit_filelist(u.top, find_design(design).make()));
    ++n;
  }
  EXPECT_EQ(n, 2);
}

// Each named design's genome name (written into its module's origin line, read by
// scripts/search_table.py to find the design among a search's rows) is the same graph.
TEST(DpRtl, NamedDesignsAreTheirGenomes) {
  for (const auto& d : designs()) {
    EXPECT_EQ(tri_graph(parse_genome_name(d.genome)).print(), d.make().print()) << d.name << " vs " << d.genome;
    EXPECT_NE(emit_sv(d.make(), "m", d.origin()).find("\n// origin: design " + d.name + " = genome " + d.genome + "\n"),
              std::string::npos);
  }
}

// dp::max_stages_expr (the registry's max Stages of any emitted graph, run-time designs included)
// counts each level kind's pipeline segments; the RTL computes MaxUsefulStages from the same level
// kinds with ru_pipe_pkg / ru_fp_pkg. The two built-in dp units alone cannot pin down four
// per-kind counts, so here one graph per kind and a mixed one, each emitted and elaborated by
// Verilator at two formats (check_against_rtl: MaxUsefulStages equal, no output register at the
// maximum, exactly one beyond it). A planted wrong expression is caught.
TEST(DpEmit, MaxStagesOfEveryLevelKindIsTheRtls) {
  if (ru::util::find_program("verilator").empty()) GTEST_SKIP() << "verilator not installed";
  ru::test::TempDir t("ru_dp_maxst");
  const std::string rtl = std::string(RU_SOURCE_DIR) + "/rtl/";
  for (const auto& e : std::filesystem::directory_iterator(rtl))  // the project's RTL, includes too
    if (e.is_regular_file()) std::filesystem::copy_file(e.path(), t.p / e.path().filename());
  const Graph tri = ray_tri_mt_graph();  // the inputs a dp unit has (ax .. tmax)
  std::map<std::string, int> id;  // input name -> node (the same in every graph: created first, in order)
  auto with_inputs = [&] {
    Graph g;
    for (const auto& i : tri.inputs()) id[i] = g.input(i);
    return g;
  };
  auto in = [&](const Graph&, const char* name) { return id.at(name); };
  struct Case {
    const char* name;
    Graph g;
  };
  std::vector<Case> cases;
  {
    Graph g = with_inputs();
    g.output("r", g.add(g.add(in(g, "ax"), in(g, "ay")), in(g, "az")));
    cases.push_back({"add2", g});
  }
  {
    Graph g = with_inputs();
    g.output("r", g.mul(in(g, "ax"), in(g, "ay")));
    cases.push_back({"mul1", g});
  }
  {
    Graph g = with_inputs();
    g.output("r", g.div(in(g, "ax"), in(g, "ay")));
    cases.push_back({"div1", g});
  }
  {
    Graph g = with_inputs();
    g.output("r", g.lt(in(g, "ax"), in(g, "ay")));
    cases.push_back({"cmp1", g});
  }
  {
    Graph g = with_inputs();
    const int p = g.mul(in(g, "ax"), in(g, "ay"));
    g.output("r", g.lt(g.div(g.sub(p, in(g, "az")), in(g, "dx")), in(g, "tmax")));
    cases.push_back({"mixed", g});
  }
  {  // an fma level (weighed as a multiplier level), and one shared by an fma and a multiplier
    Graph g = with_inputs();
    g.output("r", g.fma(in(g, "ax"), in(g, "ay"), in(g, "az")));
    cases.push_back({"fma1", g});
  }
  {
    Graph g = with_inputs();
    const int f = g.fma(in(g, "ax"), in(g, "ay"), g.neg(in(g, "az")));
    const int m = g.mul(in(g, "dx"), in(g, "dy"));
    g.output("r", g.fma(f, m, in(g, "dz")));
    g.output("s", m);
    cases.push_back({"fma_mul", g});
  }
  const ru::synth::UnitSpec base = ru::synth::find_unit("dp_ray_tri_mt");
  std::vector<ru::synth::UnitConfig> cfgs;
  for (const char* f : {"e5m10", "e8m23"}) cfgs.push_back(ru::synth::UnitConfig{ru::num::Format::parse(f), 0, {}, {}});
  for (const Case& c : cases) {
    ru::synth::UnitSpec u = base;
    u.name = std::string("dp_k_") + c.name;
    u.top = "ru_dp_k_" + std::string(c.name);
    u.filelist = u.top + ".f";
    u.max_stages_expr = max_stages_expr(c.g);
    std::ofstream(t.p / (u.top + ".sv")) << emit_sv(c.g, u.top);
    std::ofstream(t.p / u.filelist) << emit_filelist(u.top, c.g);
    const auto bad = ru::synth::check_against_rtl(u, cfgs, t.p.string());
    EXPECT_TRUE(bad.empty()) << c.name << " (" << u.max_stages_expr << "): " << (bad.empty() ? "" : bad.front());
    if (std::string(c.name) == "mixed") {  // planted: one segment too many or too few
      for (const char* d : {"+1", "-1"}) {
        u.max_stages_expr = "(" + max_stages_expr(c.g) + ")" + d;
        EXPECT_FALSE(ru::synth::check_against_rtl(u, {cfgs.front()}, t.p.string()).empty()) << d;
      }
    }
  }
}

TEST(DpEmit, UnsupportedGraphsAreOneLineErrors) {
  Graph h;
  const int a = h.input("a");
  h.output("y", h.mul(a, h.constant(3.0)));
  EXPECT_THROW(emit_sv(h, "m"), IrError);  // 3 is not 0 or +-2^k
  Graph k;
  k.output("y", k.input("a"));
  EXPECT_THROW(emit_sv(k, "m"), IrError);  // no FP operation
  Graph c;
  int v = c.input("a");
  for (int i = 0; i < 17; ++i) v = c.add(v, v);
  c.output("y", v);
  EXPECT_THROW(emit_sv(c, "m"), IrError);  // 17 levels > the chain's 16
}

}  // namespace
