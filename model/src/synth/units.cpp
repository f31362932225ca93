// The unit registry and the wrapper generator. See rayunits/synth/units.hpp.
#include "rayunits/synth/units.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace ru::synth {
namespace fs = std::filesystem;
using num::Format;

namespace {

WidthFn bits(int n) {
  return [n](const UnitConfig&) { return n; };
}
int fp_width(const UnitConfig& c) { return c.fmt.width(); }
int three_fp_width(const UnitConfig& c) { return 3 * c.fmt.width(); }

// The parameters every floating-point unit of issue 3 takes.
std::vector<ParamSpec> fp_params() {
  return {
      {"ExpW", [](const UnitConfig& c) { return static_cast<long long>(c.fmt.exp_bits); }},
      {"FracW", [](const UnitConfig& c) { return static_cast<long long>(c.fmt.frac_bits); }},
      {"Stages", [](const UnitConfig& c) { return static_cast<long long>(c.stages); }},
      {"Subnormals", [](const UnitConfig& c) { return c.fmt.subnormals ? 1LL : 0LL; }},
      {"Round", [](const UnitConfig& c) { return static_cast<long long>(c.fmt.round); }},
  };
}

std::vector<PortSpec> control_ports() {
  return {
      {"clk_i", PortDir::In, PortRole::Clock, bits(1), "clock, rising edge"},
      {"rst_ni", PortDir::In, PortRole::Reset, bits(1), "reset, active low: drops every operation in flight"},
      {"in_valid_i", PortDir::In, PortRole::Valid, bits(1), "operands valid this cycle"},
  };
}

// The fixed interface: clk_i, rst_ni, in_valid_i, operands, [op_i], out_valid_o, y_o, flags_o.
std::vector<PortSpec> fp_ports(std::vector<PortSpec> operands) {
  std::vector<PortSpec> p = control_ports();
  for (auto& o : operands) p.push_back(std::move(o));
  p.push_back({"out_valid_o", PortDir::Out, PortRole::Valid, bits(1),
               "result valid (in_valid_i delayed by the latency)"});
  p.push_back({"y_o", PortDir::Out, PortRole::Data, fp_width, "result bit pattern"});
  p.push_back(
      {"flags_o", PortDir::Out, PortRole::Data, bits(5), "{invalid, divzero, overflow, underflow, inexact}"});
  return p;
}

PortSpec operand(const char* name, const char* doc) {
  return {name, PortDir::In, PortRole::Data, fp_width, doc};
}

// ru_fp_pkg::csa_levels: carry-save (3:2) levels that reduce n partial products to two.
int csa_levels(int n) {
  int l = 0;
  while (n > 2) {
    n = 2 * (n / 3) + n % 3;
    ++l;
  }
  return l;
}

// Maximum Stages per unit: the "useful max" of rtl/README.md (every cut position registered).
// The RTL accepts more (extra registers at the output), which buys no speed, so synth/gen
// refuse it as the README suggests. L = csa_levels(FracW+1).
int max_stages_add(const UnitConfig&) { return 4; }
int max_stages_mul(const UnitConfig& c) { return csa_levels(c.fmt.frac_bits + 1) + 3; }
int max_stages_div(const UnitConfig& c) { return c.fmt.frac_bits + 4; }
int max_stages_cmp(const UnitConfig&) { return 2; }
int max_stages_dot3(const UnitConfig& c) { return csa_levels(c.fmt.frac_bits + 1) + 13; }

std::vector<UnitSpec> make_units() {
  std::vector<UnitSpec> u;
  {
    UnitSpec s;
    s.name = "fp_add";
    s.top = "ru_fp_add";
    s.summary = "floating-point adder/subtracter (op_i 0 = a+b, 1 = a-b)";
    s.filelist = "ru_fp_add.f";
    s.sources = {"ru_fp_add.sv"};
    s.params = fp_params();
    s.ports = fp_ports({operand("a_i", "operand a"),
                        operand("b_i", "operand b"),
                        {"op_i", PortDir::In, PortRole::Data, bits(1), "0 = add, 1 = subtract"}});
    s.max_stages = max_stages_add;
    u.push_back(std::move(s));
  }
  {
    UnitSpec s;
    s.name = "fp_mul";
    s.top = "ru_fp_mul";
    s.summary = "floating-point multiplier";
    s.filelist = "ru_fp_mul.f";
    s.sources = {"ru_fp_mul.sv"};
    s.params = fp_params();
    s.ports = fp_ports({operand("a_i", "operand a"), operand("b_i", "operand b")});
    s.max_stages = max_stages_mul;
    u.push_back(std::move(s));
  }
  {
    UnitSpec s;
    s.name = "fp_div";
    s.top = "ru_fp_div";
    s.summary = "floating-point divider (correctly rounded, pipelined digit recurrence)";
    s.filelist = "ru_fp_div.f";
    s.sources = {"ru_fp_div.sv"};
    s.params = fp_params();
    s.ports = fp_ports({operand("a_i", "dividend"), operand("b_i", "divisor")});
    s.max_stages = max_stages_div;
    u.push_back(std::move(s));
  }
  {
    UnitSpec s;
    s.name = "fp_cmp";
    s.top = "ru_fp_cmp";
    s.summary = "floating-point compare/min/max (op_i 0 lt, 1 le, 2 eq, 3 min, 4 max)";
    s.filelist = "ru_fp_cmp.f";
    s.sources = {"ru_fp_cmp.sv"};
    s.params = fp_params();
    s.ports = fp_ports({operand("a_i", "operand a"),
                        operand("b_i", "operand b"),
                        {"op_i", PortDir::In, PortRole::Data, bits(3), "0 lt, 1 le, 2 eq, 3 min, 4 max"}});
    s.max_stages = max_stages_cmp;
    u.push_back(std::move(s));
  }
  {
    UnitSpec s;
    s.name = "fp_dot3";
    s.top = "ru_fp_dot3";
    s.summary = "3-term dot product, three products and two sums each rounded";
    s.filelist = "ru_fp_dot3.f";
    s.sources = {"ru_fp_dot3.sv"};
    s.params = fp_params();
    s.ports =
        fp_ports({{"a_i", PortDir::In, PortRole::Data, three_fp_width, "{a2, a1, a0}, a0 in the low bits"},
                  {"b_i", PortDir::In, PortRole::Data, three_fp_width, "{b2, b1, b0}, b0 in the low bits"}});
    s.max_stages = max_stages_dot3;
    u.push_back(std::move(s));
  }
  // The intersection units (issue 4): built from the FP units, one register placement over
  // their chain of levels (rtl/ru_ray_tri_pkg.sv). Their Stages bound is the sum of the levels'
  // FP-unit maxima (every level fully pipelined); the RTL accepts more (output registers).
  {
    UnitSpec s;
    s.name = "ray_box";
    s.top = "ru_ray_box";
    s.summary = "ray-box slab test (Williams et al.), optional conservative directed rounding";
    s.filelist = "ru_ray_box.f";
    s.sources = {"ru_ray_box.sv"};
    s.params = fp_params();
    s.extra_params = {{"OptConservative", 0, 0, 1, "1: t_enter rounded down, t_exit up (never a false miss)"}};
    s.ports = control_ports();
    s.ports.push_back({"org_i", PortDir::In, PortRole::Data, three_fp_width, "ray origin {z, y, x}"});
    s.ports.push_back({"rdir_i", PortDir::In, PortRole::Data, three_fp_width, "reciprocal direction {z, y, x}"});
    s.ports.push_back(operand("tmin_i", "t_min"));
    s.ports.push_back(operand("tmax_i", "t_max"));
    s.ports.push_back({"bmin_i", PortDir::In, PortRole::Data, three_fp_width, "box minimum corner {z, y, x}"});
    s.ports.push_back({"bmax_i", PortDir::In, PortRole::Data, three_fp_width, "box maximum corner {z, y, x}"});
    s.ports.push_back({"out_valid_o", PortDir::Out, PortRole::Valid, bits(1),
                       "result valid (in_valid_i delayed by the latency)"});
    s.ports.push_back({"hit_o", PortDir::Out, PortRole::Data, bits(1), "the ray's [t_min, t_max] meets the box"});
    s.ports.push_back({"t_enter_o", PortDir::Out, PortRole::Data, fp_width, "entry distance"});
    s.ports.push_back({"t_exit_o", PortDir::Out, PortRole::Data, fp_width, "exit distance"});
    // levels: add mul cmp cmp cmp
    s.max_stages = [](const UnitConfig& c) {
      return max_stages_add(c) + max_stages_mul(c) + 3 * max_stages_cmp(c);
    };
    u.push_back(std::move(s));
  }
  for (const bool robust : {true, false}) {
    UnitSpec s;
    s.name = robust ? "ray_tri_robust" : "ray_tri_mt";
    s.top = "ru_" + s.name;
    s.summary = robust ? "ray-triangle test from signed volumes (Kensler Fig. 3.6)"
                       : "ray-triangle test, Moller-Trumbore (Kensler Eq. 3.2)";
    s.filelist = s.top + ".f";
    s.sources = {s.top + ".sv"};
    s.synth_share = false;
    s.params = fp_params();
    if (robust) s.extra_params.push_back({"OptTieBreak", 0, 0, 1, "Fig. 3.6's zero-volume tie-break"});
    s.extra_params.push_back({"OptEpsTest", 0, 0, 1, "miss when |V| < eps"});
    s.extra_params.push_back({"EpsBits", 0, 0, INT64_MAX, "eps as a bit pattern of the format"});
    s.extra_params.push_back({"OptVolOut", 0, 0, 1, "1: vol_o carries V, Va, V0..2 (else constant 0)"});
    s.ports = control_ports();
    for (const char* n : {"a_i", "d_i", "p0_i", "p1_i", "p2_i"})
      s.ports.push_back({n, PortDir::In, PortRole::Data, three_fp_width,
                         n[0] == 'a' ? "ray origin {z, y, x}" : n[0] == 'd' ? "ray direction {z, y, x}"
                                                                           : "vertex {z, y, x}"});
    s.ports.push_back(operand("tmin_i", "t_min"));
    s.ports.push_back(operand("tmax_i", "t_max"));
    s.ports.push_back({"out_valid_o", PortDir::Out, PortRole::Valid, bits(1),
                       "result valid (in_valid_i delayed by the latency)"});
    s.ports.push_back({"hit_o", PortDir::Out, PortRole::Data, bits(1), "hit inside (t_min, t_max)"});
    s.ports.push_back({"why_o", PortDir::Out, PortRole::Data, bits(3), "0 hit, 1 sign of V0..V2, 2 tie-break, 3 |V| < eps, 4 t outside (t_min, t_max)"});
    s.ports.push_back(operand("t_o", "distance t"));
    s.ports.back().dir = PortDir::Out;
    s.ports.push_back(operand("beta_o", "barycentric beta"));
    s.ports.back().dir = PortDir::Out;
    s.ports.push_back(operand("gamma_o", "barycentric gamma"));
    s.ports.back().dir = PortDir::Out;
    s.ports.push_back({"vol_o", PortDir::Out, PortRole::Data, [](const UnitConfig& c) { return 5 * c.fmt.width(); },
                       "{V2, V1, V0, Va, V} (OptVolOut)"});
    // robust levels: add mul add mul add add div cmp; MT: add mul add mul add add div mul add cmp
    if (robust)
      s.max_stages = [](const UnitConfig& c) {
        return 5 * max_stages_add(c) + 2 * max_stages_mul(c) + max_stages_div(c) + max_stages_cmp(c);
      };
    else
      s.max_stages = [](const UnitConfig& c) {
        return 6 * max_stages_add(c) + 3 * max_stages_mul(c) + max_stages_div(c) + max_stages_cmp(c);
      };
    u.push_back(std::move(s));
  }
  {
    // Kensler's gradient noise unit (fixed point, no floating-point format): an example of a
    // unit with its own parameters (--param FracBits=8 ...).
    UnitSpec s;
    s.name = "noise";
    s.top = "ru_noise";
    s.summary = "fixed-point gradient noise (Kensler sec. 4.9-4.13), one result per clock";
    s.filelist = "ru_noise.f";
    s.sources = {"ru_noise_cut.sv", "ru_noise.sv"};
    s.uses_format = false;
    s.params = {{"Stages", [](const UnitConfig& c) { return static_cast<long long>(c.stages); }}};
    s.extra_params = {{"FracBits", 8, 4, 16, "fraction bits of the coordinates"},
                      {"IntBits", 8, 1, 24, "integer bits of the coordinates (incl. sign)"},
                      {"OutW", 10, 2, 38, "output width"}};
    WidthFn coord = [](const UnitConfig& c) {
      return static_cast<int>(param_value(find_unit("noise"), c, "FracBits") +
                              param_value(find_unit("noise"), c, "IntBits"));
    };
    s.ports = control_ports();
    s.ports.push_back({"x_i", PortDir::In, PortRole::Data, coord, "x, signed fixed point"});
    s.ports.push_back({"y_i", PortDir::In, PortRole::Data, coord, "y, signed fixed point"});
    s.ports.push_back({"z_i", PortDir::In, PortRole::Data, coord, "z, signed fixed point"});
    s.ports.push_back({"out_valid_o", PortDir::Out, PortRole::Valid, bits(1),
                       "result valid (in_valid_i delayed by the latency)"});
    s.ports.push_back(
        {"value_o", PortDir::Out, PortRole::Data,
         [](const UnitConfig& c) { return static_cast<int>(param_value(find_unit("noise"), c, "OutW")); },
         "noise value, signed"});
    s.max_stages = [](const UnitConfig&) { return 6; };
    s.check = [](const UnitConfig& c) {
      const UnitSpec& n = find_unit("noise");
      const long long fb = param_value(n, c, "FracBits"), ow = param_value(n, c, "OutW");
      if (ow > 2 * fb + 6)
        throw SynthError("noise: OutW must be <= 2*FracBits+6 = " + std::to_string(2 * fb + 6) + ", got " +
                         std::to_string(ow));
    };
    u.push_back(std::move(s));
  }
  return u;
}

std::string trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  size_t e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string fmt_tag(const Format& f) {
  return "e" + std::to_string(f.exp_bits) + "m" + std::to_string(f.frac_bits);
}

}  // namespace

