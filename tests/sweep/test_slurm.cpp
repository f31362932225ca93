// Tests of the Slurm path of `rayunits sweep` (issue 17 §2, model/src/sweep/slurm.cpp), without
// Slurm: --emit-slurm's job list and sbatch script, bad #SBATCH options, hostile values through
// the script (run with bash, SLURM_ARRAY_TASK_ID set, as a task would), --run-job for every
// index, --collect against the local run row for row, missing / corrupt / failed / cancelled
// tasks and rerun.sbatch. Each check is a function returning "" or what is wrong, and each is
// shown to catch a planted error. The real single-node Slurm run is tests/sweep/slurm_e2e.sh
// (ctest label long).
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
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

std::string rayunits_exe() { return fs::weakly_canonical(std::string(RU_BINARY_DIR) + "/model/cli/rayunits").string(); }
std::string slurp(const fs::path& p) { return fs::is_regular_file(p) ? ru::synth::read_file(p.string()) : ""; }
void spit(const fs::path& p, const std::string& text) { ru::synth::write_file_atomic(p.string(), text); }

struct Proc {
  int code;
  std::string out, err;
};

Proc run(const std::vector<std::string>& argv, const std::string& cwd = "") {
  ru::util::ProcessOptions o;
  o.out = ru::util::Redirect::capture();
  o.err = ru::util::Redirect::capture();
  o.timeout_s = 300;
  o.cwd = cwd;
  const auto r = ru::util::run_process(argv, o);
  return {r.status(), r.out, r.err};
}

Proc sweep(std::vector<std::string> args, const std::string& cwd = "") {
  args.insert(args.begin(), {rayunits_exe(), "sweep"});
  return run(args, cwd);
}

// The generated script as an array task runs it: bash, SLURM_ARRAY_TASK_ID set (env, no shell
// between us and bash).
Proc task(const fs::path& script, const std::string& id, const std::string& cwd) {
  return run({"/usr/bin/env", "SLURM_ARRAY_TASK_ID=" + id, "SLURM_ARRAY_JOB_ID=4242", "/bin/bash", script.string()}, cwd);
}

int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

// ---- the checks ------------------------------------------------------------------------------

// An sbatch script for the sweep directory `dir`: the array line, the #SBATCH options, and
// one task line that execs this rayunits binary with --run-job on dir/jobs.jsonl.
std::string script_problem(const std::string& text, const std::string& array, const std::vector<std::string>& sbatch,
                           const fs::path& dir) {
  const auto ls = lines_of(text);
  if (ls.empty() || ls[0] != "#!/bin/bash") return "no #!/bin/bash line";
  int arrays = 0, execs = 0;
  for (const auto& l : ls) {
    arrays += l.rfind("#SBATCH --array=", 0) == 0;
    execs += l.rfind("exec ", 0) == 0;
  }
  if (arrays != 1) return "not one --array line";
  if (std::find(ls.begin(), ls.end(), "#SBATCH --array=" + array) == ls.end()) return "no line #SBATCH --array=" + array;
  for (const auto& o : sbatch)
    if (std::find(ls.begin(), ls.end(), "#SBATCH " + o) == ls.end()) return "no line #SBATCH " + o;
  if (execs != 1) return "not one exec line";
  const std::string want = "exec " + ru::util::shell_quote(rayunits_exe()) + " 'sweep' --run-job " +
                           ru::util::shell_quote((dir / "jobs.jsonl").string() + ":") +
                           "\"${SLURM_ARRAY_TASK_ID:?not a Slurm array task}\"";
  if (std::find(ls.begin(), ls.end(), want) == ls.end()) return "no task line " + want;
  return "";
}

