// The report's cell-flow rows read from checked-in results (issue 17 §4): a planted row whose
// rtl_hash is the hash of the current RTL is read (its planted values and its file:line, command
// and commit appear in the report); the same row with a changed rtl_hash is not used (the point
// is synthesized now and the report says the row was stale); --live-synth ignores a current row;
// a malformed results file is one error line, nothing half-written. The report runs only the
// cell table of the synthesis section (synthesis.generic=0) for fp_cmp e5m10 Stages 0, so the
// live cases cost one small cell-flow run (a few seconds).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "../common/files.hpp"
#include "../common/run_rayunits.hpp"
#include "../common/temp_dir.hpp"
#include "rayunits/num/format.hpp"
#include "rayunits/synth/checked_in.hpp"
#include "rayunits/synth/units.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using ru::test::count_lines;
using ru::test::slurp;

// The current RTL hash and wrapper top of a unit configuration (default fp_cmp e5m10 Stages 0),
// computed by the library the report uses (not copied from a results file).
struct Point {
  std::string unit, format, top, hash;
  bool share = true;
  explicit Point(std::string un = "fp_cmp", std::string fm = "e5m10", int stages = 0)
      : unit(std::move(un)), format(std::move(fm)) {
    const auto& u = ru::synth::find_unit(unit);
    ru::synth::UnitConfig c;
    if (u.uses_format) c.fmt = ru::num::Format::parse(format);
    c.stages = stages;
    top = ru::synth::wrapper_name(u, c);
    hash = ru::synth::sources_hash(ru::synth::resolve_sources(u, ru::synth::default_rtl_dir()));
    share = u.synth_share;
  }
};

// One synthesis row of the cell flow with planted (implausible) values.
json planted_row(const Point& p, const std::string& hash, double clock_ps, double area, double fmax) {
  return {{"unit", p.unit},       {"top", p.top},           {"format", p.format},  {"stages", 0},
          {"flow", "osu018"},     {"target_clock_ps", clock_ps}, {"area_um2", area}, {"fmax_mhz", fmax},
          {"period_fo4", 4.25},   {"placement", "depth"},   {"resource_sharing", p.share},
          {"rtl_hash", hash}};
}

// A sweep results.jsonl with one job line holding both clocks' rows.
void write_results(const fs::path& dir, const Point& p, const std::string& hash) {
  fs::create_directories(dir);
  json job = {{"argv", {"rayunits", "synth", "fp_cmp", "--planted-command"}},
              {"deps", {{"tool", "rayunits 0.1 model plantedcommit0123"}}},
              {"error", ""},
              {"exit", 0},
              {"result", {planted_row(p, hash, 200, 12345, 777.7), planted_row(p, hash, 1000000, 54321, 55.5)}}};
  std::ofstream(dir / "results.jsonl") << job.dump() << "\n";
}

ru::test::CmdRun report(const fs::path& results, const fs::path& out, bool live = false) {
  std::vector<std::string> a = {"report",        "--sections", "synthesis",  "--no-plots", "--quiet",
                                "--param",       "synthesis.generic=0",      "--param",    "synthesis.units=fp_cmp",
                                "--param",       "synthesis.formats=e5m10",  "--param",    "synthesis.cell_stages=0",
                                "--checked-in",  results.string(),           "--out",      out.string()};
  if (live) a.push_back("--live-synth");
  return ru::test::run_rayunits(a, 300);
}

TEST(ReportCheckedIn, CurrentRowIsRead) {
  ru::test::TempDir t("ru_checked_in");
  const Point p;
  write_results(t.p / "res", p, p.hash);
  const auto r = report(t.p / "res", t.p / "rep");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string md = slurp(t.p / "rep" / "index.md");
  EXPECT_NE(md.find("| 12345 | 777.7 |"), std::string::npos) << md;  // the planted fastest row
  EXPECT_NE(md.find("| 54321 | 55.5 |"), std::string::npos) << md;   // the planted smallest row
  EXPECT_NE(md.find("read: " + (t.p / "res" / "results.jsonl").string() + ":1"), std::string::npos) << md;
  EXPECT_NE(md.find("plantedcommit0123"), std::string::npos) << md;
  EXPECT_NE(md.find("--planted-command"), std::string::npos) << md;
  EXPECT_NE(md.find("1 point(s) read from checked-in results, 0 measured now"), std::string::npos) << md;
  EXPECT_NE(slurp(t.p / "rep" / "synth_osu018.jsonl").find("\"report_source\":\"read: "), std::string::npos);
}