const std::vector<UnitSpec>& units() {
  static const std::vector<UnitSpec> u = make_units();
  return u;
}

std::string unit_names() {
  std::string s;
  for (const auto& u : units()) s += (s.empty() ? "" : ", ") + u.name;
  return s;
}

const UnitSpec& find_unit(std::string_view name) {
  for (const auto& u : units())
    if (u.name == name) return u;
  throw SynthError("unknown unit '" + std::string(name) + "' (units: " + unit_names() + ")");
}

long long param_value(const UnitSpec& u, const UnitConfig& c, const std::string& name) {
  if (auto it = c.params.find(name); it != c.params.end()) return it->second;
  for (const auto& p : u.extra_params)
    if (p.name == name) return p.def;
  throw SynthError(u.name + " has no parameter '" + name + "'");
}

void check_config(const UnitSpec& u, const UnitConfig& c) {
  for (const auto& [k, v] : c.params) {
    auto it = std::find_if(u.extra_params.begin(), u.extra_params.end(),
                           [&](const ExtraParam& p) { return p.name == k; });
    if (it == u.extra_params.end()) {
      std::string names;
      for (const auto& p : u.extra_params) names += (names.empty() ? "" : ", ") + p.name;
      throw SynthError(u.name + " has no parameter '" + k + "' (" +
                       (names.empty() ? std::string("it takes no --param") : "parameters: " + names) + ")");
    }
    if (v < it->lo || v > it->hi)
      throw SynthError(u.name + " parameter " + k + " must be in " + std::to_string(it->lo) + ".." +
                       std::to_string(it->hi) + ", got " + std::to_string(v));
  }
  if (u.uses_format) {
    c.fmt.validate();  // FormatError for e1m10, e12m3, > 64 bits ...
    const Format& f = c.fmt;
    if (f.exp_bits < u.min_exp || f.exp_bits > u.max_exp || f.frac_bits < u.min_frac ||
        f.frac_bits > u.max_frac)
      throw SynthError(u.name + " supports exponent bits " + std::to_string(u.min_exp) + ".." +
                       std::to_string(u.max_exp) + " and fraction bits " + std::to_string(u.min_frac) + ".." +
                       std::to_string(u.max_frac) + ", got " + fmt_tag(f));
  }
  if (u.check) u.check(c);
  const int hi = u.max_stages(c);
  if (c.stages < u.min_stages || c.stages > hi)
    throw SynthError(u.name + (u.uses_format ? " " + fmt_tag(c.fmt) : std::string()) + " supports --stages " +
                     std::to_string(u.min_stages) + ".." + std::to_string(hi) + ", got " +
                     std::to_string(c.stages));
}

