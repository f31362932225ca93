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
  if (j.contains("design"))
    m = &j["design"];
  else if (j.contains("modules") && j["modules"].contains("\\" + top))
    m = &j["modules"]["\\" + top];
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

SynthResult run_flow(const std::vector<std::string>& sources, const std::string& top,
                     const std::vector<Port>& ports, const std::string& dir, const FlowOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  SynthResult r;
  r.top = top;
  r.yosys_version = yosys_version(o.yosys);
  r.share = o.share;
  const std::string yosys = find_program(o.yosys);
  std::string nextpnr;
  if (o.pnr) {
    nextpnr = find_program(o.nextpnr);
    if (nextpnr.empty())
      throw SynthError("nextpnr-ice40 not found ('" + o.nextpnr +
                       "'): install the Debian package nextpnr-ice40, pass --nextpnr PATH, or drop --fpga");
  }
  std::vector<std::string> abs_sources;
  for (const auto& s : sources) abs_sources.push_back(fs::absolute(s).lexically_normal().string());

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

SynthResult run_synth(const UnitSpec& u, const UnitConfig& c, const FlowOptions& o) {
  check_config(u, c);
  const std::string rtl = o.rtl_dir.empty() ? default_rtl_dir() : o.rtl_dir;
  const Sources src = resolve_sources(u, rtl);
  std::vector<std::string> sources = src.files;
  yosys_version(o.yosys);  // a missing yosys is reported before any work
  if (o.ice40) device(o.ice40_device);
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
  } catch (const ToolError&) {
    tmp.keep();  // the message names a log inside it
    throw;
  }
  r.unit = u.name;
  r.cfg = c;
  r.rtl_hash = sources_hash(src);
  if (o.keep_temp) r.temp_dir = tmp.path();
  return r;
}

json to_json(const SynthResult& r) {
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
  return j;
}

std::string format_table(const SynthResult& r) {
  const auto& g = r.generic;
  std::ostringstream o;
  o << r.top << ": " << (r.unit.empty() ? r.top : config_args(find_unit(r.unit), r.cfg)) << "  (latency "
    << r.cfg.stages << ", 1 op/cycle)\n";
  auto row = [&](const char* k, const std::string& v) {
    char b[32];
    std::snprintf(b, sizeof b, "  %-15s ", k);
    o << b << v << "\n";
  };
  row("area", fmt_num(g.area_nand2, 1) + " NAND2-eq, " + std::to_string(g.cells_total) + " cells, " +
                  std::to_string(g.reg_bits) + " register bits");
  row("transistors",
      std::to_string(g.transistors) +
          (g.transistors_complete ? " (stat -tech cmos)"
                                  : "+ (stat -tech cmos; " + std::to_string(g.transistors_uncounted) +
                                        " flops with reset/enable not counted)"));
  row("worst stage", std::to_string(g.depth) + " gate levels (ltp -noff) -> " + fmt_num(g.stage_ps, 0) +
                         " ps -> est. Fmax " + fmt_num(g.fmax_mhz, 0) + " MHz (" + DelayModel::kName + ")");
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
