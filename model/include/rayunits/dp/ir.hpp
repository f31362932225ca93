// rayunits dp: a datapath IR — an expression DAG of a unit's arithmetic (issue 18 §1).
//
// A Graph is a list of nodes in topological order (a node's operands are earlier nodes), named
// inputs and named outputs. Every FP node is ONE operation of one of the project's FP units
// (ru_fp_add/sub, ru_fp_mul, ru_fp_div, ru_fp_fma, ru_fp_cmp min/max/compare), so a Graph is
// at once:
//   * a golden model: evaluate<T>() runs it in double, float or ru::num::Soft (any format),
//     one operation per node in node order — bit for bit what the hand-written model of the
//     same dataflow computes (tests/dp check Fig. 3.6 and Moller-Trumbore against
//     units/ray_tri.hpp);
//   * an exact-rational model: evaluate_exact() runs the same DAG in GMP rationals (no
//     rounding), the reference of an error study;
//   * a netlist of FP units, for an RTL emitter and for an operation-count area estimate.
//
// Node kinds: FP-valued (Add, Sub, Mul, Div, Fma, Neg, Abs, Min, Max, Select), Boolean-valued
// (Lt, Gt, Le, Ge, Eq from FP operands; And, Or, Not, BConst; the bit tests SignBit, IsNan,
// IsInf of an FP value: wiring and gates, no FP unit). Inputs are FP values; an FP constant is a
// double rounded into the format once (Const; +-INF allowed). Outputs name a node of either kind.
// An add, sub, mul, div or fma may carry its own rounding mode (Node::round; the text form's
// trailing rne/rtz/rdn/rup): the directed roundings of a conservative unit. Without one it
// rounds as the format does.
//
// Mixed precision: a graph may have a second, wide format, the unit's format widened by DE
// exponent and DM fraction bits (set_wide; the text form's `wide DE DM` line): a cvt node converts
// its operand into the other format (ru_fp_cvt f2f, one rounding with the format's mode and
// subnormal handling), and every other node computes in the format of its FP operands (Node::wide,
// derived as nodes are built: operands in different formats are an error). Inputs are in the
// unit's format, a constant in either (`const V w`), outputs whatever their node is (an FP output
// of a wide node is W' bits wide). Evaluating a graph with wide nodes needs Soft (its wide format
// is the thread's format widened); the exact evaluator treats cvt as the identity.
//
// Text form (print / parse, one node per line, '#' comments):
//   in NAME            const VALUE          add A B     sub A B     mul A B     div A B
//   fma A B C          neg A                abs A       min A B     max A B     sel P A B
//   lt A B   gt A B    le A B   ge A B      eq A B      and P Q     or P Q      not P
//   true | false       out NAME N            sgn A    nan A    inf A      cvt A
//   wide DE DM (before any node)             const VALUE w (a constant of the wide format)
//   add/sub/mul/div/fma lines may end in a rounding mode: rne rtz rdn rup
// where A, B, ... are node numbers (0-based, earlier lines' nodes; `out` lines create none).
#pragma once

#include <gmpxx.h>

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayunits/num/fp.hpp"

