// The standard-cell flow's library reader, STA harness and OpenSTA runs (cell.hpp).
#include "rayunits/synth/cell.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <regex>
#include <sstream>

#include "rayunits/synth/process.hpp"

namespace ru::synth {
namespace fs = std::filesystem;

const std::vector<std::string>& flow_names() {
  static const std::vector<std::string> n = {"generic", "osu018", "osu035", "osu050"};
  return n;
}

std::string flow_names_list() {
  std::string s;
  for (const auto& n : flow_names()) s += (s.empty() ? "" : ", ") + n;
  return s;
}

bool is_cell_flow(const std::string& flow) { return flow != "generic" && !flow.empty(); }

void check_flow_name(const std::string& flow) {
  for (const auto& n : flow_names())
    if (n == flow) return;
  throw SynthError("unknown flow '" + flow + "' (flows: " + flow_names_list() + ")");
}

CellLibrary parse_liberty(const std::string& name, const std::string& path) {
  const std::string text = read_file(path);
  CellLibrary lib;
  lib.name = name;
  lib.liberty = path;
  // Walk the group structure: `cell (NAME) {` opens a cell; inside it, the first `area : X;` at
  // the cell's own level and any `ff (` / `latch (` group classify it.
  static const std::regex cell_re(R"re(^\s*cell\s*\(\s*"?([A-Za-z0-9_]+)"?\s*\)\s*\{)re");
  static const std::regex area_re(R"re(^\s*area\s*:\s*([0-9.eE+-]+)\s*;)re");
  static const std::regex ff_re(R"re(^\s*ff\s*\()re");
  static const std::regex latch_re(R"re(^\s*latch\s*\()re");
  static const std::regex unit_re(R"re(^\s*area_unit\s*:\s*"?([^";]+)"?\s*;)re");
  std::istringstream in(text);
  std::string line, cell;
  int depth = 0, cell_depth = -1;
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_search(line, m, unit_re)) lib.area_unit = m[1];
    if (cell_depth < 0 && std::regex_search(line, m, cell_re)) {
      cell = m[1];
      cell_depth = depth;
      lib.area[cell] = -1;
    } else if (cell_depth >= 0) {
      if (depth == cell_depth + 1 && lib.area[cell] < 0 && std::regex_search(line, m, area_re))
        lib.area[cell] = std::stod(m[1]);
      if (std::regex_search(line, ff_re)) lib.flops.insert(cell);
      if (std::regex_search(line, latch_re)) lib.latches.insert(cell);
    }
    for (char c : line) {
      if (c == '{') ++depth;
      if (c == '}') {
        --depth;
        if (depth == cell_depth) cell_depth = -1;
      }
    }
  }
  if (lib.area.empty()) throw SynthError("no cells in liberty file '" + path + "'");
  // A cell without an area (osu035's pad cells) cannot be costed: it is left out, and a netlist
  // that uses it fails in cell_area() ("not in the library").
  for (auto it = lib.area.begin(); it != lib.area.end();) it = it->second < 0 ? lib.area.erase(it) : std::next(it);
  if (!lib.area.count(lib.flop_cell) || !lib.flops.count(lib.flop_cell) || !lib.area.count(lib.inv_cell))
    throw SynthError("liberty file '" + path + "' lacks " + lib.flop_cell + " or " + lib.inv_cell +
                     " (the harness flip-flop and the FO4 inverter)");
  return lib;
}

const CellLibrary& cell_library(const std::string& name) {
  static std::mutex mu;
  static std::map<std::string, CellLibrary> cache;
  check_flow_name(name);
  if (!is_cell_flow(name)) throw SynthError("flow 'generic' has no cell library");
  std::lock_guard<std::mutex> lock(mu);
  if (auto it = cache.find(name); it != cache.end()) return it->second;
  const char* env = std::getenv("RU_CELL_LIB_DIR");
  const std::string dir = env && *env ? std::string(env) + "/" + name : "/usr/share/qflow/tech/" + name;
  // Files are <name>_stdcells.*, except osu050's, which are osu05_stdcells.*.
  std::string stem = dir + "/" + name + "_stdcells";
  if (!fs::exists(stem + ".lib") && name.size() > 4 && name.back() == '0' &&
      fs::exists(dir + "/" + name.substr(0, name.size() - 1) + "_stdcells.lib"))
    stem = dir + "/" + name.substr(0, name.size() - 1) + "_stdcells";
  const std::string lib = stem + ".lib";
  if (!fs::exists(lib))
    throw SynthError("cell library " + name + " not found: no " + lib + " (install the Debian package qflow-tech-" +
                     name + ", or set RU_CELL_LIB_DIR)");
  CellLibrary l = parse_liberty(name, lib);
  if (fs::exists(stem + ".v")) l.verilog = stem + ".v";
  if (fs::exists(stem + ".lef")) l.lef = stem + ".lef";
  return cache.emplace(name, std::move(l)).first->second;
}

std::string sta_program(const std::string& sta) {
  const std::string exe = find_program(sta);
  if (exe.empty())
    throw SynthError("OpenSTA not found ('" + sta + "'): install the Debian package opensta or pass --sta PATH");
  return exe;
}

std::string sta_version(const std::string& sta) {
  static std::mutex mu;
  static std::map<std::string, std::string> cache;
  const std::string exe = sta_program(sta);
  std::lock_guard<std::mutex> lock(mu);
  if (auto it = cache.find(exe); it != cache.end()) return it->second;
  TempDir tmp("ru-sta-v-");
  const std::string out = tmp.path() + "/v.txt";
  ProcResult r = run_process({exe, "-version"}, tmp.path(), out, 30);
  std::string v = r.exit_code == 0 ? read_file(out) : std::string();
  while (!v.empty() && (v.back() == '\n' || v.back() == '\r')) v.pop_back();
  if (v.empty()) throw SynthError("'" + exe + "' does not look like OpenSTA (`-version` failed)");
  return cache[exe] = "OpenSTA " + v;
}

namespace {

std::string ps_to_ns(double ps) {
  std::ostringstream o;
  o.precision(6);
  o << std::fixed << ps / 1000.0;
  return o.str();
}

// Runs an STA script; returns its output. Errors of the script (a "Error:" line) are failures.
std::string run_sta_script(const std::string& sta, const std::string& script, const std::string& dir,
                           const std::string& stem, int timeout_s) {
  const std::string exe = sta_program(sta);
  const std::string tcl = dir + "/" + stem + ".tcl";
  write_file_atomic(tcl, script);
  const std::string out = dir + "/" + stem + ".log";
  ProcResult r = run_process({exe, "-no_splash", "-exit", tcl}, dir, out, timeout_s);
  if (r.timed_out) throw SynthError("sta timed out after " + std::to_string(timeout_s) + " s (log: " + out + ")");
  const std::string text = read_file(out);
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("Error", 0) == 0) throw SynthError("sta: " + line + " (log: " + out + ")");
  if (r.exit_code != 0)
    throw SynthError("sta failed (exit " + std::to_string(r.exit_code) + ") (log: " + out + ")");
  return text;
}

double num_after(const std::string& text, const std::regex& re, const std::string& what, const std::string& log) {
  std::smatch m;
  if (!std::regex_search(text, m, re)) throw SynthError("no " + what + " in the STA report (log: " + log + ")");
  return std::stod(m[1]);
}

}  // namespace

