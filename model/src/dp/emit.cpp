// SystemVerilog emitter of the datapath IR (see rayunits/dp/emit.hpp).
#include "rayunits/dp/emit.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace ru::dp {

namespace {
bool is_unit(Op o) { return *op_unit(o) != '\0'; }
// The level kind a node asks for: ru_fp_pkg::KAdd 0, KMul 1, KDiv 2, KCmp 3. An fma asks for KMul:
// the level chain's kind table (ru_fp_pkg::op_nsegs / op_wts, ru_pipe_pkg::MaxKind = 4) has no fma
// kind, and adding one would change those packages and with them the rtl_hash of every
// characterized cell row. A level holding an fma is weighed as a multiplier level (the fma's
// product tree is that level's depth, its add-normalize-round tail is not counted) and the fma
// instance places its lat(k) registers itself (automatic placement).
// A conversion (ru_fp_cvt: unpack, normalize, round-and-pack) asks for KAdd, the kind whose
// segments it resembles, for the same reason. The level kinds are those of the unit's format: a
// level of wide operations is weighed by their kinds at the unit's widths, and the wide instances
// and conversions place their lat(k) registers themselves (their segments are not the level's).
int kind_of(Op o) {
  const std::string u = op_unit(o);
  return u == "fp_add" || u == "fp_cvt" ? 0 : u == "fp_mul" || u == "fp_fma" ? 1 : u == "fp_div" ? 2 : 3;
}
const char* unit_module(Op o) {
  const std::string u = op_unit(o);
  return u == "fp_add" ? "ru_fp_add" : u == "fp_mul" ? "ru_fp_mul" : u == "fp_div" ? "ru_fp_div" : u == "fp_fma" ? "ru_fp_fma" : u == "fp_cvt" ? "ru_fp_cvt" : "ru_fp_cmp";
}
// The unit whose segments a level kind describes (its instances take the level's cut selection).
const char* kind_unit(int k) { return k == 0 ? "fp_add" : k == 1 ? "fp_mul" : k == 2 ? "fp_div" : "fp_cmp"; }
int weight(int kind) { return kind == 2 ? 3 : kind == 1 ? 2 : kind == 0 ? 1 : 0; }
const char* kind_name(int k) { return k == 0 ? "KAdd" : k == 1 ? "KMul" : k == 2 ? "KDiv" : "KCmp"; }
constexpr int kMaxLev = 16;  // ru_pipe_pkg::MaxLev
}  // namespace

Levels levels(const Graph& g) {
  const auto& ns = g.nodes();
  Levels L;
  L.level.assign(ns.size(), -1);
  L.ready.assign(ns.size(), 0);
  for (size_t i = 0; i < ns.size(); ++i) {
    const Node& n = ns[i];
    int r = 0;
    for (int x : {n.a, n.b, n.c})
      if (x >= 0) r = std::max(r, L.ready[x]);
    if (is_unit(n.op)) {
      L.level[i] = r;
      L.ready[i] = r + 1;
    } else {
      L.ready[i] = r;
    }
  }
  for (const auto& o : g.outputs()) L.nlev = std::max(L.nlev, L.ready[o.second]);
  L.kind.assign(L.nlev, 3);
  std::vector<int> best(L.nlev, -1);
  for (size_t i = 0; i < ns.size(); ++i) {
    if (L.level[i] < 0 || L.level[i] >= L.nlev) continue;
    const int k = kind_of(ns[i].op);
    if (weight(k) > best[L.level[i]]) best[L.level[i]] = weight(k), L.kind[L.level[i]] = k;
  }
  return L;
}

std::string max_stages_expr(const Graph& g) {
  const Levels L = levels(g);
  int n[4] = {0, 0, 0, 0};
  for (int k : L.kind) ++n[k];
  const int c = 6 * n[0] + 5 * n[1] + 6 * n[2] + 3 * n[3] - 1;
  auto term = [](int k, const char* v) {
    return k == 0 ? std::string() : (k == 1 ? std::string(v) : std::to_string(k) + "*" + v) + "+";
  };
  return term(n[1], "L") + term(n[2], "M") + std::to_string(c);
}

std::vector<std::string> emit_sources() {
  return {"ru_pipe_pkg.sv", "ru_fp_pkg.sv", "ru_pipe.sv", "ru_lzc.sv", "ru_fp_classify.sv", "ru_fp_normalize.sv",
          "ru_fp_round_pack.sv", "ru_umul.sv", "ru_fp_add.sv", "ru_fp_mul.sv", "ru_fp_div.sv", "ru_fp_cmp.sv"};
}

