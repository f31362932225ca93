// Datapath IR (see rayunits/dp/ir.hpp).
#include "rayunits/dp/ir.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ru::dp {

namespace {
struct OpInfo {
  Op op;
  const char* name;
  int arity;
  bool is_bool;    // result
  bool bool_args;  // operands (Select: only the first)
  const char* unit;  // the registry FP unit that carries it out, "" for logic and wiring
};
constexpr OpInfo kOps[] = {
    {Op::Input, "in", 0, false, false, ""},      {Op::Const, "const", 0, false, false, ""},
    {Op::Add, "add", 2, false, false, "fp_add"}, {Op::Sub, "sub", 2, false, false, "fp_add"},
    {Op::Mul, "mul", 2, false, false, "fp_mul"}, {Op::Div, "div", 2, false, false, "fp_div"},
    {Op::Fma, "fma", 3, false, false, "fp_fma"}, {Op::Neg, "neg", 1, false, false, ""},
    {Op::Abs, "abs", 1, false, false, ""},       {Op::Min, "min", 2, false, false, "fp_cmp"},
    {Op::Max, "max", 2, false, false, "fp_cmp"}, {Op::Select, "sel", 3, false, false, ""},
    {Op::Lt, "lt", 2, true, false, "fp_cmp"},    {Op::Gt, "gt", 2, true, false, "fp_cmp"},
    {Op::Le, "le", 2, true, false, "fp_cmp"},    {Op::Ge, "ge", 2, true, false, "fp_cmp"},
    {Op::Eq, "eq", 2, true, false, "fp_cmp"},    {Op::And, "and", 2, true, true, ""},
    {Op::Or, "or", 2, true, true, ""},           {Op::Not, "not", 1, true, true, ""},
    {Op::BConst, "bool", 0, true, false, ""},    {Op::SignBit, "sgn", 1, true, false, ""},
    {Op::IsNan, "nan", 1, true, false, ""},      {Op::IsInf, "inf", 1, true, false, ""},
    {Op::Cvt, "cvt", 1, false, false, "fp_cvt"},
};
const OpInfo& info(Op o) {
  for (const auto& i : kOps)
    if (i.op == o) return i;
  throw IrError("unknown op");
}
}  // namespace

const char* op_name(Op o) { return info(o).name; }
bool op_is_bool(Op o) { return info(o).is_bool; }
int op_arity(Op o) { return info(o).arity; }
const char* op_unit(Op o) { return info(o).unit; }
bool op_has_round(Op o) { return o == Op::Add || o == Op::Sub || o == Op::Mul || o == Op::Div || o == Op::Fma; }

int Graph::rounded(int n, num::Round r) {
  if (n < 0 || n >= static_cast<int>(nodes_.size())) throw IrError("rounded: no node " + std::to_string(n));
  if (!op_has_round(nodes_[n].op))
    throw IrError(std::string("rounded: ") + op_name(nodes_[n].op) + " has no rounding (add sub mul div fma do)");
  nodes_[n].round = static_cast<int>(r);
  return n;
}

void Graph::check_operand(int n, bool want_bool, const char* what) const {
  if (n < 0 || n >= static_cast<int>(nodes_.size()))
    throw IrError(std::string(what) + ": operand " + std::to_string(n) + " is not an earlier node (0.." +
                  std::to_string(static_cast<int>(nodes_.size()) - 1) + ")");
  if (op_is_bool(nodes_[n].op) != want_bool)
    throw IrError(std::string(what) + ": operand " + std::to_string(n) + " is " +
                  (want_bool ? "an FP value, a Boolean is needed" : "a Boolean, an FP value is needed"));
}