TEST(ReportCheckedIn, ChangedRtlHashIsNotUsed) {
  ru::test::TempDir t("ru_checked_in");
  const Point p;
  std::string other = p.hash;
  other.back() = other.back() == '0' ? '1' : '0';
  write_results(t.p / "res", p, other);
  const auto r = report(t.p / "res", t.p / "rep");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string md = slurp(t.p / "rep" / "index.md");
  EXPECT_EQ(md.find("12345"), std::string::npos) << md;
  EXPECT_EQ(md.find("54321"), std::string::npos) << md;
  EXPECT_NE(md.find("measured now (checked-in row stale)"), std::string::npos) << md;
  EXPECT_NE(md.find("has rtl_hash " + other + ", the current RTL " + p.hash), std::string::npos) << md;
  EXPECT_NE(md.find("0 point(s) read from checked-in results, 1 measured now"), std::string::npos) << md;
  // the live point ran as a job of the sweep engine (one engine for the report's loops)
  EXPECT_NE(slurp(t.p / "rep" / "synth_osu018_sweep" / "results.jsonl").find("\"status\":\"ok\""), std::string::npos);
}

TEST(ReportCheckedIn, LiveSynthIgnoresACurrentRow) {
  ru::test::TempDir t("ru_checked_in");
  const Point p;
  write_results(t.p / "res", p, p.hash);
  const auto r = report(t.p / "res", t.p / "rep", true);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string md = slurp(t.p / "rep" / "index.md");
  EXPECT_EQ(md.find("12345"), std::string::npos) << md;
  EXPECT_NE(md.find("measured now (--live-synth)"), std::string::npos) << md;
}

