// rayunits sweep on a cluster: Slurm job arrays (rayunits/sweep/sweep.hpp, docs/SWEEPS.md).
//
// --emit-slurm writes the job list and an sbatch script; each array task runs one job through
// run_one (the local runner's launcher: an argv vector, no shell) and writes its own result
// file; --collect merges them with the local runner's row format and results_csv.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "rayunits/sweep/sweep.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/process.hpp"

namespace ru::sweep {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string slurp(const std::string& path) { return fs::is_regular_file(path) ? synth::read_file(path) : ""; }

// A value that may stand unquoted in an #SBATCH line: sbatch splits those lines itself (no
// shell), so they hold only characters that need no quoting for either.
bool sbatch_plain(const std::string& s) {
  return !s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=./:,@") ==
                           std::string::npos;
}

}  // namespace

std::vector<Job> read_jobs(const std::string& file) {
  if (!fs::is_regular_file(file)) throw std::runtime_error("no job list '" + file + "'");
  std::istringstream in(synth::read_file(file));
  std::vector<Job> jobs;
  std::size_t line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (line.empty()) continue;
    try {
      jobs.push_back(job_from_json(json::parse(line)));
    } catch (const std::exception& e) {
      throw std::runtime_error(file + ":" + std::to_string(line_no) + ": not a job: " + e.what());
    }
    if (jobs.back().index != jobs.size() - 1)
      throw std::runtime_error(file + ":" + std::to_string(line_no) + ": job index " +
                               std::to_string(jobs.back().index) + " out of order");
  }
  return jobs;
}

namespace {

json options_json(const SlurmOptions& o) {
  return json{{"exe", o.exe},   {"partition", o.partition}, {"time", o.time},       {"mem", o.mem},
              {"cpus", o.cpus}, {"max_parallel", o.max_parallel}, {"timeout_s", o.timeout_s},
              {"job_name", o.job_name}};
}

SlurmOptions options_from_json(const json& j) {
  SlurmOptions o;
  o.exe = j.at("exe").get<std::string>();
  o.partition = j.value("partition", "");
  o.time = j.value("time", "");
  o.mem = j.value("mem", "");
  o.cpus = j.value("cpus", 0);
  o.max_parallel = j.value("max_parallel", 0);
  o.timeout_s = j.value("timeout_s", 0.0);
  o.job_name = j.value("job_name", "rayunits-sweep");
  return o;
}

std::string number_text(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

}  // namespace

void check_slurm_options(const SlurmOptions& o) {
  auto bad = [](const std::string& opt, const std::string& v, const std::string& want) {
    std::string shown;  // one line: control characters as \xNN
    for (unsigned char c : v) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      shown += c < 0x20 || c == 0x7f ? std::string(buf) : std::string(1, static_cast<char>(c));
    }
    throw std::invalid_argument(opt + " '" + shown + "': expected " + want);
  };
  static const std::regex partition("[A-Za-z0-9_.+-]+(,[A-Za-z0-9_.+-]+)*");
  static const std::regex time("[0-9]+|[0-9]+:[0-9]+|[0-9]+:[0-9]+:[0-9]+|[0-9]+-[0-9]+|[0-9]+-[0-9]+:[0-9]+|"
                               "[0-9]+-[0-9]+:[0-9]+:[0-9]+");
  static const std::regex mem("[0-9]+[KMGT]?");
  if (!o.partition.empty() && !std::regex_match(o.partition, partition))
    bad("--partition", o.partition, "a partition name or a comma-separated list (letters, digits, _ . + -)");
  if (!o.time.empty()) {
    if (!std::regex_match(o.time, time))
      bad("--time", o.time, "minutes, M:S, H:M:S, D-H, D-H:M or D-H:M:S (Slurm's --time)");
    if (o.time.find_first_not_of("0:-") == std::string::npos) bad("--time", o.time, "a time limit above zero");
  }
  if (!o.mem.empty() && !std::regex_match(o.mem, mem))
    bad("--mem", o.mem, "a size in megabytes or with a unit suffix K, M, G or T (e.g. 4G)");
  if (o.cpus < 0 || o.cpus > 100000) bad("--cpus", std::to_string(o.cpus), "1..100000");
  if (o.max_parallel < 0) bad("--max-parallel", std::to_string(o.max_parallel), "a count of at least 1");
  if (o.exe.empty() || o.exe[0] != '/') bad("the rayunits executable", o.exe, "an absolute path");
  if (!sbatch_plain(o.job_name)) bad("the job name", o.job_name, "letters, digits and _ . + - = : , @ /");
}

