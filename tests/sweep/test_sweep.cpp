// Tests of the sweep engine (`rayunits sweep`, rayunits/sweep/sweep.hpp): grid expansion and
// hashes, validation of bad grids (one line, exit 2, nothing written), shell metacharacters in
// values (never executed), a real synth sweep, resume / --force, failing and timed-out jobs, and
// the table after an interrupt (SIGTERM and SIGKILL of the runner).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <mutex>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "rayunits/sweep/sweep.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/csv.hpp"
#include "rayunits/util/process.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace ru::sweep;

std::string rayunits_exe() { return std::string(RU_BINARY_DIR) + "/model/cli/rayunits"; }

// A file's text ("" when there is none) and writing one: the synth helpers.
std::string slurp(const fs::path& p) { return fs::is_regular_file(p) ? ru::synth::read_file(p.string()) : ""; }
void spit(const fs::path& p, const std::string& text) { ru::synth::write_file_atomic(p.string(), text); }

struct CmdRun {
  int code;
  std::string out, err;
};

// `rayunits sweep ARGS...` (argv, no shell), stdout and stderr captured.
CmdRun sweep(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {rayunits_exe(), "sweep"};
  argv.insert(argv.end(), args.begin(), args.end());
  ru::util::ProcessOptions o;
  o.out = ru::util::Redirect::capture();
  o.err = ru::util::Redirect::capture();
  o.timeout_s = 600;
  const auto r = ru::util::run_process(argv, o);
  return {r.status(), r.out, r.err};
}

// Processes whose working directory is `d` (a sweep's jobs run in its directory).
int processes_in(const fs::path& d) {
  int n = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc", ec)) {
    std::error_code ec2;
    if (fs::read_symlink(e.path() / "cwd", ec2) == d) ++n;
  }
  return n;
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

class Sweep : public ::testing::Test {
 protected:
  void SetUp() override { tmp_ = std::make_unique<ru::synth::TempDir>("ru-test-sweep-"); }
  fs::path dir() const { return tmp_->path(); }
  fs::path grid(const std::string& name, const std::string& text) const {
    spit(dir() / name, text);
    return dir() / name;
  }
  std::unique_ptr<ru::synth::TempDir> tmp_;
};

ExpandOptions fixed_tool(const std::string& tool = "tool-A") {
  ExpandOptions o;
  o.tool = tool;
  return o;
}

// Checks that DIR/results.jsonl is whole JSON lines, one per hash (at most `allow_dup` repeats),
// and that results.csv has a header plus one line per result row of the latest rows.
// Returns "" or what is wrong.
// exact: results.csv must hold every row (after a run that ended by itself; a killed runner
// may leave it up to RunOptions::csv_period_s behind results.jsonl).
std::string table_problem(const fs::path& d, bool exact = true) {
  const std::string text = slurp(d / "results.jsonl");
  if (!text.empty() && text.back() != '\n') return "results.jsonl ends inside a line";
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const json r = json::parse(line, nullptr, false);
    if (r.is_discarded() || !r.contains("hash") || !r.contains("status")) return "bad line: " + line;
  }
  const auto rows = read_results(d.string());
  std::size_t want = 1;
  for (const auto& r : rows) want += std::max<std::size_t>(1, r["result"].size());
  const auto csv = ru::util::csv_read_file((d / "results.csv").string());
  // results.csv holds the rows of the current job list (a subset of results.jsonl's hashes).
  if (csv.empty() || csv.size() > want || (exact && csv.size() != want)) return "results.csv has " + std::to_string(csv.size()) + " records";
  for (const auto& rec : csv)
    if (rec.size() != csv[0].size()) return "results.csv has a ragged record";
  return "";
}

// ---- expansion ------------------------------------------------------------------------------

const char* const kSynthGrid = R"(
kind = "synth"
unit = ["fp_add", "fp_mul"]
format = ["e5m10", "e6m12", "e7m16"]
stages = [0, 1]
generic_only = true
)";

TEST_F(Sweep, ExpansionIsTheProductOfTheAxesInOrder) {
  const Expansion e = expand_grid(kSynthGrid, (dir() / "g.toml").string(), fixed_tool());
  ASSERT_EQ(e.jobs.size(), 2u * 3u * 2u);
  EXPECT_TRUE(e.skipped.empty());
  std::set<std::string> labels, hashes;
  for (const Job& j : e.jobs) {
    labels.insert(j.label);
    hashes.insert(j.hash);
    EXPECT_EQ(j.hash.size(), 16u);
    EXPECT_EQ(j.params["generic_only"], true);
    EXPECT_EQ(j.argv[0], "rayunits");
    EXPECT_EQ(j.argv[1], "synth");
    EXPECT_EQ(j.result, "out/" + j.hash + "/synth.jsonl");
    EXPECT_NE(std::find(j.argv.begin(), j.argv.end(), "--json=" + j.result), j.argv.end());
    EXPECT_EQ(std::count(j.argv.begin(), j.argv.end(), "--generic-only"), 1);
  }
  EXPECT_EQ(labels.size(), e.jobs.size());
  EXPECT_EQ(hashes.size(), e.jobs.size());
  // Keys in sorted order, the last varying fastest: format, stages, unit.
  EXPECT_EQ(e.jobs[0].label, "synth fp_add format=e5m10 generic_only=true stages=0");
  EXPECT_EQ(e.jobs[1].label, "synth fp_mul format=e5m10 generic_only=true stages=0");
  EXPECT_EQ(e.jobs[2].label, "synth fp_add format=e5m10 generic_only=true stages=1");
  EXPECT_EQ(e.jobs.back().label, "synth fp_mul format=e7m16 generic_only=true stages=1");
  const std::vector<std::string> want = {"rayunits", "synth", "fp_add", "--format=e5m10", "--stages=0",
                                         "--generic-only", "--json=" + e.jobs[0].result};
  EXPECT_EQ(e.jobs[0].argv, want);
  // jobs.jsonl round trip
  for (const Job& j : e.jobs) EXPECT_EQ(job_json(job_from_json(json::parse(job_json(j).dump()))), job_json(j));
}