std::string wrapper_name(const UnitSpec& u, const UnitConfig& c) {
  std::string n = "ru_" + u.name + (u.uses_format ? "_" + fmt_tag(c.fmt) : std::string()) + "_s" +
                  std::to_string(c.stages);
  for (const auto& p : u.extra_params) {
    const long long v = param_value(u, c, p.name);
    if (v != p.def) n += "_" + p.name + (v < 0 ? "m" + std::to_string(-v) : std::to_string(v));
  }
  if (u.uses_format) {
    if (c.fmt.round != num::Round::RNE) n += std::string("_") + num::round_name(c.fmt.round);
    if (!c.fmt.subnormals) n += "_ftz";
  }
  return n;
}

std::string config_args(const UnitSpec& u, const UnitConfig& c) {
  std::string s = u.name;
  if (u.uses_format) s += " --format " + fmt_tag(c.fmt);
  s += " --stages " + std::to_string(c.stages);
  for (const auto& p : u.extra_params) {
    const long long v = param_value(u, c, p.name);
    if (v != p.def) s += " --param " + p.name + "=" + std::to_string(v);
  }
  if (u.uses_format) {
    if (c.fmt.round != num::Round::RNE) s += std::string(" --round ") + num::round_name(c.fmt.round);
    if (!c.fmt.subnormals) s += " --ftz";
  }
  return s;
}