int Graph::node(Op op, int a, int b, int c) {
  const OpInfo& i = info(op);
  if (op == Op::Input || op == Op::Const || op == Op::BConst)
    throw IrError(std::string(i.name) + ": use input() / constant() / boolean()");
  const int args[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    if (k >= i.arity) {
      if (args[k] != -1) throw IrError(std::string(i.name) + ": takes " + std::to_string(i.arity) + " operand(s)");
      continue;
    }
    const bool want_bool = op == Op::Select ? k == 0 : i.bool_args;
    check_operand(args[k], want_bool, i.name);
  }
  Node n;
  n.op = op;
  n.a = a, n.b = b, n.c = c;
  // The node's format: that of its FP operands (which must agree); a cvt's is the other one.
  int fmt = -1;
  for (int k = 0; k < i.arity; ++k) {
    const bool want_bool = op == Op::Select ? k == 0 : i.bool_args;
    if (want_bool) continue;
    const int w = nodes_[args[k]].wide ? 1 : 0;
    if (fmt >= 0 && w != fmt)
      throw IrError(std::string(i.name) + ": operands " + std::to_string(args[0]) + ".." + std::to_string(args[k]) +
                    " are in different formats (convert one with cvt)");
    fmt = w;
  }
  n.wide = fmt == 1;
  if (op == Op::Cvt) {
    if (!has_wide()) throw IrError("cvt: the graph has no wide format (a 'wide DE DM' line first)");
    n.wide = !n.wide;
  }
  nodes_.push_back(n);
  if (n.wide) ++wide_nodes_;
  return static_cast<int>(nodes_.size()) - 1;
}

void Graph::set_wide(int de, int dm) {
  if (!nodes_.empty()) throw IrError("wide: before any node");
  if (de < 0 || dm < 0 || (de == 0 && dm == 0))
    throw IrError("wide: " + std::to_string(de) + " " + std::to_string(dm) +
                  ": exponent and fraction bits to add, each >= 0, not both 0");
  wide_de_ = de, wide_dm_ = dm;
}

num::Format Graph::wide_format(const num::Format& f) const {
  num::Format w = f;
  w.exp_bits += wide_de_;
  w.frac_bits += wide_dm_;
  if (w.exp_bits > num::Format::kMaxExp || w.frac_bits > num::Format::kMaxFrac)
    throw IrError("wide format of " + f.name() + " widened by " + std::to_string(wide_de_) + " " +
                  std::to_string(wide_dm_) + " is e" + std::to_string(w.exp_bits) + "m" +
                  std::to_string(w.frac_bits) + ": beyond e" + std::to_string(num::Format::kMaxExp) + "m" +
                  std::to_string(num::Format::kMaxFrac));
  return w;
}

int Graph::input(const std::string& name) {
  if (name.empty() || name.find_first_of(" \t\n#") != std::string::npos)
    throw IrError("input: bad name '" + name + "'");
  if (input_index(name) >= 0) throw IrError("input '" + name + "' defined twice");
  Node n;
  n.op = Op::Input;
  n.name = name;
  nodes_.push_back(n);
  inputs_.push_back(name);
  input_nodes_.push_back(static_cast<int>(nodes_.size()) - 1);
  return input_nodes_.back();
}

int Graph::constant(double v, bool wide) {
  if (std::isnan(v)) throw IrError("const: value must be a number or +-inf");
  if (wide && !has_wide()) throw IrError("const: a wide constant in a graph without a wide format");
  Node n;
  n.op = Op::Const;
  n.value = v;
  n.wide = wide;
  nodes_.push_back(n);
  if (wide) ++wide_nodes_;
  return static_cast<int>(nodes_.size()) - 1;
}

int Graph::boolean(bool v) {
  Node n;
  n.op = Op::BConst;
  n.value = v ? 1 : 0;
  nodes_.push_back(n);
  return static_cast<int>(nodes_.size()) - 1;
}

void Graph::output(const std::string& name, int n) {
  if (n < 0 || n >= static_cast<int>(nodes_.size())) throw IrError("out " + name + ": no node " + std::to_string(n));
  for (const auto& o : outputs_)
    if (o.first == name) throw IrError("output '" + name + "' defined twice");
  outputs_.emplace_back(name, n);
}

int Graph::input_index(const std::string& name) const {
  for (size_t i = 0; i < inputs_.size(); ++i)
    if (inputs_[i] == name) return static_cast<int>(i);
  return -1;
}

int Graph::output_node(const std::string& name) const {
  for (const auto& o : outputs_)
    if (o.first == name) return o.second;
  throw IrError("no output '" + name + "'");
}

