// `rayunits rtl` and the sweep kind `rtl` (issue 17 §1): one configuration under the RTL
// scoreboard with its Verilator build cached by content. One cache directory per test, so the
// first run builds (the model library and the harness come from ccache after the main build).
//   - a run builds, passes and reports a typed row; the same run again is a cache hit;
//   - a planted RTL error (the adder's sticky bit dropped, in a copy given with --rtl) gets a new
//     key, is built and FAILS: the job is a real scoreboard run, not a cached verdict;
//   - an rtl grid of two configurations: one hit (built above), one miss; a rerun skips both;
//   - bad input: unknown unit, Stages out of range, a missing Verilator: one line, exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "../common/files.hpp"
#include "../common/run_rayunits.hpp"
#include "../common/temp_dir.hpp"
#include "rayunits/sweep/sweep.hpp"
#include "rayunits/util/process.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ru::test::run_rayunits;

json row_of(const fs::path& f) { return json::parse(ru::test::slurp(f)); }

TEST(RtlCache, BuildsOnceHitsAfterwardsCatchesAPlantedErrorAndSweeps) {
  if (ru::util::find_program("verilator").empty()) GTEST_SKIP() << "verilator not installed";
  ru::test::TempDir t("ru_rtl_cache");
  const fs::path cache = t.p / "cache";
  const std::vector<std::string> base = {"rtl",       "fp_add",    "--format", "e4m3", "--stages",
                                         "1",         "--vectors", "500",      "--cache", cache.string()};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = base;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };

  // 1. First run: a miss, built, every test passes.
  auto r1 = run_rayunits(with({"--json", (t.p / "a.jsonl").string()}), 900);
  ASSERT_EQ(r1.code, 0) << r1.out << r1.err;
  const json a = row_of(t.p / "a.jsonl");
  EXPECT_EQ(a["status"], "pass");
  EXPECT_FALSE(a["cache_hit"].get<bool>());
  EXPECT_GT(a["build_s"].get<double>(), 0);
  EXPECT_GE(a["tests"].get<int>(), 3);  // special, random, reset at least
  EXPECT_EQ(a["failed"], 0);
  EXPECT_EQ(a["config"], "e4m3:s1");
  EXPECT_EQ(a["unit"], "fp_add");
  EXPECT_TRUE(fs::exists(cache / "bin" / a["key"].get<std::string>() / "tb"));
  EXPECT_TRUE(fs::exists(cache / "bin" / a["key"].get<std::string>() / "manifest.json"));
  EXPECT_NE((r1.out + r1.err).find("results checked"), std::string::npos) << "the scoreboard did not run:\n" << r1.out;

  // 2. Same configuration again: a hit, same key, still run (not a cached verdict).
  auto r2 = run_rayunits(with({"--json", "-", "--quiet"}), 300);
  ASSERT_EQ(r2.code, 0) << r2.err;
  const json b = json::parse(r2.out.substr(r2.out.rfind("\n{") + 1));
  EXPECT_TRUE(b["cache_hit"].get<bool>());
  EXPECT_EQ(b["build_s"].get<double>(), 0);
  EXPECT_EQ(b["key"], a["key"]);
  EXPECT_EQ(b["status"], "pass");
  EXPECT_NE((r2.out + r2.err).find("results checked"), std::string::npos);

  // 3. A planted error in a copy of the RTL: a new key, built, and caught by the scoreboard.
  const fs::path rtl = t.p / "rtl";
  fs::copy(fs::path(RU_SOURCE_DIR) / "rtl", rtl, fs::copy_options::recursive);
  const fs::path add = rtl / "ru_fp_add.sv";
  std::string src = ru::test::slurp(add);
  const std::string good = "assign s1_y   = {y_sh[XW-1:1], y_sh[0] | (|lost)};";
  const size_t at = src.find(good);
  ASSERT_NE(at, std::string::npos) << "the planted edit no longer matches rtl/ru_fp_add.sv";
  src.replace(at, good.size(), "assign s1_y   = {y_sh[XW-1:1], y_sh[0]};");  // the sticky bit dropped
  std::ofstream(add) << src;
  auto r3 = run_rayunits(with({"--rtl", rtl.string(), "--json", (t.p / "p.jsonl").string(), "--quiet"}), 900);
  EXPECT_EQ(r3.code, 1) << r3.out << r3.err;
  const json p = row_of(t.p / "p.jsonl");
  EXPECT_EQ(p["status"], "fail");
  EXPECT_GT(p["failed"].get<int>(), 0);
  EXPECT_NE(p["key"], a["key"]);
  EXPECT_NE(p["rtl_hash"], a["rtl_hash"]);
  EXPECT_FALSE(p["first_failure"].get<std::string>().empty());

  // 4. A grid of two configurations through the sweep engine, sharing the cache: e4m3 Stages 1
  //    is a hit (built in 1.), Stages 0 a miss; a rerun skips both jobs.
  const fs::path grid = t.p / "g.toml";
  std::ofstream(grid) << "kind = 'rtl'\nunit = 'fp_add'\nformat = 'e4m3'\nstages = [0, 1]\nvectors = 500\n";
  setenv("RU_RTL_CACHE", cache.c_str(), 1);
  auto s1 = run_rayunits({"sweep", grid.string(), "--out", (t.p / "sw").string(), "-j", "2"}, 900);
  ASSERT_EQ(s1.code, 0) << s1.err;
  const auto rows = ru::sweep::read_results((t.p / "sw").string());
  ASSERT_EQ(rows.size(), 2u);
  int hits = 0;
  for (const json& r : rows) {
    EXPECT_EQ(r["status"], "ok");
    const json& res = r["result"][0];
    EXPECT_EQ(res["status"], "pass");
    hits += res["cache_hit"].get<bool>();
    if (res["stages"] == 1) {
      EXPECT_TRUE(res["cache_hit"].get<bool>()) << res.dump();
    }
  }
  EXPECT_EQ(hits, 1);
  EXPECT_NE(ru::test::slurp(t.p / "sw" / "results.csv").find("cache_hit"), std::string::npos);
  auto s2 = run_rayunits({"sweep", grid.string(), "--out", (t.p / "sw").string()}, 300);
  EXPECT_EQ(s2.code, 0);
  EXPECT_NE(s2.err.find("2 with an ok result"), std::string::npos) << s2.err;
  unsetenv("RU_RTL_CACHE");
}

