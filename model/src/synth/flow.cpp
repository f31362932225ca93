// The synthesis flow: Yosys generic gates (area, depth, delay model), synth_ice40 (+ nextpnr-ice40
// Fmax through a register harness), synth_xilinx. Method and numbers: synth/README.md.
#include "rayunits/synth/flow.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <regex>
#include <sstream>

#include "rayunits/synth/process.hpp"

namespace ru::synth {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A tool run failed: run_synth keeps its temp dir so the log named in the message survives.
class ToolError : public SynthError {
 public:
  using SynthError::SynthError;
};

// NAND2-equivalent weights of the combinational cells of Yosys's generic library, modelled on
// the X1 cell areas of a typical open standard-cell library (NAND2 = 1): see synth/README.md.
const std::map<std::string, double>& gate_weights() {
  static const std::map<std::string, double> w = {
      {"$_BUF_", 1.0},      {"$_NOT_", 2.0 / 3},  {"$_NAND_", 1.0},       {"$_NOR_", 1.0},
      {"$_AND_", 4.0 / 3},  {"$_OR_", 4.0 / 3},   {"$_ANDNOT_", 4.0 / 3}, {"$_ORNOT_", 4.0 / 3},
      {"$_XOR_", 2.0},      {"$_XNOR_", 2.0},     {"$_MUX_", 7.0 / 3},    {"$_NMUX_", 2.0},
      {"$_AOI3_", 4.0 / 3}, {"$_OAI3_", 4.0 / 3}, {"$_AOI4_", 5.0 / 3},   {"$_OAI4_", 5.0 / 3},
  };
  return w;
}

// Flip-flop weights: D flip-flop 17/3 (DFF_X1 / NAND2_X1), +1 for an asynchronous set or reset,
// +7/3 for both (or an async load), +7/3 for a clock enable (a MUX2 in front), +4/3 for a
// synchronous reset/set (an AND2/OR2 in front).
struct FlopKind {
  bool flop = false, latch = false;
  double weight = 0;
};

FlopKind flop_kind(const std::string& t) {
  static const std::regex dff(R"(\$_DFF_[NP]_)");
  static const std::regex dff_ar(R"(\$_DFF_[NP][NP][01]_)");
  static const std::regex dffe(R"(\$_DFFE_[NP][NP]_)");
  static const std::regex dffe_ar(R"(\$_DFFE_[NP][NP][01][NP]_)");
  static const std::regex dffsr(R"(\$_(DFFSR_[NP]{3}|ALDFF_[NP]{2})_)");
  static const std::regex dffsre(R"(\$_(DFFSRE_[NP]{4}|ALDFFE_[NP]{3})_)");
  static const std::regex sdff(R"(\$_SDFF_[NP][NP][01]_)");
  static const std::regex sdffe(R"(\$_SDFF(C)?E_[NP][NP][01][NP]_)");
  static const std::regex ff(R"(\$_FF_)");
  static const std::regex latch(R"(\$_(DLATCH|DLATCHSR|SR)_[NP01]*_?)");
  const double d = 17.0 / 3, ar = 1.0, sr2 = 7.0 / 3, en = 7.0 / 3, sync = 4.0 / 3;
  FlopKind k;
  if (std::regex_match(t, dff) || std::regex_match(t, ff))
    k = {true, false, d};
  else if (std::regex_match(t, dff_ar))
    k = {true, false, d + ar};
  else if (std::regex_match(t, dffe))
    k = {true, false, d + en};
  else if (std::regex_match(t, dffe_ar))
    k = {true, false, d + ar + en};
  else if (std::regex_match(t, dffsr))
    k = {true, false, d + sr2};
  else if (std::regex_match(t, dffsre))
    k = {true, false, d + sr2 + en};
  else if (std::regex_match(t, sdff))
    k = {true, false, d + sync};
  else if (std::regex_match(t, sdffe))
    k = {true, false, d + sync + en};
  else if (std::regex_match(t, latch))
    k = {false, true, 0};
  return k;
}

// A file name as a Yosys script word. Not util::shell_quote: Yosys's command tokenizer is not
// a POSIX shell (single quotes are not special; a word with blanks is written "...", with \"
// for a quote inside), so the script language needs its own quoting.
std::string quote(const std::string& p) {
  if (p.find_first_of(" \t\"") == std::string::npos) return p;
  std::string q = "\"";
  for (char c : p) {
    if (c == '"') q += '\\';
    q += c;
  }
  return q + "\"";
}

std::string read_sources(const std::vector<std::string>& sources) {
  std::string s;
  for (const auto& f : sources) s += "read_verilog -sv " + quote(f) + "\n";
  return s;
}

struct Device {
  const char* name;
  const char* pnr_flag;
  const char* package;
  long luts;
  long dsps;
};
const Device& device(const std::string& name) {
  static const Device d[] = {{"hx8k", "--hx8k", "ct256", 7680, 0}, {"up5k", "--up5k", "sg48", 5280, 8}};
  for (const auto& x : d)
    if (name == x.name) return x;
  throw SynthError("unknown iCE40 device '" + name + "' (devices: hx8k, up5k)");
}

std::string first_error_line(const std::string& log_path) {
  std::string text;
  try {
    text = read_file(log_path);
  } catch (const SynthError&) {
    return {};
  }
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line)) {
    if (line.rfind("ERROR:", 0) == 0) return line;
    if (!line.empty()) last = line;
  }
  return last;
}

// `out` collects the tool's stdout/stderr (where Yosys -q prints errors); `log` is the full log
// named in error messages.
double run_tool(const std::string& what, const std::vector<std::string>& argv, const std::string& dir,
                const std::string& out, const std::string& log, int timeout_s) {
  ProcResult r = run_process(argv, dir, out, timeout_s);
  if (r.timed_out)
    throw ToolError(what + " timed out after " + std::to_string(timeout_s) + " s (log: " + log + ")");
  if (r.exit_code != 0) {
    std::string e = first_error_line(out);
    throw ToolError(what + " failed (exit " + std::to_string(r.exit_code) + ")" +
                    (e.empty() ? "" : ": " + e) + " (log: " + log + ")");
  }
  return r.seconds;
}