double measure_fo4_ps(const CellLibrary& lib, const std::string& sta, int timeout_s) {
  static std::mutex mu;
  static std::map<std::string, double> cache;
  std::lock_guard<std::mutex> lock(mu);
  if (auto it = cache.find(lib.liberty); it != cache.end()) return it->second;
  // s0 -> s1 -> dut -> 4 loads; s0 and s1 each drive four inverters too, so dut sees the input
  // slope of an FO4 stage.
  const std::string& inv = lib.inv_cell;
  std::ostringstream v;
  v << "module ru_fo4 (a, y);\n  input a;\n  output y;\n  wire n0, n1, n2;\n";
  auto cellv = [&](const std::string& n, const std::string& a, const std::string& y) {
    v << "  " << inv << " " << n << " (.A(" << a << "), .Y(" << y << "));\n";
  };
  cellv("s0", "a", "n0");
  cellv("s1", "n0", "n1");
  cellv("dut", "n1", "n2");
  for (int i = 0; i < 3; ++i) {
    cellv("s0l" + std::to_string(i), "n0", "");
    cellv("s1l" + std::to_string(i), "n1", "");
  }
  cellv("l0", "n2", "y");
  for (int i = 1; i < 4; ++i) cellv("l" + std::to_string(i), "n2", "");
  v << "endmodule\n";
  TempDir tmp("ru-fo4-");
  write_file_atomic(tmp.path() + "/fo4.v", v.str());
  const std::string script = "read_liberty {" + lib.liberty +
                             "}\nread_verilog fo4.v\nlink_design ru_fo4\n"
                             "report_checks -unconstrained -rise_through [get_pins dut/Y] -digits 6\n"
                             "report_checks -unconstrained -fall_through [get_pins dut/Y] -digits 6\n";
  const std::string text = run_sta_script(sta, script, tmp.path(), "fo4", timeout_s);
  static const std::regex re(R"re(^\s*([0-9.]+)\s+[0-9.]+\s+[v^]\s+dut/Y\b)re");
  std::vector<double> d;
  std::istringstream in(text);
  std::string line;
  std::smatch m;
  while (std::getline(in, line))
    if (std::regex_search(line, m, re)) d.push_back(std::stod(m[1]) * 1000.0);
  if (d.size() != 2) throw SynthError("FO4 measurement: expected a rise and a fall delay of dut/Y from sta");
  return cache[lib.liberty] = (d[0] + d[1]) / 2;
}

