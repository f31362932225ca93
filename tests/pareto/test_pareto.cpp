// Tests of `rayunits pareto` (rayunits/pareto/pareto.hpp): the fronts against the definition of
// dominance checked point by point (and a planted wrong flag caught by that check), a hand-worked
// example, axis aliases and directions, the derived unit roundoff, targets and the cheapest pick,
// the profile plan, the loaders (CSV, JSON Lines, JSON, sweep directory) and bad input through
// the command (one line, exit 2, nothing written).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "../common/run_rayunits.hpp"
#include "../common/temp_dir.hpp"
#include "rayunits/pareto/pareto.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/csv.hpp"
#include "rayunits/util/process.hpp"

namespace {

namespace fs = std::filesystem;
using namespace ru::pareto;
using nlohmann::json;

Row row(json j) { return flatten(j); }

// Independent of compute(): p dominates q when p is no worse on every axis and better on one.
bool dominates(const std::vector<double>& p, const std::vector<double>& q, const std::vector<Axis>& axes) {
  bool strictly = false;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const double a = axes[k].minimize ? p[k] : -p[k], b = axes[k].minimize ? q[k] : -q[k];
    if (a > b) return false;
    strictly = strictly || a < b;
  }
  return strictly;
}

// "" when every point's flag agrees with the definition, else what is wrong.
std::string check_front(const Result& r) {
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const auto& p = r.points[i];
    bool any = false;
    for (std::size_t j = 0; j < r.points.size(); ++j)
      if (r.points[j].group == p.group && dominates(r.points[j].v, p.v, r.axes)) any = true;
    if (any != p.dominated) return "point " + std::to_string(i) + " flag " + std::to_string(p.dominated);
    if (p.dominated && (r.points[p.dominated_by].group != p.group ||
                        !dominates(r.points[p.dominated_by].v, p.v, r.axes)))
      return "point " + std::to_string(i) + " dominated_by does not dominate it";
  }
  return "";
}

TEST(Pareto, RandomFrontsAgreeWithTheDefinitionAndAPlantedFlagIsCaught) {
  std::mt19937_64 g(7);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Row> rows;
    std::uniform_int_distribution<int> small(0, 6);  // few values: many ties
    for (int i = 0; i < 60; ++i)
      rows.push_back(row({{"unit", trial % 2 ? "u1" : (i % 2 ? "a" : "b")},
                          {"e", small(g)}, {"area_um2", small(g) * 10.0}, {"fmax_mhz", 100.0 + small(g)}}));
    Options o;
    o.axes = {parse_axis("e"), parse_axis("area"), parse_axis("fmax")};
    Result r = compute(rows, o);
    ASSERT_EQ(r.points.size(), 60u);
    ASSERT_EQ(check_front(r), "") << "trial " << trial;
    // planted: flip one flag; the check must see it
    r.points[trial % 60].dominated = !r.points[trial % 60].dominated;
    EXPECT_NE(check_front(r), "") << "trial " << trial;
  }
}

TEST(Pareto, HandWorkedExample) {
  // minimize error and area, maximize fmax:
  //   A (1, 10, 100)  front
  //   B (1, 12, 100)  dominated by A (more area, nothing better)
  //   C (2,  5, 100)  front (least area)
  //   D (1, 10,  90)  dominated by A (slower)
  //   E (3, 20, 300)  front (fastest)
  //   F (1, 10, 100)  equal to A: neither dominates the other -> front
  std::vector<Row> rows;
  const char* names = "ABCDEF";
  const double v[6][3] = {{1, 10, 100}, {1, 12, 100}, {2, 5, 100}, {1, 10, 90}, {3, 20, 300}, {1, 10, 100}};
  for (int i = 0; i < 6; ++i)
    rows.push_back(row({{"name", std::string(1, names[i])}, {"err", v[i][0]}, {"area_um2", v[i][1]},
                        {"fmax_mhz", v[i][2]}}));
  Options o;
  o.axes = {parse_axis("err"), parse_axis("area"), parse_axis("fmax")};
  o.label = {"name"};
  const Result r = compute(rows, o);
  ASSERT_EQ(r.groups.size(), 1u);
  EXPECT_EQ(r.groups[0].name, "all");
  EXPECT_EQ(r.groups[0].fields, (std::vector<std::string>{"err", "area_um2", "fmax_mhz"}));
  std::string front;
  for (const auto& p : r.points)
    if (!p.dominated) front += p.label;
  EXPECT_EQ(front, "ACEF");
  EXPECT_EQ(r.points[1].dominated_by, 0u);  // B by A
  EXPECT_EQ(r.groups[0].front, 4u);
  // 2-D (err, area): E (3, 20) is dominated by A now
  o.axes.pop_back();
  const Result r2 = compute(rows, o);
  front.clear();
  for (const auto& p : r2.points)
    if (!p.dominated) front += p.label;
  EXPECT_EQ(front, "ACDF");  // D (1, 10) ties A on both axes
}