TEST(RtlCache, BadInputIsOneLineExit2) {
  ru::test::TempDir t("ru_rtl_bad");
  const std::string cache = (t.p / "cache").string();
  struct Case {
    std::vector<std::string> args;
    std::string needle;
  };
  const std::vector<Case> cases = {
      {{"rtl", "fp_addd", "--format", "e5m10", "--stages", "0"}, "unknown unit 'fp_addd'"},
      {{"rtl", "fp_add", "--format", "e5m10", "--stages", "99"}, "supports --stages 0..5, got 99"},
      {{"rtl", "fp_add", "--format", "e1m10", "--stages", "0"}, "e1m10"},
      {{"rtl", "fp_add", "--format", "e5m10", "--stages", "0", "--vectors", "0"}, "--vectors"},
      {{"rtl", "fp_add", "--format", "e5m10", "--stages", "0", "--rtl", "/nonexistent"}, "--rtl"},
      {{"rtl", "fp_add", "--format", "e5m10", "--stages", "0", "--colour"}, "unknown option '--colour'"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> a = c.args;
    a.push_back("--cache");
    a.push_back(cache);
    const auto r = run_rayunits(a, 120);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(ru::test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << r.err;
    EXPECT_EQ(r.err.rfind("rayunits rtl: error: ", 0), 0u) << r.err;
  }
  EXPECT_FALSE(fs::exists(cache)) << "a rejected request created the cache";
  // A machine without Verilator: one line naming the tool and its package.
  ru::util::ProcessOptions o;
  o.out = ru::util::Redirect::capture();
  o.err = ru::util::Redirect::capture();
  o.timeout_s = 120;
  const auto r = ru::util::run_process({"/usr/bin/env", "PATH=" + (t.p / "nothing").string(),
                                        std::string(RU_BINARY_DIR) + "/model/cli/rayunits", "rtl", "fp_add",
                                        "--format", "e5m10", "--stages", "0", "--cache", cache},
                                       o);
  EXPECT_EQ(r.status(), 2) << r.err;
  EXPECT_EQ(ru::test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("missing tool 'verilator' (Debian package verilator)"), std::string::npos) << r.err;
}

}  // namespace
