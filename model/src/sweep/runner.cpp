// rayunits sweep: the local runner and the results table (rayunits/sweep/sweep.hpp).
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <csignal>
#include <condition_variable>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "rayunits/sweep/sweep.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/csv.hpp"
#include "rayunits/util/interrupt.hpp"
#include "rayunits/util/parallel.hpp"
#include "rayunits/util/process.hpp"

namespace ru::sweep {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

[[noreturn]] void io_fail(const std::string& what, const std::string& path) {
  throw std::runtime_error("cannot " + what + " '" + path + "': " + std::strerror(errno));
}

// The text of a file; "" when there is none.
std::string slurp(const std::string& path) { return fs::is_regular_file(path) ? synth::read_file(path) : ""; }

// Appends one whole line with a single write() and makes it durable before returning.
void append_line(const std::string& path, const std::string& line) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) io_fail("open", path);
  std::size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = ::write(fd, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      ::close(fd);
      io_fail("write", path);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) io_fail("write", path);
}

// A torn last line (power loss, a full disk) is cut off so that appends start on a line boundary.
void trim_torn_tail(const std::string& path) {
  const std::string text = slurp(path);
  if (text.empty() || text.back() == '\n') return;
  const std::size_t keep = text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1;
  if (::truncate(path.c_str(), static_cast<off_t>(keep)) != 0) io_fail("truncate", path);
}

std::string now_iso() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string duration_text(double s) {
  char buf[32];
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%dm%02ds", int(s / 60), int(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", int(s / 3600), int(s / 60) % 60);
  return buf;
}

// The last non-empty line of a log (a failed command's error line), at most 400 characters.
std::string last_line(const std::string& log) {
  std::istringstream in(slurp(log));
  std::string line, last;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty() && line[0] != '#') last = line;
  }
  return last.size() > 400 ? last.substr(0, 400) + "..." : last;
}

json csv_value(const std::string& s) {
  if (s.empty()) return s;
  char* end = nullptr;
  errno = 0;
  const long long i = std::strtoll(s.c_str(), &end, 10);
  if (!*end && !errno) return i;
  const double d = std::strtod(s.c_str(), &end);
  if (!*end && std::isfinite(d)) return d;
  return s;
}

// The typed result a job wrote: JSON Lines (synth --json, rtl --json), one JSON value (trax), CSV with a header line (the studies'
// tables; "# ..." lines skipped) or a picture (render: its path and size).
json read_result(const fs::path& file, const std::string& rel) {
  if (!fs::is_regular_file(file)) throw std::runtime_error("no result file " + rel);
  json rows = json::array();
  const std::string ext = file.extension().string();
  if (ext == ".json") {  // one JSON value (trax's summary.json): an object is one row
    json v = json::parse(slurp(file.string()));
    if (v.is_array())
      rows = v;
    else
      rows.push_back(v);
  } else if (ext == ".jsonl") {
    std::istringstream in(slurp(file.string()));
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) rows.push_back(json::parse(line));
  } else if (ext == ".csv") {
    const auto t = util::csv_read_file(file.string(), '#');
    if (t.empty()) throw std::runtime_error("empty result file " + rel);
    for (std::size_t r = 1; r < t.size(); ++r) {
      json o = json::object();
      for (std::size_t c = 0; c < t[0].size() && c < t[r].size(); ++c) o[t[0][c]] = csv_value(t[r][c]);
      rows.push_back(o);
    }
  } else {
    rows.push_back(json{{"file", rel}, {"bytes", fs::file_size(file)}});
  }
  if (rows.empty()) throw std::runtime_error("no result rows in " + rel);
  return rows;
}

void flatten(const json& v, const std::string& prefix, std::map<std::string, std::string>& out) {
  if (v.is_object()) {
    for (auto it = v.begin(); it != v.end(); ++it) flatten(it.value(), prefix.empty() ? it.key() : prefix + "." + it.key(), out);
  } else if (v.is_string()) {
    out[prefix] = v.get<std::string>();
  } else if (v.is_null()) {
    out[prefix] = "";
  } else {
    out[prefix] = v.dump();  // numbers as JSON writes them (round-trip), arrays as JSON
  }
}