namespace ru::dp {

enum class Op : uint8_t {
  Input, Const, Add, Sub, Mul, Div, Fma, Neg, Abs, Min, Max, Select,  // FP-valued
  Lt, Gt, Le, Ge, Eq, And, Or, Not, BConst, SignBit, IsNan, IsInf,    // Boolean-valued
  Cvt,                                                                 // FP-valued: to the other format
};
const char* op_name(Op o);
bool op_is_bool(Op o);  // the node's value is a Boolean
int op_arity(Op o);
// The registry FP unit that carries the operation out in RTL ("fp_add" for add and sub, "fp_cmp" for
// min/max/comparisons, ...), "" for logic and wiring (neg, abs, select, and/or/not, inputs, constants).
const char* op_unit(Op o);

struct Node {
  Op op = Op::Input;
  int a = -1, b = -1, c = -1;  // operands (node numbers), -1 unused; Select: a ? b : c
  double value = 0;            // Const: the value; BConst: 0 or 1
  std::string name;            // Input: its name
  int round = -1;              // add/sub/mul/div/fma: a num::Round of its own, -1 the format's
  bool wide = false;           // computes in (an FP node: its value is in) the graph's wide format
};
bool op_has_round(Op o);  // add, sub, mul, div, fma

class IrError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Graph {
 public:
  // Builders: each returns the new node's number and checks operand kinds (FP vs Boolean).
  int input(const std::string& name);
  int constant(double v, bool wide = false);
  int boolean(bool v);
  int add(int a, int b) { return node(Op::Add, a, b); }
  int sub(int a, int b) { return node(Op::Sub, a, b); }
  int mul(int a, int b) { return node(Op::Mul, a, b); }
  int div(int a, int b) { return node(Op::Div, a, b); }
  int fma(int a, int b, int c) { return node(Op::Fma, a, b, c); }  // a*b + c, one rounding
  int neg(int a) { return node(Op::Neg, a); }
  int abs(int a) { return node(Op::Abs, a); }
  int min(int a, int b) { return node(Op::Min, a, b); }
  int max(int a, int b) { return node(Op::Max, a, b); }
  int select(int p, int a, int b) { return node(Op::Select, p, a, b); }  // p ? a : b
  int lt(int a, int b) { return node(Op::Lt, a, b); }
  int gt(int a, int b) { return node(Op::Gt, a, b); }
  int le(int a, int b) { return node(Op::Le, a, b); }
  int ge(int a, int b) { return node(Op::Ge, a, b); }
  int eq(int a, int b) { return node(Op::Eq, a, b); }
  int land(int p, int q) { return node(Op::And, p, q); }
  int lor(int p, int q) { return node(Op::Or, p, q); }
  int lnot(int p) { return node(Op::Not, p); }
  int signbit(int a) { return node(Op::SignBit, a); }  // the sign bit (also of -0 and NaN)
  int isnan(int a) { return node(Op::IsNan, a); }
  int isinf(int a) { return node(Op::IsInf, a); }
  int cvt(int a) { return node(Op::Cvt, a); }  // a in the other format (set_wide first)
  // The wide format is the unit's widened by de exponent and dm fraction bits (each >= 0, not both
  // 0); before any node is built.
  void set_wide(int de, int dm);
  bool has_wide() const { return wide_de_ > 0 || wide_dm_ > 0; }
  int wide_de() const { return wide_de_; }
  int wide_dm() const { return wide_dm_; }
  bool mixed() const { return wide_nodes_ > 0; }  // some node computes in the wide format
  // f widened by (wide_de, wide_dm), rounding and subnormals as f; throws IrError naming the
  // formats when the wide one is out of range (E <= 11, M <= 52).
  num::Format wide_format(const num::Format& f) const;
  // Node n (an add, sub, mul, div or fma) rounds with r, not the format's mode; returns n.
  int rounded(int n, num::Round r);
  int node(Op op, int a = -1, int b = -1, int c = -1);
  void output(const std::string& name, int n);

  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<std::string>& inputs() const { return inputs_; }  // in order of creation
  const std::vector<std::pair<std::string, int>>& outputs() const { return outputs_; }
  int input_index(const std::string& name) const;  // position in inputs(), -1 if none
  int output_node(const std::string& name) const;  // throws IrError if none

  // Operations per kind of FP unit (add counts Add and Sub; cmp counts Lt..Eq, Min, Max) and
  // the Boolean / select gates; what an area estimate multiplies by unit areas.
  std::map<std::string, int> op_counts() const;
  // Longest chain of FP unit operations from an input to any output (Neg/Abs/Select/Boolean
  // nodes count 0: wiring and gates).
  int fp_depth() const;

  std::string print() const;
  static Graph parse(const std::string& text);  // throws IrError "line N: ..."