std::map<std::string, int> Graph::op_counts() const {
  std::map<std::string, int> c;
  for (const Node& n : nodes_) {
    const std::string w = n.wide ? "_w" : "";  // an FP unit of the wide format
    switch (n.op) {
      case Op::Add: case Op::Sub: ++c["add" + w]; break;
      case Op::Mul: ++c["mul" + w]; break;
      case Op::Div: ++c["div" + w]; break;
      case Op::Fma: ++c["fma" + w]; break;
      case Op::Cvt: ++c[n.wide ? "cvt_up" : "cvt_down"]; break;
      case Op::Lt: case Op::Gt: case Op::Le: case Op::Ge: case Op::Eq: case Op::Min: case Op::Max: ++c["cmp" + w]; break;
      case Op::Select: ++c["select"]; break;
      case Op::And: case Op::Or: case Op::Not: ++c["gate"]; break;
      case Op::IsNan: case Op::IsInf: ++c["bittest"]; break;
      default: break;
    }
  }
  return c;
}

int Graph::fp_depth() const {
  std::vector<int> d(nodes_.size(), 0);
  int best = 0;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    int m = 0;
    for (int x : {n.a, n.b, n.c})
      if (x >= 0) m = std::max(m, d[x]);
    d[i] = m + (*op_unit(n.op) ? 1 : 0);
  }
  for (const auto& o : outputs_) best = std::max(best, d[o.second]);
  return best;
}

std::string Graph::print() const {
  std::ostringstream s;
  if (has_wide()) s << "wide " << wide_de_ << " " << wide_dm_ << "\n";
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    switch (n.op) {
      case Op::Input: s << "in " << n.name; break;
      case Op::Const: {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", n.value);
        s << "const " << buf << (n.wide ? " w" : "");
        break;
      }
      case Op::BConst: s << (n.value != 0 ? "true" : "false"); break;
      default:
        s << op_name(n.op);
        for (int x : {n.a, n.b, n.c})
          if (x >= 0) s << " " << x;
        if (n.round >= 0) s << " " << num::round_name(static_cast<num::Round>(n.round));
    }
    s << "   # " << i << "\n";
  }
  for (const auto& o : outputs_) s << "out " << o.first << " " << o.second << "\n";
  return s.str();
}

Graph Graph::parse(const std::string& text) {
  Graph g;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word)) continue;
    auto fail = [&](const std::string& why) { throw IrError("line " + std::to_string(lineno) + ": " + why); };
    auto number = [&](const char* what) {
      std::string t;
      if (!(ls >> t)) fail(word + ": missing " + what);
      size_t used = 0;
      int v = -1;
      try {
        v = std::stoi(t, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != t.size() || v < 0) fail(word + ": " + what + " '" + t + "' is not a node number");
      return v;
    };
    try {
      if (word == "in") {
        std::string name;
        if (!(ls >> name)) fail("in: missing name");
        g.input(name);
      } else if (word == "const") {
        std::string t;
        if (!(ls >> t)) fail("const: missing value");
        size_t used = 0;
        double v = 0;
        try {
          v = std::stod(t, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != t.size()) fail("const: '" + t + "' is not a number");
        std::string w;
        const bool wide = static_cast<bool>(ls >> w);
        if (wide && w != "w") fail("const: '" + w + "' after the value (only 'w', a wide constant)");
        g.constant(v, wide);
      } else if (word == "wide") {
        int de = 0, dm = 0;
        if (!(ls >> de >> dm)) fail("wide: needs two numbers, exponent and fraction bits to add (e.g. wide 1 7)");
        g.set_wide(de, dm);
      } else if (word == "true" || word == "false") {
        g.boolean(word == "true");
      } else if (word == "out") {
        std::string name;
        if (!(ls >> name)) fail("out: missing name");
        g.output(name, number("node"));
      } else {
        const OpInfo* op = nullptr;
        for (const auto& i : kOps)
          if (word == i.name && i.arity > 0) op = &i;
        if (!op)
          fail("unknown operation '" + word +
               "' (in const true false add sub mul div fma neg abs min max sel lt gt le ge eq and or not sgn nan inf "
               "cvt wide out)");
        int args[3] = {-1, -1, -1};
        for (int k = 0; k < op->arity; ++k) args[k] = number("operand");
        const int id = g.node(op->op, args[0], args[1], args[2]);
        std::string mode;
        if (op_has_round(op->op) && (ls >> mode)) {
          if (mode != "rne" && mode != "rtz" && mode != "rdn" && mode != "rup")
            fail(word + ": '" + mode + "' is not a rounding mode (rne rtz rdn rup)");
          g.rounded(id, num::parse_round(mode));
        }
      }
      std::string extra;
      if (ls >> extra) fail("unexpected '" + extra + "'");
    } catch (const IrError& e) {
      const std::string m = e.what();
      if (m.rfind("line ", 0) == 0) throw;
      fail(m);
    }
  }
  return g;
}