double run_yosys(const std::string& yosys, const std::string& what, const std::string& script_text,
                 const std::string& dir, const std::string& stem, int timeout_s) {
  const std::string script = dir + "/" + stem + ".ys";
  write_file_atomic(script, script_text);
  const std::string log = dir + "/" + stem + ".log";
  return run_tool("yosys (" + what + ")", {yosys, "-q", "-l", log, script}, dir, dir + "/" + stem + ".out",
                  log, timeout_s);
}

// num_cells_by_type of the top of a `stat -json` file.
std::map<std::string, long> stat_cells(const std::string& path, const std::string& top) {
  json j;
  try {
    j = json::parse(read_file(path));
  } catch (const json::exception& e) {
    throw SynthError("cannot parse Yosys statistics '" + path + "': " + e.what());
  }
  const json* m = nullptr;
  // The module itself first: in the cell flow the design also holds the STA harness.
  if (j.contains("modules") && j["modules"].contains("\\" + top))
    m = &j["modules"]["\\" + top];
  else if (j.contains("design"))
    m = &j["design"];
  else if (j.contains("modules") && j["modules"].size() == 1)
    m = &j["modules"].begin().value();
  if (!m || !m->contains("num_cells_by_type"))
    throw SynthError("no cell statistics for '" + top + "' in '" + path + "'");
  std::map<std::string, long> cells;
  for (auto it = (*m)["num_cells_by_type"].begin(); it != (*m)["num_cells_by_type"].end(); ++it)
    cells[it.key()] = it.value().get<long>();
  return cells;
}

long count_prefix(const std::map<std::string, long>& cells, const std::vector<std::string>& prefixes) {
  long n = 0;
  for (const auto& [t, c] : cells)
    for (const auto& p : prefixes)
      if (t.rfind(p, 0) == 0) {
        n += c;
        break;
      }
  return n;
}

std::string harness_verilog(const std::string& top, const std::vector<Port>& ports) {
  int in_w = 0, out_w = 0;
  for (const auto& p : ports) {
    if (p.dir == PortDir::In && p.role != PortRole::Clock && p.role != PortRole::Reset) in_w += p.width;
    if (p.dir == PortDir::Out) out_w += p.width;
  }
  std::ostringstream o;
  o << "// FPGA timing harness (rayunits synth --fpga): every unit input comes from a shift\n"
       "// register fed by one pin and every output goes into a capture register, so nextpnr's\n"
       "// clock Fmax covers all paths of the unit (input -> first register and last register ->\n"
       "// output included) with 4 pins. The XOR of the captured outputs keeps all of them live.\n"
       "module ru_fpga_harness (\n  input logic clk_i,\n  input logic rst_ni,\n"
       "  input logic din_i,\n  output logic dout_o\n);\n"
    << "  logic [" << std::max(in_w, 2) - 1 << ":0] in_q;\n"
    << "  logic [" << out_w - 1 << ":0] out_d, out_q;\n"
    << "  always_ff @(posedge clk_i) in_q <= {in_q[" << std::max(in_w, 2) - 2 << ":0], din_i};\n"
    << "  always_ff @(posedge clk_i) out_q <= out_d;\n"
    << "  assign dout_o = ^out_q;\n"
    << "  " << top << " u_dut (\n";
  int ib = 0, ob = 0;
  for (size_t i = 0; i < ports.size(); ++i) {
    const auto& p = ports[i];
    std::string src;
    if (p.role == PortRole::Clock)
      src = "clk_i";
    else if (p.role == PortRole::Reset)
      src = "rst_ni";
    else if (p.dir == PortDir::In) {
      src = "in_q[" + std::to_string(ib + p.width - 1) + ":" + std::to_string(ib) + "]";
      ib += p.width;
    } else {
      src = "out_d[" + std::to_string(ob + p.width - 1) + ":" + std::to_string(ob) + "]";
      ob += p.width;
    }
    o << "    ." << p.name << "(" << src << ")" << (i + 1 < ports.size() ? "," : "") << "\n";
  }
  o << "  );\nendmodule\n";
  return o.str();
}

std::string fmt_num(double v, int prec) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

}  // namespace

double nand2_weight(const std::string& t) {
  const auto& g = gate_weights();
  if (auto it = g.find(t); it != g.end()) return it->second;
  FlopKind k = flop_kind(t);
  if (k.flop) return k.weight;
  if (k.latch) throw SynthError("the design contains latch cells (" + t + "): latches are not allowed");
  throw SynthError("cell type '" + t + "' has no NAND2-equivalent weight (unmapped cell?)");
}

bool is_flop_cell(const std::string& t) { return flop_kind(t).flop; }

std::string generic_script(const std::vector<std::string>& sources, const std::string& top, bool measure,
                           bool share) {
  std::string s = read_sources(sources);
  s += "hierarchy -check -top " + top + "\n";
  s += std::string("synth -flatten") + (share ? "" : " -noshare") + " -top " + top + "\n";
  s += "check -assert\n";
  if (measure) {
    s += "tee -q -o stat.json stat -json\n";
    s += "tee -q -o cmos.txt stat -tech cmos\n";
    s += "tee -q -o ltp.txt ltp -noff\n";
  } else {
    s += "stat\nstat -tech cmos\nltp -noff\n";
  }
  return s;
}

std::string yosys_version(const std::string& yosys) {
  static std::mutex mu;
  static std::map<std::string, std::string> cache;
  const std::string exe = find_program(yosys);
  if (exe.empty())
    throw SynthError("yosys not found ('" + yosys +
                     "'): install the Debian package yosys (0.23) or pass --yosys PATH");
  std::lock_guard<std::mutex> lock(mu);
  if (auto it = cache.find(exe); it != cache.end()) return it->second;
  TempDir tmp("ru-yosys-v-");
  const std::string log = tmp.path() + "/v.txt";
  ProcResult r = run_process({exe, "-V"}, tmp.path(), log, 30);
  std::string v = r.exit_code == 0 ? read_file(log) : std::string();
  while (!v.empty() && (v.back() == '\n' || v.back() == '\r')) v.pop_back();
  if (v.rfind("Yosys ", 0) != 0)
    throw SynthError("'" + exe + "' does not look like yosys (`-V` printed '" + v + "')");
  cache[exe] = v;
  return v;
}

