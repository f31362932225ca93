// Report infrastructure: section registry, context helpers, atomic report directory.
// See rayunits/report/report.hpp and docs/CLI.md.
#include "rayunits/report/report.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rayunits/util/git.hpp"
#include "rayunits/util/interrupt.hpp"
#include "rayunits/util/parallel.hpp"
#include "rayunits/util/process.hpp"

namespace ru::report {

namespace fs = std::filesystem;

// ------------------------------------------------------------------------------ registry
static std::vector<Section>& registry() {
  static std::vector<Section> r;
  return r;
}
bool register_section(const Section& s) {
  registry().push_back(s);
  return true;
}
std::vector<Section> sections() {
  std::vector<Section> v = registry();
  std::stable_sort(v.begin(), v.end(), [](const Section& a, const Section& b) { return a.order < b.order; });
  return v;
}

// ------------------------------------------------------------------------------ cancellation
// SIGINT/SIGTERM during a run: util::InterruptGuard (util/interrupt.hpp) sets the flag that
// check_cancelled() and parallel_for poll.

namespace {
// Removes a directory tree on scope exit unless released.
class DirGuard {
 public:
  explicit DirGuard(fs::path p) : p_(std::move(p)) {}
  ~DirGuard() {
    if (!p_.empty()) {
      std::error_code ec;
      fs::remove_all(p_, ec);
    }
  }
  void release() { p_.clear(); }

 private:
  fs::path p_;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Runs argv (argv[0] searched in PATH); returns the exit status (-1 if it could not start).
// quiet: stdout and stderr go to /dev/null.
int spawn_wait(const std::vector<std::string>& args, bool quiet) {
  util::ProcessOptions o;
  if (quiet) o.out = o.err = util::Redirect::null();
  o.in = util::Redirect::inherit();
  try {
    const util::ProcessResult r = util::run_process(args, o);
    return r.started ? r.status() : -1;
  } catch (const util::ProcessError&) {
    return -1;
  }
}
}  // namespace

// ------------------------------------------------------------------------------ context
std::string Context::param(const std::string& key, const std::string& dflt) const {
  auto it = opts.params.find(key);
  return it == opts.params.end() ? dflt : it->second;
}

void Context::progress(const std::string& msg) const {
  if (opts.quiet) return;
  std::fprintf(stderr, "report: %s: %s\n", section.c_str(), msg.c_str());
}

void Context::check_cancelled() const {
  if (util::interrupted()) throw ReportError("interrupted");
}

void Context::parallel_for(size_t n, const std::string& what, const std::function<void(size_t)>& fn) const {
  if (n == 0) return;
  const auto t0 = std::chrono::steady_clock::now();
  util::ParallelOptions po;
  po.stop = [] { return util::interrupted(); };
  po.progress = [&](size_t d, size_t total) {
    char buf[160];
    const double el = seconds_since(t0);
    double left = d ? el * static_cast<double>(total - d) / static_cast<double>(d) : 0;
    std::snprintf(buf, sizeof buf, "%s %zu/%zu (%.0f%%), %.0f s elapsed, ~%.0f s left", what.c_str(), d, total,
                  100.0 * static_cast<double>(d) / static_cast<double>(total), el, left);
    progress(buf);
  };
  util::parallel_for(n, static_cast<int>(threads_), fn, po);
  check_cancelled();
  char buf[120];
  std::snprintf(buf, sizeof buf, "%s %zu/%zu done in %.1f s", what.c_str(), n, n, seconds_since(t0));
  progress(buf);
}

void Context::run_python(const std::string& script, const std::vector<std::string>& args) const {
  fs::path sp = scripts_dir() / script;
  if (!fs::exists(sp)) throw ReportError("plot script not found: " + sp.string() + " (set RU_SCRIPTS_DIR)");
  std::vector<std::string> cmd = {find_python(), sp.string()};
  cmd.insert(cmd.end(), args.begin(), args.end());
  int rc = spawn_wait(cmd, false);
  check_cancelled();
  if (rc != 0)
    throw ReportError("plot script " + script + " failed (exit status " + std::to_string(rc) +
                      "; its messages are above)");
}

// ------------------------------------------------------------------------------ tools
std::string git_commit(const fs::path& source_dir) { return util::git_commit(source_dir.string()); }

std::string find_python() {
  static std::mutex mu;
  static std::string found;
  std::lock_guard<std::mutex> lock(mu);
  if (!found.empty()) return found;
  std::vector<std::string> candidates;
  const char* env = std::getenv("RU_PYTHON");
  if (env && *env) {
    candidates.push_back(env);
  } else {
    candidates = {"python3", "/usr/bin/python3"};
  }
  std::string tried;
  for (const auto& c : candidates) {
    int rc = spawn_wait({c, "-c", "import matplotlib; matplotlib.use('Agg'); import matplotlib.pyplot, numpy"}, true);
    if (rc == 0) return found = c;
    tried += (tried.empty() ? "" : ", ") + c;
  }
  throw ReportError("no python3 with matplotlib and numpy found (tried " + tried +
                    "); install python3-matplotlib python3-numpy (scripts/install-deps.sh) or set RU_PYTHON");
}

fs::path scripts_dir() {
  const char* env = std::getenv("RU_SCRIPTS_DIR");
  if (env && *env) return env;
#ifdef RU_SOURCE_DIR
  return fs::path(RU_SOURCE_DIR) / "scripts";
#else
  return "scripts";
#endif
}

std::string utc_now_iso8601() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string md_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  std::string s = "|";
  for (const auto& h : header) s += " " + h + " |";
  s += "\n|";
  for (size_t i = 0; i < header.size(); ++i) s += i == 0 ? "---|" : "--:|";
  s += "\n";
  for (const auto& r : rows) {
    s += "|";
    for (const auto& c : r) s += " " + c + " |";
    s += "\n";
  }
  return s;
}

// ------------------------------------------------------------------------------ run_report
static void write_file(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
  f.close();
  if (!f) throw ReportError("cannot write " + p.string());
}

Summary run_report(const Options& opts) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string date = utc_now_iso8601();