std::vector<std::string> emit_sources(const Graph& g) {
  std::vector<std::string> s = emit_sources();
  bool fma = false, cvt = false;
  for (const Node& n : g.nodes()) fma |= n.op == Op::Fma, cvt |= n.op == Op::Cvt;
  if (fma) s.push_back("ru_fp_fma.sv");
  if (cvt) s.push_back("ru_fp_cvt.sv");
  return s;
}

std::string emit_filelist(const std::string& module, const Graph& g) {
  std::string f;
  for (const auto& s : emit_sources(g)) f += s + "\n";
  return f + module + ".sv\n";
}

std::string emit_sv(const Graph& g, const std::string& module, const std::string& origin) {
  const auto& ns = g.nodes();
  const Levels L = levels(g);
  if (L.nlev < 1) throw IrError("emit: the graph has no FP operation on a path to an output");
  if (L.nlev > kMaxLev)
    throw IrError("emit: " + std::to_string(L.nlev) + " levels, the level chain holds " + std::to_string(kMaxLev));
  for (const auto& o : g.outputs())
    if (o.first.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") != std::string::npos)
      throw IrError("emit: output name '" + o.first + "' is not a Verilog identifier");
  for (const auto& in : g.inputs())
    if (in.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") != std::string::npos)
      throw IrError("emit: input name '" + in + "' is not a Verilog identifier");

  for (const auto& o : g.outputs())
    if (ns[o.second].wide && !op_is_bool(ns[o.second].op))
      throw IrError("emit: output '" + o.first + "' is a value of the wide format (convert it with cvt)");

  std::ostringstream h, b;  // header, body
  // Names of a node's format in the emitted module: the unit's (W, ExpW, FracW) or the wide one's.
  auto Wn = [&](int n) { return std::string(ns[n].wide ? "WW" : "W"); };
  auto En = [&](int n) { return std::string(ns[n].wide ? "WExpW" : "ExpW"); };
  auto Fn = [&](int n) { return std::string(ns[n].wide ? "WFracW" : "FracW"); };
  auto wid = [&](int n) { return op_is_bool(ns[n].op) ? std::string("1") : Wn(n); };
  auto decl = [&](int n) { return op_is_bool(ns[n].op) ? std::string("logic ") : "logic [" + Wn(n) + "-1:0] "; };
  auto sig = [](int n) { return "n" + std::to_string(n); };

  // delay lines: (node, level) -> signal name of the node's value at that level
  std::map<std::pair<int, int>, std::string> at;
  int npipes = 0;
  std::ostringstream pipes;
  auto value_at = [&](int n, int lev) -> std::string {
    if (lev <= L.ready[n]) return sig(n);
    const auto key = std::make_pair(n, lev);
    auto it = at.find(key);
    if (it != at.end()) return it->second;
    const std::string name = sig(n) + "_l" + std::to_string(lev);
    pipes << "  " << decl(n) << name << ";\n  ru_pipe #(.Width(" << wid(n) << "), .Depth(span(" << L.ready[n] << ", "
          << lev << "))) u_" << name << " (.clk_i, .rst_ni, .valid_i(1'b0), .valid_o(unused_dly[" << npipes
          << "]), .data_i(" << sig(n) << "), .data_o(" << name << "));\n";
    ++npipes;
    return at[key] = name;
  };

  h << "// " << module << ": generated by rayunits dp (model/src/dp/emit.cpp) from a datapath graph; do not edit.\n"
    << (origin.empty() ? std::string() : "// origin: " + origin + "\n") << "// " << L.nlev << " levels; register placement by the level chain (rtl/ru_level_chain.svh).\n"
    << "module " << module << " #(\n"
    << "  parameter int unsigned ExpW = 8,\n  parameter int unsigned FracW = 23,\n  parameter int unsigned Stages = 0,\n"
    << "  parameter int unsigned Subnormals = 1,\n  parameter int unsigned Round = 0"
    << (g.has_wide() ? ",\n  // the wide format of the mixed-precision nodes (the graph's `wide " + std::to_string(g.wide_de()) + " " +
                           std::to_string(g.wide_dm()) + "`)\n  parameter int unsigned WExpW = ExpW + " +
                           std::to_string(g.wide_de()) + ",\n  parameter int unsigned WFracW = FracW + " +
                           std::to_string(g.wide_dm())
                     : std::string())
    << "\n) (\n"
    << "  input  logic clk_i,\n  input  logic rst_ni,\n  input  logic in_valid_i,\n";
  for (const auto& in : g.inputs()) h << "  input  logic [ExpW+FracW:0] " << in << "_i,\n";
  h << "  output logic out_valid_o";
  for (const auto& o : g.outputs())
    h << ",\n  output logic " << (op_is_bool(ns[o.second].op) ? "" : "[ExpW+FracW:0] ") << o.first << "_o";
  h << "\n);\n\n  localparam int unsigned W = 1 + ExpW + FracW;\n"
    << (g.has_wide() ? "  localparam int unsigned WW = 1 + WExpW + WFracW;\n" : "") << "  localparam int unsigned NLev = " << L.nlev
    << ";\n  localparam logic [4*ru_pipe_pkg::MaxLev-1:0] Kinds = {";
  if (L.nlev < kMaxLev) h << (4 * (kMaxLev - L.nlev)) << "'d0, ";
  for (int k = L.nlev - 1; k >= 0; --k) h << "ru_fp_pkg::" << kind_name(L.kind[k]) << (k ? ", " : "");
  h << "};\n  `include \"ru_level_chain.svh\"\n\n";

  int nunits = 0;
  size_t next_in = 0;
  for (size_t i = 0; i < ns.size(); ++i) {
    const Node& n = ns[i];
    const int id = static_cast<int>(i);
    const std::string s = sig(id);
    b << "  " << decl(id) << s << ";  // " << op_name(n.op) << "\n";
    if (n.op == Op::Input) {
      b << "  assign " << s << " = " << g.inputs()[next_in++] << "_i;\n";
    } else if (n.op == Op::Const) {
      const double v = n.value;
      const std::string E = En(id), F = Fn(id);
      if (v == 0) {
        b << "  assign " << s << " = '0;\n";
      } else if (std::isinf(v)) {
        b << "  assign " << s << " = {1'b" << (v < 0 ? 1 : 0) << ", {" << E << "{1'b1}}, " << F << "'(0)};\n";
      } else {
        int e = 0;
        const double m = std::frexp(std::fabs(v), &e);  // |v| = m 2^e, m in [0.5, 1)
        if (m != 0.5) throw IrError("emit: constant " + std::to_string(v) + " is not 0, +-inf or +-2^k");
        const int k = e - 1;
        b << "  assign " << s << " = {1'b" << (v < 0 ? 1 : 0) << ", " << E << "'((1 << (" << E << " - 1)) - 1 + (" << k
          << ")), " << F << "'(0)};\n"
          << "  if ((1 << (" << E << " - 1)) - 1 + (" << k << ") < 1 || (1 << (" << E << " - 1)) - 1 + (" << k
          << ") > (1 << " << E << ") - 2) begin : gen_const_" << id << "\n    $error(\"constant 2^" << k
          << " is not a normal number of the format\");\n  end\n";
      }
    } else if (n.op == Op::BConst) {
      b << "  assign " << s << " = 1'b" << (n.value != 0 ? 1 : 0) << ";\n";
    } else if (is_unit(n.op)) {
      const int lev = L.level[id];
      const int k = kind_of(n.op);
      const std::string A = value_at(n.a, lev), B = n.b >= 0 ? value_at(n.b, lev) : "";
      const std::string C = n.op == Op::Fma ? value_at(n.c, lev) : "";
      const char* mod = unit_module(n.op);
      // the level's cut selection describes a unit of the unit's format of the level's kind
      const bool lcut = !n.wide && k == L.kind[lev] && std::string(op_unit(n.op)) == kind_unit(k);
      std::string a = A, bb = B, op;
      switch (n.op) {
        case Op::Add: op = "1'b0"; break;
        case Op::Sub: op = "1'b1"; break;
        case Op::Lt: op = "3'd0"; break;
        case Op::Gt: op = "3'd0", std::swap(a, bb); break;
        case Op::Le: op = "3'd1"; break;
        case Op::Ge: op = "3'd1", std::swap(a, bb); break;
        case Op::Eq: op = "3'd2"; break;
        case Op::Min: op = "3'd3"; break;
        case Op::Max: op = "3'd4"; break;
        case Op::Fma: op = "2'd0"; break;  // a*b + c (a subtraction is an fma on a neg node)
        default: break;
      }
      const bool bool_out = op_is_bool(n.op);
      if (bool_out)  // a comparison's result is bit 0 of y_o
        b << "  /* verilator lint_off UNUSEDSIGNAL */ logic [" << Wn(id) << "-1:0] " << s << "_y; /* verilator lint_on UNUSEDSIGNAL */\n";
      if (n.op == Op::Cvt) {
        // f2f into this node's format from the other one (IntW 2: the integer ports stay narrow)
        const std::string from_e = n.wide ? "ExpW" : "WExpW", from_f = n.wide ? "FracW" : "WFracW";
        b << "  ru_fp_cvt #(.ExpW(" << En(id) << "), .FracW(" << Fn(id) << "), .Stages(lat(" << lev
          << ")), .Subnormals(Subnormals), .Round(Round), .InExpW(" << from_e << "), .InFracW(" << from_f
          << "), .InSubnormals(Subnormals), .IntW(2)) u_" << s << " (\n    .clk_i, .rst_ni, .in_valid_i(1'b1), .a_i("
          << (n.wide ? "{{(WW-W){1'b0}}, " + A + "}" : A) << "), .op_i(2'd0),\n    .out_valid_o(unused_valid["
          << nunits << "]), .y_o(" << s << "), .flags_o(unused_flags[" << 5 * nunits << " +: 5]));\n";
        ++nunits;
        continue;
      }
      b << "  " << mod << " #(.ExpW(" << En(id) << "), .FracW(" << Fn(id) << "), .Stages(lat(" << lev
        << ")), .Subnormals(Subnormals), .Round(" << (n.round >= 0 ? std::to_string(n.round) : std::string("Round")) << ")" << (lcut ? ", .CutSel(lcut(" + std::to_string(lev) + "))" : "")
        << ") u_" << s << " (\n    .clk_i, .rst_ni, .in_valid_i(1'b1), .a_i(" << a << "), .b_i(" << bb << ")"
        << (n.op == Op::Fma ? ", .c_i(" + C + ")" : "")
        << (op.empty() ? "" : ", .op_i(" + op + ")") << ",\n    .out_valid_o(unused_valid[" << nunits
        << "]), .y_o(" << (bool_out ? s + "_y" : s) << "), .flags_o(unused_flags[" << 5 * nunits << " +: 5]));\n";
      if (bool_out) b << "  assign " << s << " = " << s << "_y[0];\n";
      ++nunits;
    } else {
      const int r = L.ready[id];
      auto v = [&](int x) { return value_at(x, r); };
      // the operand's format (neg, abs and the bit tests)
      const std::string W = n.a >= 0 ? Wn(n.a) : "W", F = n.a >= 0 ? Fn(n.a) : "FracW";
      switch (n.op) {
        case Op::Neg: b << "  assign " << s << " = {~" << v(n.a) << "[" << W << "-1], " << v(n.a) << "[" << W << "-2:0]};\n"; break;
        case Op::Abs: b << "  assign " << s << " = {1'b0, " << v(n.a) << "[" << W << "-2:0]};\n"; break;
        case Op::Select: b << "  assign " << s << " = " << v(n.a) << " ? " << v(n.b) << " : " << v(n.c) << ";\n"; break;
        case Op::And: b << "  assign " << s << " = " << v(n.a) << " & " << v(n.b) << ";\n"; break;
        case Op::Or: b << "  assign " << s << " = " << v(n.a) << " | " << v(n.b) << ";\n"; break;
        case Op::Not: b << "  assign " << s << " = ~" << v(n.a) << ";\n"; break;
        case Op::SignBit: b << "  assign " << s << " = " << v(n.a) << "[" << W << "-1];\n"; break;
        case Op::IsNan:
          b << "  assign " << s << " = (&" << v(n.a) << "[" << W << "-2:" << F << "]) & (|" << v(n.a) << "[" << F << "-1:0]);\n";
          break;
        case Op::IsInf:
          b << "  assign " << s << " = (&" << v(n.a) << "[" << W << "-2:" << F << "]) & ~(|" << v(n.a) << "[" << F << "-1:0]);\n";
          break;
        default: throw IrError(std::string("emit: unexpected ") + op_name(n.op));
      }
    }
  }
  b << "\n  // outputs at the last level\n";
  for (const auto& o : g.outputs()) b << "  assign " << o.first << "_o = " << value_at(o.second, L.nlev) << ";\n";

  std::ostringstream out;
  out << h.str() << "  // valid bits and flags of the instances and delay lines are not used: one valid line\n"
      << "  /* verilator lint_off UNUSEDSIGNAL */\n"
      << "  logic [" << std::max(nunits, 1) - 1 << ":0] unused_valid;\n"
      << "  logic [" << 5 * std::max(nunits, 1) - 1 << ":0] unused_flags;\n"
      << "  logic [" << std::max(npipes, 1) - 1 << ":0] unused_dly;\n"
      << "  logic unused_vd;\n  /* verilator lint_on UNUSEDSIGNAL */\n"
      << "  ru_pipe #(.Width(1), .Depth(Stages)) u_valid (.clk_i, .rst_ni, .valid_i(in_valid_i), .valid_o(out_valid_o),\n"
      << "                                              .data_i(1'b0), .data_o(unused_vd));\n\n"
      << b.str() << "\n" << pipes.str() << (nunits == 0 ? "  assign unused_valid = '0;\n" : "")
      << (npipes == 0 ? "  assign unused_dly = '0;\n" : "") << "\nendmodule\n";
  return out.str();
}

}  // namespace ru::dp