std::string default_rtl_dir() {
  if (const char* e = std::getenv("RU_RTL_DIR"); e && *e) return e;
#ifdef RU_SOURCE_DIR
  return std::string(RU_SOURCE_DIR) + "/rtl";
#else
  return "rtl";
#endif
}

Sources resolve_sources(const UnitSpec& u, const std::string& rtl_dir) {
  std::error_code ec;
  if (!fs::is_directory(rtl_dir, ec)) throw SynthError("RTL directory '" + rtl_dir + "' not found");
  const fs::path root = fs::absolute(rtl_dir).lexically_normal();
  Sources out;
  const fs::path fl = root / u.filelist;
  if (!u.filelist.empty() && fs::is_regular_file(fl, ec)) {
    std::ifstream in(fl);
    std::string line;
    int lineno = 0;
    while (std::getline(in, line)) {
      ++lineno;
      for (const char* c : {"//", "#"}) {
        size_t p = line.find(c);
        if (p != std::string::npos) line.erase(p);
      }
      line = trim(line);
      if (line.empty()) continue;
      if (line[0] == '-' || line[0] == '+')
        throw SynthError(fl.string() + ":" + std::to_string(lineno) + ": option '" + line +
                         "' is not supported in a unit file list (list source files only)");
      fs::path p = line;
      if (p.is_relative()) p = root / p;
      out.files.push_back(p.lexically_normal().string());
    }
    if (out.files.empty()) throw SynthError(fl.string() + " lists no source files");
  } else {
    for (const auto& s : u.sources) out.files.push_back((root / s).lexically_normal().string());
  }
  for (const auto& p : out.files)
    if (!fs::is_regular_file(p, ec)) throw SynthError("source '" + p + "' of unit " + u.name + " not found");
  // `include "x": looked up next to the including file (Yosys and Verilator both search there).
  static const std::regex inc(R"(^\s*`include\s+\"([^\"]+)\")");
  std::set<std::string> seen;
  std::vector<std::string> todo = out.files;
  while (!todo.empty()) {
    const std::string f = todo.back();
    todo.pop_back();
    std::ifstream in(f);
    std::string line;
    while (std::getline(in, line)) {
      std::smatch m;
      if (!std::regex_search(line, m, inc)) continue;
      const std::string p = (fs::path(f).parent_path() / m[1].str()).lexically_normal().string();
      if (!fs::is_regular_file(p, ec))
        throw SynthError("'" + m[1].str() + "' included by '" + f + "' not found");
      if (seen.insert(p).second) {
        out.includes.push_back(p);
        todo.push_back(p);
      }
    }
  }
  return out;
}