TEST(Pareto, AxisDirectionsAliasesAndErrors) {
  EXPECT_TRUE(parse_axis("area_um2").minimize);
  EXPECT_TRUE(parse_axis("error_pct").minimize);
  EXPECT_FALSE(parse_axis("fmax_mhz").minimize);
  EXPECT_FALSE(parse_axis("rays_per_s").minimize);
  EXPECT_FALSE(parse_axis("psnr_db").minimize);
  EXPECT_TRUE(parse_axis("psnr_db:min").minimize);
  EXPECT_FALSE(parse_axis("area:max").minimize);
  EXPECT_THROW(parse_axis("area:up"), ParetoError);
  EXPECT_THROW(parse_axis(":min"), ParetoError);
  // `area` takes the first candidate every row of the group has: area_um2 here, although
  // one row also has area_nand2
  std::vector<Row> rows = {row({{"area_um2", 5.0}, {"area_nand2", 1.0}, {"x", 1}}), row({{"area_um2", 3.0}, {"x", 2}})};
  Options o;
  o.axes = {parse_axis("x"), parse_axis("area")};
  EXPECT_EQ(compute(rows, o).groups[0].fields[1], "area_um2");
  o.axes = {parse_axis("x"), parse_axis("nosuch")};
  try {
    compute(rows, o);
    FAIL();
  } catch (const ParetoError& e) {
    EXPECT_NE(std::string(e.what()).find("'nosuch'"), std::string::npos) << e.what();
  }
  // a group without the field is left out and named; the others keep their fronts
  std::vector<Row> mixed = {row({{"unit", "fp_add"}, {"format", "e5m10"}, {"area_um2", 1.0}}),
                            row({{"unit", "noise"}, {"area_um2", 2.0}})};
  for (auto& r : mixed) derive(r);
  o.axes = {parse_axis("error"), parse_axis("area")};
  const Result r = compute(mixed, o);
  ASSERT_EQ(r.groups.size(), 1u);
  EXPECT_EQ(r.groups[0].name, "fp_add");
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_NE(r.skipped[0].find("'noise'"), std::string::npos) << r.skipped[0];
}

TEST(Pareto, UnitRoundoffFollowsTheFormatAndRounding) {
  Row a = row({{"format", "e5m10"}});
  derive(a);
  EXPECT_EQ(a["exp_bits"], 5);
  EXPECT_EQ(a["frac_bits"], 10);
  EXPECT_EQ(a["unit_roundoff"].get<double>(), std::ldexp(1.0, -11));
  Row b = row({{"format", "e8m23"}, {"round", "rtz"}});
  derive(b);
  EXPECT_EQ(b["unit_roundoff"].get<double>(), std::ldexp(1.0, -23));
  Row c = row({{"format", "double"}});
  derive(c);
  EXPECT_FALSE(c.contains("unit_roundoff"));
}

