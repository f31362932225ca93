// Tests of the synthesis flow, the generator and the `synth` / `gen` / `synth-sweep` commands.
// Fast suite: small formats, generic gates, one tiny nextpnr run. Long_*: bigger designs.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "rayunits/dp/formulas.hpp"
#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/gen.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/synth/sweep.hpp"
#include "rayunits/synth/units.hpp"

#include "../common/files.hpp"

namespace {

namespace fs = std::filesystem;
using namespace ru::synth;
using nlohmann::json;
using ru::num::Format;

std::string rayunits_exe() {
#ifdef RU_RAYUNITS_EXE
  return RU_RAYUNITS_EXE;
#else
  return std::string(RU_BINARY_DIR) + "/model/cli/rayunits";
#endif
}

using ru::test::slurp;

void spit(const std::string& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

struct CliRun {
  int code;
  std::string out, err;
};

// Runs a shell command line with stdout/stderr captured separately.
CliRun sh(const std::string& cmd) {
  TempDir t("ru-test-sh-");
  const std::string o = t.path() + "/out", e = t.path() + "/err";
  const int st = std::system((cmd + " >" + o + " 2>" + e).c_str());
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, slurp(o), slurp(e)};
}

std::string q(const std::string& s) { return "'" + s + "'"; }

CliRun cli(const std::string& args) { return sh(q(rayunits_exe()) + " " + args); }

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n + (!s.empty() && s.back() != '\n');
}

FlowOptions generic_only() {
  FlowOptions o;
  o.ice40 = o.xilinx = o.pnr = false;
  return o;
}

UnitConfig cfg(const std::string& fmt, int stages, ru::num::Round r = ru::num::Round::RNE) {
  UnitConfig c;
  c.fmt = Format::parse(fmt);
  c.fmt.round = r;
  c.stages = stages;
  return c;
}

// ---------------------------------------------------------------------------------------------
// Registry

TEST(SynthRegistry, UnknownUnitNamesTheKnownOnes) {
  try {
    find_unit("fp_foo");
    FAIL() << "no error";
  } catch (const SynthError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("fp_foo"), std::string::npos) << m;
    for (const auto& u : units()) EXPECT_NE(m.find(u.name), std::string::npos) << m;
  }
}

TEST(SynthRegistry, WrapperNamesDescribeTheConfiguration) {
  const UnitSpec& mul = find_unit("fp_mul");
  EXPECT_EQ(wrapper_name(mul, cfg("e7m16", 3)), "ru_fp_mul_e7m16_s3");
  EXPECT_EQ(wrapper_name(mul, cfg("e7m16", 3, ru::num::Round::RTZ)), "ru_fp_mul_e7m16_s3_rtz");
  EXPECT_EQ(wrapper_name(mul, cfg("e5m10-ftz", 0)), "ru_fp_mul_e5m10_s0_ftz");
  EXPECT_EQ(wrapper_name(mul, cfg("e5m10-ftz", 1, ru::num::Round::RUP)), "ru_fp_mul_e5m10_s1_rup_ftz");
  const UnitSpec& noise = find_unit("noise");
  UnitConfig n;
  n.stages = 4;
  EXPECT_EQ(wrapper_name(noise, n), "ru_noise_s4");
  n.params["FracBits"] = 10;
  EXPECT_EQ(wrapper_name(noise, n), "ru_noise_s4_FracBits10");
  n.params["FracBits"] = 8;  // the default: not part of the name
  EXPECT_EQ(wrapper_name(noise, n), "ru_noise_s4");
}