// An exclusive lock on DIR/.lock for the runner's lifetime: one runner per sweep directory.
class DirLock {
 public:
  explicit DirLock(const std::string& dir) {
    const std::string p = dir + "/.lock";
    fd_ = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) io_fail("open", p);
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      throw std::runtime_error("another `rayunits sweep` is running in '" + dir + "'");
    }
  }
  ~DirLock() { ::close(fd_); }
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace

std::vector<json> read_results(const std::string& dir) {
  std::istringstream in(slurp(dir + "/results.jsonl"));
  std::map<std::string, std::size_t> at;
  std::vector<json> rows;
  for (std::string line; std::getline(in, line);) {
    if (in.eof()) break;  // no '\n': a torn line
    json r = json::parse(line, nullptr, false);
    if (r.is_discarded() || !r.is_object() || !r.contains("hash")) continue;
    const std::string h = r["hash"].get<std::string>();
    auto it = at.find(h);
    if (it != at.end()) rows[it->second] = json();  // superseded
    at[h] = rows.size();
    rows.push_back(std::move(r));
  }
  std::vector<json> out;
  for (auto& r : rows)
    if (!r.is_null()) out.push_back(std::move(r));
  return out;
}

std::vector<json> current_results(const std::string& dir) {
  const fs::path jobs_file = fs::path(dir) / "jobs.jsonl";
  if (!fs::exists(jobs_file)) return read_results(dir);
  std::map<std::string, json> latest;
  for (json& r : read_results(dir)) {
    const std::string h = r.value("hash", "");  // (not in the subscript: the move is sequenced first)
    latest[h] = std::move(r);
  }
  std::vector<json> rows;
  for (const Job& j : read_jobs(jobs_file.string()))
    if (latest.count(j.hash)) rows.push_back(latest[j.hash]);
  return rows;
}

std::string results_csv(const std::vector<json>& rows) {
  const std::vector<std::string> fixed = {"hash", "index", "kind", "status", "wall_s", "error"};
  std::vector<std::string> pcols, rcols;
  std::set<std::string> pseen, rseen;
  std::vector<std::pair<std::map<std::string, std::string>, std::vector<std::map<std::string, std::string>>>> flat;
  for (const json& r : rows) {
    std::map<std::string, std::string> base, params;
    for (const auto& k : fixed)
      if (r.contains(k)) flatten(r[k], k, base);
    flatten(r.value("params", json::object()), "", params);
    for (const auto& [k, v] : params) {
      base[k] = v;
      if (pseen.insert(k).second) pcols.push_back(k);
    }
    std::vector<std::map<std::string, std::string>> res;
    for (const json& row : r.value("result", json::array())) {
      std::map<std::string, std::string> f;
      flatten(row, "", f);
      for (const auto& [k, v] : f)
        if (!pseen.count(k) && rseen.insert(k).second) rcols.push_back(k);
      res.push_back(std::move(f));
    }
    flat.emplace_back(std::move(base), std::move(res));
  }
  std::vector<std::string> cols = fixed;
  cols.insert(cols.end(), pcols.begin(), pcols.end());
  for (const auto& c : rcols)
    if (std::find(cols.begin(), cols.end(), c) == cols.end()) cols.push_back(c);
  std::string out = util::csv_row(cols);
  for (auto& [base, res] : flat) {
    if (res.empty()) res.emplace_back();
    for (const auto& f : res) {
      std::vector<std::string> cells;
      for (const auto& c : cols) {
        auto b = base.find(c);
        auto x = f.find(c);
        cells.push_back(b != base.end() ? b->second : x != f.end() ? x->second : "");
      }
      out += util::csv_row(cells);
    }
  }
  return out;
}

// What argv[0] of a job execs. This program itself (the executable named by /proc/self/exe when
// the sweep started) runs as "/proc/self/exe": a forked child execs the image of its parent, so a
// sweep keeps running the binary it started with even when a rebuild replaces the file during a
// long run (the new binary's jobs would have other hashes and possibly other rows). Any other
// executable runs as given. "This program" is fixed by the first call (run_jobs makes it at its
// start; a Slurm task at its one job's start).
const std::string& started_as() {
  static const std::string self = util::self_exe();
  return self;
}
std::string exec_path(const std::string& exe) {
  const std::string& self = started_as();
  return !self.empty() && (exe == self || exe == "/proc/self/exe") ? std::string("/proc/self/exe") : exe;
}

