// Report sections built from the project's studies: synthesis (issue 3 section 5), intersection
// (issue 4 section 6) and noise (issue 5 section 6).
//
// Each section calls the function its command calls (synth::run_sweep_rows, run_tri_study,
// run_box_study, run_watertight_study in model/cli/studies.hpp, noise::run_study_result) with the
// options that the command line shown in the report sets, and builds its tables from the typed
// results. A study's printout (what the command prints) is kept as a text file of the report.
// The command lines are printed relative to the report directory, so every table can be
// reproduced with `cd REPORT && rayunits ...`.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/noise/study.hpp"
#include "rayunits/report/report.hpp"
#include "rayunits/synth/checked_in.hpp"
#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/process.hpp"
#include "rayunits/sweep/sweep.hpp"
#include "rayunits/synth/sweep.hpp"
#include "studies.hpp"

namespace ru::cli {
namespace {

using ru::report::Context;
using ru::report::ReportError;
using Table = std::vector<std::vector<std::string>>;

// ---- calling the studies ----------------------------------------------------------------------

// The command line as shown in the report (and recorded by the studies): paths inside the
// report directory made relative, so `cd REPORT && <line>` reproduces the table.
std::string shown(const Context& ctx, const std::string& cmd, const std::vector<std::string>& args) {
  const std::string dir = ctx.dir.string() + "/";
  std::vector<std::string> rel{cmd};
  for (std::string r : args) {
    for (size_t p; (p = r.find(dir)) != std::string::npos;) r.erase(p, dir.size());
    rel.push_back(r);
  }
  std::vector<char*> av;
  for (auto& r : rel) av.push_back(r.data());
  return command_line(("rayunits " + cmd).c_str(), static_cast<int>(av.size()), av.data());
}

std::string relative(const Context& ctx, std::string text) {
  const std::string dir = ctx.dir.string() + "/";
  for (size_t q; (q = text.find(dir)) != std::string::npos;) text.erase(q, dir.size());
  return text;
}

void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::trunc);
  f << text;
  if (!f) throw ReportError("cannot write " + p.string());
}

// A study's printout (what the command prints on stdout) into <txt>, paths relative to the
// report; its warnings into <txt minus .txt>.log with --quiet, else on stderr.
class Printout {
 public:
  Printout(Context& ctx, std::string txt) : ctx_(ctx), txt_(std::move(txt)) {
    out = open_memstream(&buf_, &len_);
    if (!out) throw ReportError("cannot capture the printout of " + txt_);
    if (ctx.opts.quiet) {
      const std::string log = txt_.substr(0, txt_.rfind('.')) + ".log";
      err = std::fopen(ctx.path(log).c_str(), "w");
      if (!err) throw ReportError("cannot write " + ctx.path(log).string());
    }
  }
  ~Printout() {
    if (out) std::fclose(out);
    std::free(buf_);
    if (err != stderr) std::fclose(err);
  }
  // Writes <txt>; returns its text.
  std::string finish() {
    std::fclose(out);
    out = nullptr;
    const std::string text = relative(ctx_, std::string(buf_, len_));
    write_text(ctx_.path(txt_), text);
    std::fflush(err);
    return text;
  }
  std::FILE* out = nullptr;
  std::FILE* err = stderr;

 private:
  Context& ctx_;
  std::string txt_;
  char* buf_ = nullptr;
  size_t len_ = 0;
};

// Runs fn() (a study); a failure becomes the report's one-line error naming the command.
template <class F>
auto call(const std::string& line, F&& fn) -> decltype(fn()) {
  try {
    return fn();
  } catch (const std::exception& e) {
    throw ReportError(line + " failed: " + e.what());
  }
}

// ---- values -------------------------------------------------------------------------------------