TEST(SynthRegistry, PortWidthsFollowTheFormat) {
  for (const char* f : {"e4m3", "e5m10", "e8m23", "e11m52"}) {
    const UnitConfig c = cfg(f, 0);
    const int w = c.fmt.width();
    for (const auto& u : units()) {
      if (!u.uses_format) continue;
      std::map<std::string, int> width;
      for (const auto& p : ports_for(u, c)) width[p.name] = p.width;
      SCOPED_TRACE(u.name + " " + f);
      for (const char* k : {"clk_i", "rst_ni", "in_valid_i", "out_valid_o"}) EXPECT_EQ(width[k], 1) << k;
      if (u.name.rfind("ray_", 0) == 0) {  // issue 4's interfaces (rtl/ru_ray_*.sv headers)
        std::map<std::string, int> want =
            u.name == "ray_box"
                ? std::map<std::string, int>{{"org_i", 3 * w}, {"rdir_i", 3 * w}, {"tmin_i", w}, {"tmax_i", w},
                                             {"bmin_i", 3 * w}, {"bmax_i", 3 * w}, {"hit_o", 1}, {"t_enter_o", w},
                                             {"t_exit_o", w}}
                : std::map<std::string, int>{{"a_i", 3 * w},  {"d_i", 3 * w},  {"p0_i", 3 * w}, {"p1_i", 3 * w},
                                             {"p2_i", 3 * w}, {"tmin_i", w},   {"tmax_i", w},   {"hit_o", 1},
                                             {"why_o", 3},    {"t_o", w},      {"beta_o", w},   {"gamma_o", w},
                                             {"vol_o", 5 * w}};
        if (u.name == "ray_tri_exact") {  // issue 14: no vol_o; the handshake and slow_o
          want.erase("vol_o");
          want["in_ready_o"] = 1;
          want["slow_o"] = 1;
        }
        EXPECT_EQ(width.size(), want.size() + 4);
        for (const auto& [name, bits] : want) EXPECT_EQ(width[name], bits) << name;
        continue;
      }
      if (u.name.rfind("dp_", 0) == 0) {  // emitted from the IR: a W-bit port per graph input/output
        const ru::dp::Graph g = ru::dp::find_design(u.name.substr(3)).make();
        EXPECT_EQ(width.size(), g.inputs().size() + g.outputs().size() + 4);
        for (const auto& in : g.inputs()) EXPECT_EQ(width[in + "_i"], w) << in;
        for (const auto& [name, n] : g.outputs())
          EXPECT_EQ(width[name + "_o"], ru::dp::op_is_bool(g.nodes()[n].op) ? 1 : w) << name;
        continue;
      }
      if (u.name == "fp_cvt") {  // rtl/ru_fp_cvt.sv: a_i max(W, 1+InExpW+InFracW, IntW), y_o max(W, IntW)
        EXPECT_EQ(width.size(), 8u);
        EXPECT_EQ(width["op_i"], 2);
        EXPECT_EQ(width["a_i"], std::max(w, 32));  // defaults: G = e8m23, IntW = 32
        EXPECT_EQ(width["y_o"], std::max(w, 32));
        EXPECT_EQ(width["flags_o"], 5);
        UnitConfig c2 = c;
        c2.params = {{"InExpW", 5}, {"InFracW", 10}, {"IntW", 12}};
        std::map<std::string, int> w2;
        for (const auto& p : ports_for(u, c2)) w2[p.name] = p.width;
        EXPECT_EQ(w2["a_i"], std::max(w, 16));
        EXPECT_EQ(w2["y_o"], std::max(w, 12));
        continue;
      }
      const int op_w = u.name == "fp_add" ? 1 : u.name == "fp_fma" ? 2 : u.name == "fp_cmp" ? 3 : 0;
      EXPECT_EQ(width.count("op_i") ? width["op_i"] : 0, op_w);
      const int k = (u.name == "fp_dot3" || u.name == "fp_dot3_fused") ? 3 : 1;
      EXPECT_EQ(width["a_i"], k * w);
      if (u.name == "fp_sqrt")  // one operand
        EXPECT_EQ(width.count("b_i"), 0u);
      else
        EXPECT_EQ(width["b_i"], k * w);
      if (u.name == "fp_fma")  // three operands
        EXPECT_EQ(width["c_i"], w);
      else
        EXPECT_EQ(width.count("c_i"), 0u);
      EXPECT_EQ(width["y_o"], w);
      EXPECT_EQ(width["flags_o"], 5);
    }
  }
}

TEST(SynthRegistry, RejectsBadConfigurations) {
  const UnitSpec& mul = find_unit("fp_mul");
  EXPECT_THROW(check_config(mul, cfg("e5m10", mul.max_stages(cfg("e5m10", 0)) + 1)), SynthError);
  EXPECT_NO_THROW(check_config(mul, cfg("e5m10", mul.max_stages(cfg("e5m10", 0)))));
  UnitConfig bad = cfg("e5m10", 1);
  bad.fmt.exp_bits = 1;
  EXPECT_THROW(check_config(mul, bad), ru::num::FormatError);
  UnitConfig p = cfg("e5m10", 1);
  p.params["FracBits"] = 8;  // fp_mul takes no extra parameters
  EXPECT_THROW(check_config(mul, p), SynthError);
  const UnitSpec& noise = find_unit("noise");
  UnitConfig n;
  n.stages = 2;
  n.params["FracBits"] = 3;  // below the range
  EXPECT_THROW(check_config(noise, n), SynthError);
  n.params["FracBits"] = 4;
  n.params["OutW"] = 15;  // > 2*FracBits+6
  EXPECT_THROW(check_config(noise, n), SynthError);
}

// The maximum useful Stages: tests/synth/test_registry.cpp (against the RTL and rtl/README.md).

TEST(SynthRegistry, WrapperFixesParametersDeterministically) {
  const UnitSpec& add = find_unit("fp_add");
  UnitConfig c = cfg("e7m16-ftz", 3, ru::num::Round::RDN);
  const std::string v = wrapper_verilog(add, c);
  EXPECT_EQ(v, wrapper_verilog(add, c));
  EXPECT_NE(v.find("module ru_fp_add_e7m16_s3_rdn_ftz ("), std::string::npos) << v;
  for (const char* s :
       {".ExpW(7)", ".FracW(16)", ".Stages(3)", ".Subnormals(0)", ".Round(2)", "input  logic [23:0] a_i",
        "input  logic op_i", "output logic [4:0] flags_o", "ru_fp_add #("})
    EXPECT_NE(v.find(s), std::string::npos) << s << "\n" << v;
}