TEST(Pareto, TargetsAndTheCheapestPick) {
  EXPECT_THROW(parse_target("psnr"), ParetoError);
  EXPECT_THROW(parse_target("psnr>=x"), ParetoError);
  EXPECT_THROW(parse_target(">=3"), ParetoError);
  const Target t = parse_target("psnr_db>=40");
  EXPECT_TRUE(t.met(40));
  EXPECT_FALSE(t.met(39.9));
  EXPECT_DOUBLE_EQ(t.margin(41.5), 1.5);
  const Target u = parse_target("error_pct<0.1");
  EXPECT_FALSE(u.met(0.1));
  EXPECT_DOUBLE_EQ(u.margin(0.04), 0.06);
  std::vector<Row> rows;
  const double psnr[] = {30, 41, 45, 60}, area[] = {100, 110, 105, 200};
  for (int i = 0; i < 4; ++i)
    rows.push_back(row({{"format", "f" + std::to_string(i)}, {"psnr_db", psnr[i]}, {"area_mm2", area[i]},
                        {"rays_per_s", 1e6}}));
  Options o;
  o.axes = {parse_axis("psnr_db"), parse_axis("area"), parse_axis("fmax")};
  const Result r = compute(rows, o);
  auto picks = cheapest(r, rows, {t});
  ASSERT_EQ(picks.size(), 1u);
  ASSERT_TRUE(picks[0].point.has_value());
  EXPECT_EQ(r.points[*picks[0].point].label, "f2");  // 105 < 110, both meet 40 dB
  EXPECT_DOUBLE_EQ(picks[0].margin, 5);
  picks = cheapest(r, rows, {parse_target("psnr_db>=70")});
  EXPECT_FALSE(picks[0].point.has_value());
  EXPECT_EQ(picks[0].candidates, 4u);
}

TEST(Pareto, ProfilePlanPicksTheCheapestToleratedFormatWithEveryUnit) {
  const json prof = {{"scene", "s"},
                     {"units", {"fp_add", "ray_box"}},
                     {"target", {{"max_error_fraction", 0.001}, {"min_psnr", 40}}},
                     {"recommended_exp_bits", 6},
                     {"fraction_widths",
                      {{{"frac_bits", 10}, {"errors", 50}, {"pixels", 1000}, {"psnr", 30.0}, {"meets", false}},
                       {{"frac_bits", 12}, {"errors", 0}, {"pixels", 1000}, {"psnr", 47.0}, {"meets", true}},
                       {{"frac_bits", 14}, {"errors", 0}, {"pixels", 1000}, {"psnr", 57.0}, {"meets", true}}}}};
  std::vector<Row> rows;
  auto add = [&](const char* u, const char* f, double a, int s, double fm) {
    Row r = row({{"unit", u}, {"format", f}, {"area_um2", a}, {"stages", s}, {"fmax_mhz", fm}});
    derive(r);
    rows.push_back(r);
  };
  add("fp_add", "e6m10", 10, 0, 100);
  add("ray_box", "e6m10", 20, 0, 100);
  add("fp_add", "e6m12", 12, 0, 100);
  add("fp_add", "e6m12", 30, 3, 300);
  add("ray_box", "e6m12", 25, 0, 90);
  add("fp_add", "e6m14", 14, 0, 100);  // no ray_box row at e6m14
  const ProfilePlan p = plan_from_profile(prof, rows, parse_axis("area"), {});
  ASSERT_EQ(p.formats.size(), 3u);
  ASSERT_TRUE(p.pick.has_value());
  EXPECT_EQ(p.formats[*p.pick].format, "e6m12");
  EXPECT_DOUBLE_EQ(p.formats[*p.pick].cost, 12 + 25);
  EXPECT_EQ(p.formats[2].missing, (std::vector<std::string>{"ray_box"}));
  EXPECT_FALSE(p.formats[0].meets);
  // a per-unit condition: fmax >= 95 rules out the e6m12 ray_box row -> nothing is complete
  const ProfilePlan q = plan_from_profile(prof, rows, parse_axis("area"), {parse_target("fmax_mhz>=95")});
  EXPECT_FALSE(q.pick.has_value());
  EXPECT_EQ(q.formats[1].missing, (std::vector<std::string>{"ray_box"}));
  // with it, the faster fp_add row is taken at e6m12 only if it is the cheapest meeting it
  EXPECT_EQ(q.formats[1].unit_rows.at(0).second, 2u);
  EXPECT_THROW(plan_from_profile(json{{"scene", "s"}}, rows, parse_axis("area"), {}), ParetoError);
}