std::string sta_harness_verilog(const std::string& unit_top, const std::vector<Port>& ports) {
  std::ostringstream o;
  o << "// STA register harness (rayunits synth --flow <library>): every unit input comes from a\n"
       "// flip-flop and every output goes into one, so each path is timed register to register\n"
       "// with a real clock-to-Q, load and setup time. The unit keeps its hierarchy, so its area\n"
       "// is reported without these registers.\n"
       "module ru_sta_harness (\n";
  for (size_t i = 0; i < ports.size(); ++i) {
    const Port& p = ports[i];
    o << "  " << (p.dir == PortDir::In ? "input " : "output") << " logic ";
    if (p.width > 1) o << "[" << p.width - 1 << ":0] ";
    o << p.name << (i + 1 < ports.size() ? "," : "") << "\n";
  }
  o << ");\n";
  std::string clk;
  for (const Port& p : ports)
    if (p.role == PortRole::Clock) clk = p.name;
  if (clk.empty()) throw SynthError("the unit " + unit_top + " has no clock port: the STA harness needs one");
  for (const Port& p : ports) {
    if (p.role == PortRole::Clock || p.role == PortRole::Reset) continue;
    const std::string w = p.width > 1 ? "[" + std::to_string(p.width - 1) + ":0] " : "";
    if (p.dir == PortDir::In) {
      o << "  logic " << w << p.name << "_q;\n";
      o << "  always_ff @(posedge " << clk << ") " << p.name << "_q <= " << p.name << ";\n";
    } else {
      o << "  logic " << w << p.name << "_d;\n";
      o << "  always_ff @(posedge " << clk << ") " << p.name << " <= " << p.name << "_d;\n";
    }
  }
  o << "  " << unit_top << " u_dut (\n";
  for (size_t i = 0; i < ports.size(); ++i) {
    const Port& p = ports[i];
    std::string src = p.name;
    if (p.role != PortRole::Clock && p.role != PortRole::Reset) src += p.dir == PortDir::In ? "_q" : "_d";
    o << "    ." << p.name << "(" << src << ")" << (i + 1 < ports.size() ? "," : "") << "\n";
  }
  o << "  );\nendmodule\n";
  return o.str();
}