TEST(SynthRegistry, FileListsAndIncludesAreFollowed) {
  TempDir t("ru-test-rtl-");
  const std::string d = t.path();
  spit(d + "/ru_fp_mul.f", "// sources\nru_a.sv\n\n  ru_b.sv   # second\n");
  spit(d + "/ru_a.sv", "module a; endmodule\n");
  spit(d + "/ru_b.sv", "module b;\n  `include \"ru_b.svh\"\nendmodule\n");
  spit(d + "/ru_b.svh", "`include \"ru_c.svh\"\n");
  spit(d + "/ru_c.svh", "// nothing\n");
  const Sources s = resolve_sources(find_unit("fp_mul"), d);
  ASSERT_EQ(s.files.size(), 2u);
  EXPECT_EQ(fs::path(s.files[0]).filename(), "ru_a.sv");
  EXPECT_EQ(fs::path(s.files[1]).filename(), "ru_b.sv");
  ASSERT_EQ(s.includes.size(), 2u);
  EXPECT_EQ(fs::path(s.includes[0]).filename(), "ru_b.svh");
  EXPECT_EQ(fs::path(s.includes[1]).filename(), "ru_c.svh");
  fs::remove(d + "/ru_c.svh");
  EXPECT_THROW(resolve_sources(find_unit("fp_mul"), d), SynthError);
  spit(d + "/ru_fp_mul.f", "+incdir+foo\nru_a.sv\n");
  EXPECT_THROW(resolve_sources(find_unit("fp_mul"), d), SynthError);
  spit(d + "/ru_fp_mul.f", "ru_missing.sv\n");
  EXPECT_THROW(resolve_sources(find_unit("fp_mul"), d), SynthError);
}

TEST(SynthRegistry, EveryFpUnitHasItsRtlSources) {
  // Fails while a unit of the registry has no RTL yet: the registry must not promise units
  // that do not exist.
  for (const auto& u : units()) {
    SCOPED_TRACE(u.name);
    EXPECT_NO_THROW(resolve_sources(u, default_rtl_dir()));
  }
}

// The registry's port list must match the RTL: Verilator -Wall flags any width mismatch
// between the generated wrapper and the unit (and the RTL itself must be lint clean).
TEST(SynthRegistry, WrappersLintCleanAgainstTheRtl) {
  TempDir t("ru-test-lint-");
  for (const auto& u : units()) {
    SCOPED_TRACE(u.name);
    UnitConfig c = cfg("e5m10", 0);
    c.stages = std::min(2, u.max_stages(c));
    GenOptions o;
    o.out_dir = t.path() + "/" + u.name;
    o.run_flow = false;
    try {
      generate(u, c, o);
    } catch (const SynthError& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    const CliRun r = sh("cd " + q(o.out_dir) + " && verilator --lint-only -Wall --top-module " +
                        wrapper_name(u, c) + " -f files.f");
    EXPECT_EQ(r.code, 0) << r.out << r.err;
    EXPECT_EQ(r.err.find("%Warning"), std::string::npos) << r.err;
  }
  // The check catches a planted one-bit width error in a wrapper port.
  const UnitConfig c = cfg("e5m10", 2);  // as generated in the loop above
  const std::string dir = t.path() + "/fp_mul", top = wrapper_name(find_unit("fp_mul"), c);
  std::string w = slurp(dir + "/" + top + ".sv");
  const std::string good = "input  logic [15:0] a_i";
  ASSERT_NE(w.find(good), std::string::npos);
  w.replace(w.find(good), good.size(), "input  logic [16:0] a_i");
  spit(dir + "/" + top + ".sv", w);
  const CliRun bad =
      sh("cd " + q(dir) + " && verilator --lint-only -Wall --top-module " + top + " -f files.f");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.err.find("%Warning-WIDTH"), std::string::npos) << bad.err;
}

// ---------------------------------------------------------------------------------------------
// NAND2 weights and the generic flow on hand-made designs with known answers

TEST(SynthWeights, OrderAndRejections) {
  EXPECT_DOUBLE_EQ(nand2_weight("$_NAND_"), 1.0);
  EXPECT_LT(nand2_weight("$_NOT_"), nand2_weight("$_NAND_"));
  EXPECT_LT(nand2_weight("$_NAND_"), nand2_weight("$_AND_"));
  EXPECT_LT(nand2_weight("$_AND_"), nand2_weight("$_XOR_"));
  EXPECT_LT(nand2_weight("$_XOR_"), nand2_weight("$_MUX_"));
  EXPECT_LT(nand2_weight("$_MUX_"), nand2_weight("$_DFF_P_"));
  EXPECT_LT(nand2_weight("$_DFF_P_"), nand2_weight("$_DFF_PN0_"));
  EXPECT_LT(nand2_weight("$_DFF_P_"), nand2_weight("$_DFFE_PP_"));
  EXPECT_LT(nand2_weight("$_DFF_P_"), nand2_weight("$_SDFF_PP0_"));
  EXPECT_TRUE(is_flop_cell("$_SDFFE_PN0P_"));
  EXPECT_FALSE(is_flop_cell("$_XOR_"));
  EXPECT_THROW(nand2_weight("$_DLATCH_P_"), SynthError);
  EXPECT_THROW(nand2_weight("$add"), SynthError);
  EXPECT_THROW(nand2_weight("SB_LUT4"), SynthError);
}