TEST(ReportCheckedIn, MalformedFileIsOneErrorLine) {
  ru::test::TempDir t("ru_checked_in");
  const Point p;
  struct Case {
    std::string second_line, must_contain;
  };
  json no_hash = planted_row(p, p.hash, 200, 1, 1);
  no_hash.erase("rtl_hash");
  for (const Case& c : {Case{"{\"argv\": [\"rayunits\"], \"result\": [", "results.jsonl:2: malformed results row: not JSON"},
                        Case{"[1, 2]", "results.jsonl:2: malformed results row: expected a JSON object"},
                        Case{no_hash.dump(), "results.jsonl:2: malformed results row: no \"rtl_hash\""}}) {
    write_results(t.p / "res", p, p.hash);
    std::ofstream(t.p / "res" / "results.jsonl", std::ios::app) << c.second_line << "\n";
    const auto r = report(t.p / "res", t.p / "rep");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("rayunits report: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.must_contain), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(t.p / "rep"));
  }
}

// One generic-flow row (NAND2-eq estimate) with a planted area.
json planted_generic(const Point& p, const std::string& hash, double nand2) {
  return {{"unit", p.unit},   {"top", p.top},   {"format", p.format}, {"stages", 0},
          {"flow", "generic"}, {"area_nand2", nand2}, {"reg_bits", 0}, {"depth", 7},
          {"stage_delay_ps", 1234.0}, {"resource_sharing", p.share}, {"rtl_hash", hash}};
}

// The intersection section's area table reads the ray units' relaxed (1 us) cell rows alone —
// the fastest mapping of a ray-triangle unit takes hours, so none is needed — and its ratio is
// computed from the rows read (planted values: 3000 / 2000 = 1.50).
TEST(ReportCheckedIn, RayUnitAreasReadTheRelaxedRowsOnly) {
  ru::test::TempDir t("ru_checked_in");
  fs::create_directories(t.p / "res");
  std::ofstream f(t.p / "res" / "rows.jsonl");
  const std::pair<const char*, double> units[] = {{"ray_box", 1000}, {"ray_tri_robust", 3000}, {"ray_tri_mt", 2000}};
  for (const auto& [u, area] : units) {
    const Point p(u, "e4m3");
    json row = planted_row(p, p.hash, 1000000, area, 1.5);
    row["command"] = std::string("planted ") + u;
    f << row.dump() << "\n";
  }
  f.close();
  const auto r = ru::test::run_rayunits(
      {"report", "--sections", "intersection", "--no-plots", "--quiet", "--param", "intersection.tri_pairs=64",
       "--param", "intersection.box_pairs=100", "--param", "intersection.rays=50", "--param",
       "intersection.watertight_formats=e5m10", "--param", "intersection.synth_formats=e4m3", "--checked-in",
       (t.p / "res").string(), "--out", (t.p / "rep").string()},
      300);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string md = slurp(t.p / "rep" / "index.md");
  EXPECT_NE(md.find("| e4m3 | 1000 | 3000 | 2000 | 1.50 |"), std::string::npos) << md;
  EXPECT_NE(md.find("3 point(s) read from checked-in results, 0 measured now"), std::string::npos) << md;
  EXPECT_NE(md.find("planted ray_tri_robust"), std::string::npos) << md;
  EXPECT_FALSE(fs::exists(t.p / "rep" / "ray_osu018_sweep"));  // nothing synthesized
  EXPECT_EQ(count_lines(slurp(t.p / "rep" / "ray_osu018.jsonl")), 3);
}

// The noise section's generic-gate table and its ratios come from generic-flow rows read like the
// cell rows: current ones are read (planted areas give the planted ratio), a stale one is
// measured now by the sweep engine (fp_add e8m23 --generic-only: seconds).
TEST(ReportCheckedIn, NoiseGenericRowsAreReadOrMeasured) {
  ru::test::TempDir t("ru_checked_in");
  fs::create_directories(t.p / "res");
  const Point noise("noise", ""), add("fp_add", "e8m23"), mul("fp_mul", "e8m23"), dot("fp_dot3", "e8m23");
  auto write = [&](bool stale_add) {
    std::ofstream f(t.p / "res" / "rows.jsonl");
    for (const Point* p : {&noise, &add, &mul, &dot}) {
      std::string h = p->hash;
      if (stale_add && p == &add) h.back() = h.back() == '0' ? '1' : '0';
      f << planted_row(*p, p->hash, 200, 100, 10).dump() << "\n" << planted_row(*p, p->hash, 1000000, 100, 5).dump() << "\n";
      f << planted_generic(*p, h, p == &noise ? 6000 : p == &add ? 1000 : p == &mul ? 2000 : 4000).dump() << "\n";
    }
  };
  auto run = [&](const char* out) {
    return ru::test::run_rayunits({"report", "--sections", "noise", "--no-plots", "--quiet", "--param", "noise.size=64",
                                   "--param", "noise.error_samples=2000", "--param", "noise.range_samples=20000",
                                   "--param", "noise.stages=0", "--checked-in", (t.p / "res").string(), "--out",
                                   (t.p / out).string()},
                                  300);
  };
  write(false);
  auto r = run("rep");
  ASSERT_EQ(r.code, 0) << r.err;
  std::string md = slurp(t.p / "rep" / "index.md");
  EXPECT_NE(md.find("noise / (fp_add + fp_mul) = 2.00"), std::string::npos) << md;  // 6000 / (1000 + 2000)
  EXPECT_NE(md.find("noise / e8m23 fp_dot3 = 1.50"), std::string::npos) << md;
  EXPECT_NE(md.find("8 point(s) read from checked-in results, 0 measured now"), std::string::npos) << md;
  EXPECT_FALSE(fs::exists(t.p / "rep" / "noise_osu018_sweep"));
  write(true);
  r = run("rep2");
  ASSERT_EQ(r.code, 0) << r.err;
  md = slurp(t.p / "rep2" / "index.md");
  EXPECT_EQ(md.find("noise / (fp_add + fp_mul) = 2.00"), std::string::npos) << md;  // fp_add measured now
  EXPECT_NE(md.find("7 point(s) read from checked-in results, 1 measured now"), std::string::npos) << md;
  EXPECT_NE(md.find("--generic-only"), std::string::npos) << md;
  const std::string res = slurp(t.p / "rep2" / "noise_osu018_sweep" / "results.jsonl");
  EXPECT_EQ(count_lines(res), 1) << res;
  EXPECT_NE(res.find("\"status\":\"ok\""), std::string::npos) << res;
  EXPECT_NE(res.find("\"flow\":\"generic\""), std::string::npos) << res;
}

// The repository's own checked-in results load (a malformed line there would stop every report).
TEST(ReportCheckedIn, RepositoryResultsLoad) {
  const std::string src = RU_SOURCE_DIR;
  const auto rows = ru::synth::CheckedInRows::load({src + "/sweeps/results/default", src + "/synth/results/cell"});
  EXPECT_GT(rows.rows().size(), 0u);
  EXPECT_EQ(rows.files().front(), src + "/sweeps/results/default/results.jsonl");
}

}  // namespace