struct Tmp : ru::test::TempDir {
  Tmp() : TempDir("ru-pareto") {}
};

void spit(const fs::path& p, const std::string& s) { ru::synth::write_file_atomic(p.string(), s); }

TEST(Pareto, LoadersReadEveryInputKind) {
  Tmp t;
  spit(t.p / "a.csv", "# a comment line\nformat,area_mm2,psnr_db,note\ne5m10,310.7,32.77,\"x, y\"\n");
  auto rows = load_rows((t.p / "a.csv").string());
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_DOUBLE_EQ(rows[0]["area_mm2"].get<double>(), 310.7);
  EXPECT_EQ(rows[0]["note"], "x, y");
  EXPECT_EQ(rows[0]["frac_bits"], 10);  // derived
  spit(t.p / "b.jsonl", "{\"unit\":\"fp_add\",\"critical_path\":{\"cells\":82},\"area_um2\":5}\n\n");
  rows = load_rows((t.p / "b.jsonl").string());
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0]["critical_path.cells"], 82);
  spit(t.p / "c.json", "{\"rows\":[{\"a\":1},{\"a\":2}]}");
  EXPECT_EQ(load_rows((t.p / "c.json").string()).size(), 2u);
  // a sweep directory: ok jobs' params merged with each result row; failed jobs left out
  fs::create_directories(t.p / "sw");
  spit(t.p / "sw" / "results.jsonl",
       "{\"hash\":\"h1\",\"kind\":\"synth\",\"status\":\"ok\",\"params\":{\"unit\":\"fp_add\",\"stages\":1},"
       "\"result\":[{\"area_um2\":7,\"target_clock_ps\":900},{\"area_um2\":6,\"target_clock_ps\":1000}]}\n"
       "{\"hash\":\"h2\",\"kind\":\"synth\",\"status\":\"failed\",\"params\":{\"unit\":\"fp_mul\"},\"result\":[]}\n");
  rows = load_rows((t.p / "sw").string());
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1]["unit"], "fp_add");
  EXPECT_EQ(rows[1]["stages"], 1);
  EXPECT_EQ(rows[1]["target_clock_ps"], 1000);
  // bad inputs: one line naming the file
  spit(t.p / "bad.csv", "a,b\n1\n");
  EXPECT_THROW(load_rows((t.p / "bad.csv").string()), ParetoError);
  spit(t.p / "bad.jsonl", "{\"a\":1}\nnot json\n");
  try {
    load_rows((t.p / "bad.jsonl").string());
    FAIL();
  } catch (const ParetoError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_rows((t.p / "nosuch.csv").string()), ParetoError);
  EXPECT_THROW(load_rows((t.p / "a.txt").string()), ParetoError);
  fs::create_directories(t.p / "empty");
  EXPECT_THROW(load_rows((t.p / "empty").string()), ParetoError);
  EXPECT_THROW(expand_inputs({(t.p / "*.nomatch").string()}), ParetoError);
  EXPECT_EQ(expand_inputs({(t.p / "*.json*").string()}).size(), 3u);  // b.jsonl c.json bad.jsonl
}