struct Design {
  TempDir dir{"ru-test-flow-"};
  std::string file;
  explicit Design(const std::string& verilog) {
    file = dir.path() + "/d.sv";
    spit(file, verilog);
  }
  SynthResult run(const std::string& top, const FlowOptions& o = generic_only(),
                  const std::vector<Port>& ports = {}) {
    return run_flow({file}, top, ports, dir.path(), o);
  }
};

// A 16-input XOR needs ceil(log2 16) = 4 levels of 2-input gates; ABC reaches that bound.
TEST(SynthFlow, DepthOfACombinationalParityTree) {
  Design d(
      "module par16 (input logic [15:0] x_i, output logic y_o);\n"
      "  assign y_o = ^x_i;\nendmodule\n");
  const SynthResult r = d.run("par16");
  EXPECT_EQ(r.generic.depth, 4);
  EXPECT_EQ(r.generic.reg_bits, 0);
  EXPECT_EQ(r.generic.cells_total, 15);  // a tree of 15 two-input XOR/XNOR
  EXPECT_GT(r.generic.fmax_mhz, 0);
  EXPECT_TRUE(r.generic.transistors_complete);
  EXPECT_GT(r.generic.transistors, 0);
}

// Registers after the two 8-input halves cut the tree: the worst stage is 3 levels, not 4.
// (If `ltp -noff` did not cut at flip-flops, this would report 4.)
TEST(SynthFlow, DepthIsPerPipelineStage) {
  Design d(
      "module par16r (input logic clk_i, input logic [15:0] x_i, output logic y_o);\n"
      "  logic lo_q, hi_q;\n"
      "  always_ff @(posedge clk_i) begin lo_q <= ^x_i[7:0]; hi_q <= ^x_i[15:8]; end\n"
      "  assign y_o = lo_q ^ hi_q;\nendmodule\n");
  const SynthResult r = d.run("par16r");
  EXPECT_EQ(r.generic.depth, 3);
  EXPECT_EQ(r.generic.reg_bits, 2);
  EXPECT_LT(r.generic.stage_ps, DelayModel::stage_ps(4));
}

TEST(SynthFlow, AreaIsTheDocumentedWeightedSum) {
  // 8 flip-flops with asynchronous reset feeding 8 inverters: README table, 20/3 and 2/3.
  Design d(
      "module inv8 (input logic clk_i, input logic rst_ni, input logic [7:0] x_i,\n"
      "              output logic [7:0] y_o);\n"
      "  logic [7:0] q;\n"
      "  always_ff @(posedge clk_i or negedge rst_ni) if (!rst_ni) q <= '0; else q <= x_i;\n"
      "  assign y_o = ~q;\nendmodule\n");
  const SynthResult r = d.run("inv8");
  const std::map<std::string, long> want = {{"$_DFF_PN0_", 8}, {"$_NOT_", 8}};
  EXPECT_EQ(r.generic.cells, want);
  EXPECT_NEAR(r.generic.area_nand2, 8 * 20.0 / 3 + 8 * 2.0 / 3, 1e-9);
  EXPECT_EQ(r.generic.reg_bits, 8);
  EXPECT_EQ(r.generic.depth, 1);
  EXPECT_FALSE(r.generic.transistors_complete);  // Yosys 0.23 has no count for reset flops
  EXPECT_EQ(r.generic.transistors_uncounted, 8);
}

TEST(SynthFlow, LatchesAreRejected) {
  Design d(
      "module lat (input logic en_i, input logic d_i, output logic q_o);\n"
      "  always_latch if (en_i) q_o = d_i;\nendmodule\n");
  try {
    d.run("lat");
    FAIL() << "a latch was accepted";
  } catch (const SynthError& e) {
    EXPECT_NE(std::string(e.what()).find("latch"), std::string::npos) << e.what();
  }
}

TEST(SynthFlow, CombinationalLoopFailsCheckAssert) {
  Design d(
      "module loop (input logic x_i, output logic y_o);\n"
      "  logic a, b;\n  assign a = b ^ x_i;\n  assign b = a & x_i;\n  assign y_o = b;\nendmodule\n");
  try {
    d.run("loop");
    FAIL() << "a combinational loop passed";
  } catch (const SynthError& e) {
    EXPECT_NE(std::string(e.what()).find("yosys (generic) failed"), std::string::npos) << e.what();
  }
}

