// Synthesis sweeps (`rayunits synth-sweep`): the points run as one grid of the sweep engine, then
// the CSV/JSON/PNG tables of synth_sweep.* are written from the jobs' typed rows.
#include "rayunits/synth/sweep.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <set>
#include <sstream>

#include "rayunits/sweep/sweep.hpp"
#include "rayunits/synth/args.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/csv.hpp"
#include "rayunits/util/git.hpp"
#include "rayunits/util/process.hpp"

namespace ru::synth {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string flow_signature(const FlowOptions& f) {
  // Bump the "v" number when the flow's method changes (weights, delay model, scripts).
  return std::string("v1:generic") + (f.ice40 ? "+ice40-" + f.ice40_device : "") + (f.pnr ? "+pnr" : "") +
         (f.xilinx ? "+xilinx" : "");
}

std::string hms(double s) {
  char b[32];
  int t = static_cast<int>(s + 0.5);
  if (t >= 3600)
    std::snprintf(b, sizeof b, "%dh%02dm%02ds", t / 3600, t / 60 % 60, t % 60);
  else if (t >= 60)
    std::snprintf(b, sizeof b, "%dm%02ds", t / 60, t % 60);
  else
    std::snprintf(b, sizeof b, "%ds", t);
  return b;
}

std::string csv_cell(const json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return util::csv_cell(v.get<std::string>());
  if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
  return v.dump();
}

json get_path(const json& row, const std::string& key) {
  size_t dot = key.find('.');
  if (dot == std::string::npos) return row.contains(key) ? row[key] : json(nullptr);
  const std::string head = key.substr(0, dot);
  if (!row.contains(head) || row[head].is_null()) return nullptr;
  return get_path(row[head], key.substr(dot + 1));
}

// Short HEAD, "+dirty-rtl" when rtl/ differs from it (the sweep's rows describe rtl/).
std::string git_commit() {
#ifdef RU_SOURCE_DIR
  if (find_program("git").empty()) return "unknown";
  const auto c = util::git_commit_info(RU_SOURCE_DIR, /*short_hash=*/true, {"rtl"});
  if (!c) return "none (no commit)";
  return c->hash + (c->dirty ? "+dirty-rtl" : "");
#else
  return "unknown";
#endif
}

}  // namespace

std::vector<SweepPoint> sweep_points(const SweepOptions& o, std::vector<std::string>* skipped) {
  if (o.units.empty() || o.formats.empty() || o.stages.empty())
    throw SynthError("empty sweep: give at least one unit, format and stage count");
  std::vector<num::Format> fmts;
  for (const auto& f : o.formats) {
    num::Format x = num::Format::parse(f);
    x.round = num::parse_round(o.round);
    fmts.push_back(x);
  }
  std::vector<SweepPoint> pts;
  for (const auto& un : o.units) {
    const UnitSpec& u = find_unit(un);
    // Units without a floating-point format get one point per stage count.
    const std::vector<num::Format> ufmts = u.uses_format ? fmts : std::vector<num::Format>{num::Format{}};
    for (const auto& f : ufmts) {
      std::set<int> st;
      UnitConfig c;
      c.fmt = f;
      const int hi = u.max_stages(c);
      const std::string tag = u.name + (u.uses_format ? " " + f.name() : std::string());
      for (const auto& s : o.stages) {
        int n = s == "max" ? hi : parse_int("--stages", s, 0, 1000);
        if (n > hi) {
          if (skipped)
            skipped->push_back(tag + " s" + std::to_string(n) + ": above the unit's maximum of " +
                               std::to_string(hi));
          continue;
        }
        st.insert(n);
      }
      for (int n : st) {
        c.stages = n;
        check_config(u, c);
        pts.push_back({&u, c});
      }
    }
  }
  return pts;
}

std::string sweep_csv(const json& rows) {
  static const std::vector<std::string> cols = {
      "unit",           "format",       "exp_bits",     "frac_bits",        "width",       "stages",
      "round",          "area_nand2",   "cells_total",  "transistors_cmos", "reg_bits",    "depth",
      "stage_delay_ps", "fmax_est_mhz", "ice40.device", "ice40.luts",       "ice40.ffs",   "ice40.fits",
      "ice40.fmax_mhz", "ice40.reason", "xilinx.luts",  "xilinx.ffs",       "xilinx.dsps", "xilinx.carry4",
      "seconds",        "error"};
  std::string s;
  for (size_t i = 0; i < cols.size(); ++i) {
    std::string c = cols[i];
    std::replace(c.begin(), c.end(), '.', '_');
    s += (i ? "," : "") + c;
  }
  s += "\n";
  for (const auto& r : rows) {
    for (size_t i = 0; i < cols.size(); ++i) s += (i ? "," : "") + csv_cell(get_path(r, cols[i]));
    s += "\n";
  }
  return s;
}

