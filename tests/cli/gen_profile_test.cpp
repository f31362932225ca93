// `rayunits gen --from-profile` (issue 17 §3, "model only what a scene requires"): exactly the
// profile's units at its format, one directory each, counts and Stages from the chip
// configuration, the chip datasheet's areas equal to the units' own datasheets, bad input one
// line with nothing written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "../common/run_rayunits.hpp"
#include "rayunits/util/process.hpp"
#include "rayunits/num/format.hpp"
#include "rayunits/synth/units.hpp"
#include "../common/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Dir : ru::test::TempDir {
  Dir() : TempDir("ru_gen_profile") {}
};

json read_json(const fs::path& p) {
  std::ifstream f(p);
  return json::parse(f);
}

// Each profile gets a file of its own (profile-1.json, ...).
fs::path write_profile(const fs::path& dir, const json& units, const json& format = "e5m10") {
  static int n = 0;
  const fs::path p = dir / ("profile-" + std::to_string(++n) + ".json");
  std::ofstream(p) << json{{"scene", "test"}, {"units", units}, {"recommended_format", format}, {"tri", "robust"},
                           {"bvh", "sah"}}
                          .dump();
  return p;
}

std::set<std::string> entries(const fs::path& d) {
  std::set<std::string> s;
  for (const auto& e : fs::directory_iterator(d)) s.insert(e.path().filename().string());
  return s;
}

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(GenProfile, ExactlyTheProfilesUnitsWithTheChipsCountsAndStages) {
  Dir d;
  const auto prof = write_profile(d.p, {"fp_add", "fp_cmp", "fp_sqrt"});
  const auto out = d.p / "chip";
  const auto r = ru::test::run_rayunits({"gen", "--from-profile", prof.string(), "--out", out.string(), "--no-synth"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(entries(out), (std::set<std::string>{"chip.json", "chip.md", "fp_add", "fp_cmp", "fp_sqrt"}));
  const json chip = read_json(out / "chip.json");
  EXPECT_EQ(chip["format"], "e5m10");
  ASSERT_EQ(chip["units"].size(), 3u);
  // the built-in chip (model/data/trax/default.toml): 4 TMs; per TM 4 adders, 4 comparators,
  // 1 square root; latencies add 2, cmp 1, sqrt 16 — above sqrt's useful maximum at e5m10
  // (the registry's maximum, M + 3 = 13, read from it below), so the unit has that many Stages
  // and the chip the rest as delay registers outside it
  EXPECT_EQ(chip["units"][0]["count"], 16);
  EXPECT_EQ(chip["units"][0]["stages"], 2);
  EXPECT_EQ(chip["units"][0]["top"], "ru_fp_add_e5m10_s2");
  EXPECT_EQ(chip["units"][1]["count"], 16);
  EXPECT_EQ(chip["units"][1]["stages"], 1);
  EXPECT_EQ(chip["units"][2]["count"], 4);
  ru::synth::UnitConfig sq;
  sq.fmt = ru::num::Format::parse("e5m10");
  const int sqrt_max = ru::synth::find_unit("fp_sqrt").max_stages(sq);
  ASSERT_LT(sqrt_max, 16);  // the case this checks: the chip's latency above the unit's maximum
  EXPECT_EQ(chip["units"][2]["stages"], sqrt_max);
  EXPECT_EQ(chip["units"][2]["chip_latency"], 16);
  EXPECT_TRUE(fs::exists(out / "fp_add" / "ru_fp_add_e5m10_s2.sv"));
  // a second run into the same directory needs --force, which replaces it
  EXPECT_EQ(ru::test::run_rayunits({"gen", "--from-profile", prof.string(), "--out", out.string(), "--no-synth"}).code, 2);
  const auto p2 = write_profile(d.p, {"fp_mul"});
  ASSERT_EQ(ru::test::run_rayunits(
                {"gen", "--from-profile", p2.string(), "--out", out.string(), "--no-synth", "--force"}).code, 0);
  EXPECT_EQ(entries(out), (std::set<std::string>{"chip.json", "chip.md", "fp_mul"}));
}

TEST(GenProfile, ChipAreaIsTheSumOfTheUnitsOwnDatasheets) {
  Dir d;
  const auto prof = write_profile(d.p, {"fp_cmp", "fp_add"}, "e4m3");
  const auto out = d.p / "chip";
  const auto r = ru::test::run_rayunits(
      {"gen", "--from-profile", prof.string(), "--out", out.string(), "--generic-only"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json chip = read_json(out / "chip.json");
  double total = 0;
  for (const auto& u : chip["units"]) {
    const json ds = read_json(out / u["dir"].get<std::string>() / "datasheet.json");
    ASSERT_TRUE(ds["area_nand2"].is_number()) << u["unit"];
    EXPECT_GT(ds["area_nand2"].get<double>(), 0);
    EXPECT_EQ(u["area_nand2"].get<double>(), ds["area_nand2"].get<double>()) << u["unit"];
    total += u["area_nand2"].get<double>() * u["count"].get<int>();
  }
  EXPECT_DOUBLE_EQ(chip["total_area_nand2"].get<double>(), total);
  EXPECT_GT(chip["chip_clock_mhz"].get<double>(), 0);
}

// --clock: each unit at the fewest Stages whose osu018 STA meets the clock (the clock search of
// `gen --clock`), recorded in its datasheet; the chip clock is the slowest unit's Fmax.
TEST(GenProfile, ClockPicksTheFewestStagesMeetingIt) {
  Dir d;
  const auto prof = write_profile(d.p, {"fp_cmp"});
  const auto out = d.p / "chip";
  const auto r = ru::test::run_rayunits({"gen", "--from-profile", prof.string(), "--out", out.string(), "--clock", "5ns"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json chip = read_json(out / "chip.json");
  ASSERT_EQ(chip["units"].size(), 1u);
  const json& u = chip["units"][0];
  const json ds = read_json(out / "fp_cmp" / "datasheet.json");
  EXPECT_EQ(chip["flow"], "osu018");
  EXPECT_GE(u["fmax_mhz"].get<double>(), 200.0);  // meets 5 ns
  EXPECT_EQ(u["stages"], ds["latency"]);  // every unit's latency is its Stages
  ASSERT_TRUE(ds.contains("clock_search")) << ds.dump();
  // every probe below the chosen Stages missed the clock, the chosen one met it
  for (const auto& p : ds["clock_search"]["probes"]) {
    if (p["stages"].get<int>() < u["stages"].get<int>()) {
      EXPECT_FALSE(p["met"].get<bool>()) << p;
    }
    if (p["stages"] == u["stages"]) {
      EXPECT_TRUE(p["met"].get<bool>()) << p;
    }
  }
  EXPECT_DOUBLE_EQ(chip["chip_clock_mhz"].get<double>(), u["fmax_mhz"].get<double>());
}

TEST(GenProfile, BadInputIsOneLineAndWritesNothing) {
  Dir d;
  const auto out = d.p / "chip";
  std::ofstream(d.p / "notjson.json") << "{";
  const std::vector<std::vector<std::string>> bad = {
      {"--from-profile", (d.p / "nosuch.json").string()},
      {"--from-profile", (d.p / "notjson.json").string()},
      {"--from-profile", write_profile(d.p, {"fp_add", "fp_fancy"}).string()},
      {"--from-profile", write_profile(d.p, json::array()).string()},
      {"--from-profile", write_profile(d.p, {"fp_add"}, nullptr).string()},
      {"--from-profile", write_profile(d.p, {"fp_add"}, "e1m2").string()},
      {"--from-profile", write_profile(d.p, {"fp_add"}).string(), "--clock", "2ns", "--no-synth"},
      {"--from-profile", write_profile(d.p, {"fp_add"}).string(), "--bogus"},
  };
  for (auto args : bad) {
    args.insert(args.begin(), "gen");
    args.push_back("--out");
    args.push_back(out.string());
    if (std::find(args.begin(), args.end(), "--clock") == args.end()) args.push_back("--no-synth");
    const auto r = ru::test::run_rayunits(args);
    EXPECT_EQ(r.code, 2) << args[2] << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(out)) << args[2];
  }
  for (const auto& e : fs::directory_iterator(d.p))  // no temporary directory left behind
    EXPECT_EQ(e.path().filename().string().find(".chip.tmp"), std::string::npos) << e.path();
}

}  // namespace

// The scene runs on the chip model with --cosim against exactly the units `gen --from-profile`
// generated (issue 17 §3): `trax --from-profile P --cosim-build` builds (rtl build cache) a
// companion whose ray_box / ray_tri_robust / noise configurations are the generated units' own
// RTL parameters (datasheet.json "parameters": format, Stages, options), and every unit result of
// the frame equals the RTL's bit for bit.
TEST(GenProfile, SceneCosimulatedAgainstExactlyTheGeneratedUnits) {
  Dir d;
  const auto prof = write_profile(
      d.p, {"fp_add", "fp_mul", "fp_div", "fp_sqrt", "fp_cmp", "ray_box", "ray_tri_robust", "noise"}, "e5m10");
  const auto chip = d.p / "chip";
  ASSERT_EQ(ru::test::run_rayunits({"gen", "--from-profile", prof.string(), "--out", chip.string(), "--no-synth"}).code, 0);
  const fs::path cache = d.p / "cache";
  setenv("RU_RTL_CACHE", cache.c_str(), 1);
  const auto r = ru::test::run_rayunits({"trax", "--scene", "default", "--from-profile", prof.string(), "--size",
                                         "4x4", "--cosim-build", "--out", (d.p / "trax").string()},
                                        1200);
  unsetenv("RU_RTL_CACHE");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("unit results equal to the RTL bit for bit (box="), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("box=0 "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("tri=0 "), std::string::npos) << r.out;
  // The companion's configurations (its --list) against the generated units' datasheets.
  std::string exe;
  for (const auto& e : fs::directory_iterator(cache / "bin"))
    if (read_json(e.path() / "manifest.json").value("kind", "") == "cosim") exe = (e.path() / "tb").string();
  ASSERT_FALSE(exe.empty()) << "no co-simulation companion in the cache";
  ru::util::ProcessOptions o;
  o.out = ru::util::Redirect::capture();
  const auto list = ru::util::run_process({exe, "--list"}, o);
  ASSERT_EQ(list.exit_code, 0);
  std::map<std::string, json> built;  // unit -> parameters
  std::istringstream in(list.out);
  for (std::string line; std::getline(in, line);) {
    const std::string name = line.substr(0, line.find(':'));
    std::string unit;
    for (const char* u : {"ray_box", "ray_tri_robust", "noise"})
      if (name.rfind(u, 0) == 0) unit = u;
    ASSERT_FALSE(unit.empty()) << line;
    std::istringstream kv(line.substr(line.find(':') + 1));
    for (std::string t; kv >> t;) built[unit][t.substr(0, t.find('='))] = std::stoll(t.substr(t.find('=') + 1));
  }
  ASSERT_EQ(built.size(), 3u) << list.out;
  for (const char* u : {"ray_box", "ray_tri_robust", "noise"}) {
    SCOPED_TRACE(u);
    EXPECT_EQ(built[u], read_json(chip / u / "datasheet.json")["parameters"]);
  }
}