json run_one(const Job& j, const std::string& dir_, const RunOptions& opt) {
  const fs::path dir = fs::absolute(dir_);
  const std::string log_rel = "logs/" + j.hash + ".log";
  const std::string log = (dir / log_rel).string();
  fs::create_directories(dir / "logs");
  fs::create_directories(dir / j.out_dir);
  std::error_code ec;
  fs::remove(dir / j.result, ec);  // a stale result of an earlier attempt must not count
  std::vector<std::string> argv = j.argv;
  argv[0] = opt.exe;
  {
    std::ofstream h(log, std::ios::binary | std::ios::trunc);
    h << "# " << j.label << "\n# cwd " << dir.string() << "\n# " << util::shell_join(argv) << "\n";
  }
  argv[0] = exec_path(opt.exe);
  util::ProcessOptions p;
  p.cwd = dir.string();
  p.timeout_s = opt.timeout_s;
  p.out = util::Redirect::file(log, true);
  p.err_to_out = true;
  p.parent_death_signal = SIGTERM;  // a killed runner takes its jobs along
  util::ProcessResult r;
  try {
    r = util::run_process(argv, p);
  } catch (const std::exception& e) {
    r.started = false;
    r.error = e.what();
  }
  json row = {{"hash", j.hash},     {"index", j.index}, {"kind", j.kind},   {"label", j.label},
              {"params", j.params}, {"deps", j.deps},   {"argv", j.argv},   {"log", log_rel},
              {"wall_s", std::round(r.seconds * 1000) / 1000}, {"exit", r.status()},
              {"finished", now_iso()}};
  std::string status = "ok", error;
  if (r.interrupted) {
    status = "interrupted";
  } else if (r.timed_out) {
    status = "timeout";
    error = "timed out after " + duration_text(opt.timeout_s) + " (--timeout)";
  } else if (!r.started) {
    status = "failed";
    error = r.error.empty() ? "cannot run " + argv[0] : r.error;
  } else if (r.status() != 0) {
    status = "failed";
    error = last_line(log);
    if (error.empty()) error = "exit status " + std::to_string(r.status());
  } else {
    try {
      row["result"] = read_result(dir / j.result, j.result);
    } catch (const std::exception& e) {
      status = "failed";
      error = e.what();
    }
  }
  if (!row.contains("result")) row["result"] = json::array();
  row["status"] = status;
  row["error"] = error;
  return row;
}