TEST(SynthFlow, FpgaFlowsOnASmallDesign) {
  Design d(
      "module par16r (input logic clk_i, input logic rst_ni, input logic in_valid_i,\n"
      "                input logic [15:0] x_i, output logic out_valid_o, output logic y_o);\n"
      "  logic lo_q, hi_q, v_q;\n"
      "  always_ff @(posedge clk_i or negedge rst_ni)\n"
      "    if (!rst_ni) v_q <= 1'b0; else v_q <= in_valid_i;\n"
      "  always_ff @(posedge clk_i) begin lo_q <= ^x_i[7:0]; hi_q <= ^x_i[15:8]; end\n"
      "  assign y_o = lo_q ^ hi_q;\n  assign out_valid_o = v_q;\nendmodule\n");
  FlowOptions o;
  o.pnr = true;
  const std::vector<Port> ports = {
      {"clk_i", PortDir::In, PortRole::Clock, 1, ""},        {"rst_ni", PortDir::In, PortRole::Reset, 1, ""},
      {"in_valid_i", PortDir::In, PortRole::Valid, 1, ""},   {"x_i", PortDir::In, PortRole::Data, 16, ""},
      {"out_valid_o", PortDir::Out, PortRole::Valid, 1, ""}, {"y_o", PortDir::Out, PortRole::Data, 1, ""}};
  const SynthResult r = d.run("par16r", o, ports);
  ASSERT_TRUE(r.ice40.run);
  EXPECT_TRUE(r.ice40.fits) << r.ice40.reason;
  // 8-input XOR: at least 3 LUT4 per half (ceil(7/3)), a LUT for the final XOR.
  EXPECT_GE(r.ice40.luts, 6);
  EXPECT_LT(r.ice40.luts, 20);
  EXPECT_EQ(r.ice40.ffs, 3);
  EXPECT_TRUE(r.ice40.pnr_ok) << r.ice40.reason;
  EXPECT_GT(r.ice40.fmax_mhz, 10.0);
  EXPECT_GE(r.ice40.lcs, r.ice40.luts);
  ASSERT_TRUE(r.xilinx.run);
  EXPECT_GE(r.xilinx.luts, 2);  // two LUT6 halves at least... (8 inputs > 6)
  EXPECT_EQ(r.xilinx.ffs, 3);
  const json j = to_json(r);
  EXPECT_TRUE(j["ice40"]["fmax_mhz"].is_number());
  EXPECT_EQ(j["xilinx"]["luts"].get<long>(), r.xilinx.luts);
}

// ---------------------------------------------------------------------------------------------
// Real units (small formats, generic gates)

TEST(SynthUnits, FpMulAreaGrowsWithWidthAndRegistersWithStages) {
  const UnitSpec& mul = find_unit("fp_mul");
  const SynthResult small = run_synth(mul, cfg("e5m10", 0), generic_only());
  const SynthResult wide = run_synth(mul, cfg("e8m23", 0), generic_only());
  EXPECT_GT(wide.generic.area_nand2, 1.5 * small.generic.area_nand2);
  EXPECT_GT(wide.generic.transistors, small.generic.transistors);
  EXPECT_EQ(small.generic.reg_bits, 0);
  EXPECT_EQ(wide.generic.reg_bits, 0);
  EXPECT_GT(small.generic.depth, 10);
  EXPECT_GE(wide.generic.depth, small.generic.depth);

  // The same unit through the command line, pipelined: JSON row on a file, table on stdout.
  TempDir t("ru-test-cli-");
  const std::string jf = t.path() + "/row.json";
  const CliRun run = cli("synth fp_mul --format e5m10 --stages 2 --generic-only --json " + q(jf));
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("ru_fp_mul_e5m10_s2"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("NAND2-eq"), std::string::npos) << run.out;
  const json j = json::parse(slurp(jf));
  for (const char* k : {"unit",           "top",
                        "format",         "exp_bits",
                        "frac_bits",      "width",
                        "round",          "stages",
                        "latency",        "throughput",
                        "cells",          "cells_total",
                        "area_nand2",     "transistors_cmos",
                        "reg_bits",       "depth",
                        "stage_delay_ps", "fmax_est_mhz",
                        "delay_model",    "yosys",
                        "ice40",          "xilinx"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_EQ(j["top"], "ru_fp_mul_e5m10_s2");
  EXPECT_EQ(j["stages"], 2);
  EXPECT_TRUE(j["ice40"].is_null());
  long cells = 0;
  for (auto& [k, v] : j["cells"].items()) cells += v.get<long>();
  EXPECT_EQ(cells, j["cells_total"].get<long>());
  // Pipelining: registers appear (at least the valid bit of each stage), the worst stage
  // gets shallower, the estimated Fmax higher.
  EXPECT_GE(j["reg_bits"].get<long>(), 2);
  EXPECT_LT(j["depth"].get<int>(), small.generic.depth);
  EXPECT_GT(j["fmax_est_mhz"].get<double>(), small.generic.fmax_mhz);
  EXPECT_GT(j["area_nand2"].get<double>(), small.generic.area_nand2);
}

// ---------------------------------------------------------------------------------------------
// Command line: every bad request is one line on stderr, nothing on stdout, exit 2.

TEST(SynthCli, BadRequestsGiveOneLine) {
  TempDir t("ru-test-bad-");
  const std::string full = t.path() + "/full";
  fs::create_directories(full);
  spit(full + "/keep.txt", "x");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"synth fp_foo --format e5m10 --stages 1", "unknown unit 'fp_foo'"},
      {"synth fp_mul --format e1m10 --stages 1", "e1m10"},
      {"synth fp_mul --format e5m10x --stages 1", "e5m10x"},
      {"synth fp_mul --format e5m10 --stages 99", "supports --stages 0.."},
      {"synth fp_mul --format e5m10 --stages -1", "--stages"},
      {"synth fp_mul --format e5m10 --stages 1 --yosys /nonexistent/yosys", "yosys not found"},
      {"synth fp_mul --format e5m10 --stages 1 --round rnx", "rnx"},
      {"synth fp_mul --stages 1", "--format"},
      {"synth fp_mul --format e5m10", "--stages"},
      {"synth fp_mul --format e5m10 --stages 1 --bogus", "unknown option '--bogus'"},
      {"synth fp_mul --format e5m10 --stages 1 --device ecp5", "hx8k or up5k"},
      {"synth", "missing unit"},
      {"synth noise --stages 2 --format e5m10", "no floating-point format"},
      {"synth noise --stages 2 --param Bogus=1", "no parameter 'Bogus'"},
      {"gen fp_mul --format e5m10 --stages 1", "--out"},
      {"gen fp_mul --format e5m10 --stages 1 --no-synth --out " + q(full), "not empty"},
      {"gen fp_mul --format e5m10 --stages 1 --out " + q(t.path() + "/x") + " --rtl /nonexistent",
       "not found"},
      {"synth-sweep --out " + q(t.path() + "/sw") + " --units fp_foo", "unknown unit"},
      {"synth-sweep --out " + q(t.path() + "/sw") + " --formats e5m10,e99m1", "e99m1"},
      {"synth-sweep --units fp_mul", "--out"},
  };
  for (const auto& [args, want] : cases) {
    SCOPED_TRACE(args);
    const CliRun r = cli(args);
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(want), std::string::npos) << r.err;
  }
  EXPECT_EQ(slurp(full + "/keep.txt"), "x");  // the refused gen left the directory alone
  EXPECT_FALSE(fs::exists(t.path() + "/sw"));
}