  // Which sections.
  std::vector<Section> all = sections(), chosen;
  std::string known;
  for (const auto& s : all) known += (known.empty() ? "" : ", ") + std::string(s.id);
  if (opts.sections.empty()) {
    for (const auto& s : all)
      if (s.default_on) chosen.push_back(s);
  } else {
    for (const auto& id : opts.sections) {
      auto it = std::find_if(all.begin(), all.end(), [&](const Section& s) { return id == s.id; });
      if (it == all.end()) throw ReportError("unknown report section '" + id + "' (sections: " + known + ")");
      chosen.push_back(*it);
    }
  }
  if (chosen.empty()) throw ReportError("no report sections selected (sections: " + known + ")");
  for (const auto& s : chosen)
    if (s.needs_python && opts.plots) {
      find_python();  // fail before hours of work, not after
      break;
    }

  // Where: a temporary sibling of the output directory, renamed into place at the end.
  fs::path out = fs::absolute(opts.out_dir).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();
  const std::string shown = opts.out_dir.string();
  std::error_code ec;
  if (fs::exists(out, ec)) {
    if (!fs::is_directory(out, ec)) throw ReportError("output '" + shown + "' exists and is not a directory");
    bool empty = fs::is_empty(out, ec);
    if (!empty && !fs::exists(out / ".rayunits-report", ec))
      throw ReportError("output directory '" + shown +
                        "' exists and is not a rayunits report (no .rayunits-report file); remove it or choose "
                        "another --out");
  }
  fs::path parent = out.parent_path();
  fs::create_directories(parent, ec);
  if (ec) throw ReportError("cannot create directory '" + parent.string() + "': " + ec.message());
  std::string tmpl = (parent / ("." + out.filename().string() + ".tmp-XXXXXX")).string();
  if (!mkdtemp(tmpl.data()))
    throw ReportError("cannot write report directory '" + shown + "': " + std::strerror(errno));
  fs::path tmp = tmpl;
  DirGuard guard(tmp);
  util::InterruptGuard signals;

  unsigned threads = opts.threads ? opts.threads : util::hardware_threads();
  Context ctx(opts, tmp, threads);
  std::string commit = git_commit(
#ifdef RU_SOURCE_DIR
      RU_SOURCE_DIR
#else
      fs::current_path()
#endif
  );