TEST_F(Sweep, HashesAreStableAndFollowParametersAndTool) {
  const Expansion a = expand_grid(kSynthGrid, (dir() / "g.toml").string(), fixed_tool());
  // The same grid written differently (other key order, a scalar as a one-value axis, another
  // file and directory) gives the same hashes.
  fs::create_directories(dir() / "elsewhere");
  const Expansion b = expand_grid(R"(generic_only = [true]
stages = [0, 1]
format = ["e5m10", "e6m12", "e7m16"]
unit = ["fp_add", "fp_mul"]
kind = "synth"
name = "another name"
)", (dir() / "elsewhere/h.toml").string(), fixed_tool());
  ASSERT_EQ(a.jobs.size(), b.jobs.size());
  for (std::size_t i = 0; i < a.jobs.size(); ++i) EXPECT_EQ(a.jobs[i].hash, b.jobs[i].hash) << a.jobs[i].label;
  // One parameter changed: only the affected jobs change hash.
  const Expansion c = expand_grid(R"(
kind = "synth"
unit = ["fp_add", "fp_mul"]
format = ["e5m10", "e6m12", "e7m17"]
stages = [0, 1]
generic_only = true
)", (dir() / "g.toml").string(), fixed_tool());
  int same = 0;
  for (std::size_t i = 0; i < a.jobs.size(); ++i) same += a.jobs[i].hash == c.jobs[i].hash;
  EXPECT_EQ(same, 8);  // the e7m16 -> e7m17 jobs (4) differ
  // Another tool identity (rayunits code) changes every hash.
  const Expansion d = expand_grid(kSynthGrid, (dir() / "g.toml").string(), fixed_tool("tool-B"));
  for (std::size_t i = 0; i < a.jobs.size(); ++i) EXPECT_NE(a.jobs[i].hash, d.jobs[i].hash);
  // The RTL the unit is built from is part of the hash (deps.rtl_sources from the registry's list).
  for (const Job& j : a.jobs) EXPECT_EQ(j.deps["rtl_sources"].get<std::string>().size(), 16u);
  EXPECT_NE(a.jobs[0].deps["rtl_sources"], a.jobs[1].deps["rtl_sources"]);  // fp_add vs fp_mul
  EXPECT_FALSE(a.jobs[0].deps.contains("liberty"));  // generic flow
  const Expansion cell = expand_grid("kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=0\nflow=['osu018','osu035']\n",
                                     (dir() / "g.toml").string(), fixed_tool());
  ASSERT_EQ(cell.jobs.size(), 2u);
  EXPECT_TRUE(cell.jobs[0].deps.contains("liberty"));
  if (cell.jobs[0].deps["liberty"] != "missing") {
    EXPECT_NE(cell.jobs[0].deps["liberty"], cell.jobs[1].deps["liberty"]);
  }
  // The default tool id names this repository's model/ tree.
  EXPECT_EQ(tool_id(RU_SOURCE_DIR).rfind("rayunits ", 0), 0u);
  EXPECT_EQ(tool_id(RU_SOURCE_DIR).find("unknown"), std::string::npos);
}

TEST_F(Sweep, MaxStagesAreResolvedAndPointsBeyondTheUnitSkipped) {
  const Expansion e = expand_grid(R"(
kind = "synth"
unit = ["fp_add", "noise"]
format = "e5m10"
stages = [0, "max", 99]
)", (dir() / "g.toml").string(), fixed_tool());
  // 2 units x 3 stages = 6 points: 2 beyond the maximum are skipped.
  ASSERT_EQ(e.jobs.size(), 4u);
  ASSERT_EQ(e.skipped.size(), 2u);
  for (const Job& j : e.jobs) {
    EXPECT_TRUE(j.params["stages"].is_number_integer());
    if (j.params["unit"] == "noise") {
      EXPECT_FALSE(j.params.contains("format"));  // a unit without a format
    }
  }
}

// ---- validation -----------------------------------------------------------------------------

struct BadGrid {
  const char* what;
  const char* text;
  const char* needle;  // the key (and what is wrong) the one-line error names
};