// ---------------------------------------------------------------------------------------------
// Generation

std::map<std::string, std::string> dir_contents(const std::string& d) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(d)) m[e.path().filename().string()] = slurp(e.path().string());
  return m;
}

std::vector<std::string> siblings(const std::string& parent) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(parent)) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

TEST(SynthGen, WritesADeterministicSelfContainedDirectory) {
  TempDir t("ru-test-gen-");
  const std::string a = t.path() + "/a", b = t.path() + "/b";
  ASSERT_EQ(cli("gen fp_mul --format e5m10 --stages 2 --round rtz --no-synth --out " + q(a)).code, 0);
  ASSERT_EQ(cli("gen fp_mul --format e5m10 --stages 2 --round rtz --no-synth --out " + q(b)).code, 0);
  const auto ca = dir_contents(a), cb = dir_contents(b);
  EXPECT_EQ(ca, cb);  // byte for byte: usable from a build system
  const std::string top = "ru_fp_mul_e5m10_s2_rtz";
  for (const std::string& f :
       std::vector<std::string>{top + ".sv", "files.f", "synth.ys", "datasheet.md", "datasheet.json"})
    EXPECT_EQ(ca.count(f), 1u) << f;
  // Every compile unit of files.f is in the directory, the wrapper last.
  std::istringstream fl(ca.at("files.f"));
  std::vector<std::string> listed;
  for (std::string l; std::getline(fl, l);) {
    EXPECT_EQ(ca.count(l), 1u) << l;
    listed.push_back(l);
  }
  ASSERT_FALSE(listed.empty());
  EXPECT_EQ(listed.back(), top + ".sv");
  const Sources src = resolve_sources(find_unit("fp_mul"), default_rtl_dir());
  EXPECT_EQ(listed.size(), src.files.size() + 1);
  for (const auto& s : src.files) EXPECT_EQ(ca.at(fs::path(s).filename().string()), slurp(s)) << s;
  // The datasheet.
  const json ds = json::parse(ca.at("datasheet.json"));
  EXPECT_EQ(ds["top"], top);
  EXPECT_EQ(ds["latency"], 2);
  EXPECT_EQ(ds["throughput"], 1);
  EXPECT_EQ(ds["format"]["name"], "e5m10");
  EXPECT_EQ(ds["round"], "rtz");
  EXPECT_TRUE(ds["area_nand2"].is_null());  // --no-synth
  std::map<std::string, std::pair<std::string, int>> ports;
  for (const auto& p : ds["ports"]) ports[p["name"]] = {p["direction"], p["width"]};
  EXPECT_EQ(ports["a_i"], std::make_pair(std::string("input"), 16));
  EXPECT_EQ(ports["y_o"], std::make_pair(std::string("output"), 16));
  EXPECT_EQ(ports["flags_o"], std::make_pair(std::string("output"), 5));
  EXPECT_EQ(ports.size(), 8u);
  EXPECT_NE(ca.at("datasheet.md").find("| latency | 2 cycles |"), std::string::npos);
  // The generated script synthesizes from the directory alone and passes check -assert.
  const CliRun y = sh("cd " + q(a) + " && yosys -q synth.ys");
  EXPECT_EQ(y.code, 0) << y.out << y.err;
  // No staging directories left behind.
  EXPECT_EQ(siblings(t.path()), (std::vector<std::string>{"a", "b"}));
}