// The grid file of a synth-sweep: kind synth, the unit/format/stages axes and the flow options
// as keys (docs/SWEEPS.md); strings quoted as JSON strings (valid TOML basic strings).
std::string sweep_grid(const SweepOptions& o) {
  auto q = [](const std::string& v) { return json(v).dump(); };
  auto axis = [&](const std::vector<std::string>& vs, bool stages) {
    std::string a;
    for (const auto& v : vs) a += (a.empty() ? "" : ", ") + (stages && v != "max" ? v : q(v));
    return "[" + a + "]";
  };
  const FlowOptions& f = o.flow;
  std::string g = "# written by rayunits synth-sweep: " + o.command + "\nkind = \"synth\"\n";
  g += "unit = " + axis(o.units, false) + "\nformat = " + axis(o.formats, false) + "\nstages = " +
       axis(o.stages, true) + "\nround = " + q(o.round) + "\n";
  if (!f.ice40 && !f.pnr) g += "no_ice40 = true\n";
  if (!f.xilinx) g += "no_xilinx = true\n";
  if (f.pnr) g += "fpga = true\n";
  if (f.ice40_device != "hx8k") g += "device = " + q(f.ice40_device) + "\n";
  if (!f.share) g += "no_share = true\n";
  if (f.timeout_s > 0) g += "timeout = " + std::to_string(f.timeout_s) + "\n";
  if (!f.rtl_dir.empty()) g += "rtl = " + q(fs::absolute(f.rtl_dir).string()) + "\n";
  if (f.yosys != "yosys") g += "yosys = " + q(f.yosys) + "\n";
  if (f.nextpnr != "nextpnr-ice40") g += "nextpnr = " + q(f.nextpnr) + "\n";
  if (f.keep_temp) g += "keep = true\n";
  return g;
}