RunSummary run_jobs(const std::vector<Job>& jobs, const RunOptions& opt) {
  if (opt.exe.empty()) throw std::runtime_error("run_jobs: no rayunits executable");
  started_as();
  const fs::path dir = fs::absolute(opt.dir);
  fs::create_directories(dir / "logs");
  fs::create_directories(dir / "out");
  DirLock lock(dir.string());
  synth::write_file_atomic((dir / "jobs.jsonl").string(), jobs_jsonl(jobs));
  if (!opt.grid_text.empty()) synth::write_file_atomic((dir / "grid.toml").string(), opt.grid_text);
  const std::string results = (dir / "results.jsonl").string();
  if (fs::exists(results)) trim_torn_tail(results);

  std::map<std::string, json> latest;  // hash -> its last row
  for (json& r : read_results(dir.string())) {
    const std::string h = r["hash"].get<std::string>();
    latest[h] = std::move(r);
  }
  auto write_csv = [&] {
    std::vector<json> rows;
    for (const Job& j : jobs)
      if (latest.count(j.hash)) rows.push_back(latest[j.hash]);
    synth::write_file_atomic((dir / "results.csv").string(), results_csv(rows));
  };

  RunSummary sum;
  sum.total = jobs.size();
  std::vector<const Job*> todo;
  for (const Job& j : jobs) {
    auto it = latest.find(j.hash);
    if (!opt.force && it != latest.end() && it->second.value("status", "") == "ok")
      ++sum.skipped;
    else
      todo.push_back(&j);
  }
  const int workers = std::max(1, std::min<int>(opt.jobs, static_cast<int>(std::max<std::size_t>(1, todo.size()))));
  auto say = [&](const std::string& s) {
    if (opt.progress) opt.progress(s);
  };
  say("[sweep] " + std::to_string(jobs.size()) + " jobs: " + std::to_string(todo.size()) + " to run, " +
      std::to_string(sum.skipped) + " with an ok result (skipped" + (opt.force ? "" : "; --force reruns them") +
      "), " + std::to_string(workers) + " worker(s), " + dir.string());
  write_csv();
  auto csv_at = std::chrono::steady_clock::now();
  bool csv_stale = false;

  std::mutex m;
  std::size_t finished = 0, running = 0;
  std::set<std::string> running_labels;
  const auto t0 = std::chrono::steady_clock::now();
  auto last_line_at = t0;
  auto eta = [&] {
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::size_t left = todo.size() - finished;
    if (!left) return std::string("0s");
    if (!finished) return std::string("?");
    return duration_text(el / static_cast<double>(finished) * static_cast<double>(left));
  };
  auto status_line = [&] {  // under m
    return "[sweep] " + std::to_string(finished) + "/" + std::to_string(todo.size()) + " done (" +
           std::to_string(sum.failed) + " failed), " + std::to_string(running) + " running, ETA " + eta();
  };
  // Heartbeat: the status and what is running when no job finished for a while.
  std::condition_variable cv;
  bool over = false;
  std::thread beat([&] {
    if (!(opt.heartbeat_s > 0)) return;
    std::unique_lock<std::mutex> l(m);
    while (!over) {
      cv.wait_for(l, std::chrono::duration<double>(opt.heartbeat_s));
      if (over) break;
      if (std::chrono::steady_clock::now() - last_line_at < std::chrono::duration<double>(opt.heartbeat_s)) continue;
      std::string names;
      for (const auto& n : running_labels) names += (names.empty() ? ": " : "; ") + n;
      say(status_line() + names);
      last_line_at = std::chrono::steady_clock::now();
    }
  });
  struct Stop {  // ends the heartbeat however the loop below ends
    std::mutex& m;
    std::condition_variable& cv;
    bool& over;
    std::thread& t;
    ~Stop() {
      {
        std::lock_guard<std::mutex> l(m);
        over = true;
      }
      cv.notify_all();
      t.join();
    }
  } stop_beat{m, cv, over, beat};
  util::ParallelOptions po;
  po.stop = [] { return util::interrupted(); };
  util::parallel_for(
      todo.size(), workers,
      [&](std::size_t i) {
        const Job& j = *todo[i];
        {
          std::lock_guard<std::mutex> l(m);
          ++running;
          running_labels.insert(j.label);
        }
        json row = run_one(j, dir.string(), opt);
        const std::string status = row["status"], error = row["error"];
        std::lock_guard<std::mutex> l(m);
        --running;
        running_labels.erase(j.label);
        if (status == "interrupted") {
          ++sum.not_run;
          return;  // not recorded: the job runs again next time
        }
        append_line(results, row.dump() + "\n");
        latest[j.hash] = row;
        if (std::chrono::steady_clock::now() - csv_at >= std::chrono::duration<double>(opt.csv_period_s)) {
          write_csv();  // at most every csv_period_s: a rewrite costs O(rows), and rows grow
          csv_at = std::chrono::steady_clock::now();
          csv_stale = false;
        } else {
          csv_stale = true;
        }
        ++finished;
        (status == "ok" ? sum.ok : sum.failed)++;
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.1f s", row["wall_s"].get<double>());
        say(status_line() + ": " + j.label + ": " + status + " " + buf + (error.empty() ? "" : " (" + error + ")"));
        last_line_at = std::chrono::steady_clock::now();
      },
      po);
  if (csv_stale) write_csv();
  sum.interrupted = util::interrupted();
  if (sum.interrupted) sum.not_run = todo.size() - finished;
  return sum;
}

}  // namespace ru::sweep