std::string array_spec(std::vector<std::size_t> idx, int max_parallel) {
  std::sort(idx.begin(), idx.end());
  idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
  if (idx.empty()) throw std::invalid_argument("array_spec: no index");
  std::string s;
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t k = i;
    while (k + 1 < idx.size() && idx[k + 1] == idx[k] + 1) ++k;
    s += (s.empty() ? "" : ",") + std::to_string(idx[i]);
    if (k > i) s += "-" + std::to_string(idx[k]);
    i = k + 1;
  }
  if (max_parallel > 0) s += "%" + std::to_string(max_parallel);
  return s;
}

std::string sbatch_script(const std::string& dir, const std::vector<std::size_t>& indices, const SlurmOptions& o) {
  check_slurm_options(o);
  const std::string jobs_file = (fs::path(dir) / "jobs.jsonl").string();
  std::string s = "#!/bin/bash\n";
  s += "#SBATCH --job-name=" + o.job_name + "\n";
  s += "#SBATCH --array=" + array_spec(indices, o.max_parallel) + "\n";
  if (!o.partition.empty()) s += "#SBATCH --partition=" + o.partition + "\n";
  if (!o.time.empty()) s += "#SBATCH --time=" + o.time + "\n";
  if (!o.mem.empty()) s += "#SBATCH --mem=" + o.mem + "\n";
  if (o.cpus > 0) s += "#SBATCH --cpus-per-task=" + std::to_string(o.cpus) + "\n";
  // sbatch reads #SBATCH lines without a shell: a path that would need quoting there is left
  // out (Slurm then writes slurm-%A_%a.out into the directory sbatch was run from).
  const std::string out = (fs::path(dir) / "slurm" / "%A_%a.out").string();
  if (sbatch_plain(dir))
    s += "#SBATCH --output=" + out + "\n";
  else
    s += "# (no --output: the sweep directory's path needs quoting; pass sbatch --output=... yourself)\n";
  s += "# Generated by `rayunits sweep --emit-slurm` (docs/SWEEPS.md). Each array task runs one job of\n"
       "# jobs.jsonl and writes results/<index>.json; `rayunits sweep --collect` merges them.\n"
       "set -eu\n";
  std::vector<std::string> argv = {o.exe, "sweep"};
  if (o.timeout_s > 0) argv.push_back("--timeout=" + number_text(o.timeout_s));
  s += "exec";
  for (const auto& a : argv) s += " " + util::shell_quote(a);
  s += " --run-job " + util::shell_quote(jobs_file + ":") + "\"${SLURM_ARRAY_TASK_ID:?not a Slurm array task}\"\n";
  return s;
}

std::string emit_slurm(const std::vector<Job>& jobs, const std::string& dir_, const SlurmOptions& o,
                       const std::string& grid_text) {
  if (jobs.empty()) throw std::invalid_argument("no jobs to emit");
  const fs::path dir = fs::absolute(dir_).lexically_normal();
  std::vector<std::size_t> all;
  for (const Job& j : jobs) all.push_back(j.index);
  const std::string script = sbatch_script(dir.string(), all, o);  // checks the options first
  for (const char* sub : {"results", "logs", "slurm", "out"}) fs::create_directories(dir / sub);
  synth::write_file_atomic((dir / "jobs.jsonl").string(), jobs_jsonl(jobs));
  synth::write_file_atomic((dir / "slurm.json").string(), options_json(o).dump(2) + "\n");
  if (!grid_text.empty()) synth::write_file_atomic((dir / "grid.toml").string(), grid_text);
  std::error_code ec;
  fs::remove(dir / "rerun.sbatch", ec);  // belongs to an earlier job list
  synth::write_file_atomic((dir / "sweep.sbatch").string(), script);
  return (dir / "sweep.sbatch").string();
}

std::pair<std::string, std::size_t> parse_job_ref(const std::string& ref) {
  const std::size_t c = ref.rfind(':');
  const std::string idx = c == std::string::npos ? "" : ref.substr(c + 1);
  if (c == std::string::npos || c == 0 || idx.empty() || idx.size() > 9 ||
      idx.find_first_not_of("0123456789") != std::string::npos)
    throw std::invalid_argument("--run-job '" + ref + "': expected FILE:INDEX (e.g. DIR/jobs.jsonl:0)");
  return {ref.substr(0, c), static_cast<std::size_t>(std::stoul(idx))};
}