// The rows of a collected sweep directory against a local run's: the same jobs in the same
// order with the same parameters, command, status and typed result (times and the task's host
// aside), and results.csv equal but for the wall_s column.
std::string rows_problem(const fs::path& local, const fs::path& collected) {
  auto rows = [](const fs::path& d) {
    std::vector<json> v;
    for (const auto& l : lines_of(slurp(d / "results.jsonl"))) v.push_back(json::parse(l, nullptr, false));
    std::sort(v.begin(), v.end(), [](const json& a, const json& b) { return a.value("index", 0) < b.value("index", 0); });
    return v;
  };
  const auto a = rows(local), b = rows(collected);
  if (a.size() != b.size()) return std::to_string(b.size()) + " rows, the local run has " + std::to_string(a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    for (const char* k : {"hash", "index", "kind", "label", "params", "deps", "argv", "status", "exit", "error", "result", "log"})
      if (a[i].value(k, json()) != b[i].value(k, json()))
        return "row " + std::to_string(i) + " differs in " + k + ": " + a[i].value(k, json()).dump() + " vs " +
               b[i].value(k, json()).dump();
  auto table = [](const fs::path& d) {
    auto t = ru::util::csv_read_file((d / "results.csv").string());
    if (t.empty()) return t;
    const auto w = std::find(t[0].begin(), t[0].end(), "wall_s") - t[0].begin();
    for (auto& r : t)
      if (static_cast<std::size_t>(w) < r.size()) r.erase(r.begin() + w);
    return t;
  };
  if (table(local) != table(collected)) return "results.csv differs";
  return "";
}

// What collect said and wrote: the exit status, the indices it names missing / failed, and the
// --array of rerun.sbatch ("" : none must exist).
std::string collect_problem(const Proc& r, const fs::path& dir, const std::vector<std::size_t>& missing,
                            const std::vector<std::size_t>& failed, const std::string& rerun_array) {
  const bool complete = missing.empty() && failed.empty();
  if (r.code != (complete ? 0 : 1)) return "exit " + std::to_string(r.code) + ": " + r.err;
  const std::string counts = std::to_string(failed.size()) + " failed, " + std::to_string(missing.size()) + " missing";
  if (r.err.find(counts) == std::string::npos) return "no '" + counts + "' in " + r.err;
  for (std::size_t i : missing)
    if (r.err.find("task " + std::to_string(i) + " (") == std::string::npos ||
        r.err.find("missing (no results/" + std::to_string(i) + ".json)") == std::string::npos)
      return "task " + std::to_string(i) + " not reported missing: " + r.err;
  for (std::size_t i : failed)
    if (r.err.find("task " + std::to_string(i) + " (") == std::string::npos) return "task " + std::to_string(i) + " not reported";
  const fs::path rerun = dir / "rerun.sbatch";
  if (rerun_array.empty()) return fs::exists(rerun) ? "a rerun.sbatch after a complete collect" : "";
  if (!fs::exists(rerun)) return "no rerun.sbatch";
  return script_problem(slurp(rerun), rerun_array, {}, dir);
}

const char* const kGrid = "kind='study'\nstudy='box'\nformat=['e5m10','e6m12','e7m16']\nsynthetic=2000\nthreads=1\n";

class SweepSlurm : public ::testing::Test {
 protected:
  void SetUp() override { tmp_ = std::make_unique<ru::synth::TempDir>("ru-test-slurm-"); }
  fs::path dir() const { return tmp_->path(); }
  fs::path grid(const std::string& text) const {
    spit(dir() / "g.toml", text);
    return dir() / "g.toml";
  }
  std::unique_ptr<ru::synth::TempDir> tmp_;
};

// ---- tests -----------------------------------------------------------------------------------

TEST(SweepSlurmArray, ArraySpecsAreRangesThenTheLimit) {
  EXPECT_EQ(array_spec({0, 1, 2, 3}, 0), "0-3");
  EXPECT_EQ(array_spec({0, 1, 2, 3}, 2), "0-3%2");
  EXPECT_EQ(array_spec({8, 0, 2, 1, 5, 7, 2}, 0), "0-2,5,7-8");
  EXPECT_EQ(array_spec({4}, 3), "4%3");
  EXPECT_THROW(array_spec({}, 0), std::invalid_argument);
  EXPECT_EQ(parse_job_ref("a:b/jobs.jsonl:12"), std::make_pair(std::string("a:b/jobs.jsonl"), std::size_t{12}));
  for (const char* bad : {"jobs.jsonl", "jobs.jsonl:", ":3", "j:-1", "j:1x", "j: 1", "j:0; touch x"})
    EXPECT_THROW(parse_job_ref(bad), std::invalid_argument) << bad;
}

TEST_F(SweepSlurm, EmitWritesTheJobListAndAnArrayScript) {
  const fs::path g = grid(kGrid);
  const fs::path s = dir() / "s";
  Proc r = sweep({g.string(), "--emit-slurm", s.string(), "--partition", "short,long", "--time", "0-00:10", "--mem", "2G",
                 "--cpus", "1", "--max-parallel", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("3 jobs"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--array=0-2%2"), std::string::npos) << r.err;
  // The job list is the local runner's (the same lines as --dry-run prints).
  const Proc dry = sweep({g.string(), "--out", (dir() / "unused").string(), "--dry-run"});
  ASSERT_EQ(dry.code, 0);
  EXPECT_EQ(slurp(s / "jobs.jsonl"), dry.out);
  EXPECT_EQ(count_lines(dry.out), 3);
  const std::string script = slurp(s / "sweep.sbatch");
  EXPECT_EQ(script_problem(script, "0-2%2",
                           {"--partition=short,long", "--time=0-00:10", "--mem=2G", "--cpus-per-task=1",
                            "--output=" + (s / "slurm/%A_%a.out").string()},
                           s),
            "")
      << script;
  // Planted: the check sees a wrong array, a missing option, a second task line, an unquoted path.
  auto planted = [&](const std::string& from, const std::string& to) {
    std::string t = script;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  EXPECT_NE(script_problem(planted("0-2%2", "0-3%2"), "0-2%2", {}, s), "");
  EXPECT_NE(script_problem(planted("--mem=2G", "--mem=3G"), "0-2%2", {"--mem=2G"}, s), "");
  EXPECT_NE(script_problem(script + "exec /bin/true\n", "0-2%2", {}, s), "");
  EXPECT_NE(script_problem(planted("'" + rayunits_exe() + "'", rayunits_exe()), "0-2%2", {}, s), "");
  for (const char* f : {"slurm.json", "grid.toml"}) EXPECT_TRUE(fs::is_regular_file(s / f)) << f;
  for (const char* d : {"results", "logs", "slurm"}) EXPECT_TRUE(fs::is_directory(s / d)) << d;
  EXPECT_FALSE(fs::exists(s / "results.jsonl"));  // nothing ran
  // Without a limit: --array=0-2; no #SBATCH line for options not given.
  const fs::path s2 = dir() / "s2";
  ASSERT_EQ(sweep({g.string(), "--emit-slurm", s2.string()}).code, 0);
  EXPECT_EQ(script_problem(slurp(s2 / "sweep.sbatch"), "0-2", {}, s2), "");
  EXPECT_EQ(slurp(s2 / "sweep.sbatch").find("--partition"), std::string::npos);
}

TEST_F(SweepSlurm, BadOptionsGiveOneLineExit2AndWriteNothing) {
  const fs::path g = grid(kGrid);
  const fs::path canary = dir() / "CANARY";
  const std::string touch = "touch " + canary.string();
  const fs::path s = dir() / "s";
  struct Bad {
    std::vector<std::string> args;
    const char* needle;
  };
  const std::vector<Bad> cases = {
      {{"--partition", "x; " + touch}, "--partition 'x; touch"},
      {{"--partition", "$(" + touch + ")"}, "--partition '$(touch"},
      {{"--partition", ""}, "--partition"},
      {{"--time", "1h"}, "--time '1h': expected minutes"},
      {{"--time", "10`" + touch + "`"}, "--time '10`touch"},
      {{"--time", "0:00"}, "--time '0:00': expected a time limit above zero"},
      {{"--mem", "4GB"}, "--mem '4GB': expected a size"},
      {{"--mem", "4G\n#SBATCH --uid=0"}, "--mem"},
      {{"--cpus", "0"}, "--cpus"},
      {{"--max-parallel", "0"}, "--max-parallel"},
  };
  for (const Bad& c : cases) {
    std::vector<std::string> a = {g.string(), "--emit-slurm", s.string()};
    a.insert(a.end(), c.args.begin(), c.args.end());
    const Proc r = sweep(a);
    SCOPED_TRACE(c.args[0] + " " + c.args[1]);
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s)) << "a bad option wrote " << s;
  }
  // A bad grid value with --emit-slurm: the grid's one line, nothing written.
  const fs::path bad = dir() / "bad.toml";
  spit(bad, "kind='study'\nstudy='box'\nformat=['e5m10', 'e7m16; " + touch + "']\n");
  Proc r = sweep({bad.string(), "--emit-slurm", s.string()});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("key 'format': bad format name"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s));
  // Mode mistakes.
  for (const std::vector<std::string>& a :
       std::vector<std::vector<std::string>>{{g.string(), "--out", s.string(), "--partition", "p"},
                                             {g.string(), "--out", s.string(), "--emit-slurm", s.string()},
                                             {g.string(), "--emit-slurm", s.string(), "--dry-run"},
                                             {g.string(), "--run-job", "x:0"},
                                             {"--collect", s.string(), "-j", "2"},
                                             {"--run-job", "nowhere/jobs.jsonl:0"},
                                             {"--collect", s.string()},
                                             {"--run-job", "jobs.jsonl"}}) {
    const Proc m = sweep(a);
    EXPECT_EQ(m.code, 2) << a[1];
    EXPECT_EQ(count_lines(m.err), 1) << m.err;
  }
  EXPECT_FALSE(fs::exists(s));
  EXPECT_FALSE(fs::exists(canary));
}

// Hostile text where the script can see it: in the sweep directory's name (single quotes, $(),
// ;) and in grid values that are passed literally (a program path). The script is run as a
// task would run it; the canary must not appear. Control: the same task line without its
// quoting does create it.
TEST_F(SweepSlurm, HostileValuesThroughTheScriptAreNeverExecuted) {
  const std::string canary = "CANARY";  // relative: created in the task's working directory dir()
  const fs::path g = grid("kind='synth'\nunit='fp_add'\nformat='e5m10'\nstages=0\ngeneric_only=true\n"
                          "yosys = ['$(touch " + canary + ")', 'touch " + canary + "; true', 'x`touch " + canary + "`']\n");
  // Unquoted, `s'x'$(touch CANARY) y` runs the substitution (the planted control below).
  const fs::path s = dir() / ("s'x'$(touch " + canary + ") y");
  Proc r = sweep({g.string(), "--emit-slurm", s.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string script = slurp(s / "sweep.sbatch");
  EXPECT_EQ(script_problem(script, "0-2", {}, s), "") << script;
  EXPECT_EQ(script.find("#SBATCH --output"), std::string::npos) << "a path that needs quoting in an #SBATCH line";
  for (const char* id : {"0", "1", "2"}) {
    r = task(s / "sweep.sbatch", id, dir().string());
    EXPECT_EQ(r.code, 1) << r.err;  // the job ran and failed: no such yosys
    const json row = json::parse(slurp(s / "results" / (std::string(id) + ".json")));
    EXPECT_EQ(row["status"], "failed");
    EXPECT_NE(row["error"].get<std::string>().find("yosys not found ('"), std::string::npos) << row["error"];
    EXPECT_NE(row["error"].get<std::string>().find("touch " + canary), std::string::npos);  // literally
    EXPECT_EQ(row["task"]["SLURM_ARRAY_TASK_ID"], id);
    EXPECT_FALSE(fs::exists(dir() / canary)) << "task " << id;
  }
  // A hostile task id reaches --run-job as one argument and is rejected there.
  r = task(s / "sweep.sbatch", "0; touch " + canary, dir().string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("expected FILE:INDEX"), std::string::npos) << r.err;
  r = task(s / "sweep.sbatch", "$(touch " + canary + ")", dir().string());
  EXPECT_EQ(r.code, 2);
  EXPECT_FALSE(fs::exists(dir() / canary));
  // Control (planted): the task line with the directory unquoted does run the canary.
  std::string unquoted = script;
  const std::string q = ru::util::shell_quote((s / "jobs.jsonl").string() + ":");
  const auto at = unquoted.find(q);
  ASSERT_NE(at, std::string::npos);
  unquoted.replace(at, q.size(), (s / "jobs.jsonl").string() + ":");
  spit(dir() / "planted.sbatch", unquoted);
  task(dir() / "planted.sbatch", "0", dir().string());
  EXPECT_TRUE(fs::exists(dir() / canary)) << "the control did not execute: the canary check proves nothing";
}

TEST_F(SweepSlurm, TasksAndCollectGiveTheLocalRunsTableAndRerunExactlyTheMissing) {
  const fs::path g = grid(kGrid);
  const fs::path local = dir() / "local", s = dir() / "s";
  ASSERT_EQ(sweep({g.string(), "--out", local.string()}).code, 0);
  ASSERT_EQ(sweep({g.string(), "--emit-slurm", s.string(), "--max-parallel", "2"}).code, 0);
  for (const char* id : {"2", "0", "1"}) {  // any order, as Slurm may run them
    const Proc r = task(s / "sweep.sbatch", id, dir().string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("): ok; " + (s / "results" / (std::string(id) + ".json")).string()), std::string::npos) << r.err;
  }
  Proc c = sweep({"--collect", s.string()});
  EXPECT_EQ(collect_problem(c, s, {}, {}, ""), "");
  EXPECT_NE(c.err.find("3 jobs: 3 ok, 0 failed, 0 missing"), std::string::npos) << c.err;
  EXPECT_EQ(rows_problem(local, s), "");
  // Idempotent: collecting again writes the same bytes.
  const std::string jsonl = slurp(s / "results.jsonl"), csv = slurp(s / "results.csv");
  ASSERT_EQ(sweep({"--collect", s.string()}).code, 0);
  EXPECT_EQ(slurp(s / "results.jsonl"), jsonl);
  EXPECT_EQ(slurp(s / "results.csv"), csv);
  // Planted: the row comparison sees a changed result value, a missing row, a changed CSV cell.
  {
    const fs::path p = dir() / "planted";
    fs::create_directories(p);
    std::string t = jsonl;
    const auto at = t.find("\"pairs\":2000");
    ASSERT_NE(at, std::string::npos);
    spit(p / "results.jsonl", t.replace(at, 12, "\"pairs\":2001"));
    spit(p / "results.csv", csv);
    EXPECT_NE(rows_problem(local, p), "");
    spit(p / "results.jsonl", jsonl.substr(0, jsonl.find('\n') + 1));
    EXPECT_NE(rows_problem(local, p), "");
    spit(p / "results.jsonl", jsonl);
    std::string tc = csv;
    tc.replace(tc.find("e6m12"), 5, "e6m13");
    spit(p / "results.csv", tc);
    EXPECT_NE(rows_problem(local, p), "");
  }
  // A task that was run again when it already had an ok row: skipped (--force reruns it).
  const std::string row1 = slurp(s / "results/1.json");
  json marked = json::parse(row1);
  marked["marker"] = "planted";
  spit(s / "results/1.json", marked.dump() + "\n");
  Proc r = sweep({"--run-job", (s / "jobs.jsonl").string() + ":1"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.err.find("ok earlier"), std::string::npos) << r.err;
  EXPECT_EQ(json::parse(slurp(s / "results/1.json")).value("marker", ""), "planted");  // not run
  r = sweep({"--run-job", (s / "jobs.jsonl").string() + ":1", "--force"});
  EXPECT_EQ(r.code, 0);
  EXPECT_FALSE(json::parse(slurp(s / "results/1.json")).contains("marker"));  // run again: a new row

  // One result deleted: reported missing, rerun.sbatch names exactly it, the others are kept.
  fs::remove(s / "results/1.json");
  c = sweep({"--collect", s.string()});
  EXPECT_EQ(collect_problem(c, s, {1}, {}, "1%2"), "") << c.err;
  EXPECT_EQ(count_lines(slurp(s / "results.jsonl")), 2);
  // Planted: the collect check sees a wrong rerun array and an unreported task.
  EXPECT_NE(collect_problem(c, s, {1}, {}, "0-2%2"), "");
  EXPECT_NE(collect_problem(c, s, {0}, {}, "1%2"), "");
  EXPECT_NE(collect_problem(c, s, {}, {}, ""), "");

  // A corrupt result (torn JSON) and a result of another job: both counted failed and rerun.
  const std::string row2 = slurp(s / "results/2.json");
  spit(s / "results/2.json", row2.substr(0, row2.size() / 2));
  spit(s / "results/0.json", row2);  // job 2's row in job 0's file
  c = sweep({"--collect", s.string()});
  EXPECT_EQ(collect_problem(c, s, {1}, {0, 2}, "0-2%2"), "") << c.err;
  EXPECT_NE(c.err.find("task 2 (study box format=e7m16 synthetic=2000 threads=1): failed: unreadable results/2.json"),
            std::string::npos)
      << c.err;
  EXPECT_NE(c.err.find("task 0 (study box format=e5m10 synthetic=2000 threads=1): failed: results/0.json belongs to another job"),
            std::string::npos)
      << c.err;
  EXPECT_EQ(slurp(s / "results.jsonl"), "");
  // A task whose job failed: its row is kept (status failed, as the local runner records it).
  json failed = json::parse(row2);
  failed["status"] = "failed";
  failed["error"] = "planted";
  spit(s / "results/2.json", failed.dump() + "\n");
  c = sweep({"--collect", s.string()});
  EXPECT_EQ(collect_problem(c, s, {1}, {0, 2}, "0-2%2"), "") << c.err;
  EXPECT_NE(c.err.find("task 2 (study box format=e7m16 synthetic=2000 threads=1): failed: planted"), std::string::npos) << c.err;
  EXPECT_EQ(count_lines(slurp(s / "results.jsonl")), 1);

  // The rerun script recovers them all; the table equals the local run's again.
  for (const char* id : {"0", "1", "2"}) {
    const Proc t = task(s / "rerun.sbatch", id, dir().string());
    EXPECT_EQ(t.code, 0) << t.err;
  }
  c = sweep({"--collect", s.string()});
  EXPECT_EQ(collect_problem(c, s, {}, {}, ""), "") << c.err;
  EXPECT_EQ(rows_problem(local, s), "");
}

// scancel sends SIGTERM to the task: the job is stopped and nothing is written, so collect
// counts the task missing (a half-finished job never counts).
TEST_F(SweepSlurm, ACancelledTaskWritesNoResult) {
  const fs::path g = grid("[[grid]]\nkind='study'\nstudy='box'\nformat=['e5m10','e6m12']\nsynthetic=2000\nthreads=1\n"
                          "[[grid]]\nkind='study'\nstudy='box'\nformat='e8m23'\nsynthetic=3000000\nthreads=1\n");
  const fs::path s = dir() / "s";
  ASSERT_EQ(sweep({g.string(), "--emit-slurm", s.string()}).code, 0);
  const auto jobs = lines_of(slurp(s / "jobs.jsonl"));
  ASSERT_EQ(jobs.size(), 3u);
  std::size_t longest = 0;
  for (std::size_t i = 0; i < jobs.size(); ++i)
    if (json::parse(jobs[i])["params"] == json{{"format", "e8m23"}, {"synthetic", 3000000}, {"threads", 1}}) longest = i;
  ru::util::ProcessOptions o;
  o.out = o.err = ru::util::Redirect::null();
  ru::util::Child t({rayunits_exe(), "sweep", "--run-job", (s / "jobs.jsonl").string() + ":" + std::to_string(longest)}, o);
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path log = s / "logs" / (json::parse(jobs[longest])["hash"].get<std::string>() + ".log");
  while (!fs::exists(log) && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(t.pid(), SIGTERM);
  const auto res = t.wait();
  EXPECT_EQ(res.exit_code, 130);
  EXPECT_FALSE(fs::exists(s / "results" / (std::to_string(longest) + ".json")));
  for (std::size_t i = 0; i < jobs.size(); ++i)
    if (i != longest) {
      ASSERT_EQ(sweep({"--run-job", (s / "jobs.jsonl").string() + ":" + std::to_string(i)}).code, 0);
    }
  const Proc c = sweep({"--collect", s.string()});
  EXPECT_EQ(collect_problem(c, s, {longest}, {}, std::to_string(longest)), "") << c.err;
  EXPECT_EQ(count_lines(slurp(s / "results.jsonl")), 2);
}

}  // namespace
