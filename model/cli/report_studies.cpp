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
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/noise/study.hpp"
#include "rayunits/report/report.hpp"
#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/synth/sweep.hpp"
#include "rayunits/util/parallel.hpp"
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

// Which tool steps a sweep runs (Xilinx never: the report does not show it).
enum class Flow { Generic, Ice40Luts, Ice40Fmax };

struct Sweep {
  std::string cmd;                    // the command line that reproduces it
  std::vector<synth::SweepRow> rows;  // in the order of synth_sweep.csv
  // area of "unit format stages" (format "" for units without one); NaN if missing or failed
  double area(const std::string& unit, const std::string& format, int stages) const {
    for (const auto& r : rows)
      if (r.unit == unit && r.format == format && r.stages == stages) return r.error.empty() ? r.area_nand2 : std::nan("");
    return std::nan("");
  }
};


// `rayunits synth-sweep` into <dir>/<sub> (synth::run_sweep_rows, as the command runs it); the
// progress goes to <sub>.log with --quiet, else to stderr; <sub>.txt is its (empty) printout.
Sweep run_sweep(Context& ctx, const std::string& sub, const std::string& units, const std::string& formats,
                const std::string& stages, Flow flow, bool plot = true) {
  std::vector<std::string> a{"--out", ctx.path(sub).string(), "--units", units, "--stages", stages, "-j",
                             threads_arg(ctx)};
  if (!formats.empty()) a.insert(a.end(), {"--formats", formats});
  if (flow == Flow::Generic) a.push_back("--generic-only");
  if (flow != Flow::Generic) a.push_back("--no-xilinx");
  if (flow == Flow::Ice40Fmax) a.push_back("--fpga");
  if (!ctx.opts.plots || !plot) a.push_back("--no-plot");
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
  if (flow == Flow::Generic) so.flow.ice40 = so.flow.pnr = false;
  so.flow.xilinx = false;
  if (flow == Flow::Ice40Fmax) so.flow.ice40 = so.flow.pnr = true;
  so.plot = ctx.opts.plots && plot;

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

// The same points through the cell-library flow (rayunits synth ... --flow osu018, without a
// target clock): area in um2 and the OpenSTA clock; rows appended to <sub>.jsonl.
struct CellRows {
  std::string cmd;  // the command line pattern
  std::map<std::string, nlohmann::json> rows;  // "unit format stages" -> row
  const nlohmann::json* find(const std::string& unit, const std::string& format, int stages) const {
    auto it = rows.find(unit + " " + format + " " + std::to_string(stages));
    return it == rows.end() ? nullptr : &it->second;
  }
  std::vector<std::string> cells(const std::string& unit, const std::string& format, int stages) const {
    const nlohmann::json* j = find(unit, format, stages);
    if (!j) return {"-", "-", "-"};
    return {fmt("%.0f", (*j)["area_um2"].get<double>()), fmt("%.1f", (*j)["fmax_mhz"].get<double>()),
            fmt("%.1f", (*j)["period_fo4"].get<double>())};
  }
};

CellRows run_cell_rows(Context& ctx, const std::string& sub, const std::vector<synth::SweepRow>& pts) {
  CellRows c;
  c.cmd = "rayunits synth <unit> --format <format> --stages <stages> --flow osu018 --json " + sub +
          ".jsonl   # each row below";
  ctx.progress(c.cmd);
  std::vector<nlohmann::json> out(pts.size());
  synth::install_interrupt_handler();
  util::ParallelOptions po;
  po.stop = [] { return synth::interrupted(); };
  std::string err;
  std::mutex mu;
  util::parallel_for(
      pts.size(), threads_of(ctx),
      [&](size_t i) {
        const synth::SweepRow& r = pts[i];
        if (!r.error.empty()) return;
        const synth::UnitSpec& u = synth::find_unit(r.unit);
        synth::UnitConfig cfg;
        if (u.uses_format) cfg.fmt = num::Format::parse(r.format);
        cfg.stages = r.stages;
        synth::FlowOptions fo;
        fo.flow = "osu018";
        try {
          out[i] = synth::to_json(synth::run_synth(u, cfg, fo));
        } catch (const std::exception& e) {
          std::lock_guard<std::mutex> l(mu);
          if (err.empty()) err = std::string("rayunits synth ") + synth::config_args(u, cfg) + " --flow osu018: " + e.what();
        }
      },
      po);
  if (!err.empty()) throw ReportError(err);
  std::string jsonl;
  for (size_t i = 0; i < pts.size(); ++i) {
    if (out[i].is_null()) continue;
    jsonl += out[i].dump() + "\n";
    c.rows[pts[i].unit + " " + pts[i].format + " " + std::to_string(pts[i].stages)] = out[i];
  }
  synth::write_file_atomic(ctx.path(sub + ".jsonl").string(), jsonl);
  return c;
}

// ---- section: synthesis -----------------------------------------------------------------------

std::string synthesis_section(Context& ctx) {
  const std::string units = ctx.param("synthesis.units", "fp_add,fp_mul,fp_div");
  const std::string formats = ctx.param("synthesis.formats", "e5m10,e6m12,e7m16,e8m23");
  const std::string stages = ctx.param("synthesis.stages", "0,4");
  const bool fpga = ctx.param("synthesis.fpga", "1") != "0";
  const Sweep sw = run_sweep(ctx, "synth", units, formats, stages, fpga ? Flow::Ice40Fmax : Flow::Ice40Luts);

  const CellRows cr = run_cell_rows(ctx, "synth_osu018", sw.rows);

  std::string md =
      "The speed side of the speed/accuracy trade: every unit mapped onto the osu018 180 nm standard-cell library "
      "and timed by OpenSTA (synth/README.md, \"The cell-library flow\": area in um2, Fmax = 1 / (period - slack) "
      "through a register harness, before placement; FO4 = 98.3 ps), beside the generic flow's estimates (Yosys "
      "gates in NAND2 equivalents, worst-stage depth from `ltp -noff` and its fo4-v1 delay estimate) and iCE40 "
      "HX8K place and route by nextpnr. The accuracy side is the section above: its rows for the same formats "
      "are repeated here.\n\n" +
      code_block("cd REPORT && " + cr.cmd + "\ncd REPORT && " + sw.cmd);
  Table t;
  for (const auto& r : sw.rows) {
    std::vector<std::string> row{r.unit, r.format, std::to_string(r.stages)};
    if (!r.error.empty()) {
      row.insert(row.end(), {"error: " + r.error, "", "", "", "", "", "", "", ""});
    } else {
      auto k = cr.cells(r.unit, r.format, r.stages);
      row.insert(row.end(), k.begin(), k.end());
      auto c = synth_cells(r);
      row.insert(row.end(), c.begin(), c.end());
    }
    t.push_back(row);
  }
  md += ru::report::md_table(
      {"unit", "format", "stages", "area (um2, osu018)", "Fmax (MHz, STA)", "cycle (FO4)", "area est. (NAND2-eq)",
       "register bits", "depth (gates)", "stage est. (ps, fo4-v1)", "iCE40 LUTs", "iCE40 Fmax (MHz)"},
      t);
  md += "\nData: [synth/synth_sweep.csv](synth/synth_sweep.csv), one JSON per point in `synth/points/`; tool "
        "output in [synth.txt](synth.txt).\n\n";
  if (ctx.opts.plots) md += "![area vs fraction bits, Fmax vs stages](synth/synth_sweep.png)\n\n";

  // Side by side with the accuracy section, when it ran in this report.
  if (!ctx.accuracy.empty()) {
    const auto& accm = ctx.accuracy;
    Table s;
    for (const auto& r : sw.rows) {
      if (r.stages != 0 || !r.error.empty()) continue;
      const std::string op = r.unit.substr(3);  // fp_mul -> mul
      auto it = accm.find(r.format + " " + op);
      if (it == accm.end()) continue;
      const auto k = cr.cells(r.unit, r.format, r.stages);
      s.push_back({r.unit, r.format, k[0], k[1], fmt("%.3g", it->second.mean_rel), fmt("%.3g", it->second.max_rel),
                   std::to_string(it->second.out_of_range)});
    }
    if (!s.empty()) {
      md += "Speed and accuracy side by side (combinational units; errors from the accuracy section's workload):\n\n";
      md += ru::report::md_table({"unit", "format", "area (um2, osu018)", "Fmax (MHz, STA)", "mean rel. error",
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
  const std::string synth_formats = ctx.param("intersection.synth_formats", "e5m10");
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
    const std::string csv = ctx.path("watertight.csv").string();
    std::vector<std::string> cmds;
    Table t;
    std::stringstream fl(wt_formats);
    for (std::string f; std::getline(fl, f, ',');)
      for (const char* tri : {"robust", "mt"}) {
        const std::string cmd =
            shown(ctx, "study watertight",
                  {"--scene", "icosphere", "--format", f, "--tri", tri, "--rays", rays, "--seed", seed, "--threads",
                   threads_arg(ctx), "--csv", csv, "--quiet"});
        ctx.progress(cmd);
        cmds.push_back(cmd);
        WatertightArgs wa;
        wa.scene = "icosphere";
        wa.format = f;
        wa.tri = tri;
        wa.rays = count("intersection.rays", rays);
        wa.seed = ctx.opts.seed;
        wa.threads = threads_of(ctx);
        wa.csv = csv;
        wa.quiet = true;
        Printout p(ctx, "watertight_" + f + "_" + tri + ".txt");
        const WatertightRun w = call(cmd, [&] { return run_watertight_study(wa, p.out, p.err); });
        p.finish();
        const auto& r = w.result;
        t.push_back({w.format, tri, std::to_string(r.edge.rays), std::to_string(r.edge.leaks),
                     std::to_string(r.edge.double_hits), std::to_string(r.vertex.rays),
                     std::to_string(r.vertex.leaks), std::to_string(r.vertex.double_hits),
                     std::to_string(r.overflow_rays)});
      }
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

  // 4. Area of the units: robust vs MT.
  if (synth) {
    const Sweep sw = run_sweep(ctx, "ray_synth", "ray_box,ray_tri_robust,ray_tri_mt", synth_formats, "0", Flow::Generic);
    Table t;
    std::stringstream fl(synth_formats);
    for (std::string f; std::getline(fl, f, ',');) {
      const double rb = sw.area("ray_tri_robust", f, 0), mt = sw.area("ray_tri_mt", f, 0),
                   bx = sw.area("ray_box", f, 0);
      t.push_back({f, fmt("%.0f", bx), fmt("%.0f", rb), fmt("%.0f", mt), fmt("%.2f", rb / mt)});
    }
    md += "\n### Area: robust vs Moller-Trumbore\n\n" + code_block("cd REPORT && " + sw.cmd) +
          "Combinational units (Stages 0), NAND2-equivalent area of the whole unit from the same flow as the "
          "synthesis section. Kensler estimates 35-42 % more arithmetic for the robust test. Data: "
          "[ray_synth/synth_sweep.csv](ray_synth/synth_sweep.csv).\n\n" +
          ru::report::md_table({"format", "ray_box", "ray_tri_robust", "ray_tri_mt", "robust / MT"}, t);
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
    // it does not fit an iCE40; the sweep's plot is for FP formats (the table shows the noise rows)
    const Sweep nz = run_sweep(ctx, "noise_synth", "noise", "", stages, Flow::Ice40Luts, false);
    const Sweep fp = run_sweep(ctx, "noise_fp_synth", "fp_add,fp_mul,fp_dot3", "e8m23", "0", Flow::Generic);
    std::vector<synth::SweepRow> cell_pts = nz.rows;
    cell_pts.insert(cell_pts.end(), fp.rows.begin(), fp.rows.end());
    const CellRows cr = run_cell_rows(ctx, "noise_osu018", cell_pts);
    Table t;
    for (const auto& r : nz.rows) {
      if (!r.error.empty()) {
        t.push_back({std::to_string(r.stages), "error: " + r.error});
        continue;
      }
      std::vector<std::string> row{std::to_string(r.stages)};
      auto k = cr.cells("noise", "", r.stages);
      row.insert(row.end(), k.begin(), k.end());
      auto cells = synth_cells(r);
      row.insert(row.end(), cells.begin(), cells.end());
      t.push_back(row);
    }
    md += "### Area and speed by pipeline depth (Table 4.1 in this flow)\n\n" +
          code_block("cd REPORT && " + cr.cmd + "\ncd REPORT && " + nz.cmd + "\ncd REPORT && " + fp.cmd) +
          ru::report::md_table({"stages", "area (um2, osu018)", "Fmax (MHz, STA)", "cycle (FO4)", "area est. (NAND2-eq)",
                                "register bits", "depth (gates)", "stage est. (ps, fo4-v1)", "iCE40 LUTs",
                                "iCE40 Fmax (MHz)"},
                               t);
    {
      auto um2 = [&](const std::string& u, const std::string& f) {
        const nlohmann::json* j = cr.find(u, f, 0);
        return j ? (*j)["area_um2"].get<double>() : std::nan("");
      };
      const double n = um2("noise", ""), a = um2("fp_add", "e8m23"), m = um2("fp_mul", "e8m23"),
                   d = um2("fp_dot3", "e8m23");
      md += "\nIn osu018 (Stages 0, um2): noise / (fp_add + fp_mul) = " + fmt("%.2f", n / (a + m)) +
            ", noise / fp_dot3 = " + fmt("%.2f", n / d) + " (noise " + fmt("%.0f", n) + ", fp_add " + fmt("%.0f", a) +
            ", fp_mul " + fmt("%.0f", m) + ", fp_dot3 " + fmt("%.0f", d) +
            "). The generic-gate ratios below are estimates.\n";
    }
    const double n0 = nz.area("noise", "", 0);
    const double add = fp.area("fp_add", "e8m23", 0), mul = fp.area("fp_mul", "e8m23", 0),
                 dot = fp.area("fp_dot3", "e8m23", 0);
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
