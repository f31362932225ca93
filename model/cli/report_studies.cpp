// Report sections that run the project's own commands: synthesis (issue 3 section 5),
// intersection (issue 4 section 6) and noise (issue 5 section 6).
//
// Each section runs registered subcommands in-process with the arguments a user would type
// (the same code path as the command line, not a second copy of the study), captures their
// stdout into a text file of the report, and builds its Markdown from the CSV files they wrote.
// The command lines are printed in the report relative to the report directory, so every
// table can be reproduced with `cd REPORT && rayunits ...`.
#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/report/report.hpp"

namespace ru::cli {
namespace {

using ru::report::Context;
using ru::report::ReportError;
using Table = std::vector<std::vector<std::string>>;

// ---- running a subcommand -----------------------------------------------------------------

const Command& find_command(const std::string& name) {
  for (const auto& c : commands())
    if (name == c.name) return c;
  throw ReportError("internal: no command '" + name + "'");
}

// The command line as shown in the report: paths inside the report directory made relative.
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

// Paths inside the (temporary) report directory made relative in a file the commands wrote
// (they print their own command lines and output paths).
void relativize_file(const Context& ctx, const std::filesystem::path& p) {
  std::string text;
  {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    text = ss.str();
  }
  const std::string dir = ctx.dir.string() + "/";
  bool changed = false;
  for (size_t q; (q = text.find(dir)) != std::string::npos; changed = true) text.erase(q, dir.size());
  if (changed) std::ofstream(p, std::ios::trunc) << text;
}

// Runs `rayunits <cmd> args...` with stdout redirected into ctx.path(txt). Throws ReportError
// with the command's own error line on failure. Returns the command line for the report.
std::string run_captured(Context& ctx, const std::string& cmd, std::vector<std::string> args,
                         const std::string& txt) {
  const Command& c = find_command(cmd);
  const std::string line = shown(ctx, cmd, args);
  ctx.progress(line);
  const std::string last_word = cmd.substr(cmd.rfind(' ') + 1);
  std::vector<char*> av{const_cast<char*>(last_word.c_str())};
  for (auto& a : args) av.push_back(a.data());
  av.push_back(nullptr);

  // stdout -> <txt>; with --quiet also stderr (the command's progress) -> <txt minus .txt>.log
  const std::string log = txt.substr(0, txt.rfind('.')) + ".log";
  std::fflush(stdout);
  std::fflush(stderr);
  const int fd = ::open(ctx.path(txt).c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) throw ReportError("cannot write " + ctx.path(txt).string());
  const int saved = ::dup(1);
  ::dup2(fd, 1);
  ::close(fd);
  int saved_err = -1;
  if (ctx.opts.quiet) {
    const int efd = ::open(ctx.path(log).c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (efd >= 0) {
      saved_err = ::dup(2);
      ::dup2(efd, 2);
      ::close(efd);
    }
  }
  int rc = 0;
  std::string err;
  try {
    rc = c.run(static_cast<int>(av.size()) - 1, av.data());
  } catch (const std::exception& e) {
    err = e.what();
    rc = 2;
  }
  std::fflush(stdout);
  std::fflush(stderr);
  ::dup2(saved, 1);
  ::close(saved);
  if (saved_err >= 0) {
    ::dup2(saved_err, 2);
    ::close(saved_err);
  }
  if (rc != 0 && err.empty() && saved_err >= 0) {  // its own error line went to the log
    std::ifstream f(ctx.path(log));
    for (std::string l; std::getline(f, l);)
      if (!l.empty()) err = l;
  }
  if (rc != 0)
    throw ReportError(line + " failed" + (err.empty() ? " (exit " + std::to_string(rc) + ")" : ": " + err));
  relativize_file(ctx, ctx.path(txt));
  return line;
}

// ---- reading what the commands wrote --------------------------------------------------------

struct Csv {
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
};

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"') {
      quoted = !quoted;
    } else if (ch == ',' && !quoted) {
      out.push_back(cur);
      cur.clear();
    } else if (ch != '\r') {
      cur += ch;
    }
  }
  out.push_back(cur);
  return out;
}

// Reads a CSV with a header line; lines starting with '#' are comments.
Csv read_csv(const std::filesystem::path& p) {
  std::ifstream f(p);
  if (!f) throw ReportError("cannot read " + p.string());
  Csv c;
  for (std::string line; std::getline(f, line);) {
    if (line.empty() || line[0] == '#') continue;
    auto cells = split_csv_line(line);
    if (c.header.empty()) {
      c.header = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < c.header.size() && i < cells.size(); ++i) row[c.header[i]] = cells[i];
    c.rows.push_back(std::move(row));
  }
  if (c.header.empty()) throw ReportError(p.string() + " is empty");
  return c;
}