ExactValues evaluate_exact(const Graph& g, const std::vector<double>& in) {
  if (in.size() != g.inputs().size())
    throw IrError("evaluate_exact: " + std::to_string(in.size()) + " input values for " +
                  std::to_string(g.inputs().size()) + " inputs");
  const auto& ns = g.nodes();
  ExactValues r;
  r.q.resize(ns.size());
  r.b.assign(ns.size(), false);
  r.defined.assign(ns.size(), true);
  size_t next_in = 0;
  for (size_t i = 0; i < ns.size(); ++i) {
    const Node& n = ns[i];
    bool def = true;
    for (int x : {n.a, n.b, n.c})
      if (x >= 0 && !r.defined[x]) def = false;
    if (n.op == Op::Select) def = r.defined[n.a] && r.defined[r.b[n.a] ? n.b : n.c];
    r.defined[i] = def;
    if (!def && n.op != Op::Input) continue;
    const mpq_class* A = n.a >= 0 ? &r.q[n.a] : nullptr;
    const mpq_class* B = n.b >= 0 ? &r.q[n.b] : nullptr;
    switch (n.op) {
      case Op::Input: {
        const double x = in[next_in++];
        if (!std::isfinite(x)) throw IrError("evaluate_exact: input '" + n.name + "' is not finite");
        r.q[i] = mpq_class(x);
        r.defined[i] = true;
        break;
      }
      case Op::Const:
        if (!std::isfinite(n.value)) throw IrError("evaluate_exact: the constant " + std::to_string(n.value) + " is not finite");
        r.q[i] = mpq_class(n.value);
        break;
      case Op::BConst: r.b[i] = n.value != 0; break;
      case Op::Add: r.q[i] = *A + *B; break;
      case Op::Sub: r.q[i] = *A - *B; break;
      case Op::Mul: r.q[i] = *A * *B; break;
      case Op::Div:
        if (sgn(*B) == 0) {
          r.defined[i] = false;
        } else {
          r.q[i] = *A / *B;
          r.q[i].canonicalize();
        }
        break;
      case Op::Fma: r.q[i] = *A * *B + r.q[n.c]; break;
      case Op::Neg: r.q[i] = -*A; break;
      case Op::Abs: r.q[i] = ::abs(*A); break;
      case Op::Min: r.q[i] = *A < *B ? *A : *B; break;
      case Op::Max: r.q[i] = *A > *B ? *A : *B; break;
      case Op::Select: r.q[i] = r.b[n.a] ? *B : r.q[n.c]; break;
      case Op::Lt: r.b[i] = *A < *B; break;
      case Op::Gt: r.b[i] = *A > *B; break;
      case Op::Le: r.b[i] = *A <= *B; break;
      case Op::Ge: r.b[i] = *A >= *B; break;
      case Op::Eq: r.b[i] = *A == *B; break;
      case Op::And: r.b[i] = r.b[n.a] && r.b[n.b]; break;
      case Op::Or: r.b[i] = r.b[n.a] || r.b[n.b]; break;
      case Op::Not: r.b[i] = !r.b[n.a]; break;
      case Op::SignBit: r.b[i] = sgn(*A) < 0; break;
      case Op::IsNan: case Op::IsInf: r.b[i] = false; break;
      case Op::Cvt: r.q[i] = *A; break;  // exact: a conversion changes nothing
    }
  }
  return r;
}

}  // namespace ru::dp
