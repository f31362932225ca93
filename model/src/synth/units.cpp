// The unit registry and the wrapper generator. See rayunits/synth/units.hpp.
#include "rayunits/synth/units.hpp"

#include "rayunits/dp/emit.hpp"
#include "rayunits/dp/formulas.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rayunits/synth/process.hpp"
#include "rayunits/synth/unit_models.hpp"

namespace ru::synth {
namespace fs = std::filesystem;
using num::Format;

namespace {

// The parameters every floating-point unit takes.
std::vector<ParamSpec> fp_params() {
  return {
      {"ExpW", [](const UnitConfig& c) { return static_cast<long long>(c.fmt.exp_bits); }},
      {"FracW", [](const UnitConfig& c) { return static_cast<long long>(c.fmt.frac_bits); }},
      {"Stages", [](const UnitConfig& c) { return static_cast<long long>(c.stages); }},
      {"Subnormals", [](const UnitConfig& c) { return c.fmt.subnormals ? 1LL : 0LL; }},
      {"Round", [](const UnitConfig& c) { return static_cast<long long>(c.fmt.round); }},
  };
}

PortSpec port(const char* name, PortDir dir, PortRole role, const char* width, const char* doc,
              FieldKind kind = FieldKind::Bits) {
  PortSpec p;
  p.name = name;
  p.dir = dir;
  p.role = role;
  p.width = width;
  p.doc = doc;
  p.kind = kind;
  return p;
}
PortSpec in(const char* name, const char* width, const char* doc, FieldKind kind = FieldKind::Bits) {
  return port(name, PortDir::In, PortRole::Data, width, doc, kind);
}
PortSpec out(const char* name, const char* width, const char* doc, FieldKind kind = FieldKind::Bits) {
  return port(name, PortDir::Out, PortRole::Data, width, doc, kind);
}
PortSpec fin(const char* name, const char* width, const char* doc) { return in(name, width, doc, FieldKind::Float); }
PortSpec fout(const char* name, const char* width, const char* doc) { return out(name, width, doc, FieldKind::Float); }
// A packed vector of `names.size()` format values, element 0 in the low bits.
PortSpec fvec(PortSpec p, std::vector<std::string> names) {
  p.kind = FieldKind::Float;
  p.elems = static_cast<int>(names.size());
  p.elem_names = std::move(names);
  return p;
}
// A 3-vector {z, y, x} of format values named <base>.x, .y, .z.
PortSpec vec3(const char* name, const std::string& base, const char* doc) {
  return fvec(in(name, "3*W", doc), {base + ".x", base + ".y", base + ".z"});
}
PortSpec enum_in(const char* name, const char* width, const char* doc, std::vector<std::string> names) {
  PortSpec p = in(name, width, doc, FieldKind::Enum);
  p.enum_names = std::move(names);
  return p;
}

std::vector<PortSpec> control_ports() {
  return {
      port("clk_i", PortDir::In, PortRole::Clock, "1", "clock, rising edge"),
      port("rst_ni", PortDir::In, PortRole::Reset, "1", "reset, active low: drops every operation in flight"),
      port("in_valid_i", PortDir::In, PortRole::Valid, "1", "operands valid this cycle"),
  };
}
PortSpec out_valid() {
  return port("out_valid_o", PortDir::Out, PortRole::Valid, "1", "result valid (in_valid_i delayed by the latency)");
}

// The fixed interface: clk_i, rst_ni, in_valid_i, operands, [op_i], out_valid_o, y_o, flags_o.
std::vector<PortSpec> fp_ports(std::vector<PortSpec> operands) {
  std::vector<PortSpec> p = control_ports();
  for (auto& o : operands) p.push_back(std::move(o));
  p.push_back(out_valid());
  p.push_back(fout("y_o", "W", "result bit pattern"));
  p.push_back(out("flags_o", "5", "{invalid, divzero, overflow, underflow, inexact}", FieldKind::Flags));
  return p;
}

using models::FpOp;
using models::FpShape;

// A floating-point unit: operands (and op_i, whose enum names are the operations), its golden
// model (ru::num: one op per op_i code) and its test matrices.
UnitSpec fp_unit(const char* name, const char* summary, std::vector<PortSpec> operands, const char* max_stages,
                 FpShape shape, std::vector<FpOp> ops, std::vector<std::string> tests,
                 std::vector<std::string> long_tests) {
  UnitSpec s;
  s.name = name;
  s.top = std::string("ru_") + name;
  s.summary = summary;
  s.filelist = s.top + ".f";
  s.params = fp_params();
  s.ports = fp_ports(std::move(operands));
  s.max_stages_expr = max_stages;
  s.seg_weights_param = true;
  s.golden = [shape, ops](const UnitConfig& c) { return models::fp_golden(c, shape, ops); };
  const int nops = static_cast<int>(ops.size());
  s.random_inputs = [shape, nops](const UnitConfig& c, uint64_t seed) { return models::fp_inputs(c, seed, shape, nops); };
  s.tests = std::move(tests);
  s.long_tests = std::move(long_tests);
  return s;
}

// The fast matrix of the two-operand FP units (tb/README.md): three formats at Stages 0, 1 and
// the maximum, e8m23 one past it (the extra output register) with the planted-error tests, two
// exhaustive small formats.
std::vector<std::string> fp_fast(const char* ex1, const char* ex2) {
  return {"e5m10:s0", "e5m10:s1", "e5m10:smax", "e7m16:s0", "e7m16:s1",  "e7m16:smax",
          "e8m23:s0", "e8m23:s1", "e8m23:smax+1:selftest",  ex1, ex2};
}
// The long matrix of add, mul, div, cmp: double precision, every rounding mode, flush to zero,
// exhaustive small formats in every rounding mode; `mid` a mid-pipeline Stages.
std::vector<std::string> fp_long(const std::string& mid) {
  const std::string m = ":s" + mid;
  return {"e11m52:s0", "e11m52:s2", "e11m52" + m, "e8m23:s2", "e8m23" + m + ":rtz", "e8m23" + m + ":rdn",
          "e8m23" + m + ":rup", "e8m23-ftz:s2", "e8m23-ftz:s1:rdn", "e5m10-ftz:s1:rup", "e11m52-ftz" + m + ":rtz",
          "e4m3:s1:rtz:exhaustive", "e4m3:s1:rdn:exhaustive", "e4m3:s1:rup:exhaustive", "e4m3-ftz:s0:exhaustive",
          "e5m2-ftz:s2:rup:exhaustive"};
}

// Maximum useful Stages: the number of internal cut positions of the unit's register chain
// (rtl/README.md, "Pipelining"), with L = csa_levels(M+1). FP units: add 6 segments, mul L+5,
// div M+6, sqrt M+4, fma L+7, cmp 3, dot3 = mul + 2 add, dot3_fused L+8. The ray units place their registers on the chain of their
// levels' FP segments (one mechanism, rtl/README.md), so their maximum is the sum of the levels'
// segment counts minus one: ray_box = add mul cmp cmp cmp, ray_tri_robust = add mul add mul add
// add div cmp (4 add, 2 mul), ray_tri_mt = add mul add mul add add div mul add cmp (5 add, 3 mul).
// (The registry before this one counted one add level too many for both triangle units.) Checked against each top module's MaxUsefulStages
// (check_against_rtl, ctest Registry.MaxUsefulStagesMatchRtl).
// A ray-triangle or ray-box datapath graph (dp/ir.hpp) as a registry unit dp_<stem>: module
// ru_dp_<stem>, file list ru_dp_<stem>.f, one W-bit port per graph input and output (a Boolean
// output is 1 bit), the graph itself as the golden model (models::dp_golden), the ray-triangle
// (17 fields) or ray-box (14 fields) workload as inputs in the graphs' input order, the maximum
// Stages from the graph's levels.
UnitSpec dp_unit(const std::string& stem, const std::string& summary, std::shared_ptr<const dp::Graph> g) {
  const dp::Graph tri = dp::ray_tri_mt_graph(), box = dp::box_graph(dp::box_plain_genome());
  const bool is_box = g->inputs() == box.inputs();
  if (g->inputs() != tri.inputs() && !is_box)
    throw SynthError("datapath design " + stem +
                     ": a unit needs the ray-triangle inputs (ax ay az dx .. tmax) or the ray-box inputs (ox oy oz ix .. "
                     "hiz), got " + std::to_string(g->inputs().size()) + " inputs");
  UnitSpec s;
  s.name = "dp_" + stem;
  s.top = "ru_dp_" + stem;
  s.summary = summary;
  s.filelist = s.top + ".f";
  s.synth_share = false;
  s.params = fp_params();
  s.ports = control_ports();
  for (const auto& in : g->inputs()) s.ports.push_back(fin((in + "_i").c_str(), "W", ("graph input " + in).c_str()));
  s.ports.push_back(out_valid());
  for (const auto& [name, n] : g->outputs()) {
    const std::string pn = name + "_o", doc = "graph output " + name;
    s.ports.push_back(dp::op_is_bool(g->nodes()[n].op) ? out(pn.c_str(), "1", doc.c_str())
                                                        : fout(pn.c_str(), "W", doc.c_str()));
  }
  s.golden = [g](const UnitConfig& c) { return models::dp_golden(c, g); };
  s.random_inputs = is_box ? models::ray_box_inputs : models::ray_tri_inputs;
  s.large_model = true;
  s.max_stages_expr = dp::max_stages_expr(*g);
  return s;
}

std::vector<UnitSpec> runtime_dp_units() {
  std::vector<UnitSpec> out;
  const char* dir = std::getenv("RU_DP_DESIGNS");
  if (!dir || !*dir) return out;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw SynthError(std::string("RU_DP_DESIGNS: no such directory: ") + dir);
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (e.path().extension() == ".dp") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    const std::string stem = f.stem().string();
    const bool ok = !stem.empty() && std::all_of(stem.begin(), stem.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
    if (!ok) throw SynthError("RU_DP_DESIGNS: " + f.string() + ": a design name is [a-z0-9_]+");
    if (stem == "ray_tri_robust" || stem == "ray_tri_mt")
      throw SynthError("RU_DP_DESIGNS: " + f.string() + ": dp_" + stem + " is a built-in unit");
    std::shared_ptr<const dp::Graph> g;
    try {
      g = std::make_shared<const dp::Graph>(dp::Graph::parse(read_file(f.string())));
    } catch (const dp::IrError& e) {
      throw SynthError("RU_DP_DESIGNS: " + f.string() + ": " + e.what());
    }
    UnitSpec s = dp_unit(stem, "datapath design " + f.filename().string() + " (run time, RU_DP_DESIGNS)", g);
    s.design_file = std::filesystem::absolute(f).string();
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<UnitSpec> make_units() {
  using num::Op;
  std::vector<UnitSpec> u;
  u.push_back(fp_unit("fp_add", "floating-point adder/subtracter (op_i 0 = a+b, 1 = a-b)",
                      {fin("a_i", "W", "operand a"), fin("b_i", "W", "operand b"),
                       enum_in("op_i", "1", "0 = add, 1 = subtract", {"add", "sub"})},
                      "5", FpShape::Binary, {{Op::Add}, {Op::Sub}}, fp_fast("e4m3:s1:exhaustive", "e5m2:s2:exhaustive"),
                      fp_long("3")));
  u.push_back(fp_unit("fp_mul", "floating-point multiplier", {fin("a_i", "W", "operand a"), fin("b_i", "W", "operand b")},
                      "L+4", FpShape::Binary, {{Op::Mul}}, fp_fast("e4m3:s1:exhaustive", "e5m2:s3:exhaustive"),
                      fp_long("3")));
  u.push_back(fp_unit("fp_div", "floating-point divider (correctly rounded, pipelined digit recurrence)",
                      {fin("a_i", "W", "dividend"), fin("b_i", "W", "divisor")}, "M+5", FpShape::Binary, {{Op::Div}},
                      fp_fast("e4m3:s2:exhaustive", "e5m2:s6:exhaustive"), fp_long("7")));
  u.push_back(fp_unit("fp_sqrt", "floating-point square root (correctly rounded, pipelined digit recurrence)",
                      {fin("a_i", "W", "radicand")}, "M+3", FpShape::Unary, {{Op::Sqrt}},
                      {"e4m3:s0:exhaustive", "e5m2:s2:exhaustive", "e2m1:s1:exhaustive", "e4m3-ftz:s0:exhaustive",
                       "e5m10:s1:exhaustive", "e5m10-ftz:s1:rdn:exhaustive", "e8m23:s0", "e8m23:smax+1:selftest"},
                      {"e11m52:s0", "e11m52:s7", "e11m52:smax", "e7m16:s0", "e7m16:s1", "e7m16:smax",
                       "e5m10:smax:exhaustive", "e8m23:s1", "e8m23:s7:rtz", "e8m23:s7:rdn", "e8m23:s7:rup",
                       "e8m23-ftz:s2", "e8m23-ftz:s1:rdn", "e11m52-ftz:s7:rtz", "e5m10:s2:rup:exhaustive",
                       "e4m3:s1:rtz:exhaustive", "e4m3:s1:rdn:exhaustive", "e4m3:s1:rup:exhaustive",
                       "e2m1:s0:rtz:exhaustive", "e2m1:s0:rup:exhaustive", "e2m1-ftz:s0:exhaustive",
                       "e5m2-ftz:s2:rup:exhaustive"}));
  u.push_back(fp_unit("fp_fma",
                      "fused multiply-add, one rounding (op_i 0 a*b+c, 1 a*b-c, 2 -(a*b)+c, 3 -(a*b)-c)",
                      {fin("a_i", "W", "multiplicand a"), fin("b_i", "W", "multiplier b"), fin("c_i", "W", "addend c"),
                       enum_in("op_i", "2", "bit 0 negates c, bit 1 negates a*b", {"fma", "fms", "fnms", "fnma"})},
                      "L+6", FpShape::Ternary, {{Op::Fma, 0}, {Op::Fma, 1}, {Op::Fma, 2}, {Op::Fma, 3}},
                      {"e3m2:s0:exhaustive", "e2m3:s2:exhaustive", "e3m2-ftz:s1:exhaustive", "e2m1:s1:exhaustive",
                       "e5m10:s0", "e5m10:smax+1", "e8m23:s0", "e8m23:smax+1:selftest"},
                      {"e11m52:s0", "e11m52:s5", "e11m52:smax", "e7m16:s0", "e7m16:s4", "e7m16:smax", "e5m10:s3",
                       "e4m3:s2", "e8m23:s5:rtz", "e8m23:s5:rdn", "e8m23:s5:rup", "e8m23-ftz:s2", "e8m23-ftz:s1:rdn",
                       "e5m10-ftz:s1:rup", "e11m52-ftz:s5:rtz", "e3m2:s1:rtz:exhaustive", "e3m2:s1:rdn:exhaustive",
                       "e3m2:s1:rup:exhaustive", "e2m3:s0:rtz:exhaustive", "e2m3-ftz:s3:rdn:exhaustive",
                       "e3m2-ftz:s2:rup:exhaustive"}));
  u.push_back(fp_unit("fp_cmp", "floating-point compare/min/max (op_i 0 lt, 1 le, 2 eq, 3 min, 4 max)",
                      {fin("a_i", "W", "operand a"), fin("b_i", "W", "operand b"),
                       enum_in("op_i", "3", "0 lt, 1 le, 2 eq, 3 min, 4 max", {"lt", "le", "eq", "min", "max"})},
                      "2", FpShape::Binary, {{Op::Lt}, {Op::Le}, {Op::Eq}, {Op::Min}, {Op::Max}},
                      fp_fast("e4m3:s1:exhaustive", "e5m2:s2:exhaustive"), fp_long("3")));
  u.push_back(fp_unit("fp_dot3", "3-term dot product, three products and two sums each rounded",
                      {fvec(in("a_i", "3*W", "{a2, a1, a0}, a0 in the low bits"), {"a0", "a1", "a2"}),
                       fvec(in("b_i", "3*W", "{b2, b1, b0}, b0 in the low bits"), {"b0", "b1", "b2"})},
                      "L+16", FpShape::Dot3, {{Op::Fma}},
                      {"e5m10:s0", "e5m10:s1", "e5m10:s6", "e7m16:s0", "e7m16:s1", "e7m16:smax", "e8m23:s0",
                       "e8m23:s1", "e8m23:smax+1:selftest"},
                      {"e11m52:s0", "e11m52:s4", "e8m23:s3:rtz", "e8m23:s3:rdn", "e8m23:s3:rup", "e8m23-ftz:s2",
                       "e5m10-ftz:s2:rup", "e4m3:s2", "e5m2:s1"}));
  u.back().seg_weights_param = false;  // its FP instances get their cuts from its level chain
  u.push_back(fp_unit("fp_dot3_fused", "fused 3-term dot product, the exact sum of the exact products rounded once",
                      {fvec(in("a_i", "3*W", "{a2, a1, a0}, a0 in the low bits"), {"a0", "a1", "a2"}),
                       fvec(in("b_i", "3*W", "{b2, b1, b0}, b0 in the low bits"), {"b0", "b1", "b2"})},
                      "L+7", FpShape::Dot3Fused, {{Op::Fma}},
                      {"e5m10:s0", "e5m10:smax+1", "e3m2:s2", "e4m3-ftz:s1:rdn", "e7m16:s3", "e8m23:s0",
                       "e8m23:smax+1:selftest", "e2m1:s1:exhaustive"},
                      {"e11m52:s0", "e11m52:s6", "e11m52:smax", "e8m23:s4:rtz", "e8m23:s4:rdn", "e8m23:s4:rup",
                       "e8m23-ftz:s2", "e5m10-ftz:s2:rup", "e4m3:s2", "e5m2:s1", "e2m5:s3", "e6m1:s0",
                       "e2m1:s0:rtz:exhaustive", "e2m1-ftz:s2:rup:exhaustive", "e2m1:s3:rdn:exhaustive"}));
  {
    // Conversions: F = the configuration's format, G = InExpW/InFracW/InSubnormals, IntW-bit integers.
    UnitSpec s;
    s.name = "fp_cvt";
    s.top = "ru_fp_cvt";
    s.summary = "conversions: format G to F (f2f), integer to F (i2f), F to integer (f2i, f2i_rtz), saturating";
    s.filelist = "ru_fp_cvt.f";
    s.params = fp_params();
    s.extra_params = {{"InExpW", 8, Format::kMinExp, Format::kMaxExp, "exponent bits of the source format G (f2f)"},
                      {"InFracW", 23, Format::kMinFrac, Format::kMaxFrac, "fraction bits of G"},
                      {"InSubnormals", 1, 0, 1, "0: G is flush-to-zero (its subnormals read as zero)"},
                      {"IntW", 32, 2, 64, "integer width (two's complement) of i2f, f2i, f2i_rtz"}};
    s.ports = control_ports();
    for (PortSpec p : {in("a_i", "max(max(W, 1+InExpW+InFracW), IntW)",
                          "f2f: a value of G in the low bits; i2f: an IntW-bit integer; f2i: a value of F"),
                       enum_in("op_i", "2", "0 f2f, 1 i2f, 2 f2i (mode Round), 3 f2i_rtz (toward zero)",
                               {"f2f", "i2f", "f2i", "f2i_rtz"}),
                       out_valid(), out("y_o", "max(W, IntW)", "f2f, i2f: a value of F; f2i: an IntW-bit integer"),
                       out("flags_o", "5", "{invalid, divzero, overflow, underflow, inexact}", FieldKind::Flags)})
      s.ports.push_back(std::move(p));
    s.max_stages_expr = "3";
    s.seg_weights_param = true;
    s.golden = models::fp_cvt_golden;
    s.random_inputs = models::fp_cvt_inputs;
    s.tests = {"e7m16:s0",        "e8m23:smax+1:InExpW=7:InFracW=16:selftest",
               "e5m10:s1:IntW=16",                     "e8m23:s2:InExpW=5:InFracW=10:IntW=64",
               "e4m3:s1:InExpW=5:InFracW=2:IntW=8:exhaustive",
               "e3m2-ftz:s2:rtz:InExpW=4:InFracW=3:InSubnormals=0:IntW=6:exhaustive"};
    s.long_tests = {"e11m52:s0:InExpW=8:InFracW=23:IntW=64", "e11m52:s3:IntW=64", "e8m23:s3:InExpW=11:InFracW=52",
                    "e7m16:s1:rtz", "e7m16:s2:rdn:IntW=16", "e7m16:s3:rup:IntW=64",
                    "e8m23-ftz:s1:InSubnormals=0", "e5m10-ftz:s2:rup:InExpW=8:InFracW=23:InSubnormals=0",
                    "e2m1:s0:InExpW=3:InFracW=2:IntW=4:exhaustive", "e4m3:s3:rdn:InExpW=3:InFracW=4:IntW=10:exhaustive",
                    "e5m2-ftz:s1:rup:InExpW=4:InFracW=3:IntW=7:exhaustive", "e2m5:s2:rtz:InExpW=5:InFracW=2:IntW=2:exhaustive"};
    u.push_back(std::move(s));
  }
  {
    UnitSpec s;
    s.name = "ray_box";
    s.top = "ru_ray_box";
    s.summary = "ray-box slab test (Williams et al.), optional conservative directed rounding";
    s.filelist = "ru_ray_box.f";
    s.params = fp_params();
    s.extra_params = {{"OptConservative", 0, 0, 2,
                       "1: t_enter rounded down, t_exit up (never a false miss); 2: also conservative "
                       "against d when rdir_i = RNE(1/d)"}};
    s.ports = control_ports();
    for (PortSpec p : {vec3("org_i", "org", "ray origin {z, y, x}"), vec3("rdir_i", "rdir", "reciprocal direction {z, y, x}"),
                       fin("tmin_i", "W", "t_min"), fin("tmax_i", "W", "t_max"),
                       vec3("bmin_i", "bmin", "box minimum corner {z, y, x}"),
                       vec3("bmax_i", "bmax", "box maximum corner {z, y, x}"), out_valid(),
                       out("hit_o", "1", "the ray's [t_min, t_max] meets the box"),
                       fout("t_enter_o", "W", "entry distance"), fout("t_exit_o", "W", "exit distance")})
      s.ports.push_back(std::move(p));
    s.golden = models::ray_box_golden;
    s.random_inputs = models::ray_box_inputs;
    s.large_model = true;
    s.tests = {"e5m10:s0:OptConservative=1", "e7m16:s1", "e8m23:smax+1:OptConservative=2:selftest",
               "e5m10-ftz:s3:OptConservative=2"};
    s.long_tests = {"e5m10:s1", "e5m10:s6:OptConservative=1", "e7m16:s0:OptConservative=1", "e7m16:s10",
                    "e8m23:s0", "e8m23:s1:OptConservative=1", "e8m23:s20", "e8m23-ftz:s2:OptConservative=1",
                    "e7m16-ftz:s0", "e5m10:s2:rtz", "e7m16:s3:rup:OptConservative=1", "e11m52:s6:OptConservative=1",
                    "e5m10-ftz:s1:OptConservative=1", "e7m16:s2:OptConservative=2", "e8m23-ftz:s0:OptConservative=2",
                    "e8m23:s5:rdn:OptConservative=2"};
    s.max_stages_expr = "L+19";  // 6 + (L+5) + 3*3 segments, minus one
    u.push_back(std::move(s));
  }
  for (const bool robust : {true, false}) {
    UnitSpec s;
    s.name = robust ? "ray_tri_robust" : "ray_tri_mt";
    s.top = "ru_" + s.name;
    s.summary = robust ? "ray-triangle test from signed volumes (Kensler Fig. 3.6)"
                       : "ray-triangle test, Moller-Trumbore (Kensler Eq. 3.2)";
    s.filelist = s.top + ".f";
    s.synth_share = false;
    s.params = fp_params();
    if (robust) s.extra_params.push_back({"OptTieBreak", 0, 0, 1, "Fig. 3.6's zero-volume tie-break"});
    s.extra_params.push_back({"OptEpsTest", 0, 0, 1, "miss when |V| < eps"});
    s.extra_params.push_back({"EpsBits", 0, 0, INT64_MAX, "eps as a bit pattern of the format"});
    s.extra_params.push_back({"OptVolOut", 0, 0, 1, "1: vol_o carries V, Va, V0..2 (else constant 0)"});
    if (robust)
      s.extra_params.push_back({"OptRecip", 0, 0, 1, "1: one reciprocal 1/V and three multiplications (issue 14)"});
    s.ports = control_ports();
    PortSpec why = out("why_o", "3", "0 hit, 1 sign of V0..V2, 2 tie-break, 3 |V| < eps, 4 t outside (t_min, t_max)",
                       FieldKind::Enum);
    why.enum_names = {"hit", "sign", "tie_break", "eps", "interval"};
    for (PortSpec p : {vec3("a_i", "a", "ray origin {z, y, x}"), vec3("d_i", "d", "ray direction {z, y, x}"),
                       vec3("p0_i", "p0", "vertex {z, y, x}"), vec3("p1_i", "p1", "vertex {z, y, x}"),
                       vec3("p2_i", "p2", "vertex {z, y, x}"), fin("tmin_i", "W", "t_min"), fin("tmax_i", "W", "t_max"),
                       out_valid(), out("hit_o", "1", "hit inside (t_min, t_max)"), why,
                       fout("t_o", "W", "distance t"), fout("beta_o", "W", "barycentric beta"),
                       fout("gamma_o", "W", "barycentric gamma"),
                       fvec(out("vol_o", "5*W", "{V2, V1, V0, Va, V} (OptVolOut)"), {"V", "Va", "V0", "V1", "V2"})})
      s.ports.push_back(std::move(p));
    s.golden = [robust](const UnitConfig& c) { return models::ray_tri_golden(c, robust); };
    s.random_inputs = models::ray_tri_inputs;
    s.large_model = true;
    if (robust) {
      s.tests = {"e5m10:s0:OptVolOut=1", "e7m16:s1:OptVolOut=1:OptTieBreak=1",
                 "e8m23:smax+1:OptTieBreak=1:OptEpsTest=1:EpsBits=981467136:selftest",
                 "e5m10:smax:OptRecip=1:OptVolOut=1:selftest"};
      s.long_tests = {"e5m10:s1:OptTieBreak=1", "e5m10:s12:OptVolOut=1", "e7m16:s0:OptEpsTest=1:EpsBits=3473408",
                      "e7m16:s20:OptVolOut=1:OptTieBreak=1", "e8m23:s0:OptVolOut=1",
                      "e8m23:s1:OptVolOut=1:OptTieBreak=1", "e8m23:s60:OptVolOut=1",
                      "e5m10-ftz:s3:OptVolOut=1:OptTieBreak=1", "e8m23:s8:rdn:OptVolOut=1", "e11m52:s16:OptVolOut=1",
                      "e8m23:s0:OptRecip=1:OptVolOut=1",
                      "e8m23:smax+1:OptRecip=1:OptTieBreak=1:OptEpsTest=1:EpsBits=981467136",
                      "e5m10-ftz:s7:OptRecip=1:OptVolOut=1"};
    } else {
      s.tests = {"e5m10:s1:OptVolOut=1", "e7m16:s0:OptEpsTest=1:EpsBits=3473408:OptVolOut=1", "e8m23:smax+1:selftest"};
      s.long_tests = {"e5m10:s0:OptEpsTest=1:EpsBits=5120", "e5m10:s12:OptVolOut=1", "e7m16:s1:OptVolOut=1",
                      "e7m16:s20:OptVolOut=1", "e8m23:s0:OptVolOut=1", "e8m23:s1:OptEpsTest=1:EpsBits=981467136",
                      "e8m23:s60:OptVolOut=1", "e5m10-ftz:s3:OptVolOut=1", "e8m23:s8:rup:OptVolOut=1",
                      "e11m52:s16:OptVolOut=1"};
    }
    // robust: 4*6 + 2*(L+5) + (M+6) + 3 segments (OptRecip: + L+5 for the multiplications);
    // MT: 5*6 + 3*(L+5) + (M+6) + 3; minus one
    s.max_stages_expr = robust ? "2*L+M+42+OptRecip*(L+5)" : "3*L+M+53";
    u.push_back(std::move(s));
  }
  {
    // The exactly-once watertight unit (issue 14, docs/UNITS.md "Exactly-once triangles"): the
    // fast pipeline of ru_ray_tri_robust plus the filter, an order buffer and the exact side path
    // ru_exact_path behind it. Variable latency, results in order: `handshake`.
    UnitSpec s;
    s.name = "ray_tri_exact";
    s.top = "ru_ray_tri_exact";
    s.summary = "exactly-once watertight ray-triangle test: exact edge signs and interval (filtered, exact side path)";
    s.filelist = "ru_ray_tri_exact.f";
    s.synth_share = false;
    s.handshake = true;
    s.params = fp_params();
    s.extra_params = {{"DigitW", 16, 1, 64, "multiplier digit of the exact side path ru_exact_path (bits)"},
                      {"Slack", 1, 0, 64, "order-buffer entries beyond Stages + 1 (keeps accepting while the side path works)"},
                      {"Plant", 0, 0, 2, "tests only: 1 shrinks the edge bound (wrong results), 2 no early stop (other timing)"}};
    s.max_exp = 8;
    s.max_frac = 23;
    s.check = [](const UnitConfig& c) {
      if (c.fmt.round != num::Round::RNE && c.fmt.frac_bits < 2)
        throw SynthError("ray_tri_exact: directed rounding needs fraction bits >= 2, got " + c.fmt.name());
    };
    s.ports = control_ports();
    s.ports.push_back(port("in_ready_o", PortDir::Out, PortRole::Ready, "1",
                           "the unit accepts a test this cycle (in_valid_i && in_ready_o)"));
    PortSpec why = out("why_o", "3", "0 hit, 1 edge signs disagree (or a non-finite operand), 4 t outside (t_min, t_max)",
                       FieldKind::Enum);
    why.enum_names = {"hit", "sign", "tie_break", "eps", "interval"};
    for (PortSpec p : {vec3("a_i", "a", "ray origin {z, y, x}"), vec3("d_i", "d", "ray direction {z, y, x}"),
                       vec3("p0_i", "p0", "vertex {z, y, x}"), vec3("p1_i", "p1", "vertex {z, y, x}"),
                       vec3("p2_i", "p2", "vertex {z, y, x}"), fin("tmin_i", "W", "t_min"), fin("tmax_i", "W", "t_max"),
                       port("out_valid_o", PortDir::Out, PortRole::Valid, "1",
                            "result valid (in input order, Stages or more cycles after acceptance)"),
                       out("hit_o", "1", "the exact hit of the perturbed ray inside (t_min, t_max)"), why,
                       fout("t_o", "W", "distance t (Fig. 3.6)"), fout("beta_o", "W", "barycentric beta"),
                       fout("gamma_o", "W", "barycentric gamma"),
                       out("slow_o", "1", "the exact side path took part in the decision")})
      s.ports.push_back(std::move(p));
    s.golden = models::ray_tri_exact_golden;
    s.random_inputs = models::ray_tri_exact_inputs;
    s.large_model = true;
    // 6 add, 4 mul, div, cmp levels: 6*6 + 4*(L+5) + (M+6) + 3 segments, minus one
    s.max_stages_expr = "4*L+M+64";
    // Its own plan on the shared scoreboard (tb/exact/ray_tri_exact_plan.cpp: results in order,
    // every cycle of the handshake against a replay of the unit's timing rules). At M <= 3 every
    // test takes the side path; Plant=1/2: the RTL's planted errors, which must be reported.
    s.tests = {"e5m10:s2:selftest"};
    s.long_tests = {"e5m10:s0", "e5m10:smax+1", "e8m23:s6:DigitW=32:Slack=2", "e4m3-ftz:s3:DigitW=8:Slack=0",
                    "e6m12:s2:rtz:DigitW=8", "e5m10:s2:Plant=1", "e5m10:s2:Plant=2"};
    u.push_back(std::move(s));
  }
  // Units emitted from the datapath IR (issue 18 §1, docs/DATAPATH.md): `rayunits dp emit <design>
  // --out rtl` wrote rtl/ru_dp_<design>.sv/.f (ctest DpRtl.CheckedInModulesAreTheEmitterOutput). The
  // same dataflow as the hand-written units, so the same level chain and maximum Stages; one
  // W-bit port per graph input and output (a Boolean output is 1 bit); the golden model is the
  // graph itself (models::dp_golden); the inputs are the ray-triangle workload (17 fields in the
  // graphs' input order).
  for (const bool robust : {true, false}) {
    const std::string design = robust ? "ray_tri_robust" : "ray_tri_mt";
    UnitSpec s = dp_unit(design,
                         std::string(robust ? "Kensler Fig. 3.6" : "Moller-Trumbore") +
                             " emitted from the datapath IR (rayunits dp emit " + design + ")",
                         std::make_shared<const dp::Graph>(dp::find_design(design).make()));
    s.tests = {robust ? "e5m10:smax+1" : "e5m10:smax+1:selftest"};  // e5m10: the build is ~1/3 of e8m23's
    s.long_tests = {"e8m23:smax+1", "e8m23:s0", "e7m16:s20:rtz", "e5m10-ftz:s2"};
    u.push_back(std::move(s));
  }
  // Datapath designs given at run time (a search's front, docs/DATAPATH.md): every <stem>.dp graph
  // file in $RU_DP_DESIGNS is the unit dp_<stem>, RTL ru_dp_<stem>.sv/.f (`rayunits dp emit`), in
  // the RTL directory the caller names (`rayunits rtl --rtl DIR`, `synth --rtl DIR`).
  for (auto& s : runtime_dp_units()) u.push_back(std::move(s));
  // Kensler's gradient noise unit (fixed point, no floating-point format): an example of a unit
  // with its own parameters (--param FracBits=8 ...). Two datapaths, same ports and parameters:
  // `noise` (ru_noise, Kensler's: every product exact, then floored; the baseline) and
  // `noise_trunc` (ru_noise_trunc, issue 15: the kernel weight from a table, truncated dot
  // products, narrower widths; FracBits 5..12; docs/NOISE.md).
  for (const bool trunc : {false, true}) {
    UnitSpec s;
    s.name = trunc ? "noise_trunc" : "noise";
    s.top = trunc ? "ru_noise_trunc" : "ru_noise";
    s.summary = trunc ? "fixed-point gradient noise, truncated datapath (smaller; docs/NOISE.md), one result per clock"
                      : "fixed-point gradient noise (Kensler sec. 4.9-4.13), one result per clock";
    s.filelist = s.top + ".f";
    s.uses_format = false;
    s.params = {{"Stages", [](const UnitConfig& c) { return static_cast<long long>(c.stages); }}};
    s.extra_params = {{"FracBits", 8, trunc ? 5 : 4, trunc ? 12 : 16, "fraction bits of the coordinates"},
                      {"IntBits", 8, 1, 24, "integer bits of the coordinates (incl. sign)"},
                      {"OutW", 10, 2, 38, "output width"}};
    s.ports = control_ports();
    for (PortSpec p : {in("x_i", "FracBits+IntBits", "x, signed fixed point"),
                       in("y_i", "FracBits+IntBits", "y, signed fixed point"),
                       in("z_i", "FracBits+IntBits", "z, signed fixed point"), out_valid(),
                       out("value_o", "OutW", "noise value, signed")})
      s.ports.push_back(std::move(p));
    s.max_stages_expr = "7";  // 8 segments (rtl/ru_noise.sv, rtl/ru_noise_trunc.sv)
    s.golden = trunc ? models::noise_trunc_golden : models::noise_golden;
    s.random_inputs = models::noise_inputs;
    if (trunc) {
      s.tests = {"s4:selftest", "s2:FracBits=5:IntBits=3:OutW=12", "smax+1:FracBits=12:IntBits=24:OutW=30"};
      s.long_tests = {"s0:selftest", "s1", "s2", "s3", "s5", "s6", "s7", "s1:FracBits=5:IntBits=1:OutW=2",
                      "s3:FracBits=12:IntBits=10:OutW=20"};
    } else {
      s.tests = {"s0:selftest", "s4:selftest", "s2:FracBits=5:IntBits=3:OutW=12", "smax+1:FracBits=16:IntBits=24:OutW=38"};
      s.long_tests = {"s1", "s2", "s3", "s5", "s6", "s7", "s9:selftest", "s1:FracBits=4:IntBits=1:OutW=2",
                      "s3:FracBits=12:IntBits=10:OutW=20"};
    }
    const std::string name = s.name;
    s.check = [name](const UnitConfig& c) {
      const UnitSpec& n = find_unit(name);
      const long long fb = param_value(n, c, "FracBits"), ow = param_value(n, c, "OutW");
      if (ow > 2 * fb + 6)
        throw SynthError(name + ": OutW must be <= 2*FracBits+6 = " + std::to_string(2 * fb + 6) + ", got " +
                         std::to_string(ow));
    };
    u.push_back(std::move(s));
  }
  {
    // The procedural texture unit (issue 15 §2, docs/NOISE.md "The procedural texture unit"):
    // octave sums and material transfer functions around Units noise units; a handshake
    // (in_ready_o: one request per ceil(n / Units) cycles), latency ceil(n / Units) + Stages + RootStages.
    UnitSpec s;
    s.name = "texture";
    s.top = "ru_texture";
    s.summary = "procedural texture: fBm / turbulence octave sums, granite, marble, wood, around 1-8 noise units";
    s.filelist = "ru_texture.f";
    s.uses_format = false;
    s.handshake = true;
    s.params = {{"Stages", [](const UnitConfig& c) { return static_cast<long long>(c.stages); }}};
    s.extra_params = {{"FracBits", 8, 5, 16, "fraction bits of the noise units' coordinates (5..12 with Trunc = 1)"},
                      {"IntBits", 8, 1, 24, "integer bits of the coordinates (incl. sign)"},
                      {"OutW", 10, 2, 38, "the noise units' output width"},
                      {"Trunc", 1, 0, 1, "1: ru_noise_trunc inside, 0: ru_noise"},
                      {"Octaves", 8, 1, 8, "most octaves per request"},
                      {"Units", 4, 1, 8, "noise units inside (1, 2, 4 or 8)"},
                      {"LacShift", 1, 1, 2, "lacunarity 2^LacShift"},
                      {"GainShift", 1, 1, 2, "gain 2^-GainShift"},
                      {"OutF", 12, 4, 20, "output fraction bits"},
                      {"RootStages", 2, 0, 8, "extra cycles of the square root (wood); latency K + Stages + RootStages"}};
    s.ports = control_ports();
    s.ports.push_back(port("in_ready_o", PortDir::Out, PortRole::Ready, "1",
                           "the unit accepts a request this cycle (in_valid_i && in_ready_o)"));
    const char* w = "IntBits+FracBits+LacShift*(Octaves-1)";
    PortSpec mode = in("mode_i", "3", "0 fbm, 1 turbulence, 2 granite, 3 marble, 4 wood (5-7 as fbm)", FieldKind::Enum);
    mode.enum_names = {"fbm", "turbulence", "granite", "marble", "wood", "fbm5", "fbm6", "fbm7"};
    for (PortSpec p : {in("x_i", w, "x, signed fixed point (FracBits + LacShift (Octaves-1) fraction bits)"),
                       in("y_i", w, "y, signed fixed point"), in("z_i", w, "z, signed fixed point"), mode,
                       in("oct_i", "4", "octaves of this request (clamped to 1..Octaves)"),
                       port("out_valid_o", PortDir::Out, PortRole::Valid, "1",
                            "result valid (in request order, ceil(n / Units) + Stages + RootStages cycles after acceptance)"),
                       out("value_o", "OutF+2", "texture value, signed, value / 2^OutF")})
      s.ports.push_back(std::move(p));
    s.max_stages_expr = "7";  // the noise units' (rtl/ru_noise_trunc.sv)
    s.min_latency = [](const UnitConfig& c) {  // one group + Stages + RootStages (rtl/ru_texture.sv)
      return 1 + c.stages + static_cast<int>(param_value(find_unit("texture"), c, "RootStages"));
    };
    s.golden = models::texture_golden;
    s.random_inputs = models::texture_inputs;
    s.check = [](const UnitConfig& c) {
      const UnitSpec& t = find_unit("texture");
      const long long units = param_value(t, c, "Units");
      if (units != 1 && units != 2 && units != 4 && units != 8)
        throw SynthError("texture: Units must be 1, 2, 4 or 8, got " + std::to_string(units));
      try {
        models::texture_config(c);
      } catch (const std::invalid_argument& e) {
        throw SynthError(e.what());
      }
    };
    // default Octaves 8, Units 4: the renderer's and the chip's texture unit (render::texture_config)
    s.tests = {"s4:Units=1:Octaves=4:selftest", "s1:Units=2:Octaves=3:GainShift=2:OutF=16:RootStages=0"};
    s.long_tests = {"s4:selftest", "s0:Units=1:Octaves=4:selftest", "s7:Units=1:Octaves=4", "smax+1", "s2:Octaves=4",
                    "s3:Units=8:FracBits=6:OutF=8", "s4:Units=1:Octaves=4:Trunc=0",
                    "s2:Units=1:Octaves=3:LacShift=2:FracBits=10:OutF=16", "s1:Units=1:Octaves=1:OutF=20:RootStages=8",
                    "s5:Units=2:Octaves=5:FracBits=12:IntBits=4:OutW=20"};
    u.push_back(std::move(s));
  }
  // The thread processors' integer units (issue 16: the TRaX chip's int and branch instruction
  // classes on units with RTL; golden models units/int_units.hpp). No floating-point format.
  {
    UnitSpec s;
    s.name = "int_alu";
    s.top = "ru_int_alu";
    s.summary = "integer ALU: add, sub, and, or, xor, shifts, set-less-than, min/max (IntW bits)";
    s.filelist = "ru_int_alu.f";
    s.uses_format = false;
    s.params = {{"Stages", [](const UnitConfig& c) { return static_cast<long long>(c.stages); }}};
    s.extra_params = {{"IntW", 32, 2, 64, "word width (two's complement)"}};
    s.ports = control_ports();
    for (PortSpec p : {in("a_i", "IntW", "operand a"), in("b_i", "IntW", "operand b (shifts: the amount, low clog2(IntW) bits)"),
                       enum_in("op_i", "4", "0 add, 1 sub, 2 and, 3 or, 4 xor, 5 sll, 6 srl, 7 sra, 8 slt, 9 sltu, 10 min, "
                                            "11 max, 12-15 mov (a)",
                               {"add", "sub", "and", "or", "xor", "sll", "srl", "sra", "slt", "sltu", "min", "max", "mov",
                                "mov13", "mov14", "mov15"}),
                       out_valid(), out("y_o", "IntW", "result")})
      s.ports.push_back(std::move(p));
    s.max_stages_expr = "1";
    s.golden = models::int_alu_golden;
    s.random_inputs = models::int_alu_inputs;
    s.tests = {"s1:selftest", "s0:IntW=4:exhaustive", "smax+1:IntW=64", "s1:IntW=5:exhaustive"};
    s.long_tests = {"s0", "s2", "s1:IntW=8:exhaustive", "s0:IntW=2:exhaustive", "s1:IntW=16", "s3:IntW=33"};
    u.push_back(std::move(s));
  }
  {
    UnitSpec s;
    s.name = "branch";
    s.top = "ru_branch";
    s.summary = "branch unit: beq/bne/blt/bge/bltu/bgeu/jump on IntW-bit registers, next PcW-bit pc";
    s.filelist = "ru_branch.f";
    s.uses_format = false;
    s.params = {{"Stages", [](const UnitConfig& c) { return static_cast<long long>(c.stages); }}};
    s.extra_params = {{"IntW", 32, 2, 64, "register width (two's complement)"},
                      {"PcW", 32, 2, 64, "program counter width (in instructions)"}};
    s.ports = control_ports();
    for (PortSpec p : {in("a_i", "IntW", "register a"), in("b_i", "IntW", "register b"),
                       in("pc_i", "PcW", "program counter of the branch"),
                       in("off_i", "PcW", "branch offset (two's complement, in instructions)"),
                       enum_in("op_i", "3", "0 beq, 1 bne, 2 blt, 3 bge, 4 bltu, 5 bgeu, 6-7 jump",
                               {"beq", "bne", "blt", "bge", "bltu", "bgeu", "jump", "jump7"}),
                       out_valid(), out("taken_o", "1", "the branch is taken"),
                       out("y_o", "PcW", "next pc: taken ? pc + off : pc + 1")})
      s.ports.push_back(std::move(p));
    s.max_stages_expr = "1";
    s.golden = models::branch_golden;
    s.random_inputs = models::branch_inputs;
    s.tests = {"s1:selftest", "s0:IntW=3:PcW=3:exhaustive", "smax+1:IntW=64:PcW=64"};
    s.long_tests = {"s0", "s2", "s1:IntW=4:PcW=4:exhaustive", "s1:IntW=2:PcW=5:exhaustive", "s0:IntW=16:PcW=20"};
    u.push_back(std::move(s));
  }
  return u;
}

// Recursive-descent evaluator of the registry's integer expressions.
class ExprParser {
 public:
  ExprParser(const std::string& e, const UnitSpec& u, const UnitConfig& c) : e_(e), u_(u), c_(c) {}
  long long run() {
    long long v = sum();
    skip();
    if (i_ != e_.size()) fail("unexpected '" + e_.substr(i_, 1) + "'");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw SynthError(u_.name + ": bad registry expression '" + e_ + "': " + why);
  }
  void skip() {
    while (i_ < e_.size() && e_[i_] == ' ') ++i_;
  }
  bool eat(char ch) {
    skip();
    if (i_ < e_.size() && e_[i_] == ch) return ++i_, true;
    return false;
  }
  long long sum() {
    long long v = product();
    for (;;) {
      if (eat('+')) v += product();
      else if (eat('-')) v -= product();
      else return v;
    }
  }
  long long product() {
    long long v = atom();
    for (;;) {
      if (eat('*')) v *= atom();
      else if (eat('/')) {
        const long long d = atom();
        if (d == 0) fail("division by zero");
        v /= d;
      } else return v;
    }
  }
  long long atom() {
    skip();
    if (eat('(')) {
      long long v = sum();
      if (!eat(')')) fail("missing ')'");
      return v;
    }
    if (eat('-')) return -atom();
    const size_t b = i_;
    if (i_ < e_.size() && std::isdigit(static_cast<unsigned char>(e_[i_]))) {
      while (i_ < e_.size() && std::isdigit(static_cast<unsigned char>(e_[i_]))) ++i_;
      return std::stoll(e_.substr(b, i_ - b));
    }
    while (i_ < e_.size() && (std::isalnum(static_cast<unsigned char>(e_[i_])) || e_[i_] == '_')) ++i_;
    if (b == i_) fail(i_ < e_.size() ? "unexpected '" + e_.substr(i_, 1) + "'" : "unexpected end");
    const std::string n = e_.substr(b, i_ - b);
    if (n == "max") {  // max(x, y)
      if (!eat('(')) fail("max needs '('");
      const long long x = sum();
      if (!eat(',')) fail("max needs two arguments");
      const long long y = sum();
      if (!eat(')')) fail("missing ')'");
      return std::max(x, y);
    }
    return name(n);
  }
  long long name(const std::string& n) const {
    if (u_.uses_format) {
      const auto& f = c_.fmt;
      if (n == "E") return f.exp_bits;
      if (n == "M") return f.frac_bits;
      if (n == "W") return 1 + f.exp_bits + f.frac_bits;
      if (n == "L") return csa_levels(f.frac_bits + 1);
    }
    for (const auto& p : u_.extra_params)
      if (p.name == n) return param_value(u_, c_, n);
    fail("unknown name '" + n + "' (E, M, W, L for units with a format, or a parameter of the unit)");
  }
  const std::string& e_;
  const UnitSpec& u_;
  const UnitConfig& c_;
  size_t i_ = 0;
};

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

int csa_levels(int n) {
  int l = 0;
  while (n > 2) {
    n = 2 * (n / 3) + n % 3;
    ++l;
  }
  return l;
}

long long eval_expr(const std::string& expr, const UnitSpec& u, const UnitConfig& c) {
  return ExprParser(expr, u, c).run();
}

int UnitSpec::max_stages(const UnitConfig& c) const { return static_cast<int>(eval_expr(max_stages_expr, *this, c)); }

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
  if (!c.seg_weights.empty()) n += "_dly";  // registers placed by measured delays (SegW)
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
  if (!c.seg_weights.empty()) s += " --placement delay";
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
  } else if (!u.filelist.empty() && u.sources.empty()) {
    std::string msg = "unit " + u.name + ": file list " + fl.string() + " not found";
    if (!u.design_file.empty())  // a run-time design: its module is not part of the project's RTL
      msg += " (a run-time design's module: write it with `rayunits dp emit " + u.design_file + " --module " +
             u.top + " --out DIR` into a copy of the project's rtl/ and pass --rtl DIR)";
    throw SynthError(msg);
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
  for (const auto& p : u.ports) {
    const long long w = eval_expr(p.width, u, c);
    if (w < 1 || w > (1 << 20))
      throw SynthError(u.name + ": port " + p.name + " width '" + p.width + "' = " + std::to_string(w) +
                       " (must be 1..2^20)");
    v.push_back({p.name, p.dir, p.role, static_cast<int>(w), p.doc});
  }
  return v;
}

std::vector<Field> fields_for(const UnitSpec& u, const UnitConfig& c, PortDir dir) {
  std::vector<Field> v;
  for (const auto& p : u.ports) {
    if (p.role != PortRole::Data || p.dir != dir) continue;
    const long long w = eval_expr(p.width, u, c);
    if (p.elems < 1 || w % p.elems != 0 || w / p.elems > 64 || w / p.elems < 1)
      throw SynthError(u.name + ": port " + p.name + " (" + std::to_string(w) + " bits) does not split into " +
                       std::to_string(p.elems) + " elements of 1..64 bits");
    if (!p.elem_names.empty() && p.elem_names.size() != static_cast<size_t>(p.elems))
      throw SynthError(u.name + ": port " + p.name + " has " + std::to_string(p.elems) + " elements but " +
                       std::to_string(p.elem_names.size()) + " element names");
    for (int i = 0; i < p.elems; ++i) {
      Field f;
      f.name = !p.elem_names.empty() ? p.elem_names[i] : p.elems == 1 ? p.name : p.name + "[" + std::to_string(i) + "]";
      f.port = p.name;
      f.elem = i;
      f.bits = static_cast<int>(w / p.elems);
      f.kind = p.kind;
      f.enum_names = p.enum_names;
      v.push_back(std::move(f));
    }
  }
  return v;
}

UnitConfig config_from_params(const UnitSpec& u, const std::map<std::string, long long>& params) {
  UnitConfig c;
  auto take = [&](const char* n, long long def) {
    auto it = params.find(n);
    return it == params.end() ? def : it->second;
  };
  for (const auto& [k, v] : params) {
    bool known = k == "Stages" || (u.uses_format && (k == "ExpW" || k == "FracW" || k == "Subnormals" || k == "Round"));
    for (const auto& e : u.extra_params) known = known || e.name == k;
    if (!known) throw SynthError(u.name + ": unknown RTL parameter '" + k + "'");
    (void)v;
  }
  if (u.uses_format) {
    c.fmt.exp_bits = static_cast<int>(take("ExpW", -1));
    c.fmt.frac_bits = static_cast<int>(take("FracW", -1));
    c.fmt.subnormals = take("Subnormals", 1) != 0;
    const long long r = take("Round", 0);
    if (r < 0 || r > 3) throw SynthError(u.name + ": Round must be 0..3, got " + std::to_string(r));
    c.fmt.round = static_cast<num::Round>(r);
  }
  c.stages = static_cast<int>(take("Stages", 0));
  for (const auto& e : u.extra_params)
    if (params.count(e.name)) c.params[e.name] = params.at(e.name);
  // Every check but the Stages maximum: the testbench runs units one past their maximum useful
  // Stages (the RTL puts the extra register at the output).
  UnitConfig probe = c;
  probe.stages = u.min_stages;
  check_config(u, probe);
  if (c.stages < u.min_stages)
    throw SynthError(u.name + ": Stages must be >= " + std::to_string(u.min_stages) + ", got " + std::to_string(c.stages));
  return c;
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
  if (u.handshake)
    o << "// latency " << u.latency(c) << " cycle" << (u.latency(c) == 1 ? "" : "s")
      << " or more (results in order), accepts an operation in each cycle with in_ready_o high.\n";
  else
    o << "// latency " << c.stages << " cycle" << (c.stages == 1 ? "" : "s") << ", one operation per cycle.\n";
  o
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
    o << "    ." << params[i].first << "(" << params[i].second << ")"
      << (i + 1 < params.size() || !c.seg_weights.empty() ? "," : "") << "\n";
  if (!c.seg_weights.empty()) {
    // Packed 8-bit weights, segment 0 in the low bits (ru_pipe_pkg::pick_w); the rest zero.
    if (!u.seg_weights_param) throw SynthError(u.name + " has no SegW parameter");
    o << "    // segment weights (segment 0 first):";
    for (int w : c.seg_weights) o << " " << w;
    o << "\n";
    o << "    .SegW(" << 8 * c.seg_weights.size() << "'h";
    for (size_t i = c.seg_weights.size(); i-- > 0;) {
      if (c.seg_weights[i] < 1 || c.seg_weights[i] > 255)
        throw SynthError("segment weight " + std::to_string(c.seg_weights[i]) + " outside 1..255");
      char b[3];
      std::snprintf(b, sizeof b, "%02x", c.seg_weights[i]);
      o << b;
    }
    o << ")\n";
  }
  o << "  ) u_unit (\n";
  for (size_t i = 0; i < ports.size(); ++i) {
    const auto& p = ports[i];
    o << "    ." << p.name << std::string(w - p.name.size(), ' ') << " (" << p.name << ")"
      << (i + 1 < ports.size() ? "," : "") << "\n";
  }
  o << "  );\n\nendmodule\n";
  return o.str();
}

std::string registry_json(const std::vector<UnitSpec>& us) {
  nlohmann::ordered_json j;
  j["about"] = "The rayunits unit registry (model/src/synth/units.cpp), written by `rayunits registry --json`; "
               "read by CMake (tb/cmake/RuTb.cmake). Do not edit: regenerate. Expressions: E=ExpW, M=FracW, "
               "W=1+E+M, L=csa_levels(M+1), and the unit's parameters by name.";
  nlohmann::ordered_json arr = nlohmann::ordered_json::array();
  for (const auto& u : us) {
    nlohmann::ordered_json e;
    e["name"] = u.name;
    e["top"] = u.top;
    e["filelist"] = u.filelist;
    e["uses_format"] = u.uses_format;
    e["min_stages"] = u.min_stages;
    e["max_stages"] = u.max_stages_expr;
    nlohmann::ordered_json params = nlohmann::ordered_json::array();
    for (const auto& p : u.params) params.push_back(p.name);
    e["rtl_params"] = params;
    nlohmann::ordered_json extra = nlohmann::ordered_json::array();
    for (const auto& p : u.extra_params)
      extra.push_back({{"name", p.name}, {"default", p.def}, {"min", p.lo}, {"max", p.hi}, {"doc", p.doc}});
    e["params"] = extra;
    nlohmann::ordered_json ports = nlohmann::ordered_json::array();
    static const char* roles[] = {"clock", "reset", "valid", "data", "ready"};
    static const char* kinds[] = {"bits", "float", "flags", "enum"};
    for (const auto& p : u.ports) {
      nlohmann::ordered_json q = {{"name", p.name},
                                  {"dir", p.dir == PortDir::In ? "in" : "out"},
                                  {"role", roles[static_cast<int>(p.role)]},
                                  {"width", p.width},
                                  {"doc", p.doc}};
      if (p.role == PortRole::Data) {
        q["kind"] = kinds[static_cast<int>(p.kind)];
        if (p.elems != 1) q["elems"] = p.elems;
        if (!p.elem_names.empty()) q["elem_names"] = p.elem_names;
        if (!p.enum_names.empty()) q["enum_names"] = p.enum_names;
      }
      ports.push_back(q);
    }
    e["ports"] = ports;
    e["large_model"] = u.large_model;
    e["tests"] = u.tests;
    e["long_tests"] = u.long_tests;
    arr.push_back(e);
  }
  j["units"] = arr;
  return j.dump(2) + "\n";
}

namespace {

// The value of `localparam <name>` of the top module in Verilator's XML netlist, -1 if absent.
// Verilator 5.006 writes each elaborated localparam as
//   <var ... name="MaxUsefulStages" ... localparam="true"> <const ... name="32'h5" .../>
// inside the <module ... topModule="1"> element (the caller passes only that element).
long long xml_localparam(const std::string& xml, const std::string& name) {
  const std::regex re("<var [^>]*name=\"" + name + "\"[^>]*localparam=\"true\"[^>]*>\\s*<const [^>]*name=\"([0-9]*)&apos;([sh]?)([hdbo]?)([0-9a-fA-F_]+)\"");
  std::smatch m;
  if (!std::regex_search(xml, m, re)) return -1;
  std::string digits = m[4].str();
  digits.erase(std::remove(digits.begin(), digits.end(), '_'), digits.end());
  const std::string base = m[2].str() == "h" ? "h" : m[3].str();
  const int radix = base == "h" ? 16 : base == "b" ? 2 : base == "o" ? 8 : 10;
  return std::stoll(digits, nullptr, radix);
}

std::string cfg_label(const UnitSpec& u, const UnitConfig& c) {
  std::string s = u.name + (u.uses_format ? " " + fmt_tag(c.fmt) : std::string());
  for (const auto& p : u.extra_params) {
    const long long v = param_value(u, c, p.name);
    if (v != p.def) s += " " + p.name + "=" + std::to_string(v);
  }
  return s;
}

}  // namespace

RtlStageFacts rtl_stage_facts(const UnitSpec& u, const UnitConfig& c, const std::string& rtl_dir) {
  const char* env = std::getenv("RU_VERILATOR");
  const std::string verilator = find_program(env && *env ? env : "verilator");
  if (verilator.empty())
    throw SynthError("verilator not found (install it: scripts/install-deps.sh; or set RU_VERILATOR)");
  const Sources src = resolve_sources(u, rtl_dir);
  TempDir tmp("ru-rtlfacts-");
  std::vector<std::string> argv = {verilator, "--xml-only", "-Wno-fatal", "-Wno-lint", "-Wno-style",
                                   "--top-module", u.top, "--xml-output", tmp.path() + "/top.xml"};
  std::set<std::string> dirs;
  for (const auto& f : src.files) dirs.insert(fs::path(f).parent_path().string());
  for (const auto& d : dirs) argv.push_back("-I" + d);
  for (const auto& [k, v] : params_for(u, c)) argv.push_back("-G" + k + "=" + std::to_string(v));
  for (const auto& f : src.files) argv.push_back(f);
  const std::string log = tmp.path() + "/verilator.log";
  const ProcResult r = run_process(argv, tmp.path(), log, 600);
  if (r.exit_code != 0) {
    std::string text = read_file(log);
    if (text.size() > 600) text = text.substr(0, 600) + "...";
    for (char& ch : text)
      if (ch == '\n') ch = ' ';
    throw SynthError(cfg_label(u, c) + ": verilator --xml-only failed: " + text);
  }
  std::string xml = read_file(tmp.path() + "/top.xml");
  // Only the top module's own localparams: submodules (the FP instances of a composite unit)
  // declare the same names.
  const size_t top = xml.find("topModule=\"1\"");
  if (top == std::string::npos) throw SynthError(cfg_label(u, c) + ": no top module in Verilator's XML output");
  xml = xml.substr(top, xml.find("</module>", top) - top);
  RtlStageFacts f;
  f.max_useful_stages = static_cast<int>(xml_localparam(xml, "MaxUsefulStages"));
  f.out_regs = static_cast<int>(xml_localparam(xml, "OutRegs"));
  return f;
}

std::vector<std::string> check_against_rtl(const UnitSpec& u, const std::vector<UnitConfig>& configs,
                                           const std::string& rtl_dir) {
  std::vector<std::string> bad;
  for (UnitConfig c : configs) {
    c.stages = 0;
    const int max = u.max_stages(c);
    const std::string at = cfg_label(u, c);
    c.stages = max;
    const RtlStageFacts a = rtl_stage_facts(u, c, rtl_dir);
    if (a.max_useful_stages < 0 || a.out_regs < 0) {
      bad.push_back(at + ": the RTL top " + u.top + " has no localparam MaxUsefulStages / OutRegs");
      continue;
    }
    if (a.max_useful_stages != max)
      bad.push_back(at + ": registry max Stages " + std::to_string(max) + ", RTL MaxUsefulStages " +
                    std::to_string(a.max_useful_stages));
    if (a.out_regs != 0)
      bad.push_back(at + ": at Stages " + std::to_string(max) + " the RTL places " + std::to_string(a.out_regs) +
                    " register(s) at the output (expected 0: every register at an internal cut)");
    c.stages = max + 1;
    const RtlStageFacts b = rtl_stage_facts(u, c, rtl_dir);
    if (b.out_regs != 1)
      bad.push_back(at + ": at Stages " + std::to_string(max + 1) + " the RTL places " + std::to_string(b.out_regs) +
                    " register(s) at the output (expected exactly the one extra)");
  }
  return bad;
}

}  // namespace ru::synth