std::string task_result_path(const std::string& dir, std::size_t index) {
  return (fs::path(dir) / "results" / (std::to_string(index) + ".json")).string();
}

TaskOutcome run_task(const std::string& jobs_file, std::size_t index, const RunOptions& opt) {
  const std::vector<Job> jobs = read_jobs(jobs_file);
  if (index >= jobs.size())
    throw std::invalid_argument("--run-job: no job " + std::to_string(index) + " in '" + jobs_file + "' (" +
                                std::to_string(jobs.size()) + " jobs)");
  const Job& j = jobs[index];
  const std::string dir = fs::absolute(jobs_file).parent_path().string();
  fs::create_directories(fs::path(dir) / "results");
  const std::string file = task_result_path(dir, index);
  TaskOutcome t;
  if (!opt.force) {
    const json old = json::parse(slurp(file), nullptr, false);
    if (old.is_object() && old.value("hash", "") == j.hash && old.value("status", "") == "ok") {
      t.row = old;
      t.skipped = true;
      return t;
    }
  }
  t.row = run_one(j, dir, opt);
  if (t.row["status"] == "interrupted") return t;  // cancelled: no result, the task is missing
  json task = json::object();
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) == 0) task["host"] = host;
  for (const char* v : {"SLURM_ARRAY_JOB_ID", "SLURM_ARRAY_TASK_ID", "SLURM_JOB_ID"})
    if (const char* x = std::getenv(v)) task[v] = x;
  t.row["task"] = task;
  synth::write_file_atomic(file, t.row.dump() + "\n");
  t.written = true;
  return t;
}

CollectSummary collect(const std::string& dir_) {
  const fs::path dir = fs::absolute(dir_).lexically_normal();
  const std::vector<Job> jobs = read_jobs((dir / "jobs.jsonl").string());
  CollectSummary s;
  s.total = jobs.size();
  std::vector<json> rows;
  for (const Job& j : jobs) {
    const std::string file = task_result_path(dir.string(), j.index);
    const std::string rel = "results/" + std::to_string(j.index) + ".json";
    const std::string name = "task " + std::to_string(j.index) + " (" + j.label + ")";
    if (!fs::exists(file)) {
      s.missing.push_back(j.index);
      s.problems.push_back(name + ": missing (no " + rel + ")");
      continue;
    }
    const json r = json::parse(slurp(file), nullptr, false);
    std::string bad;
    if (r.is_discarded() || !r.is_object())
      bad = "unreadable " + rel + " (not one JSON object)";
    else if (!r.contains("status") || !r["status"].is_string() || !r.contains("result") || !r["result"].is_array())
      bad = rel + " has no status or result";
    else if (r.value("hash", "") != j.hash || !r.contains("index") || r["index"] != j.index)
      bad = rel + " belongs to another job (hash " + r.value("hash", "?") + ", the job's is " + j.hash + ")";
    if (!bad.empty()) {
      s.failed.push_back(j.index);
      s.problems.push_back(name + ": failed: " + bad);
      continue;
    }
    rows.push_back(r);
    if (r["status"] == "ok") {
      ++s.ok;
    } else {
      s.failed.push_back(j.index);
      s.problems.push_back(name + ": " + r["status"].get<std::string>() + ": " + r.value("error", ""));
    }
  }
  std::string jsonl;
  for (const json& r : rows) jsonl += r.dump() + "\n";  // the local runner's lines (run_jobs)
  synth::write_file_atomic((dir / "results.jsonl").string(), jsonl);
  synth::write_file_atomic((dir / "results.csv").string(), results_csv(rows));
  std::vector<std::size_t> again = s.failed;
  again.insert(again.end(), s.missing.begin(), s.missing.end());
  std::sort(again.begin(), again.end());
  const fs::path rerun = dir / "rerun.sbatch";
  if (again.empty()) {
    std::error_code ec;
    fs::remove(rerun, ec);
  } else {
    const fs::path opts = dir / "slurm.json";
    if (!fs::is_regular_file(opts))
      throw std::runtime_error("no " + opts.string() + " (the directory was not made by --emit-slurm)");
    SlurmOptions o = options_from_json(json::parse(synth::read_file(opts.string())));
    o.job_name += "-rerun";
    synth::write_file_atomic(rerun.string(), sbatch_script(dir.string(), again, o));
    s.rerun = rerun.string();
  }
  return s;
}

}  // namespace ru::sweep