std::string fmt(const char* f, double v) {
  if (std::isnan(v)) return "-";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::string code_block(const std::string& cmd) { return "```sh\n" + cmd + "\n```\n\n"; }

int threads_of(const Context& ctx) { return static_cast<int>(std::max(1u, std::min(ctx.threads(), 64u))); }
std::string threads_arg(const Context& ctx) { return std::to_string(threads_of(ctx)); }

// Which iCE40 steps the synthesis section's generic sweep runs (Xilinx never: the report does not
// show it): synthesis only (LUT count) or also nextpnr (Fmax).
enum class Flow { Ice40Luts, Ice40Fmax };

struct Sweep {
  std::string cmd;                    // the command line that reproduces it
  std::vector<synth::SweepRow> rows;  // in the order of synth_sweep.csv
};


// `rayunits synth-sweep` into <dir>/<sub> (synth::run_sweep_rows, as the command runs it); the
// progress goes to <sub>.log with --quiet, else to stderr; <sub>.txt is its (empty) printout.
Sweep run_sweep(Context& ctx, const std::string& sub, const std::string& units, const std::string& formats,
                const std::string& stages, Flow flow) {
  std::vector<std::string> a{"--out", ctx.path(sub).string(), "--units", units, "--stages", stages, "-j",
                             threads_arg(ctx)};
  if (!formats.empty()) a.insert(a.end(), {"--formats", formats});
  a.push_back("--no-xilinx");
  if (flow == Flow::Ice40Fmax) a.push_back("--fpga");
  if (!ctx.opts.plots) a.push_back("--no-plot");
  Sweep s;
  s.cmd = shown(ctx, "synth-sweep", a);
  ctx.progress(s.cmd);

  // the options the command line above sets (cmd_synth_sweep.cpp, synth_options.hpp)
  synth::SweepOptions so;
  so.command = "rayunits synth-sweep";
  for (const auto& x : a) so.command += " " + x;
  so.out_dir = ctx.path(sub).string();
  so.units = split_list(units);
  if (!formats.empty()) so.formats = split_list(formats);
  so.stages = split_list(stages);
  so.jobs = threads_of(ctx);
  so.flow.xilinx = false;
  if (flow == Flow::Ice40Fmax) so.flow.ice40 = so.flow.pnr = true;
  so.plot = ctx.opts.plots;

  Printout p(ctx, sub + ".txt");
  synth::install_interrupt_handler();
  const synth::SweepResult r = call(s.cmd, [&] {
    return synth::run_sweep_rows(so, [&](const std::string& m) {
      std::fprintf(p.err, "%s\n", m.c_str());
      std::fflush(p.err);
    });
  });
  p.finish();
  if (r.failed > 0)
    throw ReportError(s.cmd + " failed: rayunits synth-sweep: error: " + std::to_string(r.failed) +
                      " point(s) failed (rows with \"error\" in " + so.out_dir + "/synth_sweep.json)");
  s.rows = r.rows;
  return s;
}

std::vector<std::string> synth_cells(const synth::SweepRow& r) {
  const std::string luts = !r.ice40_run   ? "-"
                           : r.ice40_fits ? std::to_string(r.ice40_luts)
                                          : std::to_string(r.ice40_luts) + " (does not fit)";
  // fo4-v1 is an estimate: shown as a stage delay in ps, never as a frequency (clocks: CellRows).
  return {fmt("%.0f", r.area_nand2), std::to_string(r.reg_bits), std::to_string(r.depth), fmt("%.0f", 1e6 / r.fmax_est_mhz),
          luts, r.ice40_fits ? fmt("%.1f", r.ice40_fmax_mhz) : "-"};
}

// ---- the cell-library flow: checked-in rows or live ------------------------------------------

// The two target clocks of the cell rows, those of the default grid (sweeps/default.toml) and of
// synth/cell/run.py's `ends` runs: 200 ps (every target below a unit's minimum delay gives the
// same netlist: the fastest mapping ABC finds) and 1 us (area-oriented mapping: the smallest).
constexpr double kFastPs = 200, kSmallPs = 1000000;
const char* const kClockArg = "200ps,1000000ps";

std::string source_dir() {
#ifdef RU_SOURCE_DIR
  return RU_SOURCE_DIR;
#else
  return ".";
#endif
}

// A path as shown in the report: relative to the source tree when under it.
std::string shown_path(const std::string& p) {
  const std::string root = source_dir() + "/";
  return p.rfind(root, 0) == 0 ? p.substr(root.size()) : p;
}

// The checked-in rows (--checked-in, else sweeps/results/default and synth/results/cell), read
// once per report; a malformed file is the report's one-line error.
const synth::CheckedInRows& checked_in(const Context& ctx) {
  static std::mutex mu;
  static std::unique_ptr<synth::CheckedInRows> rows;
  std::lock_guard<std::mutex> l(mu);
  if (!rows) {
    std::vector<std::string> paths = ctx.opts.checked_in;
    if (paths.empty()) paths = {source_dir() + "/sweeps/results/default", source_dir() + "/synth/results/cell"};
    try {
      rows = std::make_unique<synth::CheckedInRows>(synth::CheckedInRows::load(paths));
    } catch (const std::exception& e) {
      throw ReportError(std::string("checked-in results: ") + e.what() +
                        " (fix or remove the file, or pass --live-synth to synthesize every row now)");
    }
  }
  return *rows;
}

// Which rows a point needs: the cell flow at both target clocks, the cell flow at the relaxed
// clock only (the ray-triangle units: their fastest mapping takes hours), or the generic flow
// (NAND2-eq estimate).
enum class Rows { Ends, Small, Generic };

struct CellPoint {
  std::string unit, format;  // format "" for units without one
  int stages = 0;
  Rows rows = Rows::Ends;
};

// One point's rows and where they came from.
struct CellEnds {
  nlohmann::json fast, small, generic;  // null when the point does not need it
  bool read = false;        // every row read from checked-in results
  std::string source;       // table cell: "read: FILE:LINE" or "measured now (...)"
  std::string detail;       // the line of the sources list
};

std::string key_of(const std::string& unit, const std::string& format, int stages, Rows rows) {
  return unit + " " + format + " " + std::to_string(stages) + (rows == Rows::Generic ? " (generic)" : "");
}
std::string key_of(const CellPoint& p) { return key_of(p.unit, p.format, p.stages, p.rows); }

struct CellRows {
  std::string cmd;  // the command line patterns of live points
  std::map<std::string, CellEnds> rows;  // key_of
  int n_read = 0, n_live = 0;
  const CellEnds* find(const std::string& unit, const std::string& format, int stages, bool generic = false) const {
    auto it = rows.find(key_of(unit, format, stages, generic ? Rows::Generic : Rows::Ends));
    return it == rows.end() ? nullptr : &it->second;
  }
  static std::string area(const nlohmann::json& j) { return j.is_null() ? "-" : fmt("%.0f", j["area_um2"].get<double>()); }
  static std::string mhz(const nlohmann::json& j) { return j.is_null() ? "-" : fmt("%.1f", j["fmax_mhz"].get<double>()); }
  // fastest: area, Fmax, cycle (FO4); smallest: area, Fmax; source
  std::vector<std::string> cells(const std::string& unit, const std::string& format, int stages) const {
    const CellEnds* e = find(unit, format, stages);
    if (!e) return {"-", "-", "-", "-", "-", "-"};
    return {area(e->fast), mhz(e->fast), e->fast.is_null() ? "-" : fmt("%.1f", e->fast["period_fo4"].get<double>()),
            area(e->small), mhz(e->small), e->source};
  }
  // generic flow: area est. (NAND2-eq), register bits, depth (gates), stage est. (ps, fo4-v1); source
  std::vector<std::string> generic_cells(const std::string& unit, const std::string& format, int stages) const {
    const CellEnds* e = find(unit, format, stages, true);
    if (!e) return {"-", "-", "-", "-", "-"};
    const nlohmann::json& g = e->generic;
    return {fmt("%.0f", g["area_nand2"].get<double>()), std::to_string(g.value("reg_bits", 0)),
            std::to_string(g.value("depth", 0)), fmt("%.0f", g.value("stage_delay_ps", 0.0)), e->source};
  }
  // The Markdown under a table: what was read (file, line, its command and commit) and what ran now.
  std::string sources_md() const {
    std::string md = "Rows: " + std::to_string(n_read) + " point(s) read from checked-in results, " +
                     std::to_string(n_live) +
                     " measured now (`rayunits report --live-synth` measures all of them now). A row is read only "
                     "when it is for the same unit configuration, flow, target clock, placement and resource "
                     "sharing and its `rtl_hash` equals the hash of the current RTL sources; refresh the "
                     "checked-in rows with `rayunits sweep sweeps/default.toml --out sweeps/results/default -j 1` "
                     "(FP units) or `/usr/bin/python3 synth/cell/run.py` (synth/results/cell: delete the stale "
                     "point's file first; `--only REGEX` picks points).\n\n";
    for (const auto& [k, e] : rows) md += "- " + k + ": " + e.detail + "\n";
    return md + "\n";
  }
};

// The rows of the points (cell flow: rayunits synth ... --flow osu018 --clock 200ps,1000000ps or
// --clock 1000000ps; generic: --generic-only): read from the checked-in results when current,
// else measured now by the sweep engine; every row used is appended to <sub>.jsonl with its
// "report_source".
CellRows run_cell_rows(Context& ctx, const std::string& sub, const std::vector<CellPoint>& pts) {
  CellRows c;
  auto flow_args = [](Rows r) -> std::string {
    switch (r) {
      case Rows::Ends: return std::string("--flow osu018 --clock ") + kClockArg;
      case Rows::Small: return "--flow osu018 --clock 1000000ps";
      case Rows::Generic: return "--generic-only";
    }
    return "";
  };
  const synth::CheckedInRows* ci = ctx.opts.live_synth ? nullptr : &checked_in(ctx);
  const std::string rtl_dir = synth::default_rtl_dir();
  std::vector<CellEnds> out(pts.size());
  // the rows a point needs, in the order its live command writes them
  auto slots = [&](size_t i) {
    std::vector<std::pair<nlohmann::json*, double>> v;  // row, target clock (0: generic)
    switch (pts[i].rows) {
      case Rows::Ends: v = {{&out[i].fast, kFastPs}, {&out[i].small, kSmallPs}}; break;
      case Rows::Small: v = {{&out[i].small, kSmallPs}}; break;
      case Rows::Generic: v = {{&out[i].generic, 0}}; break;
    }
    return v;
  };
  std::vector<size_t> live;
  for (size_t i = 0; i < pts.size(); ++i) {
    const CellPoint& p = pts[i];
    const synth::UnitSpec& u = synth::find_unit(p.unit);
    synth::UnitConfig cfg;
    if (u.uses_format) cfg.fmt = num::Format::parse(p.format);
    cfg.stages = p.stages;
    if (!ci) {
      out[i].source = "measured now (--live-synth)";
      live.push_back(i);
      continue;
    }
    const std::string top = synth::wrapper_name(u, cfg);
    const std::string hash = synth::sources_hash(synth::resolve_sources(u, rtl_dir));
    std::vector<synth::CheckedInLookup> found;
    std::string why;
    for (const auto& [row, clock] : slots(i)) {
      found.push_back(ci->find(top, clock == 0 ? "generic" : "osu018", clock, "depth", u.synth_share, hash));
      if (!found.back().row && why.empty()) why = found.back().why_not;
    }
    if (why.empty()) {
      auto at = [](const synth::CheckedInRow& r) { return shown_path(r.file) + ":" + std::to_string(r.line); };
      auto made = [&](const synth::CheckedInRow& r) {
        return "`" + (r.command.empty() ? std::string("(no command recorded)") : r.command) + "` at " +
               (r.commit.empty() ? std::string("(no commit recorded)") : r.commit);
      };
      std::vector<std::string> files;
      // one entry per file:line (a sweep job's line holds both clocks' rows)
      std::vector<std::pair<const synth::CheckedInRow*, std::string>> lines;  // row, its clocks
      size_t k = 0;
      for (const auto& [row, clock] : slots(i)) {
        const synth::CheckedInRow& r = *found[k++].row;
        *row = r.row;
        const std::string what = clock == 0 ? std::string("generic") : clock == kFastPs ? "200 ps" : "1 us";
        auto same = std::find_if(lines.begin(), lines.end(), [&](const auto& x) { return at(*x.first) == at(r); });
        if (same == lines.end())
          lines.push_back({&r, what});
        else
          same->second += " and " + what;
      }
      out[i].detail = "read from ";
      for (size_t f = 0; f < lines.size(); ++f) {
        files.push_back(at(*lines[f].first));
        out[i].detail += std::string(f ? " and " : "") + files.back() + " (" + lines[f].second + ", made by " +
                         made(*lines[f].first) + ")";
      }
      out[i].read = true;
      out[i].source = "read: ";
      for (size_t f = 0; f < files.size(); ++f) out[i].source += (f ? ", " : "") + files[f];
      out[i].detail += ", rtl_hash " + hash + " = the current RTL";
      continue;
    }
    out[i].source = why.rfind("stale", 0) == 0 ? "measured now (checked-in row stale)" : "measured now (no checked-in row)";
    out[i].detail = "measured now: " + why;
    live.push_back(i);
  }
  if (!live.empty()) {
    // The live points as one grid of the sweep engine (one [[grid]] per point), in <sub>_sweep/.
    std::vector<Rows> kinds;
    for (size_t i : live)
      if (std::find(kinds.begin(), kinds.end(), pts[i].rows) == kinds.end()) kinds.push_back(pts[i].rows);
    for (Rows r : kinds)
      c.cmd += std::string(c.cmd.empty() ? "" : "\n") +
               "cd REPORT && rayunits synth <unit> --format <format> --stages <stages> " +
               flow_args(r) + " --json " + sub + ".jsonl   # each row below measured now";
    ctx.progress(std::to_string(live.size()) + " point(s) measured now by the sweep engine in " + sub + "_sweep/");
    std::string grid;
    for (size_t i : live) {
      grid += "[[grid]]\nkind = \"synth\"\nunit = " + nlohmann::json(pts[i].unit).dump() + "\n";
      if (!pts[i].format.empty()) grid += "format = " + nlohmann::json(pts[i].format).dump() + "\n";
      grid += "stages = " + std::to_string(pts[i].stages) + "\n";
      if (pts[i].rows == Rows::Generic)
        grid += "generic_only = true\n";
      else
        grid += std::string("flow = \"osu018\"\nclock = \"") + (pts[i].rows == Rows::Ends ? kClockArg : "1000000ps") +
                "\"\n";
    }
    sweep::Expansion ex;
    try {
      ex = sweep::expand_grid(grid, sub + " grid");
    } catch (const sweep::GridError& e) {
      throw ReportError(e.what());
    }
    if (ex.jobs.size() != live.size()) throw ReportError(sub + " grid: expected one job per point");
    sweep::RunOptions ro;
    ro.dir = ctx.path(sub + "_sweep").string();
    ro.jobs = threads_of(ctx);
    ro.exe = util::self_exe();
    ro.grid_text = grid;
    ro.progress = [&](const std::string& m) { ctx.progress(m); };
    synth::install_interrupt_handler();
    const sweep::RunSummary sum = sweep::run_jobs(ex.jobs, ro);
    if (sum.interrupted || synth::interrupted()) throw ReportError("interrupted");
    std::map<std::string, nlohmann::json> by_hash;
    for (const auto& r : sweep::read_results(ro.dir)) by_hash[r.value("hash", "")] = r;
    for (size_t k = 0; k < live.size(); ++k) {  // the grid's jobs are in the order of its [[grid]] tables
      const size_t i = live[k];
      const synth::UnitSpec& u = synth::find_unit(pts[i].unit);
      synth::UnitConfig cfg;
      if (u.uses_format) cfg.fmt = num::Format::parse(pts[i].format);
      cfg.stages = pts[i].stages;
      const std::string cmd = "rayunits synth " + synth::config_args(u, cfg) + " " + flow_args(pts[i].rows);
      const nlohmann::json& row = by_hash[ex.jobs[k].hash];
      const nlohmann::json res = row.value("result", nlohmann::json::array());
      const auto sl = slots(i);
      if (row.value("status", "") != "ok" || res.size() != sl.size())
        throw ReportError(cmd + ": " + row.value("error", std::string("no result")) + " (log " + ro.dir + "/" +
                          row.value("log", std::string("logs/")) + ")");
      for (size_t s = 0; s < sl.size(); ++s) *sl[s].first = res[s];
      if (out[i].detail.empty()) out[i].detail = "measured now (--live-synth)";
      out[i].detail += "; `" + cmd + "`";
    }
  }
  std::string jsonl;
  for (size_t i = 0; i < pts.size(); ++i) {
    for (const auto& [row, clock] : slots(i)) {
      nlohmann::json r = *row;
      r["report_source"] = out[i].source;
      jsonl += r.dump() + "\n";
    }
    (out[i].read ? c.n_read : c.n_live)++;
    c.rows[key_of(pts[i])] = std::move(out[i]);
  }
  synth::write_file_atomic(ctx.path(sub + ".jsonl").string(), jsonl);
  return c;
}

// "0,max" -> Stages per (unit, format): numbers as given, "max" the unit's maximum useful Stages.
std::vector<CellPoint> cell_points(const std::string& key, const std::vector<std::string>& units,
                                   const std::vector<std::string>& formats, const std::string& stages) {
  std::vector<CellPoint> pts;
  for (const auto& un : units) {
    const synth::UnitSpec* u = nullptr;
    for (const auto& x : synth::units())
      if (x.name == un) u = &x;
    if (!u) throw ReportError("--param " + key + ": unknown unit '" + un + "'");
    const std::vector<std::string> fl = u->uses_format ? formats : std::vector<std::string>{""};
    for (const auto& f : fl) {
      synth::UnitConfig cfg;
      try {
        if (u->uses_format) cfg.fmt = num::Format::parse(f);
      } catch (const std::exception& e) {
        throw ReportError("--param " + key + ": " + e.what());
      }
      std::vector<int> seen;
      for (const auto& t : split_list(stages)) {
        int st = 0;
        if (t == "max") {
          st = u->max_stages(cfg);
        } else {
          try {
            size_t used = 0;
            st = std::stoi(t, &used);
            if (used != t.size() || st < 0) throw std::invalid_argument(t);
          } catch (const std::exception&) {
            throw ReportError("--param " + key + ": expected Stages numbers or 'max', got '" + t + "'");
          }
        }
        if (std::find(seen.begin(), seen.end(), st) != seen.end()) continue;
        seen.push_back(st);
        pts.push_back({un, f, st});
      }
    }
  }
  return pts;
}

const std::vector<std::string> kCellHeader = {"area (um2, fastest)", "Fmax (MHz, fastest)", "cycle (FO4, fastest)",
                                              "area (um2, smallest)", "Fmax (MHz, smallest)", "cell rows"};
const char* const kCellIntro =
    "Cell flow: osu018 180 nm standard cells, timed by OpenSTA (synth/README.md, \"The cell-library flow\": area "
    "in um2, Fmax = 1 / (period - slack) through a register harness, before placement; FO4 = 98.3 ps), at the two "
    "target clocks of the default grid (sweeps/default.toml): 200 ps, the fastest mapping ABC finds, and 1 us, "
    "the smallest (area-oriented) one. The column \"cell rows\" says for each point whether its rows were read "
    "from the checked-in results (file:line) or measured by this report run; the list under the table gives each "
    "file's recorded command and commit.\n\n";

// ---- section: synthesis -----------------------------------------------------------------------

std::string synthesis_section(Context& ctx) {
  const std::string units = ctx.param("synthesis.units", "fp_add,fp_mul,fp_div");
  const std::string formats = ctx.param("synthesis.formats", "e5m10,e6m12,e7m16,e8m23");
  const std::string stages = ctx.param("synthesis.stages", "0,4");
  const std::string cell_stages = ctx.param("synthesis.cell_stages", "0,max");
  const bool fpga = ctx.param("synthesis.fpga", "1") != "0";
  const bool generic = ctx.param("synthesis.generic", "1") != "0";
  if (!ctx.opts.live_synth) checked_in(ctx);  // a malformed checked-in file fails before anything runs

  const std::vector<CellPoint> pts =
      cell_points("synthesis.units/formats/cell_stages", split_list(units), split_list(formats), cell_stages);
  const CellRows cr = run_cell_rows(ctx, "synth_osu018", pts);

  std::string md =
      "The speed side of the speed/accuracy trade: every unit mapped onto the osu018 standard-cell library, beside "
      "the generic flow's estimates (Yosys gates in NAND2 equivalents, worst-stage depth from `ltp -noff` and its "
      "fo4-v1 delay estimate) and iCE40 HX8K place and route by nextpnr. The accuracy side is the section above: "
      "its rows for the same formats are repeated here.\n\n### Cell flow (osu018, OpenSTA)\n\n" +
      std::string(kCellIntro);
  if (cr.n_live > 0) md += code_block(cr.cmd);
  {
    Table t;
    for (const auto& p : pts) {
      std::vector<std::string> row{p.unit, p.format, std::to_string(p.stages)};
      auto k = cr.cells(p.unit, p.format, p.stages);
      row.insert(row.end(), k.begin(), k.end());
      t.push_back(row);
    }
    std::vector<std::string> h{"unit", "format", "stages"};
    h.insert(h.end(), kCellHeader.begin(), kCellHeader.end());
    md += ru::report::md_table(h, t) + "\n" + cr.sources_md() +
          "Data: [synth_osu018.jsonl](synth_osu018.jsonl) (every row used, with its \"report_source\").\n\n";
  }

  if (generic) {
    const Sweep sw = run_sweep(ctx, "synth", units, formats, stages, fpga ? Flow::Ice40Fmax : Flow::Ice40Luts);
    md += "### Generic gates and iCE40 (measured now)\n\n" + code_block("cd REPORT && " + sw.cmd);
    Table t;
    for (const auto& r : sw.rows) {
      std::vector<std::string> row{r.unit, r.format, std::to_string(r.stages)};
      if (!r.error.empty()) {
        row.insert(row.end(), {"error: " + r.error, "", "", "", "", ""});
      } else {
        auto c = synth_cells(r);
        row.insert(row.end(), c.begin(), c.end());
      }
      t.push_back(row);
    }
    md += ru::report::md_table({"unit", "format", "stages", "area est. (NAND2-eq)", "register bits", "depth (gates)",
                                "stage est. (ps, fo4-v1)", "iCE40 LUTs", "iCE40 Fmax (MHz)"},
                               t);
    md += "\nData: [synth/synth_sweep.csv](synth/synth_sweep.csv), the sweep engine's job list, logs and rows in `synth/sweep/`; tool "
          "output in [synth.txt](synth.txt).\n\n";
    if (ctx.opts.plots) md += "![area vs fraction bits, Fmax vs stages](synth/synth_sweep.png)\n\n";
  }

  // Side by side with the accuracy section, when it ran in this report.
  if (!ctx.accuracy.empty()) {
    const auto& accm = ctx.accuracy;
    Table s;
    for (const auto& p : pts) {
      if (p.stages != 0) continue;
      const std::string op = p.unit.substr(3);  // fp_mul -> mul
      auto it = accm.find(p.format + " " + op);
      if (it == accm.end()) continue;
      const auto k = cr.cells(p.unit, p.format, p.stages);
      s.push_back({p.unit, p.format, k[3], k[1], fmt("%.3g", it->second.mean_rel), fmt("%.3g", it->second.max_rel),
                   std::to_string(it->second.out_of_range)});
    }
    if (!s.empty()) {
      md += "Speed and accuracy side by side (combinational units; errors from the accuracy section's workload; "
            "cell rows as in the table above):\n\n";
      md += ru::report::md_table({"unit", "format", "area (um2, smallest)", "Fmax (MHz, fastest)", "mean rel. error",
                                  "max rel. error", "out of range"},
                                 s);
    }
  }
  return md;
}

// ---- section: intersection ----------------------------------------------------------------------

std::string intersection_section(Context& ctx) {
  const std::string n_tri = ctx.param("intersection.tri_pairs", "8192");
  const std::string n_box = ctx.param("intersection.box_pairs", "100000");
  const std::string rays = ctx.param("intersection.rays", "20000");
  const std::string wt_formats = ctx.param("intersection.watertight_formats", "e5m10,e6m12,e7m16,e8m23");
  const std::string synth_formats = ctx.param("intersection.synth_formats", "e8m23");
  const bool synth = ctx.param("intersection.synth", "1") != "0";
  const std::string seed = std::to_string(ctx.opts.seed);
  auto count = [](const std::string& key, const std::string& v) {
    try {
      size_t used = 0;
      const unsigned long long n = std::stoull(v, &used);
      if (used == v.size()) return static_cast<size_t>(n);
    } catch (const std::exception&) {
    }
    throw ReportError("--param " + key + ": expected a count, got '" + v + "'");
  };
  std::string md;

  // 1. Tables 3.2-3.4: signed-volume errors, formula ranking, sign errors (`study tri`).
  {
    std::vector<std::string> a{"--synthetic", n_tri, "--seed", seed, "--out", ctx.path("tri").string(), "--threads",
                               threads_arg(ctx), "--quiet"};
    if (!ctx.opts.plots) a.push_back("--no-plot");
    const std::string cmd = shown(ctx, "study tri", a);
    ctx.progress(cmd);
    TriStudyArgs ta;
    ta.synthetic = count("intersection.tri_pairs", n_tri);
    ta.seed = ctx.opts.seed;
    ta.out_dir = ctx.path("tri").string();
    ta.threads = threads_of(ctx);
    ta.quiet = true;
    ta.no_plot = !ctx.opts.plots;
    Printout p(ctx, "tri.txt");
    call(cmd, [&] { return run_tri_study(ta, cmd, p.out, p.err); });
    const std::string text = p.finish();
    md += "### Signed-volume error (Tables 3.2-3.4), formula ranking, sign errors\n\n" +
          code_block("cd REPORT && " + cmd) +
          "Lowest average relative error of V, Va and V0..2 against exact rationals (GMP) per format, on the "
          "synthetic benchmark (random triangles about the origin, ray packets aimed for ~25 % hits). Full "
          "printout: [tri.txt](tri.txt); data: `tri/study_tri_*.csv`.\n\n```\n" +
          text + "```\n\n";
    if (ctx.opts.plots)
      for (const auto& e : std::filesystem::directory_iterator(ctx.path("tri")))
        if (e.path().extension() == ".png")
          md += "![" + e.path().stem().string() + "](tri/" + e.path().filename().string() + ")\n\n";
  }

  // 2. Ray-box false misses / false hits (`study box`).
  {
    const std::string cmd =
        shown(ctx, "study box",
              {"--synthetic", n_box, "--seed", seed, "--csv", ctx.path("box.csv").string(), "--threads",
               threads_arg(ctx), "--quiet"});
    ctx.progress(cmd);
    BoxStudyArgs ba;
    ba.synthetic = count("intersection.box_pairs", n_box);
    ba.seed = ctx.opts.seed;
    ba.csv = ctx.path("box.csv").string();
    ba.threads = threads_of(ctx);
    ba.quiet = true;
    Printout p(ctx, "box.txt");
    const BoxStudyRun run = call(cmd, [&] { return run_box_study(ba, cmd, p.out, p.err); });
    p.finish();
    Table t;
    for (const auto& c : run.cells) {
      const double pairs = static_cast<double>(c.records);
      auto ppm = [&](uint64_t n) { return fmt("%.0f", 1e6 * static_cast<double>(n) / pairs); };
      t.push_back({c.fmt.name(), ppm(c.plain_false_miss), ppm(c.plain_false_hit), ppm(c.cons_false_miss),
                   ppm(c.cons_false_hit)});
    }
    md += "### Ray-box test: false misses and false hits (per million pairs)\n\n" + code_block("cd REPORT && " + cmd) +
          "Against the exact slab test (GMP rationals). A false miss loses geometry; the conservative mode "
          "(t_enter rounded down, t_exit up) must have none. Data: [box.csv](box.csv).\n\n" +
          ru::report::md_table({"format", "plain false miss", "plain false hit", "conservative false miss",
                                "conservative false hit"},
                               t);
  }

  // 3. Watertightness: robust vs MT on a closed mesh, per format (`study watertight`).
  {
    // One grid of `study watertight` jobs (format x tri) run by the sweep engine in
    // watertight_sweep/; watertight.csv is their rows in grid order.
    std::vector<std::string> cmds, fmts;
    std::stringstream fl(wt_formats);
    for (std::string f; std::getline(fl, f, ',');) {
      try {
        num::Format::parse(f);
      } catch (const std::exception& e) {
        throw ReportError("rayunits study watertight --format " + f + " (--param intersection.watertight_formats): " +
                          e.what());
      }
      fmts.push_back(f);
    }
    const long long n_rays = count("intersection.rays", rays);
    std::string grid = "kind = \"study\"\nstudy = \"watertight\"\nscene = \"icosphere\"\nformat = [";
    for (size_t i = 0; i < fmts.size(); ++i) grid += (i ? ", " : "") + nlohmann::json(fmts[i]).dump();
    grid += "]\ntri = [\"robust\", \"mt\"]\nrays = " + std::to_string(n_rays) + "\nseed = " +
            std::to_string(ctx.opts.seed) + "\nthreads = " + std::to_string(threads_of(ctx)) + "\n";
    for (const auto& f : fmts)
      for (const char* tri : {"robust", "mt"}) {
        cmds.push_back(shown(ctx, "study watertight",
                             {"--scene", "icosphere", "--format", f, "--tri", tri, "--rays", rays, "--seed", seed,
                              "--threads", threads_arg(ctx), "--csv", "watertight.csv", "--quiet"}));
        ctx.progress(cmds.back());
      }
    sweep::Expansion ex;
    try {
      ex = sweep::expand_grid(grid, "watertight grid");
    } catch (const sweep::GridError& e) {
      throw ReportError(e.what());
    }
    sweep::RunOptions ro;
    ro.dir = ctx.path("watertight_sweep").string();
    ro.jobs = 1;  // each job runs on threads_of(ctx) threads
    ro.exe = util::self_exe();
    ro.grid_text = grid;
    ro.progress = [&](const std::string& m) { ctx.progress(m); };
    synth::install_interrupt_handler();
    if (sweep::run_jobs(ex.jobs, ro).interrupted || synth::interrupted()) throw ReportError("interrupted");
    std::map<std::string, nlohmann::json> by_hash;
    for (const auto& r : sweep::read_results(ro.dir)) by_hash[r.value("hash", "")] = r;
    Table t;
    std::string csv_text;
    for (size_t k = 0; k < ex.jobs.size(); ++k) {
      const nlohmann::json& row = by_hash[ex.jobs[k].hash];
      const nlohmann::json res = row.value("result", nlohmann::json::array());
      if (row.value("status", "") != "ok" || res.size() != 1)
        throw ReportError(cmds[k] + ": " + row.value("error", std::string("no result")) + " (log " + ro.dir + "/" +
                          row.value("log", std::string("logs/")) + ")");
      const nlohmann::json& r = res[0];
      auto n = [&](const char* key) { return std::to_string(r.value(key, 0LL)); };
      t.push_back({r.value("format", std::string()), ex.jobs[k].params.value("tri", ""), n("edge_rays"),
                   n("edge_leaks"), n("edge_double_hits"), n("vertex_rays"), n("vertex_leaks"),
                   n("vertex_double_hits"), n("overflow_rays")});
      const std::string job_csv = synth::read_file(ro.dir + "/" + ex.jobs[k].result);
      csv_text += k == 0 ? job_csv : job_csv.substr(job_csv.find('\n') + 1);  // one header
    }
    synth::write_file_atomic(ctx.path("watertight.csv").string(), csv_text);
    std::string cl;
    for (const auto& x : cmds) cl += "cd REPORT && " + x + "\n";
    if (!cl.empty()) cl.pop_back();
    md += "\n### Watertightness: leaks and double hits on a closed mesh\n\n" + code_block(cl) +
          "Rays from inside the mesh aimed exactly at shared edges and shared vertices (points representable "
          "in the format). A leak is a ray that hits no triangle. Data: [watertight.csv](watertight.csv).\n\n" +
          ru::report::md_table({"format", "tri", "edge rays", "edge leaks", "edge double hits", "vertex rays",
                                "vertex leaks", "vertex double hits", "rays with overflow"},
                               t);
  }

  // 4. Area of the units: robust vs MT, in the cell flow (the relaxed, area-oriented mapping: the
  // fastest mapping of a ray-triangle unit takes hours).
  if (synth) {
    std::vector<CellPoint> pts;
    for (const auto& f : split_list(synth_formats))
      for (const char* u : {"ray_box", "ray_tri_robust", "ray_tri_mt"}) pts.push_back({u, f, 0, Rows::Small});
    for (const auto& p : pts) {
      try {
        num::Format::parse(p.format);
      } catch (const std::exception& e) {
        throw ReportError("--param intersection.synth_formats: " + std::string(e.what()));
      }
    }
    const CellRows cr = run_cell_rows(ctx, "ray_osu018", pts);
    Table t;
    for (const auto& f : split_list(synth_formats)) {
      auto um2 = [&](const char* u) {
        const CellEnds* e = cr.find(u, f, 0);
        return e ? e->small["area_um2"].get<double>() : std::nan("");
      };
      const double bx = um2("ray_box"), rb = um2("ray_tri_robust"), mt = um2("ray_tri_mt");
      std::string src;
      for (const char* u : {"ray_box", "ray_tri_robust", "ray_tri_mt"}) src += (src.empty() ? "" : "; ") + cr.find(u, f, 0)->source;
      t.push_back({f, fmt("%.0f", bx), fmt("%.0f", rb), fmt("%.0f", mt), fmt("%.2f", rb / mt), src});
    }
    md += "\n### Area: robust vs Moller-Trumbore\n\n";
    if (cr.n_live > 0) md += code_block(cr.cmd);
    md += "Combinational units (Stages 0) in the cell flow (osu018, um2 of the area-oriented mapping at a 1 us "
          "target; synth/README.md, \"The cell-library flow\"). Kensler estimates 35-42 % more arithmetic for the "
          "robust test.\n\n" +
          ru::report::md_table({"format", "ray_box (um2)", "ray_tri_robust (um2)", "ray_tri_mt (um2)", "robust / MT",
                                "rows"},
                               t) +
          "\n" + cr.sources_md() + "Data: [ray_osu018.jsonl](ray_osu018.jsonl).\n";
  }
  return md;
}

// ---- section: noise -------------------------------------------------------------------------------

std::string noise_section(Context& ctx) {
  const std::string size = ctx.param("noise.size", "512");
  const std::string samples = ctx.param("noise.error_samples", "200000");
  const std::string range = ctx.param("noise.range_samples", "10000000");
  const std::string stages = ctx.param("noise.stages", "0,2,4");
  const bool synth = ctx.param("noise.synth", "1") != "0";
  if (synth && !ctx.opts.live_synth) checked_in(ctx);  // a malformed checked-in file fails before anything runs
  std::vector<std::string> a{"--out", ctx.path("noise").string(), "--size", size, "--error-samples", samples,
                             "--range-samples", range, "--seed", std::to_string(ctx.opts.seed), "--quiet"};
  if (!ctx.opts.plots) a.push_back("--no-plot");
  const std::string cmd = shown(ctx, "noise study", a);
  ctx.progress(cmd);
  auto number = [](const std::string& key, const std::string& v) {
    try {
      size_t used = 0;
      const long n = std::stol(v, &used);
      if (used == v.size()) return n;
    } catch (const std::exception&) {
    }
    throw ReportError("--param " + key + ": expected an integer, got '" + v + "'");
  };
  noise::StudyOptions o;  // what `noise study` sets from the command line above (cmd_noise_study.cpp)
  o.out_dir = ctx.path("noise").string();
  o.spectrum_size = static_cast<int>(number("noise.size", size));
  o.error_samples = number("noise.error_samples", samples);
  o.range_samples = number("noise.range_samples", range);
  o.seed = ctx.opts.seed;
  o.plot = ctx.opts.plots;
  o.progress = false;
  o.command = cmd;
  if (o.error_samples < 1 || o.range_samples < 1) throw ReportError(cmd + " failed: sample counts must be >= 1");
  Printout p(ctx, "noise.txt");
  const noise::StudyResult res = call(cmd, [&] { return noise::run_study_result(o); });
  p.finish();
  std::string md = code_block("cd REPORT && " + cmd);
  {
    std::string s = res.summary_md;
    // its images and CSVs are next to it, in noise/
    for (size_t q = 0; (q = s.find("](", q)) != std::string::npos; q += 2)
      if (s.compare(q + 2, 4, "http") != 0) s.insert(q + 2, "noise/");
    // demote its headings below this section's
    std::string out, line;
    std::stringstream in(s);
    while (std::getline(in, line)) out += (line.rfind("#", 0) == 0 ? "##" + line : line) + "\n";
    md += out + "\n";
  }

  if (synth) {
    // Table 4.1 in this flow: the unit by pipeline depth, and the e8m23 FP units beside it.
    std::vector<CellPoint> cell_pts = cell_points("noise.stages", {"noise"}, {}, stages);
    for (const char* u : {"fp_add", "fp_mul", "fp_dot3"}) cell_pts.push_back({u, "e8m23", 0});
    // the same points in the generic flow (its labelled NAND2-eq estimate), read or measured with them
    std::vector<CellPoint> pts = cell_pts;
    for (CellPoint p : cell_pts) {
      p.rows = Rows::Generic;
      pts.push_back(p);
    }
    const CellRows cr = run_cell_rows(ctx, "noise_osu018", pts);
    {
      Table t;
      for (const auto& p : cell_pts) {
        std::vector<std::string> row{p.unit, p.format.empty() ? "-" : p.format, std::to_string(p.stages)};
        auto k = cr.cells(p.unit, p.format, p.stages);
        row.insert(row.end(), k.begin(), k.end());
        t.push_back(row);
      }
      std::vector<std::string> h{"unit", "format", "stages"};
      h.insert(h.end(), kCellHeader.begin(), kCellHeader.end());
      md += "### Area and speed by pipeline depth (Table 4.1 in this flow)\n\n" + std::string(kCellIntro);
      if (cr.n_live > 0) md += code_block(cr.cmd);
      md += ru::report::md_table(h, t) + "\n";
    }
    {
      Table t;
      for (const auto& p : cell_pts) {
        std::vector<std::string> row{p.unit, p.format.empty() ? "-" : p.format, std::to_string(p.stages)};
        auto k = cr.generic_cells(p.unit, p.format, p.stages);
        row.insert(row.end(), k.begin(), k.end());
        t.push_back(row);
      }
      md += "Generic gates (`--generic-only`: Yosys gates in NAND2 equivalents, worst-stage depth; estimates, not "
            "a cell library; the noise unit does not fit an iCE40):\n\n" +
            ru::report::md_table({"unit", "format", "stages", "area est. (NAND2-eq)", "register bits",
                                  "depth (gates)", "stage est. (ps, fo4-v1)", "rows"},
                                 t) +
            "\n" + cr.sources_md() +
            "Data: [noise_osu018.jsonl](noise_osu018.jsonl) (every row used, with its \"report_source\").\n\n";
    }
    {
      auto um2 = [&](const std::string& u, const std::string& f) {
        const CellEnds* e = cr.find(u, f, 0);
        return e ? e->small["area_um2"].get<double>() : std::nan("");
      };
      const double n = um2("noise", ""), a = um2("fp_add", "e8m23"), m = um2("fp_mul", "e8m23"),
                   d = um2("fp_dot3", "e8m23");
      md += "In osu018 (Stages 0, um2 of the smallest mappings): noise / (fp_add + fp_mul) = " + fmt("%.2f", n / (a + m)) +
            ", noise / fp_dot3 = " + fmt("%.2f", n / d) + " (noise " + fmt("%.0f", n) + ", fp_add " + fmt("%.0f", a) +
            ", fp_mul " + fmt("%.0f", m) + ", fp_dot3 " + fmt("%.0f", d) +
            "). The generic-gate ratios below are estimates.\n";
    }
    auto nand2 = [&](const std::string& u, const std::string& f) {
      const CellEnds* e = cr.find(u, f, 0, true);
      return e ? e->generic["area_nand2"].get<double>() : std::nan("");
    };
    const double n0 = nand2("noise", "");
    const double add = nand2("fp_add", "e8m23"), mul = nand2("fp_mul", "e8m23"), dot = nand2("fp_dot3", "e8m23");
    md += "\nRatios (combinational, Stages 0): noise / e8m23 fp_add = " + fmt("%.2f", n0 / add) +
          ", noise / (fp_add + fp_mul) = " + fmt("%.2f", n0 / (add + mul)) +
          " (Kensler: about 2.0x an FP ALU), noise / e8m23 fp_dot3 = " + fmt("%.2f", n0 / dot) +
          " (Kensler: about 0.63x). Areas: noise " + fmt("%.0f", n0) + ", fp_add " + fmt("%.0f", add) +
          ", fp_mul " + fmt("%.0f", mul) + ", fp_dot3 " + fmt("%.0f", dot) + " NAND2-eq.\n\n";
  }
  return md;
}

}  // namespace

// id, title, order, function, needs_python, default_on
RU_REPORT_SECTION("synthesis", "Synthesis: area, depth and Fmax of the FP units by format and stages", 200,
                  &synthesis_section, true, true);
RU_REPORT_SECTION("intersection", "Ray-triangle and ray-box units: error, false misses, watertightness, area", 300,
                  &intersection_section, true, true);
RU_REPORT_SECTION("noise", "Gradient noise unit: spectra, fixed-point error, area by pipeline depth", 400,
                  &noise_section, true, true);

}  // namespace ru::cli