std::string cell_premap_script(const CellLibrary& lib, const std::vector<std::string>& sources,
                               const std::string& unit_top, bool share) {
  std::string s = "read_liberty -lib " + quote(lib.liberty) + "\n" + read_sources(sources);
  s += "read_verilog -sv sta_harness.sv\n";
  s += "hierarchy -check -top ru_sta_harness\n";
  // The unit stays one module (flattened inside): its area is reported without the harness.
  s += "setattr -mod -set keep_hierarchy 1 " + unit_top + "\n";
  s += std::string("synth -flatten") + (share ? "" : " -noshare") + " -top ru_sta_harness\n";
  s += "dfflibmap -liberty " + quote(lib.liberty) + "\n";
  s += "write_rtlil premap.il\n";
  return s;
}

std::string cell_abc_script(double target_ps) {
  // With a target: ABC's standard-cell timing flow -- delay-targeted mapping, then buffering
  // and gate sizing towards the target (the library has X1..X8 drive strengths). Its `&nf`
  // mapper, which Yosys's own `abc -D` runs, gave the same netlist for every -D here (fp_add
  // e5m10: 1 ns, 4 ns and 20 ns alike), so it cannot make an area-delay curve.
  // `topo` after `map`: buffer/upsize need a topologically ordered network (without it ABC
  // aborts with "node N has no fanout" at an unreachable target, fp_add e5m10 at 500 ps).
  // Without a target: the same flow without -D (ABC maps for delay, then sizes). Not Yosys's
  // default `&nf` script: on the flattened noise unit it did not finish in 15 minutes.
  const std::string d = target_ps > 0 ? " -D " + fmt_num(target_ps, 0) : std::string();
  return "strash\nifraig\nscorr\ndc2\nstrash\ndch -f\nmap" + d + "\ntopo\nbuffer -p\nupsize" + d + "\ndnsize" + d +
         "\n";
}

std::string cell_map_script(const CellLibrary& lib, const std::string& stem, const std::string& unit_top) {
  std::string s = "read_liberty -lib " + quote(lib.liberty) + "\nread_rtlil premap.il\n";
  s += "abc -liberty " + quote(lib.liberty) + " -script " + stem + ".abc\n";
  // -purge and -simple-lhs: no `assign {a, b} = ...`, which OpenSTA cannot read.
  s += "opt_clean -purge\ncheck -assert\n";
  s += "tee -q -o " + stem + ".json stat -json\n";
  s += "tee -q -o " + stem + ".txt stat -liberty " + quote(lib.liberty) + "\n";
  s += "write_verilog -noattr -noexpr -simple-lhs " + stem + ".v\n";
  // The unit alone (synth --netlist; gate-level simulation in tb/gls).
  s += "select " + unit_top + "\nwrite_verilog -noattr -noexpr -simple-lhs -selected " + stem + "_unit.v\nselect -clear\n";
  return s;
}

namespace {

CellResult run_cell_flow(const std::vector<std::string>& abs_sources, const std::string& top,
                         const std::vector<Port>& ports, const std::string& dir, const FlowOptions& o,
                         const std::string& yosys) {
  CellResult c;
  c.run = true;
  const CellLibrary& lib = cell_library(o.flow);
  c.library = lib.name;
  c.liberty = lib.liberty;
  c.sta_version = sta_version(o.sta);
  c.fo4_ps = measure_fo4_ps(lib, o.sta);
  write_file_atomic(dir + "/sta_harness.sv", sta_harness_verilog(top, ports));
  c.premap_s = run_yosys(yosys, "cell flow: synth + dfflibmap", cell_premap_script(lib, abs_sources, top, o.share),
                         dir, "cell_premap", o.timeout_s);
  int stages = 0;  // register levels of the unit, for the segment numbering
  std::vector<double> clocks = o.clocks_ps;
  if (clocks.empty()) clocks.push_back(0);
  for (size_t k = 0; k < clocks.size(); ++k) {
    CellRun run;
    run.target_ps = clocks[k];
    const std::string stem = "cell_" + std::to_string(k);
    write_file_atomic(dir + "/" + stem + ".abc", cell_abc_script(clocks[k]));
    run.yosys_s = run_yosys(yosys, "cell flow: abc -liberty" + (clocks[k] > 0 ? " -D " + fmt_num(clocks[k], 0) : ""),
                            cell_map_script(lib, stem, top), dir, stem, o.timeout_s);
    run.cells = stat_cells(dir + "/" + stem + ".json", top);
    run.area = cell_area(lib, run.cells);
    {
      // Self-check against Yosys's own total (stat -liberty): the same cells, the same areas.
      const std::string txt = read_file(dir + "/" + stem + ".txt");
      std::smatch m;
      const std::regex re("Chip area for module '\\\\" + top + "': ([0-9.]+)");
      if (!std::regex_search(txt, m, re)) throw SynthError("no chip area for " + top + " in " + dir + "/" + stem + ".txt");
      const double y = std::stod(m[1]);
      if (std::fabs(y - run.area.total) > 1e-6 * std::max(1.0, y))
        throw SynthError("cell area of " + top + ": Yosys says " + fmt_num(y, 3) + ", the liberty's cell areas give " +
                         fmt_num(run.area.total, 3));
    }
    run.netlist = dir + "/" + stem + "_unit.v";
    if (!o.netlist_out.empty() && k == 0) {
      try {
        fs::copy_file(run.netlist, o.netlist_out, fs::copy_options::overwrite_existing);
      } catch (const fs::filesystem_error& e) {
        throw SynthError("cannot write the netlist to '" + o.netlist_out + "': " + e.code().message());
      }
    }
    const double period = clocks[k] > 0 ? clocks[k] : kUntargetedPeriodPs;
    const auto t1 = std::chrono::steady_clock::now();
    run.sta = run_sta(lib, o.sta, dir + "/" + stem + ".v", "ru_sta_harness", period, stages, dir, stem + "_sta",
                      o.timeout_s, o.stage_periods);
    run.sta_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    run.achieved_ps = period - run.sta.slack_ps;
    run.fmax_mhz = 1e6 / run.achieved_ps;
    c.runs.push_back(std::move(run));
  }
  return c;
}

}  // namespace