std::string sta_script(const CellLibrary& lib, const std::string& netlist, const std::string& top,
                       double period_ps, bool scan_levels) {
  std::ostringstream s;
  s << "# rayunits cell flow: static timing of the unit inside its register harness (cell.hpp).\n"
       "# The liberty has no wire-load model: net delays are those of pin capacitances only,\n"
       "# i.e. before placement.\n"
    << "read_liberty {" << lib.liberty << "}\n"
    << "read_verilog {" << netlist << "}\n"
    << "link_design " << top << "\n"
    << "create_clock -name clk -period " << ps_to_ns(period_ps) << " [get_ports clk_i]\n"
    // The harness registers every input and output, so the ports' own paths (port -> harness
    // register, harness register -> port) are not part of the unit: no delay on them.
    << "set_input_delay 0 -clock clk [delete_from_list [all_inputs] [get_ports clk_i]]\n"
    << "set_output_delay 0 -clock clk [all_outputs]\n"
    << "if {[llength [get_ports -quiet rst_ni]]} { set_false_path -from [get_ports rst_ni] }\n"
    << "report_checks -path_delay max -format full -digits 4\n"
    << "report_tns -digits 4\n"
    // The pipeline segment of the path: register level of its end point. Harness input registers
    // are level 0; a register's level is one more than the highest level among the registers in
    // the fan-in of its D pin (the longest register path to it), memoized. Not "any fan-in
    // register": a unit may hold a register with no register fan-in (a constant mapped to a
    // flip-flop, level 0) next to its real pipeline (fp_mul e7m16 Stages 4: 25 harness output
    // registers see both; the first-fan-in rule gave levels outside 1..Stages+1 there).
    << "array set ru_lv {}\n"
       // Iterative depth-first search with an explicit stack (a recursive procedure hit Tcl's
       // nesting limit of 1000 on ray_tri_exact e8m23, whose register chains are deeper): the
       // same order and the same results as the recursion would give. ru_lv(x) = -1 while x
       // is on the stack (a register loop contributes level 0, as a recursion's in-progress
       // marker would) and for a cell without a D pin.
       "proc ru_fanin {inst} {\n"
       "  set d [get_pins -quiet $inst/D]\n"
       "  if {$d eq \"\"} { return {} }\n"
       "  set r {}\n"
       "  foreach c [get_fanin -to $d -flat -startpoints_only -only_cells] {\n"
       "    set n [get_full_name $c]\n"
       "    if {$n ne \"\" && $n ne $inst} { lappend r $n }\n"
       "  }\n"
       "  return [list 1 $r]\n"
       "}\n"
       "proc ru_lvl {inst} {\n"
       "  global ru_lv\n"
       "  if {[info exists ru_lv($inst)]} { return $ru_lv($inst) }\n"
       "  set stack [list $inst]\n"
       "  set ru_lv($inst) -1\n"
       "  set fi($inst) [ru_fanin $inst]\n"
       "  set ix($inst) 0\n"
       "  set best($inst) 0\n"
       "  while {[llength $stack]} {\n"
       "    set cur [lindex $stack end]\n"
       "    if {$fi($cur) eq {}} { set stack [lreplace $stack end end]; continue }\n"
       "    set ins [lindex $fi($cur) 1]\n"
       "    set k [llength $ins]\n"
       "    set pushed 0\n"
       "    while {$ix($cur) < $k} {\n"
       "      set n [lindex $ins $ix($cur)]\n"
       "      if {![info exists ru_lv($n)]} {\n"
       "        set ru_lv($n) -1\n"
       "        set fi($n) [ru_fanin $n]\n"
       "        set ix($n) 0\n"
       "        set best($n) 0\n"
       "        lappend stack $n\n"
       "        set pushed 1\n"
       "        break\n"
       "      }\n"
       "      set x [expr {$ru_lv($n) + 1}]\n"
       "      if {$x > $best($cur)} { set best($cur) $x }\n"
       "      incr ix($cur)\n"
       "    }\n"
       "    if {$pushed} continue\n"
       "    set ru_lv($cur) $best($cur)\n"
       "    set stack [lreplace $stack end end]\n"
       "  }\n"
       "  return $ru_lv($inst)\n"
       "}\n"
       "set pe [find_timing_paths -path_delay max]\n"
       "foreach e $pe {\n"
       "  set en [get_full_name [[$e vertex] pin]]\n"
       "  puts \"RU_PATH_END $en\"\n"
       "  regsub {/[^/]*$} $en {} eninst\n"
       "  puts \"RU_END_LEVEL [ru_lvl $eninst]\"\n"
       "}\n";
  if (scan_levels)
    // Every register end point: its level (ru_lvl above) and the period
    // its worst path needs; per level the largest. Output ports (no instance) are skipped: the
    // harness registers every output.
    s << "array set ru_need {}\n"
         "foreach e [find_timing_paths -path_delay max -group_count 10000000 -endpoint_count 1] {\n"
         "  set en [get_full_name [[$e vertex] pin]]\n"
         "  if {![regsub {/[^/]*$} $en {} inst]} continue\n"
         "  set l [ru_lvl $inst]\n"
         "  set need [expr {" << ps_to_ns(period_ps) << "e-9 - [$e slack]}]\n"
         "  if {![info exists ru_need($l)] || $need > $ru_need($l)} { set ru_need($l) $need }\n"
         "}\n"
         "foreach l [lsort -integer [array names ru_need]] { puts \"RU_STAGE $l [expr {$ru_need($l) * 1e12}]\" }\n";
  return s.str();
}