TEST_F(Sweep, BadGridsGiveOneLineNamingTheKeyExit2AndWriteNothing) {
  const std::vector<BadGrid> cases = {
      {"unknown key", "kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=0\ncolour=3\n", "key 'colour': unknown key"},
      {"wrong type", "kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=[0, 1.5]\n", "key 'stages': must be an integer"},
      {"wrong type (bool)", "kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=0\ngeneric_only='yes'\n",
       "key 'generic_only': must be true or false"},
      {"empty axis", "kind='synth'\nunit='fp_add'\nformat=[]\nstages=0\n", "key 'format': empty axis"},
      {"unknown unit", "kind='synth'\nunit=['fp_add','fp_addd']\nformat='e5m10'\nstages=0\n", "key 'unit': unknown unit 'fp_addd'"},
      {"unknown kind", "kind='synthesis'\n", "key 'kind': unknown kind 'synthesis'"},
      {"rtl without unit", "kind='rtl'\nstages=0\n", "key 'unit': required"},
      {"rtl unknown key", "kind='rtl'\nunit='fp_add'\nformat='e5m10'\nstages=0\nflow='osu018'\n",
       "key 'flow': unknown key for kind rtl"},
      {"rtl bad vectors", "kind='rtl'\nunit='fp_add'\nformat='e5m10'\nstages=0\nvectors=0\n", "key 'vectors'"},
      {"watertight bad scene", "kind='study'\nstudy='watertight'\nscene='teapot'\nformat='e5m10'\n",
       "key 'scene': unknown closed mesh 'teapot'"},
      {"image without frac", "kind='study'\nstudy='image'\nscene='default'\nexp=8\n", "key 'frac': required"},
      {"noise bad size", "kind='study'\nstudy='noise'\nsize=100\n", "key 'size': expects a power of two"},
      {"unknown study", "kind='study'\nstudy='teapot'\n", "key 'study': kind \"study\" needs study = "},
      {"trax double", "kind='trax'\nscene='default'\nformat='double'\n", "key 'format': the chip model takes float"},
      {"trax bad traversal", "kind='trax'\nscene='default'\ntraversal='dfs'\n", "key 'traversal'"},
      {"missing kind", "unit='fp_add'\n", "key 'kind': missing"},
      {"bad format", "kind='synth'\nunit='fp_add'\nformat='e1m10'\nstages=0\n", "key 'format': invalid format e1m10"},
      {"bad flow", "kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=0\nflow='osu999'\n", "key 'flow'"},
      {"bad clock", "kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=0\nflow='osu018'\nclock='fast'\n", "key 'clock'"},
      {"clock without cell flow", "kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=0\nflow='generic'\nclock='2ns'\n",
       "key 'clock': needs a cell-library flow"},
      {"missing key", "kind='synth'\nunit='fp_add'\nformat='e5m10'\n", "key 'stages': required"},
      {"bad param", "kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=0\n[param]\nBogus=1\n", "param: fp_add has no parameter 'Bogus'"},
      {"nested axis", "kind='synth'\nunit='fp_add'\nformat=[['e5m10']]\nstages=0\n", "key 'format': must be a string"},
      {"repeated value", "kind='synth'\nunit='fp_add'\nformat=['e5m10','e5m10']\nstages=0\n", "appears twice"},
      {"study without study", "kind='study'\nformat='e5m10'\n", "key 'study'"},
      {"study key of another study", "kind='study'\nstudy='box'\nexp=8\n", "key 'exp': unknown key for kind study box"},
      {"render bad scene", "kind='render'\nscene='nowhere'\n", "key 'scene': unknown scene"},
      {"grid entry", "[[grid]]\nkind='render'\nsize='big'\n", "key 'grid[0].size': bad --size 'big'"},
      {"render without scene", "kind='render'\nformat='e5m10'\n", "key 'scene'/'mesh': a render job needs exactly one"},
      {"toml syntax", "kind = 'synth\n", "g.toml:1"},
  };
  for (const BadGrid& c : cases) {
    SCOPED_TRACE(c.what);
    const fs::path g = grid("g.toml", c.text);
    const fs::path out = dir() / "out-bad";
    const CmdRun r = sweep({g.string(), "--out", out.string()});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("g.toml"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << "a bad grid wrote " << out;
    EXPECT_TRUE(r.out.empty());
  }
}

// The study kinds watertight, image and noise (and trax) run and give typed rows from their tables.
TEST_F(Sweep, StudyAndTraxKindsRunAndGiveTypedRows) {
  const fs::path g = grid("g.toml",
                          "[[grid]]\nkind='study'\nstudy='watertight'\nscene='icosphere'\nformat='e5m10'\n"
                          "tri=['robust','exact']\nrays=200\n"
                          "[[grid]]\nkind='study'\nstudy='image'\nscene='default'\nexp=8\nfrac=10\nsize='8x8'\n"
                          "[[grid]]\nkind='study'\nstudy='noise'\nsize=64\nerror_samples=500\nrange_samples=500\n"
                          "min_bits=6\nmax_bits=6\n"
                          "[[grid]]\nkind='trax'\nscene='default'\nformat='e7m16'\nsize='4x4'\n");
  const CmdRun r = sweep({g.string(), "--out", (dir() / "o").string(), "-j", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::map<std::string, int> rows;
  for (const json& row : read_results((dir() / "o").string())) {
    EXPECT_EQ(row["status"], "ok") << row.dump();
    const json& res = row["result"];
    ASSERT_FALSE(res.empty());
    rows[row["kind"]] += static_cast<int>(res.size());
    if (row["kind"] == "study watertight") {
      EXPECT_EQ(res[0]["edge_rays"].get<long>() > 0, true) << res.dump();
      if (row["params"]["tri"] == "exact") {
        EXPECT_EQ(res[0]["edge_leaks"], 0);
        EXPECT_EQ(res[0]["edge_double_hits"], 0);
      }
    }
    if (row["kind"] == "study image") {
      EXPECT_EQ(res[0]["pixels"], 64);
    }
    if (row["kind"] == "trax") {
      EXPECT_GT(res[0]["cycles"].get<long>(), 0);
    }
  }
  EXPECT_EQ(rows["study watertight"], 2);
  EXPECT_EQ(rows["study image"], 2);  // robust and mt
  EXPECT_GE(rows["study noise"], 1);
  EXPECT_EQ(rows["trax"], 1);
}

// Shell metacharacters in grid values: rejected by the option's check or passed literally as one
// argv element; the canary file must never appear.
TEST_F(Sweep, ShellMetacharactersAreRejectedOrPassedLiterallyNeverExecuted) {
  const fs::path canary = dir() / "CANARY";
  const std::string touch = "touch " + canary.string();
  // Control: the same text through a shell does create the canary (the check below can fail).
  ASSERT_EQ(ru::util::run_foreground({"/bin/sh", "-c", ": e7m16; " + touch}), 0);
  ASSERT_TRUE(fs::exists(canary));
  fs::remove(canary);

  // Rejected at the grid check (formats, units, enums, files).
  for (const std::string& bad :
       {"format = 'e7m16; " + touch + "'", "format = '$(" + touch + ")'", "round = '`" + touch + "`'"}) {
    const fs::path g = grid("g.toml", "kind='synth'\nunit='fp_add'\nstages=0\ngeneric_only=true\n" +
                                          (bad.rfind("format", 0) == 0 ? bad : "format='e5m10'\n" + bad) + "\n");
    const CmdRun r = sweep({g.string(), "--out", (dir() / "o1").string()});
    EXPECT_EQ(r.code, 2) << bad << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(canary)) << bad;
    EXPECT_FALSE(fs::exists(dir() / "o1"));
  }
  for (const std::string& bad : {"unit = '$(" + touch + ")'\nformat='e5m10'", "unit='fp_add'\nformat='e5m10;" + touch + "'"}) {
    const fs::path g = grid("g.toml", "kind='synth'\nstages=0\n" + bad + "\n");
    EXPECT_EQ(sweep({g.string(), "--out", (dir() / "o1").string()}).code, 2);
    EXPECT_FALSE(fs::exists(canary));
  }
  const fs::path gt = grid("g.toml", "kind='study'\nstudy='box'\ntrace='$(" + touch + ")'\n");
  EXPECT_EQ(sweep({gt.string(), "--out", (dir() / "o1").string()}).code, 2);
  EXPECT_FALSE(fs::exists(canary));

  // Passed literally: a program path is free text; the job runs `rayunits synth --yosys=<text>`
  // as argv (no shell), so the "program" is not found and the job fails with that error.
  const fs::path g = grid("g.toml", "kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=0\ngeneric_only=true\n"
                                    "yosys = ['$(" + touch + ")', '" + touch + "; true']\n");
  const CmdRun r = sweep({g.string(), "--out", (dir() / "o2").string()});
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_FALSE(fs::exists(canary));
  const auto rows = read_results((dir() / "o2").string());
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    EXPECT_EQ(row["status"], "failed");
    EXPECT_NE(row["error"].get<std::string>().find("yosys not found ('"), std::string::npos) << row["error"];
    EXPECT_NE(row["error"].get<std::string>().find(touch), std::string::npos) << row["error"];  // literally
  }
  EXPECT_EQ(table_problem(dir() / "o2"), "");
}

// ---- running --------------------------------------------------------------------------------

// Two real synthesis jobs (fp_add e5m10, generic gates only, Stages 0 and 1): results from the
// files the jobs wrote, resume skips both, --force reruns both.
TEST_F(Sweep, RealSynthSweepResumesAndForceReruns) {
  const fs::path g = grid("g.toml", "kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=[0,1]\ngeneric_only=true\n");
  const fs::path out = dir() / "s";
  CmdRun r = sweep({g.string(), "--out", out.string(), "-j", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("2 jobs: 2 to run"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("2/2 done (0 failed)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("ETA"), std::string::npos);
  auto rows = read_results(out.string());
  ASSERT_EQ(rows.size(), 2u);
  const auto jobs = slurp(out / "jobs.jsonl");
  EXPECT_EQ(count_lines(jobs), 2);
  for (const auto& row : rows) {
    EXPECT_EQ(row["status"], "ok");
    ASSERT_EQ(row["result"].size(), 1u);
    const json& res = row["result"][0];
    // The row `rayunits synth --json` wrote: the same unit, format and Stages as the parameters.
    EXPECT_EQ(res["top"], "ru_fp_add_e5m10_s" + std::to_string(row["params"]["stages"].get<int>()));
    EXPECT_GT(res["area_nand2"].get<double>(), 100);
    EXPECT_EQ(res["latency"], row["params"]["stages"]);
    EXPECT_GT(row["wall_s"].get<double>(), 0);
    EXPECT_TRUE(fs::exists(out / row["log"].get<std::string>()));
    EXPECT_NE(jobs.find(row["hash"].get<std::string>()), std::string::npos);
  }
  std::sort(rows.begin(), rows.end(), [](const json& a, const json& b) { return a["index"] < b["index"]; });
  EXPECT_EQ(rows[0]["params"]["stages"], 0);
  EXPECT_EQ(rows[0]["result"][0]["reg_bits"], 0);  // Stages 0: combinational
  EXPECT_GT(rows[1]["result"][0]["reg_bits"].get<int>(), 0);
  auto csv = ru::util::csv_read_file((out / "results.csv").string());
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[0][0], "hash");
  EXPECT_NE(std::find(csv[0].begin(), csv[0].end(), "area_nand2"), csv[0].end());
  EXPECT_EQ(table_problem(out), "");

  // Resume: nothing runs.
  r = sweep({g.string(), "--out", out.string(), "-j", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("2 jobs: 0 to run, 2 with an ok result"), std::string::npos) << r.err;
  EXPECT_EQ(count_lines(slurp(out / "results.jsonl")), 2);
  // --dry-run prints the jobs and what would run, writes nothing.
  r = sweep({g.string(), "--out", out.string(), "--dry-run"});
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(count_lines(r.out), 2);
  EXPECT_NE(r.err.find("2 with an ok result"), std::string::npos) << r.err;
  EXPECT_EQ(count_lines(slurp(out / "results.jsonl")), 2);
  // --force: both again, appended; the table keeps one row per job.
  r = sweep({g.string(), "--out", out.string(), "-j", "2", "--force"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("2 jobs: 2 to run"), std::string::npos) << r.err;
  EXPECT_EQ(count_lines(slurp(out / "results.jsonl")), 4);
  EXPECT_EQ(read_results(out.string()).size(), 2u);
  EXPECT_EQ(ru::util::csv_read_file((out / "results.csv").string()).size(), 3u);
  EXPECT_EQ(table_problem(out), "");
}

// Quick jobs for the runner tests: ray-box studies of a few thousand synthetic pairs.
std::string box_grid(const std::vector<std::string>& formats, int synthetic) {
  std::string f;
  for (const auto& x : formats) f += (f.empty() ? "'" : ", '") + x + "'";
  return "kind='study'\nstudy='box'\nformat=[" + f + "]\nsynthetic=" + std::to_string(synthetic) + "\nthreads=1\n";
}

TEST_F(Sweep, ResumeRunsExactlyTheJobsWithoutAnOkRow) {
  const fs::path g = grid("g.toml", box_grid({"e5m10", "e6m12", "e7m16"}, 2000));
  const fs::path out = dir() / "s";
  ASSERT_EQ(sweep({g.string(), "--out", out.string()}).code, 0);
  auto rows = read_results(out.string());
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) {
    EXPECT_EQ(row["status"], "ok");
    EXPECT_GE(row["result"].size(), 1u);
    EXPECT_EQ(row["result"][0]["pairs"], 2000);  // the study's CSV, typed
  }
  // Planted: drop the middle row and mark the last failed -> exactly those two run again.
  std::istringstream in(slurp(out / "results.jsonl"));
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  json last = json::parse(lines[2]);
  last["status"] = "failed";
  spit(out / "results.jsonl", lines[0] + "\n" + last.dump() + "\n");
  const CmdRun r = sweep({g.string(), "--out", out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("3 jobs: 2 to run, 1 with an ok result"), std::string::npos) << r.err;
  rows = read_results(out.string());
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) EXPECT_EQ(row["status"], "ok");
  EXPECT_EQ(table_problem(out), "");
  // A grid change reruns only the new point.
  const fs::path g2 = grid("g2.toml", box_grid({"e5m10", "e6m12", "e7m16", "e8m23"}, 2000));
  const CmdRun r2 = sweep({g2.string(), "--out", out.string()});
  EXPECT_NE(r2.err.find("4 jobs: 1 to run, 3 with an ok result"), std::string::npos) << r2.err;
}

TEST_F(Sweep, FailingAndTimedOutJobsAreRecordedAndTheRestGoOn) {
  // One job fails at once (no such yosys), two run too long (--timeout 3), two are fine. Margins
  // both ways, so that a loaded machine does not flip them: the quick jobs take ~0.2 s, the long
  // ones ~40 s (4e6 synthetic pairs; ~10 s per 1e6 here).
  const fs::path g = grid("g.toml", R"(
[[grid]]
kind = "synth"
unit = "fp_add"
format = "e5m10"
stages = 0
generic_only = true
yosys = "/nonexistent/yosys"
[[grid]]
kind = "study"
study = "box"
format = ["e5m10", "e8m23"]
synthetic = [1000, 4000000]
threads = 1
)");
  const fs::path out = dir() / "s";
  const CmdRun r = sweep({g.string(), "--out", out.string(), "-j", "2", "--timeout", "3"});
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("failed"), std::string::npos);
  const auto rows = read_results(out.string());
  ASSERT_EQ(rows.size(), 5u);
  std::map<std::string, int> by;
  for (const auto& row : rows) {
    const std::string st = row["status"];
    ++by[st];
    if (st == "failed") {
      EXPECT_NE(row["error"].get<std::string>().find("yosys not found"), std::string::npos) << row;
    }
    if (st == "timeout") {
      EXPECT_EQ(row["params"]["synthetic"], 4000000);
      EXPECT_NE(row["error"].get<std::string>().find("timed out"), std::string::npos);
      EXPECT_LT(row["wall_s"].get<double>(), 30);
    }
    if (st == "ok") {
      EXPECT_EQ(row["params"]["synthetic"], 1000);
    }
  }
  EXPECT_EQ(by["failed"], 1);
  EXPECT_EQ(by["timeout"], 2);
  EXPECT_EQ(by["ok"], 2);
  // The error lands in the CSV too.
  EXPECT_NE(slurp(out / "results.csv").find("timed out"), std::string::npos);
  EXPECT_EQ(table_problem(out), "");
  // The failed ones are tried again on the next run (and fail again), the ok ones are not.
  const CmdRun r2 = sweep({g.string(), "--out", out.string(), "-j", "2", "--timeout", "3"});
  EXPECT_EQ(r2.code, 1);
  EXPECT_NE(r2.err.find("5 jobs: 3 to run, 2 with an ok result"), std::string::npos) << r2.err;
}

// The runner killed in mid-sweep (SIGTERM: it stops its jobs; SIGKILL: it just dies) leaves a
// consistent table, and a rerun completes it without repeating recorded jobs.
TEST_F(Sweep, InterruptLeavesAConsistentTableAndARerunCompletesIt) {
  const fs::path g = grid("g.toml", box_grid({"e5m10", "e6m12", "e7m16", "e8m23", "e5m11", "e6m13"}, 60000));
  for (int sig : {SIGTERM, SIGKILL}) {
    SCOPED_TRACE(sig == SIGTERM ? "SIGTERM" : "SIGKILL");
    const fs::path out = dir() / ("s" + std::to_string(sig));
    ru::util::ProcessOptions o;
    o.out = ru::util::Redirect::null();
    o.err = ru::util::Redirect::file((dir() / "runner.err").string());
    ru::util::Child runner({rayunits_exe(), "sweep", g.string(), "--out", out.string(), "-j", "1"}, o);
    // Wait for the first recorded job, then stop the runner in the middle of the next one.
    const auto t0 = std::chrono::steady_clock::now();
    while (count_lines(slurp(out / "results.jsonl")) < 1 &&
           std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120))
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_GE(count_lines(slurp(out / "results.jsonl")), 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ::kill(runner.pid(), sig);
    const auto res = runner.wait();
    if (sig == SIGTERM) {
      EXPECT_EQ(res.exit_code, 130) << slurp(dir() / "runner.err");
    }
    // The jobs die with the runner (SIGTERM: it stops them; SIGKILL: their parent-death signal).
    const auto t1 = std::chrono::steady_clock::now();
    while (processes_in(out) > 0 && std::chrono::steady_clock::now() - t1 < std::chrono::seconds(20))
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(processes_in(out), 0) << "a job outlived its runner";
    const int recorded = count_lines(slurp(out / "results.jsonl"));
    EXPECT_LT(recorded, 6) << "the runner finished before it was stopped: make the jobs longer";
    EXPECT_EQ(table_problem(out, sig == SIGTERM), "");
    for (const auto& row : read_results(out.string())) EXPECT_EQ(row["status"], "ok");  // stopped jobs: no row
    // A torn line (as a crash in mid-write could leave) is cut off by the next run.
    if (sig == SIGKILL) {
      std::ofstream(out / "results.jsonl", std::ios::app) << R"({"hash":"0123)";
      EXPECT_NE(table_problem(out, false), "");  // planted: the check sees it
    }
    const CmdRun r = sweep({g.string(), "--out", out.string(), "-j", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("6 jobs: " + std::to_string(6 - recorded) + " to run"), std::string::npos) << r.err;
    EXPECT_EQ(count_lines(slurp(out / "results.jsonl")), 6);  // each job recorded once
    EXPECT_EQ(read_results(out.string()).size(), 6u);
    EXPECT_EQ(table_problem(out), "");
  }
}

// A SIGKILLed runner cannot stop its jobs itself: they get SIGTERM as their parent dies
// (util::ProcessOptions::parent_death_signal), instead of running on for minutes.
TEST_F(Sweep, JobsOfAKilledRunnerStop) {
  const fs::path g = grid("g.toml", box_grid({"e8m23"}, 2000000));  // 10-30 s; killed within moments of its start
  const fs::path out = dir() / "s";
  ru::util::ProcessOptions o;
  o.out = o.err = ru::util::Redirect::null();
  ru::util::Child runner({rayunits_exe(), "sweep", g.string(), "--out", out.string()}, o);
  const auto t0 = std::chrono::steady_clock::now();
  while (processes_in(out) == 0 && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(processes_in(out), 1) << "the job did not start";
  ::kill(runner.pid(), SIGKILL);
  runner.wait();
  const auto t1 = std::chrono::steady_clock::now();
  while (processes_in(out) > 0 && std::chrono::steady_clock::now() - t1 < std::chrono::seconds(5))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(processes_in(out), 0) << "the job outlived its SIGKILLed runner by 5 s";
  EXPECT_EQ(count_lines(slurp(out / "results.jsonl")), 0);
}

// A rebuild during a long sweep replaces the rayunits file; the sweep goes on running the binary
// it started with (its jobs exec /proc/self/exe), not the new file. Planted: the "new binary" is a
// script that touches a canary and fails; a runner that exec'd the path would run it.
TEST_F(Sweep, JobsKeepRunningTheBinaryTheSweepStartedWith) {
  const fs::path exe = dir() / "bin" / "rayunits";
  fs::create_directories(exe.parent_path());
  fs::copy_file(rayunits_exe(), exe);
  const fs::path canary = dir() / "canary";
  const fs::path g = grid("g.toml", box_grid({"e5m10", "e6m12", "e7m16"}, 300000));
  const fs::path out = dir() / "s";
  ru::util::ProcessOptions o;
  o.out = ru::util::Redirect::null();
  o.err = ru::util::Redirect::file((dir() / "runner.err").string());
  ru::util::Child runner({exe.string(), "sweep", g.string(), "--out", out.string(), "-j", "1"}, o);
  const auto t0 = std::chrono::steady_clock::now();
  while (processes_in(out) == 0 && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(processes_in(out), 1) << "the first job did not start";
  // "the rebuild": a new file renamed over the old one (as a linker or install does)
  spit(dir() / "bin" / "new", "#!/bin/sh\ntouch '" + canary.string() + "'\nexit 3\n");
  ::chmod((dir() / "bin" / "new").c_str(), 0755);
  fs::rename(dir() / "bin" / "new", exe);
  const auto res = runner.wait();
  EXPECT_EQ(res.exit_code, 0) << slurp(dir() / "runner.err");
  EXPECT_FALSE(fs::exists(canary)) << "a job ran the replaced file";
  const auto rows = read_results(out.string());
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& r : rows) {
    EXPECT_EQ(r["status"], "ok") << r.dump();
    EXPECT_EQ(r["deps"]["tool"], rows[0]["deps"]["tool"]);
  }
  EXPECT_NE(slurp(out / "logs" / (rows[2]["hash"].get<std::string>() + ".log")).find(exe.string()), std::string::npos)
      << "the log names the program as started";
  // and the planted "new binary" does what the check looks for when it is run
  ru::util::ProcessOptions q;
  q.out = q.err = ru::util::Redirect::null();
  EXPECT_EQ(ru::util::run_process({exe.string()}, q).status(), 3);
  EXPECT_TRUE(fs::exists(canary));
}

TEST_F(Sweep, LibraryRunnerReportsRunningJobsAndChecksEveryJob) {
  // run_jobs directly: a heartbeat line names the running job while nothing finishes.
  const Expansion e = expand_grid(box_grid({"e8m23"}, 150000), (dir() / "g.toml").string(), fixed_tool());
  RunOptions ro;
  ro.dir = (dir() / "s").string();
  ro.exe = rayunits_exe();
  ro.heartbeat_s = 0.2;
  std::vector<std::string> lines;
  std::mutex m;
  ro.progress = [&](const std::string& l) {
    std::lock_guard<std::mutex> g(m);
    lines.push_back(l);
  };
  const RunSummary sum = run_jobs(e.jobs, ro);
  EXPECT_EQ(sum.ok, 1u);
  EXPECT_EQ(sum.failed, 0u);
  bool beat = false;
  for (const auto& l : lines) beat = beat || l.find("0/1 done (0 failed), 1 running, ETA ?: study box") != std::string::npos;
  EXPECT_TRUE(beat) << "no heartbeat line (the job took " << read_results(ro.dir)[0]["wall_s"] << " s)";
  EXPECT_NE(lines.back().find("1/1 done (0 failed), 0 running, ETA 0s"), std::string::npos) << lines.back();
  // One job on its own (what a cluster task will do): its row, not written anywhere.
  const json one = run_one(e.jobs[0], (dir() / "one").string(), ro);
  EXPECT_EQ(one["status"], "ok");
  EXPECT_EQ(one["result"], read_results(ro.dir)[0]["result"]);  // deterministic study
  EXPECT_FALSE(fs::exists(dir() / "one/results.jsonl"));
  // The per-job check (the CLI parses each synth argv with `rayunits synth`'s parser) runs on
  // every job; a planted rejection names the job.
  ExpandOptions o = fixed_tool();
  int checked = 0;
  o.check_job = [&](const Job& j) {
    ++checked;
    if (j.params["stages"] == 1) throw std::runtime_error("planted");
  };
  try {
    expand_grid(kSynthGrid, (dir() / "g.toml").string(), o);
    ADD_FAILURE() << "the check did not stop the expansion";
  } catch (const GridError& err) {
    EXPECT_NE(std::string(err.what()).find("job synth fp_add format=e5m10 generic_only=true stages=1: planted"),
              std::string::npos)
        << err.what();
  }
  EXPECT_EQ(checked, 3);
}

TEST_F(Sweep, RenderAndStudyTriJobsGiveTypedRows) {
  const fs::path g = grid("g.toml", R"(
[[grid]]
kind = "render"
scene = "sphere"
format = ["e5m10", "float"]
size = "24"
threads = 1
compare = true
[[grid]]
kind = "study"
study = "tri"
exp = 8
frac = 10
synthetic = 300
no_decisions = true
threads = 1
)");
  const fs::path out = dir() / "s";
  const CmdRun r = sweep({g.string(), "--out", out.string(), "-j", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  int renders = 0, tris = 0;
  for (const auto& row : read_results(out.string())) {
    ASSERT_EQ(row["status"], "ok") << row;
    const json& res = row["result"][0];
    if (row["kind"] == "render") {
      ++renders;
      EXPECT_EQ(res["width"], 24);
      EXPECT_EQ(res["primary_rays"], 24 * 24);
      EXPECT_EQ(res["format"], row["params"]["format"]);
      EXPECT_TRUE(res["vs_double"].contains("psnr_db"));
      EXPECT_TRUE(fs::is_regular_file(out / row["result"][0]["png"].get<std::string>()));
      if (row["params"]["format"] == "e5m10") {
        EXPECT_GT(res["soft"]["ops"].get<double>(), 0);  // emulated arithmetic counted
      }
    } else {
      ++tris;
      EXPECT_EQ(row["kind"], "study tri");
      EXPECT_EQ(res["exponent_bits"], 8);
      EXPECT_EQ(res["significand_bits"], 10);
    }
  }
  EXPECT_EQ(renders, 2);
  EXPECT_EQ(tris, 1);
  EXPECT_EQ(table_problem(out), "");
}

TEST_F(Sweep, OneRunnerPerDirectory) {
  const fs::path g = grid("g.toml", box_grid({"e5m10"}, 300000));
  const fs::path out = dir() / "s";
  ru::util::ProcessOptions o;
  o.out = o.err = ru::util::Redirect::null();
  ru::util::Child first({rayunits_exe(), "sweep", g.string(), "--out", out.string()}, o);
  const auto t0 = std::chrono::steady_clock::now();
  while (!fs::exists(out / "jobs.jsonl") && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const CmdRun second = sweep({g.string(), "--out", out.string()});
  EXPECT_EQ(second.code, 2);
  EXPECT_NE(second.err.find("another `rayunits sweep` is running"), std::string::npos) << second.err;
  EXPECT_EQ(first.wait().exit_code, 0);
}

TEST(SweepCsv, ResultsCsvFlattensRowsAndKeepsColumnsAligned) {
  const std::vector<json> rows = {
      json{{"hash", "a"}, {"index", 0}, {"kind", "synth"}, {"status", "ok"}, {"wall_s", 1.5}, {"error", ""},
           {"params", {{"unit", "fp_add"}, {"stages", 0}}},
           {"result", json::array({{{"area", 10}, {"cp", {{"segment", 1}}}}, {{"area", 12}, {"x", "a,b"}}})}},
      json{{"hash", "b"}, {"index", 1}, {"kind", "synth"}, {"status", "failed"}, {"wall_s", 0.1},
           {"error", "rayunits synth: error: \"quoted\", with comma"}, {"params", {{"unit", "fp_mul"}}},
           {"result", json::array()}}};
  const auto t = ru::util::csv_parse(results_csv(rows));
  ASSERT_EQ(t.size(), 4u);  // header + 2 result rows of a + 1 line for b
  const std::vector<std::string> head = {"hash", "index", "kind", "status", "wall_s", "error", "stages", "unit",
                                         "area", "cp.segment", "x"};
  EXPECT_EQ(t[0], head);
  EXPECT_EQ(t[1][8], "10");
  EXPECT_EQ(t[1][9], "1");
  EXPECT_EQ(t[2][10], "a,b");
  EXPECT_EQ(t[3][5], "rayunits synth: error: \"quoted\", with comma");
  for (const auto& r : t) EXPECT_EQ(r.size(), head.size());
}

TEST(SweepDocs, ExampleGridExpands) {
  for (const char* f : {"/sweeps/example.toml"}) {
    const Expansion e = expand_grid_file(std::string(RU_SOURCE_DIR) + f, fixed_tool());
    EXPECT_GE(e.jobs.size(), 2u) << f;
  }
}

}  // namespace