TEST(SynthGen, DatasheetCarriesTheFlowResults) {
  TempDir t("ru-test-gen-");
  GenOptions o;
  o.out_dir = t.path() + "/g";
  o.flow = generic_only();
  const GenReport rep = generate(find_unit("fp_add"), cfg("e5m10", 1), o);
  ASSERT_TRUE(rep.synth.has_value());
  const json ds = json::parse(slurp(o.out_dir + "/datasheet.json"));
  EXPECT_EQ(ds["top"], "ru_fp_add_e5m10_s1");
  EXPECT_GT(ds["area_nand2"].get<double>(), 100);
  EXPECT_GT(ds["depth"].get<int>(), 5);
  EXPECT_EQ(ds["area_nand2"].get<double>(), to_json(*rep.synth)["area_nand2"].get<double>());
  EXPECT_NE(slurp(o.out_dir + "/datasheet.md").find("NAND2-eq"), std::string::npos);
}

TEST(SynthGen, ForceReplacesAndFailuresLeaveTheOldDirectory) {
  TempDir t("ru-test-gen-");
  const std::string out = t.path() + "/g";
  fs::create_directories(out);
  spit(out + "/stale.txt", "old");
  GenOptions o;
  o.out_dir = out;
  o.run_flow = false;
  EXPECT_THROW(generate(find_unit("fp_mul"), cfg("e5m10", 1), o), SynthError);  // not empty
  o.force = true;  // not a directory gen wrote: --force refuses too
  EXPECT_THROW(generate(find_unit("fp_mul"), cfg("e5m10", 1), o), SynthError);
  EXPECT_EQ(siblings(out), (std::vector<std::string>{"stale.txt"}));
  fs::remove(out + "/stale.txt");
  generate(find_unit("fp_add"), cfg("e5m10", 0), o);  // an earlier generation...
  spit(out + "/stale.txt", "old");                    // ...with a file added by hand

  // A flow failure half-way (broken RTL) leaves the old directory as it was.
  TempDir rtl("ru-test-rtl-");
  spit(rtl.path() + "/ru_fp_mul.sv", "module ru_fp_mul (input logic clk_i; syntax error\n");
  const auto before = dir_contents(out);
  o.run_flow = true;
  o.flow = generic_only();
  o.flow.rtl_dir = rtl.path();
  o.flow.temp_parent = t.path() + "/work";
  fs::create_directories(o.flow.temp_parent);
  EXPECT_THROW(generate(find_unit("fp_mul"), cfg("e5m10", 1), o), SynthError);
  EXPECT_EQ(dir_contents(out), before);

  // --force with good RTL replaces the contents.
  o.flow.rtl_dir.clear();
  o.run_flow = false;
  generate(find_unit("fp_mul"), cfg("e5m10", 1), o);
  EXPECT_FALSE(fs::exists(out + "/stale.txt"));
  EXPECT_TRUE(fs::exists(out + "/ru_fp_mul_e5m10_s1.sv"));
  EXPECT_EQ(siblings(t.path()), (std::vector<std::string>{"g", "work"}));
}

// synth/RuGen.cmake computes wrapper names at configure time: it must agree with wrapper_name().
TEST(SynthGen, CMakeHelperNamesAgree) {
  TempDir t("ru-test-cmake-");
  const std::string script = t.path() + "/names.cmake";
  spit(script, "include(" + std::string(RU_SOURCE_DIR) +
                   "/synth/RuGen.cmake)\n"
                   "ru_gen_top_name(a UNIT fp_mul FORMAT e7m16 STAGES 3)\n"
                   "ru_gen_top_name(b UNIT fp_add FORMAT e5m10 STAGES 0 ROUND rtz FTZ)\n"
                   "ru_gen_top_name(c UNIT fp_div FORMAT e8m23-ftz STAGES 12 ROUND rne)\n"
                   "ru_gen_top_name(d UNIT noise STAGES 4 PARAMS FracBits=10)\n"
                   "message(\"${a} ${b} ${c} ${d}\")\n");
  const CliRun r = sh("cmake -P " + q(script));
  ASSERT_EQ(r.code, 0) << r.err;
  UnitConfig b = cfg("e5m10-ftz", 0, ru::num::Round::RTZ);
  UnitConfig d;
  d.stages = 4;
  d.params["FracBits"] = 10;
  const std::string want = wrapper_name(find_unit("fp_mul"), cfg("e7m16", 3)) + " " +
                           wrapper_name(find_unit("fp_add"), b) + " " +
                           wrapper_name(find_unit("fp_div"), cfg("e8m23-ftz", 12)) + " " +
                           wrapper_name(find_unit("noise"), d) + "\n";
  EXPECT_EQ(r.err, want);  // message() prints to stderr
}