StaResult run_sta(const CellLibrary& lib, const std::string& sta, const std::string& netlist,
                  const std::string& top, double period_ps, int stages, const std::string& dir,
                  const std::string& stem, int timeout_s, bool scan_levels) {
  const std::string text =
      run_sta_script(sta, sta_script(lib, netlist, top, period_ps, scan_levels), dir, stem, timeout_s);
  const std::string log = dir + "/" + stem + ".log";
  StaResult r;
  r.period_ps = period_ps;
  r.report = text;
  r.slack_ps = num_after(text, std::regex(R"re(\n\s*(-?[0-9.]+)\s+slack \((MET|VIOLATED)\))re"), "slack", log) * 1000;
  r.tns_ps = num_after(text, std::regex(R"re(\ntns\s+(-?[0-9.]+))re"), "tns", log) * 1000;
  std::smatch m;
  if (std::regex_search(text, m, std::regex(R"re(Startpoint: (\S+))re"))) r.path.start = m[1];
  if (std::regex_search(text, m, std::regex(R"re(Endpoint: (\S+))re"))) r.path.end = m[1];
  const double arrival = num_after(text, std::regex(R"re(\n\s*(-?[0-9.]+)\s+data arrival time)re"), "arrival", log);
  r.path.setup_ps = -num_after(text, std::regex(R"re(\n\s*(-?[0-9.]+)\s+-?[0-9.]+\s+library setup time)re"),
                               "setup time", log) * 1000;
  // The start register's clock-to-Q: the first line after its CLK pin.
  if (std::regex_search(text, m, std::regex(R"re(/CLK \([A-Za-z0-9_]+\)\n\s*([0-9.]+)\s+[0-9.]+\s+[v^] \S+/Q )re")))
    r.path.clk_to_q_ps = std::stod(m[1]) * 1000;
  r.path.logic_ps = arrival * 1000 - r.path.clk_to_q_ps;
  {
    // Cells on the path: lines "delay time ^|v inst/PIN (CELL)" after the clock-to-Q line.
    static const std::regex cell_line(R"re(^\s*[0-9.]+\s+[0-9.]+\s+[v^]\s+\S+/[A-Z]+\s+\([A-Za-z0-9_]+\)\s*$)re");
    std::istringstream in(text);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
      if (line.find("data arrival time") != std::string::npos) break;
      if (std::regex_match(line, cell_line)) ++n;
    }
    r.path.cells = std::max(0, n - 3);  // minus the start register's CLK and Q and the end's D line
  }
  r.path.segments = stages + 1;
  if (std::regex_search(text, m, std::regex(R"re(RU_END_LEVEL (-?\d+))re"))) {
    const int lvl = std::stoi(m[1]);
    r.path.segment = lvl > 0 ? lvl : 0;
  }
  if (scan_levels) {
    static const std::regex re(R"re(RU_STAGE (-?\d+) (-?[0-9.eE+-]+))re");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
      r.level_ps[std::stoi((*it)[1])] = std::stod((*it)[2]);
    if (r.level_ps.empty()) throw SynthError("STA level scan printed no levels (log: " + log + ")");
  }
  return r;
}

CellArea cell_area(const CellLibrary& lib, const std::map<std::string, long>& cells) {
  CellArea a;
  for (const auto& [t, n] : cells) {
    auto it = lib.area.find(t);
    if (it == lib.area.end())
      throw SynthError("cell '" + t + "' is not in " + lib.name + " (" + lib.liberty + "): unmapped logic?");
    const double x = it->second * static_cast<double>(n);
    a.total += x;
    a.cells += n;
    if (lib.latches.count(t)) throw SynthError("the design contains latch cells (" + t + "): latches are not allowed");
    if (lib.flops.count(t)) {
      a.seq += x;
      a.seq_cells += n;
    } else {
      a.comb += x;
    }
  }
  return a;
}

}  // namespace ru::synth
