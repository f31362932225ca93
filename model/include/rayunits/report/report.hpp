// rayunits report infrastructure: a report is a directory (index.md + meta.json + the files
// its sections write: CSV, PNG, ...). A *section* is a function that writes its files into
// the report directory and returns the Markdown that index.md shows for it.
//
// Adding a section (later issues: synthesis, RTL, ...):
//   1. write `std::string my_section(ru::report::Context& ctx)` anywhere in the model library;
//      write files only under ctx.dir (use ctx.path("name.csv")), report progress with
//      ctx.progress(), poll ctx.check_cancelled() in long loops (ctx.parallel_for does),
//      run plots with ctx.run_python("plot_x.py", {...}) and declare needs_python;
//   2. register it with RU_REPORT_SECTION(...) in a file under model/cli/ (for example
//      model/cli/report_sections.cpp, which lists them). Registrations must live in a file
//      linked straight into the executable: an object file of the static model library that
//      nothing references is dropped by the linker, and its registration with it.
// The report is written into a temporary sibling directory and renamed into place only when
// every section succeeded, so a failed or interrupted run leaves no half-written report.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace ru::report {

// One-line errors (bad out dir, missing python, failed plot, interrupted run).
class ReportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Options {
  std::filesystem::path out_dir = "report";
  uint64_t seed = 1;
  unsigned threads = 0;  // 0: std::thread::hardware_concurrency()
  // The width grid every sweeping section honours: E in [exp_lo, exp_hi] x M in [frac_lo,
  // frac_hi]; cells that are not a valid format (1+E+M > 64) are skipped.
  int exp_lo = 5, exp_hi = 11, frac_lo = 8, frac_hi = 24;
  long samples = 0;                           // per grid cell; 0: each section's default
  std::vector<std::string> sections;          // ids to run; empty: every default-on section
  std::map<std::string, std::string> params;  // section-specific "--param key=value"
  std::string command;                        // the command line, recorded in the report
  bool quiet = false;                         // no progress on stderr
  bool plots = true;                          // false: sections skip their plots (no python)
  // Cell-flow rows of the synthesis and noise sections: read from these checked-in results
  // (files or directories, ru::synth::CheckedInRows::load) when current; empty: the defaults
  // (sweeps/results/default and synth/results/cell of the source tree). live_synth: never read.
  std::vector<std::string> checked_in;
  bool live_synth = false;
};

class Context;

struct Section {
  const char* id;     // short name: file prefix, anchor, --sections value
  const char* title;  // heading in index.md
  int order;          // position in the report (ascending)
  std::string (*run)(Context& ctx);  // writes files into ctx.dir, returns Markdown
  bool needs_python = false;         // checked before any section runs (unless opts.plots is off)
  bool default_on = true;
};

bool register_section(const Section& s);
std::vector<Section> sections();  // sorted by order

class Context {
 public:
  Context(const Options& o, std::filesystem::path d, unsigned threads) : opts(o), dir(std::move(d)), threads_(threads) {}

  const Options& opts;
  const std::filesystem::path dir;  // the (temporary) report directory; write only here
  std::string section;              // id of the running section

  // Typed results a section leaves for later ones (sections run in order): the accuracy
  // section's cells by "eXmY op" (op: add, mul, div, dot3), read by the synthesis section's
  // speed-and-accuracy table. Empty when the accuracy section did not run in this report.
  struct AccuracyCell {
    double mean_rel = 0, max_rel = 0;
    long out_of_range = 0;
  };
  std::map<std::string, AccuracyCell> accuracy;

  std::filesystem::path path(const std::string& file) const { return dir / file; }
  unsigned threads() const { return threads_; }
  std::string param(const std::string& key, const std::string& dflt) const;

  // "report: <section>: <msg>" on stderr (unless quiet).
  void progress(const std::string& msg) const;
  // Throws ReportError("interrupted") once SIGINT/SIGTERM arrived during the run.
  void check_cancelled() const;
  // Runs fn(i) for i in [0, n) on threads(); prints "<what> k/n" progress at most every 2 s;
  // rethrows the first exception of any worker (the others stop at their next item).
  void parallel_for(size_t n, const std::string& what, const std::function<void(size_t)>& fn) const;
  // Runs `<python> <scripts dir>/<script> args...`; throws ReportError if it fails.
  // Sections call it only when opts.plots is set.
  void run_python(const std::string& script, const std::vector<std::string>& args) const;

 private:
  unsigned threads_;
};

struct Summary {
  std::filesystem::path dir;  // the final report directory
  std::vector<std::string> sections;
  double seconds = 0;
};

// Runs the selected sections and moves the finished report to opts.out_dir. If out_dir
// exists it must be a directory that an earlier run wrote (it holds .rayunits-report) or
// empty; it is then replaced. Throws ReportError (one line) on failure; nothing is left behind.
Summary run_report(const Options& opts);

// Tools used by the report; exposed for tests and sections.
std::string git_commit(const std::filesystem::path& source_dir);  // "unknown" if not available
std::string find_python();                 // $RU_PYTHON, else python3 on PATH, else /usr/bin/python3, with matplotlib
std::filesystem::path scripts_dir();       // $RU_SCRIPTS_DIR, else <source>/scripts
std::string utc_now_iso8601();

// index.html of a report: the Markdown the report writes as one static, self-contained page
// (images embedded as data: URIs read from `dir`, sortable tables, an inline load script that
// writes "images OK/N; sections a,b; verdict ok|broken-images" into <pre id="ru-verdict">).
// Images that cannot be read are listed in *missing_images (html.cpp).
std::string markdown_to_html(const std::string& md, const std::filesystem::path& dir, const std::string& title,
                             std::vector<std::string>* missing_images = nullptr);

// Markdown table from a header and rows (cells are inserted verbatim).
std::string md_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);

}  // namespace ru::report

#define RU_REPORT_CAT2(a, b) a##b
#define RU_REPORT_CAT(a, b) RU_REPORT_CAT2(a, b)
// RU_REPORT_SECTION(id, title, order, fn, needs_python, default_on)
#define RU_REPORT_SECTION(...)                                  \
  static const bool RU_REPORT_CAT(ru_report_section_, __LINE__) = \
      ::ru::report::register_section(::ru::report::Section{__VA_ARGS__})