std::string get(const std::map<std::string, std::string>& row, const std::string& key) {
  auto it = row.find(key);
  return it == row.end() ? std::string() : it->second;
}

double num(const std::map<std::string, std::string>& row, const std::string& key) {
  const std::string s = get(row, key);
  return s.empty() ? std::nan("") : std::atof(s.c_str());
}

std::string fmt(const char* f, double v) {
  if (std::isnan(v)) return "-";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string code_block(const std::string& cmd) { return "```sh\n" + cmd + "\n```\n\n"; }

std::string threads_arg(const Context& ctx) { return std::to_string(std::max(1u, std::min(ctx.threads(), 64u))); }

// Which tool steps a sweep runs (Xilinx never: the report does not show it).
enum class Flow { Generic, Ice40Luts, Ice40Fmax };

// Runs `rayunits synth-sweep` into <dir>/<sub>; returns the command line.
std::string run_sweep(Context& ctx, const std::string& sub, const std::string& units, const std::string& formats,
                      const std::string& stages, Flow flow, bool plot = true) {
  std::vector<std::string> a{"--out", ctx.path(sub).string(), "--units", units, "--stages", stages, "-j",
                             threads_arg(ctx)};
  if (!formats.empty()) a.insert(a.end(), {"--formats", formats});
  if (flow == Flow::Generic) a.push_back("--generic-only");
  if (flow != Flow::Generic) a.push_back("--no-xilinx");
  if (flow == Flow::Ice40Fmax) a.push_back("--fpga");
  if (!ctx.opts.plots || !plot) a.push_back("--no-plot");
  return run_captured(ctx, "synth-sweep", a, sub + ".txt");
}

// The sweep's rows keyed by "unit format stages" (format "" for units without one).
std::map<std::string, std::map<std::string, std::string>> sweep_rows(const Context& ctx, const std::string& sub) {
  std::map<std::string, std::map<std::string, std::string>> m;
  for (auto& r : read_csv(ctx.path(sub) / "synth_sweep.csv").rows)
    m[get(r, "unit") + " " + get(r, "format") + " " + get(r, "stages")] = r;
  return m;
}

double area_of(const std::map<std::string, std::map<std::string, std::string>>& rows, const std::string& key) {
  auto it = rows.find(key);
  if (it == rows.end() || !get(it->second, "error").empty()) return std::nan("");
  return num(it->second, "area_nand2");
}

std::vector<std::string> synth_cells(const std::map<std::string, std::string>& r) {
  const bool ran = !get(r, "ice40_luts").empty(), fits = get(r, "ice40_fits") == "1";
  const std::string luts = !ran ? "-" : fits ? get(r, "ice40_luts") : get(r, "ice40_luts") + " (does not fit)";
  return {fmt("%.0f", num(r, "area_nand2")), get(r, "reg_bits"), get(r, "depth"), fmt("%.0f", num(r, "fmax_est_mhz")),
          luts, fits ? fmt("%.1f", num(r, "ice40_fmax_mhz")) : "-"};
}

// ---- section: synthesis -----------------------------------------------------------------------

std::string synthesis_section(Context& ctx) {
  const std::string units = ctx.param("synthesis.units", "fp_add,fp_mul,fp_div");
  const std::string formats = ctx.param("synthesis.formats", "e5m10,e6m12,e7m16,e8m23");
  const std::string stages = ctx.param("synthesis.stages", "0,4");
  const bool fpga = ctx.param("synthesis.fpga", "1") != "0";
  const std::string cmd = run_sweep(ctx, "synth", units, formats, stages, fpga ? Flow::Ice40Fmax : Flow::Ice40Luts);
  const Csv csv = read_csv(ctx.path("synth") / "synth_sweep.csv");

  std::string md =
      "The speed side of the speed/accuracy trade: every unit synthesized by the project's open flow "
      "(synth/README.md: Yosys generic gates weighted in NAND2 equivalents, worst-stage depth from `ltp -noff`, "
      "Fmax estimated with the documented gate-delay model; iCE40 HX8K place and route by nextpnr). The accuracy "
      "side is the section above: its rows for the same formats are repeated here.\n\n" +
      code_block("cd REPORT && " + cmd);
  Table t;
  for (const auto& r : csv.rows) {
    std::vector<std::string> row{get(r, "unit"), get(r, "format"), get(r, "stages")};
    if (!get(r, "error").empty()) {
      row.insert(row.end(), {"error: " + get(r, "error"), "", "", "", "", ""});
    } else {
      auto c = synth_cells(r);
      row.insert(row.end(), c.begin(), c.end());
    }
    t.push_back(row);
  }
  md += ru::report::md_table(
      {"unit", "format", "stages", "area (NAND2-eq)", "register bits", "depth (gates)", "Fmax est. (MHz)",
       "iCE40 LUTs", "iCE40 Fmax (MHz)"},
      t);
  md += "\nData: [synth/synth_sweep.csv](synth/synth_sweep.csv), one JSON per point in `synth/points/`; tool "
        "output in [synth.txt](synth.txt).\n\n";
  if (ctx.opts.plots) md += "![area vs fraction bits, Fmax vs stages](synth/synth_sweep.png)\n\n";

  // Side by side with the accuracy section, when it ran in this report.
  if (std::filesystem::exists(ctx.path("accuracy.csv"))) {
    const Csv acc = read_csv(ctx.path("accuracy.csv"));
    std::map<std::string, std::map<std::string, std::string>> accm;
    for (const auto& r : acc.rows) accm[get(r, "format") + " " + get(r, "op")] = r;
    Table s;
    for (const auto& r : csv.rows) {
      if (get(r, "stages") != "0" || !get(r, "error").empty()) continue;
      const std::string op = get(r, "unit").substr(3);  // fp_mul -> mul
      auto it = accm.find(get(r, "format") + " " + op);
      if (it == accm.end()) continue;
      s.push_back({get(r, "unit"), get(r, "format"), fmt("%.0f", num(r, "area_nand2")),
                   fmt("%.0f", num(r, "fmax_est_mhz")), fmt("%.3g", num(it->second, "mean_rel_err")),
                   fmt("%.3g", num(it->second, "max_rel_err")), get(it->second, "out_of_range")});
    }
    if (!s.empty()) {
      md += "Speed and accuracy side by side (combinational units; errors from the accuracy section's workload):\n\n";
      md += ru::report::md_table({"unit", "format", "area (NAND2-eq)", "Fmax est. (MHz)", "mean rel. error",
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
  std::string md;

  // 1. Tables 3.2-3.4: signed-volume errors, formula ranking, sign errors.
  std::vector<std::string> a{"--synthetic", n_tri, "--seed", seed, "--out", ctx.path("tri").string(), "--threads",
                             threads_arg(ctx), "--quiet"};
  if (!ctx.opts.plots) a.push_back("--no-plot");
  std::string cmd = run_captured(ctx, "study tri", a, "tri.txt");
  md += "### Signed-volume error (Tables 3.2-3.4), formula ranking, sign errors\n\n" +
        code_block("cd REPORT && " + cmd) +
        "Lowest average relative error of V, Va and V0..2 against exact rationals (GMP) per format, on the "
        "synthetic benchmark (random triangles about the origin, ray packets aimed for ~25 % hits). Full "
        "printout: [tri.txt](tri.txt); data: `tri/study_tri_*.csv`.\n\n```\n" +
        read_text(ctx.path("tri.txt")) + "```\n\n";
  if (ctx.opts.plots)
    for (const auto& e : std::filesystem::directory_iterator(ctx.path("tri")))
      if (e.path().extension() == ".png")
        md += "![" + e.path().stem().string() + "](tri/" + e.path().filename().string() + ")\n\n";

  // 2. Ray-box false misses / false hits.
  cmd = run_captured(ctx, "study box",
                     {"--synthetic", n_box, "--seed", seed, "--csv", ctx.path("box.csv").string(), "--threads",
                      threads_arg(ctx), "--quiet"},
                     "box.txt");
  {
    const Csv c = read_csv(ctx.path("box.csv"));
    Table t;
    for (const auto& r : c.rows) {
      const double pairs = num(r, "pairs");
      auto ppm = [&](const char* k) { return fmt("%.0f", 1e6 * num(r, k) / pairs); };
      t.push_back({get(r, "format"), ppm("plain_false_miss"), ppm("plain_false_hit"), ppm("cons_false_miss"),
                   ppm("cons_false_hit")});
    }
    md += "### Ray-box test: false misses and false hits (per million pairs)\n\n" + code_block("cd REPORT && " + cmd) +
          "Against the exact slab test (GMP rationals). A false miss loses geometry; the conservative mode "
          "(t_enter rounded down, t_exit up) must have none. Data: [box.csv](box.csv).\n\n" +
          ru::report::md_table({"format", "plain false miss", "plain false hit", "conservative false miss",
                                "conservative false hit"},
                               t);
  }

  // 3. Watertightness: robust vs MT on a closed mesh, per format.
  {
    const std::string csv = ctx.path("watertight.csv").string();
    std::vector<std::string> cmds;
    std::stringstream fl(wt_formats);
    for (std::string f; std::getline(fl, f, ',');)
      for (const char* tri : {"robust", "mt"})
        cmds.push_back(run_captured(ctx, "study watertight",
                                    {"--scene", "icosphere", "--format", f, "--tri", tri, "--rays", rays, "--seed",
                                     seed, "--threads", threads_arg(ctx), "--csv", csv, "--quiet"},
                                    "watertight_" + f + "_" + tri + ".txt"));
    const Csv c = read_csv(csv);
    Table t;
    const std::vector<std::string> cols{"format",       "tri",         "edge_rays",          "edge_leaks",
                                        "edge_double_hits", "vertex_rays", "vertex_leaks", "vertex_double_hits",
                                        "overflow_rays"};
    for (const auto& r : c.rows) {
      std::vector<std::string> row;
      for (const auto& h : cols) row.push_back(get(r, h));
      t.push_back(row);
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
    cmd = run_sweep(ctx, "ray_synth", "ray_box,ray_tri_robust,ray_tri_mt", synth_formats, "0", Flow::Generic);
    const auto rows = sweep_rows(ctx, "ray_synth");
    Table t;
    std::stringstream fl(synth_formats);
    for (std::string f; std::getline(fl, f, ',');) {
      const double rb = area_of(rows, "ray_tri_robust " + f + " 0"), mt = area_of(rows, "ray_tri_mt " + f + " 0"),
                   bx = area_of(rows, "ray_box " + f + " 0");
      t.push_back({f, fmt("%.0f", bx), fmt("%.0f", rb), fmt("%.0f", mt), fmt("%.2f", rb / mt)});
    }
    md += "\n### Area: robust vs Moller-Trumbore\n\n" + code_block("cd REPORT && " + cmd) +
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
  std::string cmd = run_captured(ctx, "noise study", a, "noise.txt");
  std::string md = code_block("cd REPORT && " + cmd);
  if (std::filesystem::exists(ctx.path("noise") / "noise_summary.md")) {
    relativize_file(ctx, ctx.path("noise") / "noise_summary.md");
    std::string s = read_text(ctx.path("noise") / "noise_summary.md");
    // its images and CSVs are next to it, in noise/
    for (size_t p = 0; (p = s.find("](", p)) != std::string::npos; p += 2)
      if (s.compare(p + 2, 4, "http") != 0) s.insert(p + 2, "noise/");
    // demote its headings below this section's
    std::string out, line;
    std::stringstream in(s);
    while (std::getline(in, line)) out += (line.rfind("#", 0) == 0 ? "##" + line : line) + "\n";
    md += out + "\n";
  } else {
    md += "```\n" + read_text(ctx.path("noise.txt")) + "```\n\n";
  }

  if (synth) {
    // Table 4.1 in this flow: the unit by pipeline depth, and the e8m23 FP units beside it.
    // it does not fit an iCE40; the sweep's plot is for FP formats (the table shows the noise rows)
    cmd = run_sweep(ctx, "noise_synth", "noise", "", stages, Flow::Ice40Luts, false);
    const std::string cmd2 = run_sweep(ctx, "noise_fp_synth", "fp_add,fp_mul,fp_dot3", "e8m23", "0", Flow::Generic);
    const Csv c = read_csv(ctx.path("noise_synth") / "synth_sweep.csv");
    Table t;
    for (const auto& r : c.rows) {
      if (!get(r, "error").empty()) {
        t.push_back({get(r, "stages"), "error: " + get(r, "error")});
        continue;
      }
      auto cells = synth_cells(r);
      std::vector<std::string> row{get(r, "stages")};
      row.insert(row.end(), cells.begin(), cells.end());
      t.push_back(row);
    }
    md += "### Area and speed by pipeline depth (Table 4.1 in this flow)\n\n" +
          code_block("cd REPORT && " + cmd + "\ncd REPORT && " + cmd2) +
          ru::report::md_table({"stages", "area (NAND2-eq)", "register bits", "depth (gates)", "Fmax est. (MHz)",
                                "iCE40 LUTs", "iCE40 Fmax (MHz)"},
                               t);
    const auto fp = sweep_rows(ctx, "noise_fp_synth");
    const auto nz = sweep_rows(ctx, "noise_synth");
    const double n0 = area_of(nz, "noise  0");
    const double add = area_of(fp, "fp_add e8m23 0"), mul = area_of(fp, "fp_mul e8m23 0"),
                 dot = area_of(fp, "fp_dot3 e8m23 0");
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