 private:
  void check_operand(int n, bool want_bool, const char* what) const;
  std::vector<Node> nodes_;
  std::vector<std::string> inputs_;
  std::vector<int> input_nodes_;
  std::vector<std::pair<std::string, int>> outputs_;
  int wide_de_ = 0, wide_dm_ = 0, wide_nodes_ = 0;
};

// One node's value: FP (v) or Boolean (b).
template <class T>
struct Value {
  T v{};
  bool b = false;
};

namespace detail {
// One operation of a node with its own rounding mode, by the format model (T's format with mode r:
// e8m23 / e11m52 for float / double, the thread's format for Soft).
template <class T>
T rounded_op(Op op, T a, T b, T c, num::Round r) {
  using namespace ru::num;
  Format f = fp_format<T>();
  f.round = r;
  Result res;
  switch (op) {
    case Op::Add: res = num::add(f, fp_bits(a), fp_bits(b)); break;
    case Op::Sub: res = num::sub(f, fp_bits(a), fp_bits(b)); break;
    case Op::Mul: res = num::mul(f, fp_bits(a), fp_bits(b)); break;
    case Op::Div: res = num::div(f, fp_bits(a), fp_bits(b)); break;
    default: res = num::fma(f, fp_bits(a), fp_bits(b), fp_bits(c)); break;
  }
  if constexpr (std::is_same_v<T, Soft>) {
    return Soft::wrap(res);
  } else {
    return fp_from_bits<T>(res.bits);
  }
}
template <class T>
T fma_of(T a, T b, T c);
template <>
inline double fma_of<double>(double a, double b, double c) { return std::fma(a, b, c); }
template <>
inline float fma_of<float>(float a, float b, float c) { return std::fma(a, b, c); }
template <>
inline num::Soft fma_of<num::Soft>(num::Soft a, num::Soft b, num::Soft c) {
  return num::Soft::wrap(num::fma(num::soft_format(), a.bits, b.bits, c.bits));
}
}  // namespace detail

namespace detail {
// One node's value (not Cvt) in the thread's current format.
template <class T>
void evaluate_node(const Node& n, const std::vector<Value<T>>& v, Value<T>& r, const std::vector<T>& in,
                   size_t& next_in) {
  using namespace ru::num;
  auto A = [&] { return v[n.a].v; };
  auto B = [&] { return v[n.b].v; };
  if (n.round >= 0) {
    r.v = detail::rounded_op<T>(n.op, A(), B(), n.c >= 0 ? v[n.c].v : T{}, static_cast<Round>(n.round));
    return;
  }
  switch (n.op) {
    case Op::Input: r.v = in[next_in++]; break;
    case Op::Const: r.v = fp_cast<T>(n.value); break;
    case Op::BConst: r.b = n.value != 0; break;
    case Op::Add: r.v = A() + B(); break;
    case Op::Sub: r.v = A() - B(); break;
    case Op::Mul: r.v = A() * B(); break;
    case Op::Div: r.v = A() / B(); break;
    case Op::Fma: r.v = detail::fma_of<T>(A(), B(), v[n.c].v); break;
    case Op::Neg: r.v = -A(); break;
    case Op::Abs: r.v = fp_abs(A()); break;
    case Op::Min: r.v = fp_min(A(), B()); break;
    case Op::Max: r.v = fp_max(A(), B()); break;
    case Op::Select: r.v = v[n.a].b ? v[n.b].v : v[n.c].v; break;
    case Op::Lt: r.b = A() < B(); break;
    case Op::Gt: r.b = A() > B(); break;
    case Op::Le: r.b = A() <= B(); break;
    case Op::Ge: r.b = A() >= B(); break;
    case Op::Eq: r.b = A() == B(); break;
    case Op::And: r.b = v[n.a].b && v[n.b].b; break;
    case Op::Or: r.b = v[n.a].b || v[n.b].b; break;
    case Op::Not: r.b = !v[n.a].b; break;
    case Op::SignBit: r.b = fp_signbit(A()); break;
    case Op::IsNan: r.b = fp_isnan(A()); break;
    case Op::IsInf: r.b = fp_is_pos_inf(A()) || fp_is_neg_inf(A()); break;
    case Op::Cvt: throw IrError("evaluate: cvt in a graph without a wide format");
  }
}
}  // namespace detail

// Runs the graph in T (for Soft: in the thread's SoftScope format), one FP operation per node in
// node order. in: one value per input, in the order of inputs(). Returns every node's value (a
// wide node's in the wide format: Soft bits of that format).
template <class T>
std::vector<Value<T>> evaluate(const Graph& g, const std::vector<T>& in) {
  using namespace ru::num;
  if (in.size() != g.inputs().size())
    throw IrError("evaluate: " + std::to_string(in.size()) + " input values for " +
                  std::to_string(g.inputs().size()) + " inputs");
  const auto& ns = g.nodes();
  std::vector<Value<T>> v(ns.size());
  size_t next_in = 0;
  Format narrow{}, wide{};
  if (g.mixed()) {
    if constexpr (!std::is_same_v<T, Soft>) {
      throw IrError("evaluate: a mixed-precision graph runs in Soft (its wide format is the unit's widened)");
    } else {
      narrow = soft_format();
      wide = g.wide_format(narrow);
    }
  }
  for (size_t i = 0; i < ns.size(); ++i) {
    const Node& n = ns[i];
    Value<T>& r = v[i];
    if constexpr (std::is_same_v<T, Soft>) {
      if (n.op == Op::Cvt) {  // into this node's format from the other one
        SoftFormatSwitch to(n.wide ? wide : narrow);
        r.v = Soft::wrap(num::convert(n.wide ? wide : narrow, n.wide ? narrow : wide, v[n.a].v.bits));
        continue;
      }
      if (n.wide) {
        SoftFormatSwitch in_wide(wide);
        detail::evaluate_node(n, v, r, in, next_in);
        continue;
      }
    }
    detail::evaluate_node(n, v, r, in, next_in);
  }
  return v;
}

// The graph in exact rationals: every FP node's exact value (no rounding), comparisons exact.
// Inputs must be finite; Min/Max/Select/Abs/Neg exact too; rounding modes are ignored; SignBit is
// "< 0" (an exact zero has none), IsNan and IsInf are false. A division by an exact zero (or any
// node depending on one) is undefined: defined[i] false, and comparisons on it are false.
struct ExactValues {
  std::vector<mpq_class> q;
  std::vector<bool> b;
  std::vector<bool> defined;
};
ExactValues evaluate_exact(const Graph& g, const std::vector<double>& in);

}  // namespace ru::dp