SweepResult run_sweep_rows(const SweepOptions& o, const std::function<void(const std::string&)>& progress) {
  if (o.out_dir.empty()) throw SynthError("--out DIR is required");
  std::vector<std::string> skipped;
  const std::vector<SweepPoint> pts = sweep_points(o, &skipped);  // validates units, formats, stages
  const std::string yv = yosys_version(o.flow.yosys);
  if (o.flow.pnr && find_program(o.flow.nextpnr).empty())
    throw SynthError("nextpnr-ice40 not found ('" + o.flow.nextpnr + "'): install it or drop --fpga");
  const std::string rtl_dir = o.flow.rtl_dir.empty() ? default_rtl_dir() : o.flow.rtl_dir;
  std::map<std::string, std::string> hash_at_start;  // unit -> sources_hash
  for (const auto& p : pts) hash_at_start[p.unit->name] = sources_hash(resolve_sources(*p.unit, rtl_dir));
  const std::string sig = flow_signature(o.flow);
  for (const auto& s : skipped) progress("skipped " + s);
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };

  // The points run as one grid of the sweep engine (rayunits/sweep/sweep.hpp) in DIR/sweep:
  // each a `rayunits synth` child process, resumable by content hash (--resume), logs per job.
  const std::string grid = sweep_grid(o);
  sweep::Expansion ex;
  try {
    ex = sweep::expand_grid(grid, "synth-sweep grid");
  } catch (const sweep::GridError& e) {
    throw SynthError(e.what());
  }
  const std::string sweep_dir = (fs::path(o.out_dir) / "sweep").string();
  {
    char b[160];
    std::snprintf(b, sizeof b, "synth-sweep: %zu points, %d jobs, flow %s, engine directory %s", pts.size(),
                  std::max(1, o.jobs), sig.c_str(), sweep_dir.c_str());
    progress(b);
  }
  sweep::RunOptions ro;
  ro.dir = sweep_dir;
  ro.jobs = std::max(1, o.jobs);
  ro.force = !o.resume;
  ro.exe = o.exe.empty() ? util::self_exe() : o.exe;
  ro.grid_text = grid;
  ro.timeout_s = 0;
  ro.progress = progress;
  const sweep::RunSummary sum = sweep::run_jobs(ex.jobs, ro);
  if (sum.interrupted || interrupted())
    throw SynthError("interrupted (finished points are in " + sweep_dir + "; rerun with --resume)");

  // Rows in grid order (unit, format, stages), from the jobs' typed results.
  std::map<std::string, json> by_hash;
  for (const json& r : sweep::read_results(sweep_dir)) by_hash[r.value("hash", "")] = r;
  auto point_key = [](const std::string& unit, const std::string& fmt, int stages) {
    return unit + "|" + fmt + "|" + std::to_string(stages);
  };
  std::map<std::string, json> by_point;
  for (const sweep::Job& j : ex.jobs)
    by_point[point_key(j.params.value("unit", ""), j.params.value("format", ""), j.params.value("stages", 0))] =
        by_hash.count(j.hash) ? by_hash[j.hash] : json{{"status", "not run"}, {"error", "no result"}};
  std::vector<json> rows;
  int failed = 0;
  for (const SweepPoint& p : pts) {
    const bool uf = p.unit->uses_format;
    const json& r = by_point[point_key(p.unit->name, uf ? p.cfg.fmt.name() : "", p.cfg.stages)];
    if (r.value("status", "") == "ok" && !r.value("result", json::array()).empty()) {
      rows.push_back(r["result"][0]);
      continue;
    }
    ++failed;
    rows.push_back({{"unit", p.unit->name},
                    {"top", wrapper_name(*p.unit, p.cfg)},
                    {"format", uf ? json(p.cfg.fmt.name()) : json(nullptr)},
                    {"exp_bits", uf ? json(p.cfg.fmt.exp_bits) : json(nullptr)},
                    {"frac_bits", uf ? json(p.cfg.fmt.frac_bits) : json(nullptr)},
                    {"width", uf ? json(p.cfg.fmt.width()) : json(nullptr)},
                    {"stages", p.cfg.stages},
                    {"round", uf ? json(num::round_name(p.cfg.fmt.round)) : json(nullptr)},
                    {"error", r.value("error", std::string("failed")) + " (log " + sweep_dir + "/" +
                                  r.value("log", std::string("logs/")) + ")"}});
  }

  json all = json::array();
  for (auto& r : rows) all.push_back(r);
  // Rows must all describe one version of the RTL: say so if it changed under the sweep.
  std::vector<std::string> changed;
  for (const auto& [unit, h] : hash_at_start) {
    bool differs = sources_hash(resolve_sources(find_unit(unit), rtl_dir)) != h;
    for (const auto& r : all)
      if (r.value("unit", "") == unit && r.contains("rtl_hash") && r["rtl_hash"] != h) differs = true;
    if (differs) changed.push_back(unit);
  }
  for (const auto& u : changed)
    progress("warning: the RTL of " + u +
             " changed during the sweep; rows may mix versions (rerun with --resume)");
  char started[64];
  std::time_t now = std::time(nullptr);
  std::strftime(started, sizeof started, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  json out = {{"meta",
               {{"command", o.command},
                {"commit", git_commit()},
                {"yosys", yv},
                {"flow", sig},
                {"delay_model", DelayModel::kName},
                {"finished", started},
                {"wall_seconds", std::round(elapsed() * 10) / 10},
                {"jobs", std::max(1, o.jobs)},
                {"sweep_dir", "sweep"},
                {"skipped", skipped},
                {"rtl_hash", hash_at_start},
                {"rtl_changed_during_sweep", changed}}},
              {"rows", all}};
  const std::string json_path = (fs::path(o.out_dir) / "synth_sweep.json").string();
  const std::string csv_path = (fs::path(o.out_dir) / "synth_sweep.csv").string();
  write_file_atomic(json_path, out.dump(1) + "\n");
  write_file_atomic(csv_path, sweep_csv(all));
  progress("wrote " + csv_path + " and " + json_path + " (" + hms(elapsed()) + ")");

  if (o.plot) {
    std::string py = o.python;
    if (py.empty()) py = find_program("/usr/bin/python3").empty() ? "python3" : "/usr/bin/python3";
    const std::string exe = find_program(py);
#ifdef RU_SOURCE_DIR
    const std::string script = std::string(RU_SOURCE_DIR) + "/synth/plot_sweep.py";
#else
    const std::string script = "synth/plot_sweep.py";
#endif
    const std::string png = (fs::path(o.out_dir) / "synth_sweep.png").string();
    if (exe.empty())
      throw SynthError("no plot: python '" + py + "' not found (use --python PATH or --no-plot)");
    TempDir t("ru-plot-");
    ProcResult r = run_process({exe, script, json_path, png}, ".", t.path() + "/log", 300);
    if (r.exit_code != 0) {
      std::string log = read_file(t.path() + "/log");
      std::string last;
      std::istringstream in(log);
      for (std::string l; std::getline(in, l);)
        if (!l.empty()) last = l;
      throw SynthError("plot failed (" + script + "): " + last);
    }
    progress("wrote " + png + " and " + png.substr(0, png.size() - 4) + ".md");
  }
  SweepResult res;
  res.failed = failed;
  for (const auto& r : all) res.rows.push_back(sweep_row(r));
  return res;
}

int run_sweep(const SweepOptions& o, const std::function<void(const std::string&)>& progress) {
  return run_sweep_rows(o, progress).failed;
}

SweepRow sweep_row(const json& r) {
  auto num = [](const json& v) { return v.is_number() ? v.get<double>() : std::nan(""); };
  SweepRow w;
  w.unit = r.value("unit", "");
  if (r.contains("format") && r["format"].is_string()) w.format = r["format"].get<std::string>();
  w.stages = r.value("stages", 0);
  if (r.contains("error")) {
    w.error = r["error"].is_string() ? r["error"].get<std::string>() : r["error"].dump();
    return w;
  }
  w.area_nand2 = num(get_path(r, "area_nand2"));
  w.fmax_est_mhz = num(get_path(r, "fmax_est_mhz"));
  w.reg_bits = r.value("reg_bits", 0L);
  w.depth = r.value("depth", 0);
  if (r.contains("ice40") && r["ice40"].is_object()) {
    const json& ic = r["ice40"];
    w.ice40_run = true;
    w.ice40_luts = ic.value("luts", 0L);
    w.ice40_fits = ic.value("fits", false);
    w.ice40_fmax_mhz = num(get_path(ic, "fmax_mhz"));
  }
  return w;
}

}  // namespace ru::synth