// ---------------------------------------------------------------------------------------------
// Sweep

TEST(SynthSweep, SmallSweepWritesCsvJsonAndPlot) {
  TempDir t("ru-test-sweep-");
  const std::string out = t.path() + "/sw";
  const CliRun r = cli(
      "synth-sweep --units fp_mul --formats e4m3,e5m2 --stages 0,1,99 --generic-only -j 2 --out " + q(out));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("4/4 done (0 failed)"), std::string::npos) << r.err;  // the sweep engine's progress
  EXPECT_NE(r.err.find("skipped fp_mul e4m3 s99"), std::string::npos) << r.err;
  const json j = json::parse(slurp(out + "/synth_sweep.json"));
  ASSERT_EQ(j["rows"].size(), 4u);
  for (const auto& row : j["rows"]) {
    EXPECT_FALSE(row.contains("error")) << row.dump();
    EXPECT_GT(row["area_nand2"].get<double>(), 0);
  }
  EXPECT_EQ(j["meta"]["command"].get<std::string>().rfind("rayunits synth-sweep", 0), 0u);
  const std::string csv = slurp(out + "/synth_sweep.csv");
  EXPECT_EQ(lines(csv), 5);
  EXPECT_EQ(csv.rfind("unit,format,exp_bits,frac_bits", 0), 0u) << csv;
  EXPECT_GT(fs::file_size(out + "/synth_sweep.png"), 10000u);
  // The points ran as one grid of the sweep engine: its job list and results in DIR/sweep.
  EXPECT_EQ(lines(slurp(out + "/sweep/jobs.jsonl")), 4);
  EXPECT_EQ(lines(slurp(out + "/sweep/results.jsonl")), 4);
  // --resume reuses every point (the engine skips every job with an ok row), same table.
  const CliRun again =
      cli("synth-sweep --units fp_mul --formats e4m3,e5m2 --stages 0,1 --generic-only --no-plot "
          "--resume --out " +
          q(out));
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("4 jobs: 0 to run, 4 with an ok result"), std::string::npos) << again.err;
  EXPECT_EQ(slurp(out + "/synth_sweep.csv"), csv);
  EXPECT_EQ(lines(slurp(out + "/sweep/results.jsonl")), 4);
}

// ---------------------------------------------------------------------------------------------
// Long: bigger designs and place-and-route of real units.

TEST(LongSynth, EveryUnitSynthesizesWithAllFlows) {
  FlowOptions o;
  o.pnr = true;
  for (const auto& u : units()) {
    SCOPED_TRACE(u.name);
    UnitConfig c = cfg("e5m10", 0);
    c.stages = std::min(2, u.max_stages(c));
    const SynthResult r = run_synth(u, c, o);
    EXPECT_GT(r.generic.area_nand2, 0);
    EXPECT_GT(r.generic.reg_bits, 0);
    EXPECT_TRUE(r.ice40.run);
    if (r.ice40.fits) {
      EXPECT_TRUE(r.ice40.pnr_ok) << r.ice40.reason;
    }
    EXPECT_GT(r.xilinx.luts, 0);
  }
}

// Issue 13 §5: the long suite runs the cell-library flow on every unit of the registry at least
// once (e5m10 where the unit has a format, Stages min(2, max), area-oriented 1 us target), with
// the stage scan, so the level rule and the harness are exercised on every register structure.
TEST(LongSynth, EveryUnitThroughTheCellFlow) {
  if (find_program("sta").empty() || !std::filesystem::exists("/usr/share/qflow/tech/osu018/osu018_stdcells.lib"))
    GTEST_SKIP() << "sta or osu018 not installed";
  FlowOptions o;
  o.flow = "osu018";
  o.clocks_ps = {1000000};
  for (const auto& u : units()) {
    SCOPED_TRACE(u.name);
    UnitConfig c = cfg("e5m10", 0);
    c.stages = std::min(2, u.max_stages(c));
    // Per-stage periods need a fixed-latency pipeline: a handshake unit is refused them (its
    // side path's registers lie outside the Stages levels) and runs the flow without the scan.
    o.stage_periods = !u.handshake;
    const SynthResult r = run_synth(u, c, o);
    ASSERT_EQ(r.cell.runs.size(), 1u);
    const CellRun& run = r.cell.runs[0];
    EXPECT_GT(run.area.comb, 0);
    EXPECT_GT(run.area.seq, 0);
    EXPECT_GT(run.fmax_mhz, 0);
    EXPECT_GE(run.sta.slack_ps, 0);  // met at 1 us
    if (u.handshake) {
      EXPECT_TRUE(run.stage_ps.empty());
      continue;
    }
    ASSERT_EQ(run.stage_ps.size(), static_cast<size_t>(c.stages) + 1);
    double worst = 0;
    for (double p : run.stage_ps) worst = std::max(worst, p);
    EXPECT_NEAR(worst, run.achieved_ps, 0.5);
  }
}

}  // namespace