std::string sources_hash(const Sources& s) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const std::string& t) {
    for (unsigned char ch : t) {
      h ^= ch;
      h *= 1099511628211ull;
    }
    h ^= 0xff;  // separator
    h *= 1099511628211ull;
  };
  for (const auto* list : {&s.files, &s.includes})
    for (const auto& f : *list) {
      std::ifstream in(f, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      mix(fs::path(f).filename().string());
      mix(text.str());
    }
  char b[17];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
  return b;
}

std::vector<Port> ports_for(const UnitSpec& u, const UnitConfig& c) {
  std::vector<Port> v;
  for (const auto& p : u.ports) v.push_back({p.name, p.dir, p.role, p.width(c), p.doc});
  return v;
}

std::vector<std::pair<std::string, long long>> params_for(const UnitSpec& u, const UnitConfig& c) {
  std::vector<std::pair<std::string, long long>> v;
  for (const auto& p : u.params) v.emplace_back(p.name, p.value(c));
  for (const auto& p : u.extra_params) v.emplace_back(p.name, param_value(u, c, p.name));
  return v;
}

std::string wrapper_verilog(const UnitSpec& u, const UnitConfig& c) {
  const std::string name = wrapper_name(u, c);
  const auto ports = ports_for(u, c);
  const auto params = params_for(u, c);
  std::ostringstream o;
  o << "// " << name << ": " << u.summary << "\n";
  if (u.uses_format)
    o << "// format " << fmt_tag(c.fmt) << " (" << c.fmt.width() << " bits: 1 sign, " << c.fmt.exp_bits
      << " exponent, " << c.fmt.frac_bits << " fraction), rounding " << num::round_name(c.fmt.round)
      << ", subnormals " << (c.fmt.subnormals ? "on" : "off (flush to zero)") << "\n";
  o << "// latency " << c.stages << " cycle" << (c.stages == 1 ? "" : "s") << ", one operation per cycle.\n"
    << "// Generated by: rayunits gen " << config_args(u, c) << "\n"
    << "// Do not edit: regenerate instead.\n"
    << "module " << name << " (\n";
  size_t w = 0;
  for (const auto& p : ports) w = std::max(w, p.name.size());
  for (size_t i = 0; i < ports.size(); ++i) {
    const auto& p = ports[i];
    std::string range = p.width > 1 ? "[" + std::to_string(p.width - 1) + ":0] " : "";
    o << "  " << (p.dir == PortDir::In ? "input  logic " : "output logic ") << range << p.name
      << (i + 1 < ports.size() ? "," : "") << "\n";
  }
  o << ");\n\n  " << u.top << " #(\n";
  for (size_t i = 0; i < params.size(); ++i)
    o << "    ." << params[i].first << "(" << params[i].second << ")" << (i + 1 < params.size() ? "," : "")
      << "\n";
  o << "  ) u_unit (\n";
  for (size_t i = 0; i < ports.size(); ++i) {
    const auto& p = ports[i];
    o << "    ." << p.name << std::string(w - p.name.size(), ' ') << " (" << p.name << ")"
      << (i + 1 < ports.size() ? "," : "") << "\n";
  }
  o << "  );\n\nendmodule\n";
  return o.str();
}

}  // namespace ru::synth