// `rayunits pareto ARGS...`
ru::test::CmdRun rayunits(const std::vector<std::string>& args) {
  std::vector<std::string> a = {"pareto"};
  a.insert(a.end(), args.begin(), args.end());
  return ru::test::run_rayunits(a, 300);
}

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(Pareto, CommandOnTheCheckedInChipTableAndBadInput) {
  const std::string chip = std::string(RU_SOURCE_DIR) + "/docs/trax/trax_formats.csv";
  Tmp t;
  const auto out = (t.p / "o").string();
  ru::test::CmdRun r = rayunits({chip, "--x", "psnr_db", "--y", "area_mm2", "--z", "rays_per_s", "--target", "psnr_db>=40",
                    "--out", out, "--no-plot"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("points on the front"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cheapest meeting psnr_db>=40"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(t.p / "o" / "pareto.csv"));
  EXPECT_TRUE(fs::exists(t.p / "o" / "pareto.md"));
  EXPECT_FALSE(fs::exists(t.p / "o" / "pareto.png"));
  // every CSV point's flag agrees with the definition (the table written for people, re-read)
  const auto recs = ru::util::csv_read_file((t.p / "o" / "pareto.csv").string());
  ASSERT_GT(recs.size(), 3u);
  std::vector<Axis> ax = {parse_axis("psnr_db"), parse_axis("area_mm2"), parse_axis("rays_per_s")};
  for (std::size_t i = 1; i < recs.size(); ++i) {
    bool dom = false;
    for (std::size_t j = 1; j < recs.size(); ++j)
      dom = dom || dominates({std::stod(recs[j][2]), std::stod(recs[j][3]), std::stod(recs[j][4])},
                             {std::stod(recs[i][2]), std::stod(recs[i][3]), std::stod(recs[i][4])}, ax);
    EXPECT_EQ(recs[i][8], dom ? "1" : "0") << recs[i][1];
  }
  for (const auto& bad : std::vector<std::vector<std::string>>{
           {chip, "--x", "nosuch"},
           {chip, "--x", "psnr_db:up"},
           {chip, "--target", "psnr_db=40"},
           {chip, "--where", "novalue"},
           {(t.p / "nosuch.csv").string()},
           {chip, "--unit-target", "fmax_mhz>=1"},
           {chip, "--plot-axes", "1,1"},
           {chip, "--profile", chip}}) {
    const auto b = (t.p / "bad").string();
    auto args = bad;
    args.push_back("--out");
    args.push_back(b);
    r = rayunits(args);
    EXPECT_EQ(r.code, 2) << bad[1] << " " << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("error:"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(b)) << bad.back();
  }
}

}  // namespace

namespace {

// The checked-in fronts (docs/pareto/*, sweeps/results/default/pareto) are what their recorded
// commands make today: rerun each command of pareto.md (its third line) into a temporary directory and compare
// pareto.csv byte for byte (a stale table, or a change of the front logic, fails here).
TEST(Pareto, CheckedInFrontsAreReproducedByTheirCommands) {
  int checked = 0;
  for (const char* name : {"docs/pareto/fp_units", "docs/pareto/chip", "docs/pareto/profile_default",
                           "sweeps/results/default/pareto"}) {
    const fs::path dir = fs::path(RU_SOURCE_DIR) / name;
    const std::string md = ru::synth::read_file((dir / "pareto.md").string());
    const auto a = md.find("`rayunits pareto "), b = md.find('`', a + 1);
    ASSERT_NE(a, std::string::npos) << name;
    // split the recorded command (single-quoted words as the command line writes them)
    std::vector<std::string> words;
    std::string cur;
    bool q = false, any = false;
    for (std::size_t i = a + 1; i < b; ++i) {
      const char c = md[i];
      if (c == '\'') { q = !q; any = true; continue; }
      if (c == ' ' && !q) {
        if (any || !cur.empty()) words.push_back(cur);
        cur.clear();
        any = false;
        continue;
      }
      cur += c;
    }
    if (any || !cur.empty()) words.push_back(cur);
    ASSERT_GE(words.size(), 3u);
    Tmp t;
    std::vector<std::string> args(words.begin() + 2, words.end());
    for (std::size_t i = 0; i < args.size(); ++i)
      if (args[i] == "--out" && i + 1 < args.size()) args[i + 1] = (t.p / "o").string();
    args.push_back("--no-plot");
    // the command's paths are relative to the repository
    std::vector<std::string> cmd = {"pareto"};
    cmd.insert(cmd.end(), args.begin(), args.end());
    const auto r = ru::test::run_rayunits(cmd, 300, RU_SOURCE_DIR);
    ASSERT_EQ(r.code, 0) << name << ": " << r.err;
    EXPECT_EQ(ru::synth::read_file((t.p / "o" / "pareto.csv").string()),
              ru::synth::read_file((dir / "pareto.csv").string()))
        << name << "/pareto.csv is not what its command makes today";
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

}  // namespace