void label_result(SynthResult& r, const UnitSpec& u, const UnitConfig& c, const Sources& src) {
  r.unit = u.name;
  r.cfg = c;
  r.rtl_hash = sources_hash(src);
  for (auto& run : r.cell.runs) run.sta.path.segments = c.stages + 1;
}

SynthResult run_flow(const std::vector<std::string>& sources, const std::string& top,
                     const std::vector<Port>& ports, const std::string& dir, const FlowOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  SynthResult r;
  check_flow_name(o.flow);
  r.flow = o.flow;
  r.top = top;
  r.yosys_version = yosys_version(o.yosys);
  r.share = o.share;
  const std::string yosys = find_program(o.yosys);
  std::string nextpnr;
  if (o.pnr && !is_cell_flow(o.flow)) {
    nextpnr = find_program(o.nextpnr);
    if (nextpnr.empty())
      throw SynthError("nextpnr-ice40 not found ('" + o.nextpnr +
                       "'): install the Debian package nextpnr-ice40, pass --nextpnr PATH, or drop --fpga");
  }
  std::vector<std::string> abs_sources;
  for (const auto& s : sources) abs_sources.push_back(fs::absolute(s).lexically_normal().string());

  if (is_cell_flow(o.flow)) {
    r.cell = run_cell_flow(abs_sources, top, ports, dir, o, yosys);
    for (size_t k = 0; k < r.cell.runs.size(); ++k) {
      r.step_seconds["cell_map_" + std::to_string(k)] = r.cell.runs[k].yosys_s;
      r.step_seconds["sta_" + std::to_string(k)] = r.cell.runs[k].sta_s;
    }
    r.step_seconds["cell_premap"] = r.cell.premap_s;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }

  // 1. Generic gates: area, transistors, registers, depth of the worst stage.
  r.step_seconds["generic"] =
      run_yosys(yosys, "generic", generic_script(abs_sources, top, true, o.share), dir, "generic", o.timeout_s);
  GenericResult& g = r.generic;
  g.cells = stat_cells(dir + "/stat.json", top);
  for (const auto& [t, n] : g.cells) {
    g.cells_total += n;
    g.area_nand2 += nand2_weight(t) * static_cast<double>(n);  // throws on latches/unmapped
    if (is_flop_cell(t)) g.reg_bits += n;
  }
  {
    const std::string cmos = read_file(dir + "/cmos.txt");
    std::smatch m;
    if (!std::regex_search(cmos, m, std::regex(R"(Estimated number of transistors:\s+(\d+)(\+?))")))
      throw SynthError("no transistor estimate in " + dir + "/cmos.txt");
    g.transistors = std::stol(m[1]);
    g.transistors_complete = m[2].length() == 0;
    if (!g.transistors_complete)
      for (const auto& [t, n] : g.cells)
        if (is_flop_cell(t) && t != "$_DFF_P_" && t != "$_DFF_N_") g.transistors_uncounted += n;
  }
  {
    const std::string ltp = read_file(dir + "/ltp.txt");
    static const std::regex re(R"(Longest topological path in \S+ \(length=(\d+)\))");
    bool found = false;
    for (auto it = std::sregex_iterator(ltp.begin(), ltp.end(), re); it != std::sregex_iterator(); ++it) {
      g.depth = std::max(g.depth, std::stoi((*it)[1]));
      found = true;
    }
    if (!found && g.cells_total - g.reg_bits > 0)
      throw SynthError("no longest-path report in " + dir + "/ltp.txt");
  }
  g.stage_ps = DelayModel::stage_ps(g.depth);
  g.fmax_mhz = DelayModel::fmax_mhz(g.depth);

  // 2. iCE40: LUT counts of the unit alone; with --fpga, nextpnr on the register harness.
  if (o.ice40) {
    const Device& d = device(o.ice40_device);
    Ice40Result& ic = r.ice40;
    ic.run = true;
    ic.device = d.name;
    ic.device_luts = d.luts;
    const std::string dsp = d.dsps > 0 ? " -dsp" : "";
    r.step_seconds["ice40"] =
        run_yosys(yosys, "synth_ice40",
                  read_sources(abs_sources) + "hierarchy -check -top " + top + "\nsynth_ice40 -top " + top +
                      dsp + "\ntee -q -o ice40_stat.json stat -json\n",
                  dir, "ice40", o.timeout_s);
    auto cells = stat_cells(dir + "/ice40_stat.json", top);
    ic.luts = count_prefix(cells, {"SB_LUT4"});
    ic.carries = count_prefix(cells, {"SB_CARRY"});
    ic.ffs = count_prefix(cells, {"SB_DFF"});
    ic.dsps = count_prefix(cells, {"SB_MAC16"});
    ic.brams = count_prefix(cells, {"SB_RAM"});
    ic.fits = ic.luts <= d.luts && ic.dsps <= d.dsps && ic.brams == 0;
    if (!ic.fits)
      ic.reason = ic.luts > d.luts ? std::to_string(ic.luts) + " LUT4 > " + std::to_string(d.luts)
                                   : "needs " + std::to_string(ic.dsps) + " DSP / " +
                                         std::to_string(ic.brams) + " RAM blocks";
    if (o.pnr && ic.fits) {
      ic.pnr_run = true;
      write_file_atomic(dir + "/harness.sv", harness_verilog(top, ports));
      r.step_seconds["ice40_harness"] =
          run_yosys(yosys, "synth_ice40 harness",
                    read_sources(abs_sources) + "read_verilog -sv harness.sv\n" +
                        "hierarchy -check -top ru_fpga_harness\nsynth_ice40 -top ru_fpga_harness" + dsp +
                        " -json harness.json\n",
                    dir, "ice40_harness", o.timeout_s);
      const std::string log = dir + "/nextpnr.log";
      ProcResult pr = run_process(
          {nextpnr, d.pnr_flag, "--package", d.package, "--json", "harness.json", "--pcf-allow-unconstrained",
           "--timing-allow-fail", "--freq", "12", "--seed", "1", "-q", "-l", log},
          dir, dir + "/nextpnr.out", o.timeout_s);
      r.step_seconds["nextpnr"] = pr.seconds;
      std::string text;
      try {
        text = read_file(log);
      } catch (const SynthError&) {
      }
      static const std::regex fre(R"(Max frequency for clock '[^']*': ([0-9.]+) MHz)");
      for (auto it = std::sregex_iterator(text.begin(), text.end(), fre); it != std::sregex_iterator(); ++it)
        ic.fmax_mhz = std::stod((*it)[1]);  // the last report is after routing
      std::smatch m;
      if (std::regex_search(text, m, std::regex(R"(ICESTORM_LC:\s+(\d+)/)"))) ic.lcs = std::stol(m[1]);
      if (pr.timed_out) {
        ic.reason = "nextpnr timed out after " + std::to_string(o.timeout_s) + " s";
      } else if (pr.exit_code != 0 || ic.fmax_mhz <= 0) {
        std::string e = first_error_line(log);
        if (e.empty()) e = first_error_line(dir + "/nextpnr.out");
        ic.reason = "nextpnr failed: " + e;
        // Running out of cells / routing is "does not fit", anything else is a tool failure.
        if (e.find("Unable to place") != std::string::npos || e.find("no BEL") != std::string::npos ||
            e.find("route") != std::string::npos)
          ic.fits = false;
        else
          throw ToolError(ic.reason + " (log: " + log + ")");
      } else {
        ic.pnr_ok = true;
      }
    }
  }

  // 3. Xilinx 7-series LUT/DSP counts.
  if (o.xilinx) {
    XilinxResult& x = r.xilinx;
    x.run = true;
    r.step_seconds["xilinx"] =
        run_yosys(yosys, "synth_xilinx",
                  read_sources(abs_sources) + "hierarchy -check -top " + top + "\nsynth_xilinx -top " + top +
                      " -flatten\ntee -q -o xilinx_stat.json stat -json\n" +
                      "tee -q -o xilinx_lc.txt stat -tech xilinx\n",
                  dir, "xilinx", o.timeout_s);
    auto cells = stat_cells(dir + "/xilinx_stat.json", top);
    x.luts = count_prefix(cells, {"LUT1", "LUT2", "LUT3", "LUT4", "LUT5", "LUT6"});
    x.ffs = count_prefix(cells, {"FDRE", "FDSE", "FDCE", "FDPE"});
    x.dsps = count_prefix(cells, {"DSP48"});
    x.carry4 = count_prefix(cells, {"CARRY4"});
    x.muxf = count_prefix(cells, {"MUXF7", "MUXF8"});
    x.srls = count_prefix(cells, {"SRL16", "SRLC32"});
    x.lutram = count_prefix(cells, {"RAM32", "RAM64", "RAM128", "RAM256"});
    x.bram = count_prefix(cells, {"RAMB"});
    std::smatch m;
    const std::string lc = read_file(dir + "/xilinx_lc.txt");
    if (std::regex_search(lc, m, std::regex(R"(Estimated number of LCs:\s+(\d+))"))) x.lcs = std::stol(m[1]);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

namespace {

// Register placement by measured delays (FlowOptions::placement "delay"): the unit with every
// cut position registered, mapped in the same flow for its fastest netlist (kCharacterizeTargetPs), and OpenSTA's period of
// each stage. A segment's logic delay = its stage's period minus the clock-to-Q and setup of the
// critical path (the same flip-flop cell everywhere); the weights are those delays in steps of
// ceil(max / 255) ps (the RTL's 8-bit weights), at least 1.
constexpr double kCharacterizeTargetPs = 200;
void characterize_segments(const UnitSpec& u, const UnitConfig& c, const FlowOptions& o, SynthResult& out,
                           UnitConfig& placed) {
  UnitConfig all = c;
  all.stages = u.max_stages(c);
  all.seg_weights.clear();
  FlowOptions fc = o;
  fc.placement = "depth";
  fc.stage_periods = true;
  fc.netlist_out.clear();
  fc.keep_temp = false;
  // Mapped as fast as ABC can (a target below every segment's delay): ABC speeds up a path only
  // as far as its target asks, so at a relaxed target a segment's delay says how it was mapped
  // (fp_mul e8m23 at 6.7 ns: a 5.6 ns carry-propagate adder that the same target maps in far
  // less once it shares a stage with other segments), not how long it must take.
  fc.clocks_ps = {kCharacterizeTargetPs};
  // The same characterization serves every Stages of a unit (gen --clock probes several): cached
  // for the process by configuration, flow, clock and sources.
  static std::mutex mu;
  static std::map<std::string, SynthResult> cache;
  const std::string rtl = fc.rtl_dir.empty() ? default_rtl_dir() : fc.rtl_dir;
  const std::string key = config_args(u, all) + "|" + fc.flow + "|" + (fc.clocks_ps.empty() ? "-" : fmt_num(fc.clocks_ps[0], 3)) +
                          "|" + sources_hash(resolve_sources(u, rtl)) + "|" + fc.yosys + "|" + fc.sta;
  SynthResult r;
  bool cached = false;
  {
    std::unique_lock<std::mutex> lock(mu);
    auto it = cache.find(key);
    if (it != cache.end()) {
      r = it->second;
      cached = true;
    } else {
      lock.unlock();
      r = run_synth(u, all, fc);
      lock.lock();
      cache.emplace(key, r);
    }
  }
  const CellRun& run = r.cell.runs.at(0);
  const double overhead = run.sta.path.clk_to_q_ps + run.sta.path.setup_ps;
  double dmax = 0;
  for (double p : run.stage_ps) {
    out.segment_delays_ps.push_back(std::max(0.0, p - overhead));
    dmax = std::max(dmax, out.segment_delays_ps.back());
  }
  const double step = std::max(1.0, std::ceil(dmax / 255));
  for (double d : out.segment_delays_ps) out.seg_weights.push_back(std::clamp(static_cast<int>(std::lround(d / step)), 1, 255));
  out.step_seconds["characterize"] = cached ? 0.0 : r.seconds;
  placed.seg_weights = out.seg_weights;
}

}  // namespace

SynthResult run_synth(const UnitSpec& u, const UnitConfig& c, const FlowOptions& o) {
  check_config(u, c);
  if (o.placement != "depth" && o.placement != "delay")
    throw SynthError("unknown placement '" + o.placement + "' (placements: depth, delay)");
  if (o.placement == "delay") {
    if (!is_cell_flow(o.flow))
      throw SynthError("--placement delay needs a cell-library flow (--flow osu018, osu035 or osu050): the delays "
                       "come from its static timing");
    if (!u.seg_weights_param) {
      std::string with;
      for (const auto& x : units())
        if (x.seg_weights_param) with += (with.empty() ? "" : ", ") + x.name;
      throw SynthError("--placement delay: " + u.name + " places its registers through its sub-units' chain "
                       "(units with their own placement: " + with + ")");
    }
  }
  if (o.stage_periods && u.handshake)
    throw SynthError("--stage-periods: " + u.name + " has a handshake (variable latency, registers outside its Stages "
                     "pipeline); per-stage periods need a fixed-latency pipeline (the critical path and period still apply)");
  if (!c.seg_weights.empty()) {
    if (!u.seg_weights_param) throw SynthError(u.name + " has no SegW parameter (segment weights)");
    if (static_cast<int>(c.seg_weights.size()) != u.max_stages(c) + 1)
      throw SynthError(u.name + ": " + std::to_string(c.seg_weights.size()) + " segment weights, the unit has " +
                       std::to_string(u.max_stages(c) + 1) + " segments");
  }
  if (o.placement == "delay" && c.seg_weights.empty()) {
    SynthResult r;
    UnitConfig placed = c;
    // At Stages 0 and at the maximum there is nothing to place: every cut or none.
    if (c.stages > 0 && c.stages < u.max_stages(c)) characterize_segments(u, c, o, r, placed);
    FlowOptions fp = o;
    fp.placement = "depth";  // the weights (if any) are in `placed` now
    fp.stage_periods = true;
    SynthResult f = run_synth(u, placed, fp);
    f.cfg = c;  // the request (the weights are in f.seg_weights)
    f.placement = "delay";
    f.segment_delays_ps = r.segment_delays_ps;
    f.seg_weights = r.seg_weights;
    for (const auto& [k, v] : r.step_seconds) f.step_seconds[k] = v;
    return f;
  }
  const std::string rtl = o.rtl_dir.empty() ? default_rtl_dir() : o.rtl_dir;
  const Sources src = resolve_sources(u, rtl);
  std::vector<std::string> sources = src.files;
  yosys_version(o.yosys);  // a missing yosys is reported before any work
  check_flow_name(o.flow);
  if (is_cell_flow(o.flow)) {  // a missing library or sta is reported before any work
    cell_library(o.flow);
    sta_version(o.sta);
  } else if (o.ice40) {
    device(o.ice40_device);
  }
  TempDir tmp("ru-synth-" + u.name + "-", o.temp_parent);
  if (o.keep_temp) tmp.keep();
  const std::string top = wrapper_name(u, c);
  write_file_atomic(tmp.path() + "/" + top + ".sv", wrapper_verilog(u, c));
  sources.push_back(tmp.path() + "/" + top + ".sv");
  SynthResult r;
  FlowOptions fo = o;
  fo.share = o.share && u.synth_share;
  try {
    r = run_flow(sources, top, ports_for(u, c), tmp.path(), fo);
  } catch (const SynthError& e) {
    if (std::string(e.what()).find("(log: ") != std::string::npos) tmp.keep();  // the message names a log inside it
    throw;
  }
  label_result(r, u, c, src);
  for (auto& run : r.cell.runs) {
    if (!o.stage_periods) continue;
    // Levels 1..stages+1 each once (level 0: the harness input registers); anything else means
    // the register structure is not the one the level rule assumes.
    for (const auto& [l, v] : run.sta.level_ps)
      if (l < 0 || l > c.stages + 1)
        throw SynthError(config_args(u, c) + ": STA found registers at level " + std::to_string(l) + ", expected 0.." +
                         std::to_string(c.stages + 1));
    for (int l = 1; l <= c.stages + 1; ++l) {
      auto it = run.sta.level_ps.find(l);
      if (it == run.sta.level_ps.end())
        throw SynthError(config_args(u, c) + ": STA found no register ending pipeline stage " + std::to_string(l));
      run.stage_ps.push_back(it->second);
    }
  }
  if (o.keep_temp) r.temp_dir = tmp.path();
  return r;
}

namespace {

double round_to(double v, double unit) { return std::round(v / unit) / std::round(1 / unit); }  // unit 0.1, 0.01

// The fields of a cell-flow row (synth/README.md, "Row schema").
void cell_fields(json& j, const CellResult& c, const CellRun& run) {
  j["library"] = c.library;
  j["liberty"] = c.liberty;
  j["wire_load"] = "none (the liberty has no wire-load model: before placement)";
  j["target_clock_ps"] = run.target_ps > 0 ? json(run.target_ps) : json(nullptr);
  j["target_clock_mhz"] = run.target_ps > 0 ? json(round_to(1e6 / run.target_ps, 0.01)) : json(nullptr);
  j["sta_period_ps"] = run.sta.period_ps;
  j["slack_ps"] = round_to(run.sta.slack_ps, 0.1);
  j["tns_ps"] = round_to(run.sta.tns_ps, 0.1);
  j["met"] = run.target_ps > 0 ? json(run.sta.slack_ps >= 0) : json(nullptr);
  j["period_ps"] = round_to(run.achieved_ps, 0.1);
  j["fmax_mhz"] = round_to(run.fmax_mhz, 0.1);
  j["fo4_ps"] = round_to(c.fo4_ps, 0.01);
  j["period_fo4"] = round_to(run.achieved_ps / c.fo4_ps, 0.01);
  j["area_um2"] = round_to(run.area.total, 0.01);
  j["area_comb_um2"] = round_to(run.area.comb, 0.01);
  j["area_seq_um2"] = round_to(run.area.seq, 0.01);
  j["cell_count"] = run.area.cells;
  j["seq_cells"] = run.area.seq_cells;
  j["cells"] = run.cells;
  const StaPath& p = run.sta.path;
  j["critical_path"] = {{"start", p.start},
                        {"end", p.end},
                        {"segment", p.segment > 0 ? json(p.segment) : json(nullptr)},
                        {"segments", p.segments},
                        {"clk_to_q_ps", round_to(p.clk_to_q_ps, 0.1)},
                        {"logic_ps", round_to(p.logic_ps, 0.1)},
                        {"setup_ps", round_to(p.setup_ps, 0.1)},
                        {"cells", p.cells}};
  j["sta"] = c.sta_version;
}

}  // namespace

std::vector<json> to_json_rows(const SynthResult& r) {
  const auto& g = r.generic;
  json j;
  j["unit"] = r.unit;
  j["top"] = r.top;
  const UnitSpec* u = nullptr;
  for (const auto& x : units())
    if (x.name == r.unit) u = &x;
  if (u && u->uses_format) {
    j["format"] = r.cfg.fmt.name();
    j["exp_bits"] = r.cfg.fmt.exp_bits;
    j["frac_bits"] = r.cfg.fmt.frac_bits;
    j["width"] = r.cfg.fmt.width();
    j["subnormals"] = r.cfg.fmt.subnormals;
    j["round"] = num::round_name(r.cfg.fmt.round);
  } else {
    for (const char* k : {"format", "exp_bits", "frac_bits", "width", "subnormals", "round"}) j[k] = nullptr;
  }
  json params = json::object();
  if (u)
    for (const auto& [k, v] : params_for(*u, r.cfg)) params[k] = v;
  j["params"] = params;
  j["stages"] = r.cfg.stages;
  j["latency"] = r.cfg.stages;
  j["throughput"] = 1;  // operations per cycle (fully pipelined)
  j["flow"] = r.flow;
  if (r.cell.run) {
    std::vector<json> rows;
    for (const CellRun& run : r.cell.runs) {
      json c = j;
      cell_fields(c, r.cell, run);
      c["resource_sharing"] = r.share;
      c["yosys"] = r.yosys_version;
      if (!r.rtl_hash.empty()) c["rtl_hash"] = r.rtl_hash;
      c["seconds"] = round_to(run.yosys_s + run.sta_s + r.cell.premap_s / r.cell.runs.size(), 0.01);
      c["step_seconds"] = {{"premap_shared", round_to(r.cell.premap_s, 0.01)},
                           {"abc_map", round_to(run.yosys_s, 0.01)},
                           {"sta", round_to(run.sta_s, 0.01)}};
      if (r.step_seconds.count("characterize"))
        c["step_seconds"]["characterize_shared"] = round_to(r.step_seconds.at("characterize"), 0.01);
      c["placement"] = r.placement;
      auto rounded = [](const std::vector<double>& v) {
        json a = json::array();
        for (double x : v) a.push_back(round_to(x, 0.1));
        return a;
      };
      c["segment_delays_ps"] = r.segment_delays_ps.empty() ? json(nullptr) : rounded(r.segment_delays_ps);
      c["seg_weights"] = r.seg_weights.empty() ? json(nullptr) : json(r.seg_weights);
      c["stage_periods_ps"] = run.stage_ps.empty() ? json(nullptr) : rounded(run.stage_ps);
      if (!r.temp_dir.empty()) c["temp_dir"] = r.temp_dir;
      rows.push_back(std::move(c));
    }
    return rows;
  }
  j["library"] = nullptr;
  j["cells"] = g.cells;
  j["cells_total"] = g.cells_total;
  j["area_nand2"] = std::round(g.area_nand2 * 100) / 100;
  j["transistors_cmos"] = g.transistors;
  j["transistors_complete"] = g.transistors_complete;
  j["transistors_uncounted_cells"] = g.transistors_uncounted;
  j["reg_bits"] = g.reg_bits;
  j["depth"] = g.depth;
  j["stage_delay_ps"] = g.stage_ps;
  j["fmax_est_mhz"] = std::round(g.fmax_mhz * 10) / 10;
  j["delay_model"] = DelayModel::kName;
  j["resource_sharing"] = r.share;
  if (r.ice40.run) {
    const auto& ic = r.ice40;
    json i;
    i["device"] = ic.device;
    i["luts"] = ic.luts;
    i["carries"] = ic.carries;
    i["ffs"] = ic.ffs;
    i["dsps"] = ic.dsps;
    i["device_luts"] = ic.device_luts;
    i["fits"] = ic.fits;
    i["reason"] = ic.reason;
    i["pnr"] = ic.pnr_run;
    i["fmax_mhz"] = ic.pnr_ok ? json(ic.fmax_mhz) : json(nullptr);
    i["lcs"] = ic.pnr_ok ? json(ic.lcs) : json(nullptr);
    j["ice40"] = i;
  } else {
    j["ice40"] = nullptr;
  }
  if (r.xilinx.run) {
    const auto& x = r.xilinx;
    j["xilinx"] = {{"family", "xc7"},    {"luts", x.luts}, {"ffs", x.ffs},   {"dsps", x.dsps},
                   {"carry4", x.carry4}, {"muxf", x.muxf}, {"srls", x.srls}, {"lutram", x.lutram},
                   {"bram", x.bram},     {"lcs", x.lcs}};
  } else {
    j["xilinx"] = nullptr;
  }
  j["yosys"] = r.yosys_version;
  if (!r.rtl_hash.empty()) j["rtl_hash"] = r.rtl_hash;
  j["seconds"] = std::round(r.seconds * 100) / 100;
  json steps = json::object();
  for (const auto& [k, v] : r.step_seconds) steps[k] = std::round(v * 100) / 100;
  j["step_seconds"] = steps;
  if (!r.temp_dir.empty()) j["temp_dir"] = r.temp_dir;
  return {j};
}

json to_json(const SynthResult& r) { return to_json_rows(r).front(); }

std::string format_table(const SynthResult& r) {
  const auto& g = r.generic;
  std::ostringstream o;
  const bool hs = !r.unit.empty() && find_unit(r.unit).handshake;
  o << r.top << ": " << (r.unit.empty() ? r.top : config_args(find_unit(r.unit), r.cfg)) << "  (latency "
    << (r.unit.empty() ? r.cfg.stages : find_unit(r.unit).latency(r.cfg))
    << (hs ? " or more, up to 1 op/cycle: in_ready_o)\n" : ", 1 op/cycle)\n");
  auto row = [&](const char* k, const std::string& v) {
    char b[32];
    std::snprintf(b, sizeof b, "  %-15s ", k);
    o << b << v << "\n";
  };
  if (r.cell.run) {
    const CellResult& c = r.cell;
    for (const CellRun& run : c.runs) {
      const StaPath& p = run.sta.path;
      const std::string target =
          run.target_ps > 0 ? fmt_num(run.target_ps, 0) + " ps (" + fmt_num(1e6 / run.target_ps, 1) + " MHz)"
                            : std::string("none (abc without -D)");
      row("target clock", target);
      row("area", fmt_num(run.area.total, 0) + " um2 (" + c.library + "): comb " + fmt_num(run.area.comb, 0) +
                      ", seq " + fmt_num(run.area.seq, 0) + "; " + std::to_string(run.area.cells) + " cells, " +
                      std::to_string(run.area.seq_cells) + " flip-flops");
      std::string timing = "slack " + fmt_num(run.sta.slack_ps, 0) + " ps at " + fmt_num(run.sta.period_ps, 0) +
                           " ps -> Fmax " + fmt_num(run.fmax_mhz, 1) + " MHz (" + fmt_num(run.achieved_ps, 0) +
                           " ps = " + fmt_num(run.achieved_ps / c.fo4_ps, 1) + " FO4)";
      if (run.target_ps > 0) timing += run.sta.slack_ps >= 0 ? ", met" : ", VIOLATED";
      row("timing", timing);
      row("critical path",
          p.start + " -> " + p.end + (p.segment > 0 ? ", segment " + std::to_string(p.segment) + " of " +
                                                          std::to_string(p.segments)
                                                    : std::string()) +
              ": clk-to-Q " + fmt_num(p.clk_to_q_ps, 0) + " + logic " + fmt_num(p.logic_ps, 0) + " ps (" +
              std::to_string(p.cells) + " cells) + setup " + fmt_num(p.setup_ps, 0) + " ps");
      if (!run.stage_ps.empty()) {
        std::string st;
        for (double v : run.stage_ps) st += (st.empty() ? "" : ", ") + fmt_num(v, 0);
        row("stage periods", st + " ps (stage 1 first; OpenSTA, each stage's worst register)");
      }
    }
    if (r.placement == "delay") {
      std::string d;
      for (double v : r.segment_delays_ps) d += (d.empty() ? "" : ", ") + fmt_num(v, 0);
      row("placement", r.seg_weights.empty()
                           ? std::string("delay (nothing to place at Stages ") + std::to_string(r.cfg.stages) + ")"
                           : "delay: segment logic delays " + d + " ps (every cut registered, " +
                                 fmt_num(r.step_seconds.count("characterize") ? r.step_seconds.at("characterize") : 0,
                                         1) +
                                 " s)");
    }
    row("library", c.liberty + ", FO4 " + fmt_num(c.fo4_ps, 1) + " ps (sta), no wire-load model (pre-placement)");
    row("tools", r.yosys_version + ", " + c.sta_version + ", " + fmt_num(r.seconds, 1) + " s" +
                     (r.share ? std::string() : ", synth -noshare (no resource sharing)"));
    if (!r.temp_dir.empty()) row("kept", r.temp_dir);
    return o.str();
  }
  row("area", fmt_num(g.area_nand2, 1) + " NAND2-eq, " + std::to_string(g.cells_total) + " cells, " +
                  std::to_string(g.reg_bits) + " register bits");
  row("transistors",
      std::to_string(g.transistors) +
          (g.transistors_complete ? " (stat -tech cmos)"
                                  : "+ (stat -tech cmos; " + std::to_string(g.transistors_uncounted) +
                                        " flops with reset/enable not counted)"));
  row("worst stage", std::to_string(g.depth) + " gate levels (ltp -noff); " + DelayModel::kName +
                         " estimate " + fmt_num(g.stage_ps, 0) + " ps (not a timing: --flow osu018 runs STA)");
  std::string cells;
  for (const auto& [t, n] : g.cells) cells += (cells.empty() ? "" : ", ") + t + " " + std::to_string(n);
  row("cells", cells);
  if (r.ice40.run) {
    const auto& ic = r.ice40;
    std::string s = std::to_string(ic.luts) + " LUT4, " + std::to_string(ic.carries) + " carry, " +
                    std::to_string(ic.ffs) + " FF" +
                    (ic.dsps ? ", " + std::to_string(ic.dsps) + " DSP" : std::string()) + ": ";
    if (!ic.fits)
      s += "does not fit (" + ic.reason + ")";
    else {
      s += "fits (" + fmt_num(100.0 * ic.luts / ic.device_luts, 0) + "% of " +
           std::to_string(ic.device_luts) + " LUTs)";
      if (ic.pnr_ok)
        s += ", nextpnr Fmax " + fmt_num(ic.fmax_mhz, 1) + " MHz (" + std::to_string(ic.lcs) +
             " LCs with harness)";
      else if (!ic.pnr_run)
        s += ", Fmax: not placed (use --fpga)";
    }
    row(("iCE40 " + ic.device).c_str(), s);
  }
  if (r.xilinx.run) {
    const auto& x = r.xilinx;
    row("Xilinx xc7", std::to_string(x.luts) + " LUT, " + std::to_string(x.ffs) + " FF, " +
                          std::to_string(x.dsps) + " DSP48E1, " + std::to_string(x.carry4) + " CARRY4, " +
                          std::to_string(x.muxf) + " MUXF7/8" +
                          (x.srls ? ", " + std::to_string(x.srls) + " SRL" : std::string()));
  }
  row("yosys", r.yosys_version + ", " + fmt_num(r.seconds, 1) + " s" +
                   (r.share ? std::string() : ", synth -noshare (no resource sharing)"));
  if (!r.temp_dir.empty()) row("kept", r.temp_dir);
  return o.str();
}

}  // namespace ru::synth