  struct Done {
    Section s;
    std::string md;
    double seconds;
  };
  std::vector<Done> done;
  for (const auto& s : chosen) {
    ctx.section = s.id;
    ctx.check_cancelled();
    auto ts = std::chrono::steady_clock::now();
    ctx.progress("started");
    std::string md = s.run(ctx);
    double sec = seconds_since(ts);
    char buf[64];
    std::snprintf(buf, sizeof buf, "finished in %.1f s", sec);
    ctx.progress(buf);
    done.push_back({s, md, sec});
  }
  ctx.check_cancelled();
  const double total = seconds_since(t0);

  // index.md
  std::ostringstream md;
  char grid[128];
  std::snprintf(grid, sizeof grid, "E %d..%d x M %d..%d", opts.exp_lo, opts.exp_hi, opts.frac_lo, opts.frac_hi);
  char secs[32];
  std::snprintf(secs, sizeof secs, "%.1f s", total);
  md << "# rayunits report\n\n"
     << md_table({"", ""}, {{"command", "`" + opts.command + "`"},
                            {"commit", commit},
                            {"seed", std::to_string(opts.seed)},
                            {"date (UTC)", date},
                            {"width grid", grid},
                            {"threads", std::to_string(threads)},
                            {"run time", secs}})
     << "\nRerun with the command above (same commit and seed give the same numbers).\n\n## Contents\n\n";
  for (size_t i = 0; i < done.size(); ++i)
    md << (i + 1) << ". [" << done[i].s.title << "](#" << done[i].s.id << ")\n";
  for (size_t i = 0; i < done.size(); ++i)
    md << "\n<a id=\"" << done[i].s.id << "\"></a>\n\n## " << (i + 1) << ". " << done[i].s.title << "\n\n"
       << done[i].md << (done[i].md.empty() || done[i].md.back() == '\n' ? "" : "\n");
  write_file(tmp / "index.md", md.str());
  {
    std::vector<std::string> missing;
    const std::string html = markdown_to_html(md.str(), tmp, "rayunits report", &missing);
    if (!missing.empty())
      throw ReportError("index.md names an image the report did not write: " + missing.front());
    write_file(tmp / "index.html", html);
  }

  nlohmann::json meta;
  meta["command"] = opts.command;
  meta["commit"] = commit;
  meta["seed"] = opts.seed;
  meta["date_utc"] = date;
  meta["threads"] = threads;
  meta["grid"] = {{"exp_lo", opts.exp_lo}, {"exp_hi", opts.exp_hi}, {"frac_lo", opts.frac_lo}, {"frac_hi", opts.frac_hi}};
  meta["samples"] = opts.samples;
  meta["params"] = opts.params;
  meta["plots"] = opts.plots;
  meta["seconds"] = total;
  for (const auto& d : done) meta["sections"].push_back({{"id", d.s.id}, {"title", d.s.title}, {"seconds", d.seconds}});
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(tmp))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), tmp).string());
  files.push_back("meta.json");
  std::sort(files.begin(), files.end());
  meta["files"] = files;
  write_file(tmp / "meta.json", meta.dump(2) + "\n");
  write_file(tmp / ".rayunits-report", "written by rayunits report; this directory is replaced by the next run\n");

  // Commit: move an old report aside, move the new one in, delete the old one.
  fs::path old;
  if (fs::exists(out, ec)) {
    std::string otmpl = (parent / ("." + out.filename().string() + ".old-XXXXXX")).string();
    if (!mkdtemp(otmpl.data()))
      throw ReportError("cannot replace '" + shown + "': " + std::strerror(errno));
    old = otmpl;
    fs::rename(out, old, ec);  // onto the empty directory mkdtemp made
    if (ec) {
      fs::remove(old);
      throw ReportError("cannot replace '" + shown + "': " + ec.message());
    }
  }
  fs::rename(tmp, out, ec);
  if (ec) {
    std::error_code ec2;
    if (!old.empty()) fs::rename(old, out, ec2);
    throw ReportError("cannot move the report into '" + shown + "': " + ec.message());
  }
  guard.release();
  if (!old.empty()) fs::remove_all(old, ec);

  Summary sum;
  sum.dir = out;
  for (const auto& d : done) sum.sections.push_back(d.s.id);
  sum.seconds = total;
  return sum;
}

}  // namespace ru::report
