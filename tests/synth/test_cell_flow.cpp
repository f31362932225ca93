// The standard-cell flow (synth --flow osu018; cell.hpp): the liberty reader, OpenSTA's slack and
// path as the flow parses them, on a tiny design whose area and delay follow by hand from a
// hand-written liberty; the whole flow on a small unit; its error lines.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "rayunits/synth/args.hpp"
#include "rayunits/synth/cell.hpp"
#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/synth/units.hpp"

namespace {
using namespace ru::synth;
using nlohmann::json;

bool have_sta() { return !find_program("sta").empty(); }
bool have_osu018() { return std::filesystem::exists("/usr/share/qflow/tech/osu018/osu018_stdcells.lib"); }

// A liberty with scalar (load- and slope-independent) delays, so that every number of the tiny
// design below is known by hand: INV 0.1 ns (area 16), DFF clock-to-Q 0.2 ns, setup 0.05 ns
// (area 96). `inv_ns` lets a test plant a different delay.
std::string tiny_liberty(const std::string& inv_ns = "0.1") {
  auto arc = [](const std::string& pin, const std::string& type, const std::string& sense, const std::string& ns) {
    return "      timing () {\n        related_pin : \"" + pin + "\";\n" + type + sense +
           "        cell_rise (scalar) { values (\"" + ns + "\"); }\n"
           "        cell_fall (scalar) { values (\"" + ns + "\"); }\n"
           "        rise_transition (scalar) { values (\"0.05\"); }\n"
           "        fall_transition (scalar) { values (\"0.05\"); }\n      }\n";
  };
  return "library (tiny) {\n  delay_model : table_lookup;\n  time_unit : \"1ns\";\n"
         "  voltage_unit : \"1V\";\n  current_unit : \"1uA\";\n  capacitive_load_unit (1, pf);\n"
         "  pulling_resistance_unit : \"1kohm\";\n  leakage_power_unit : \"1nW\";\n"
         "  nom_voltage : 1.8;\n  nom_temperature : 25;\n  nom_process : 1;\n"
         "  input_threshold_pct_rise : 50;\n  input_threshold_pct_fall : 50;\n"
         "  output_threshold_pct_rise : 50;\n  output_threshold_pct_fall : 50;\n"
         "  slew_lower_threshold_pct_rise : 10;\n  slew_lower_threshold_pct_fall : 10;\n"
         "  slew_upper_threshold_pct_rise : 90;\n  slew_upper_threshold_pct_fall : 90;\n"
         "  cell (INVX1) {\n    area : 16;\n"
         "    pin (A) { direction : input; capacitance : 0.01; }\n"
         "    pin (Y) {\n      direction : output;\n      function : \"(!A)\";\n" +
         arc("A", "", "        timing_sense : negative_unate;\n", inv_ns) +
         "    }\n  }\n"
         "  cell (DFFPOSX1) {\n    area : 96;\n    ff (DS0000,P0002) {\n      next_state : \"D\";\n"
         "      clocked_on : \"CLK\";\n    }\n"
         "    pin (CLK) { direction : input; capacitance : 0.01; clock : true; }\n"
         "    pin (D) {\n      direction : input;\n      capacitance : 0.01;\n"
         "      timing () {\n        related_pin : \"CLK\";\n        timing_type : setup_rising;\n"
         "        rise_constraint (scalar) { values (\"0.05\"); }\n"
         "        fall_constraint (scalar) { values (\"0.05\"); }\n      }\n    }\n"
         "    pin (Q) {\n      direction : output;\n      function : \"DS0000\";\n" +
         arc("CLK", "        timing_type : rising_edge;\n", "        timing_sense : non_unate;\n", "0.2") +
         "    }\n  }\n}\n";
}

// r0 -> three inverters -> r1: the register-to-register path is 0.2 + 3 * 0.1 + 0.05 = 0.55 ns.
const char* const kTinyNetlist =
    "module ru_sta_harness (clk_i, a_i, y_o);\n  input clk_i;\n  input a_i;\n  output y_o;\n"
    "  wire n0, n1, n2, n3;\n"
    "  DFFPOSX1 r0 (.CLK(clk_i), .D(a_i), .Q(n0));\n"
    "  INVX1 i0 (.A(n0), .Y(n1));\n  INVX1 i1 (.A(n1), .Y(n2));\n  INVX1 i2 (.A(n2), .Y(n3));\n"
    "  DFFPOSX1 r1 (.CLK(clk_i), .D(n3), .Q(y_o));\nendmodule\n";

struct Tiny {
  TempDir dir{"ru-test-cell-"};
  CellLibrary lib;
  std::string netlist;
  explicit Tiny(const std::string& inv_ns = "0.1") {
    write_file_atomic(dir.path() + "/tiny.lib", tiny_liberty(inv_ns));
    lib = parse_liberty("tiny", dir.path() + "/tiny.lib");
    netlist = dir.path() + "/tiny.v";
    write_file_atomic(netlist, kTinyNetlist);
  }
};

TEST(CellLibrary, TinyLibertyAreasAndFlops) {
  Tiny t;
  EXPECT_EQ(t.lib.area.at("INVX1"), 16);
  EXPECT_EQ(t.lib.area.at("DFFPOSX1"), 96);
  EXPECT_TRUE(t.lib.flops.count("DFFPOSX1"));
  EXPECT_FALSE(t.lib.flops.count("INVX1"));
  const CellArea a = cell_area(t.lib, {{"INVX1", 3}, {"DFFPOSX1", 2}});
  EXPECT_EQ(a.total, 3 * 16 + 2 * 96);
  EXPECT_EQ(a.seq, 2 * 96);
  EXPECT_EQ(a.comb, 3 * 16);
  EXPECT_EQ(a.cells, 5);
  EXPECT_EQ(a.seq_cells, 2);
  try {
    cell_area(t.lib, {{"NAND2X1", 1}});
    ADD_FAILURE() << "an unknown cell was costed";
  } catch (const SynthError& e) {
    EXPECT_NE(std::string(e.what()).find("'NAND2X1' is not in tiny"), std::string::npos) << e.what();
  }
}

TEST(CellLibrary, Osu018FromItsLiberty) {
  if (!have_osu018()) GTEST_SKIP() << "qflow-tech-osu018 not installed (scripts/install-deps.sh)";
  const CellLibrary& l = cell_library("osu018");
  // The values of osu018_stdcells.lib (cell INVX1: area 16; DFFPOSX1: 96; DFFSR: 176).
  EXPECT_EQ(l.area.at("INVX1"), 16);
  EXPECT_EQ(l.area.at("DFFPOSX1"), 96);
  EXPECT_EQ(l.area.at("DFFSR"), 176);
  for (const char* f : {"DFFPOSX1", "DFFNEGX1", "DFFSR"}) EXPECT_TRUE(l.flops.count(f)) << f;
  EXPECT_TRUE(l.latches.count("LATCH"));
  EXPECT_EQ(l.flops.size() + l.latches.size(), 4u);
}

TEST(CellSta, TinyDesignSlackByHand) {
  if (!have_sta()) GTEST_SKIP() << "sta (opensta) not installed";
  Tiny t;
  const StaResult r = run_sta(t.lib, "sta", t.netlist, "ru_sta_harness", 1000, 1, t.dir.path(), "sta", 60);
  EXPECT_NEAR(r.slack_ps, 1000 - (200 + 300 + 50), 0.5) << r.report;
  EXPECT_NEAR(r.path.clk_to_q_ps, 200, 0.5);
  EXPECT_NEAR(r.path.logic_ps, 300, 0.5);
  EXPECT_NEAR(r.path.setup_ps, 50, 0.5);
  EXPECT_EQ(r.path.cells, 3);
  EXPECT_EQ(r.path.start, "r0");
  EXPECT_EQ(r.path.end, "r1");
  EXPECT_EQ(r.path.segment, 1);  // r1 is one register after r0, the input register
}

TEST(CellSta, TooFastClockHasNegativeSlack) {
  if (!have_sta()) GTEST_SKIP() << "sta (opensta) not installed";
  Tiny t;
  const StaResult r = run_sta(t.lib, "sta", t.netlist, "ru_sta_harness", 400, 1, t.dir.path(), "sta", 60);
  EXPECT_NEAR(r.slack_ps, 400 - 550, 0.5) << r.report;
  EXPECT_NEAR(r.tns_ps, 400 - 550, 0.5);
}

TEST(CellSta, PlantedSlowerInverterIsSeen) {
  // The parse is not a constant: a liberty with 0.15 ns inverters moves the slack by 150 ps.
  if (!have_sta()) GTEST_SKIP() << "sta (opensta) not installed";
  Tiny t("0.15");
  const StaResult r = run_sta(t.lib, "sta", t.netlist, "ru_sta_harness", 1000, 1, t.dir.path(), "sta", 60);
  EXPECT_NEAR(r.slack_ps, 1000 - (200 + 450 + 50), 0.5);
  EXPECT_NEAR(r.path.logic_ps, 450, 0.5);
}

// Two stages by hand: r0 (input register, level 0) -> 3 inverters -> r1 (level 1) -> 1 inverter
// -> r2 (level 2). Stage periods: 0.2 + 0.3 + 0.05 = 0.55 ns and 0.2 + 0.1 + 0.05 = 0.35 ns; r0's
// own D comes from the port (input delay 0): 0.05 ns of setup.
TEST(CellSta, LevelScanByHand) {
  if (!have_sta()) GTEST_SKIP() << "sta (opensta) not installed";
  Tiny t;
  write_file_atomic(t.netlist,
                    "module ru_sta_harness (clk_i, a_i, y_o);\n  input clk_i;\n  input a_i;\n  output y_o;\n"
                    "  wire n0, n1, n2, n3, n4, n5;\n"
                    "  DFFPOSX1 r0 (.CLK(clk_i), .D(a_i), .Q(n0));\n"
                    "  INVX1 i0 (.A(n0), .Y(n1));\n  INVX1 i1 (.A(n1), .Y(n2));\n  INVX1 i2 (.A(n2), .Y(n3));\n"
                    "  DFFPOSX1 r1 (.CLK(clk_i), .D(n3), .Q(n4));\n"
                    "  INVX1 i3 (.A(n4), .Y(n5));\n"
                    "  DFFPOSX1 r2 (.CLK(clk_i), .D(n5), .Q(y_o));\nendmodule\n");
  const StaResult r = run_sta(t.lib, "sta", t.netlist, "ru_sta_harness", 1000, 1, t.dir.path(), "sta", 60, true);
  ASSERT_EQ(r.level_ps.size(), 3u) << r.report;
  EXPECT_NEAR(r.level_ps.at(0), 50, 0.5);
  EXPECT_NEAR(r.level_ps.at(1), 550, 0.5);
  EXPECT_NEAR(r.level_ps.at(2), 350, 0.5);
  // Without the scan: no levels.
  EXPECT_TRUE(run_sta(t.lib, "sta", t.netlist, "ru_sta_harness", 1000, 1, t.dir.path(), "sta2", 60).level_ps.empty());
}

// A register chain deeper than Tcl's default nesting limit (1000): the level procedure must not
// recurse per register (it did, and OpenSTA stopped with "too many nested evaluations" on
// ray_tri_exact e8m23). 1,500 registers; the slowest path (three inverters) ends at the last one.
TEST(CellSta, DeepRegisterChainHasItsLevel) {
  if (!have_sta()) GTEST_SKIP() << "sta (opensta) not installed";
  Tiny t;
  const int n = 1500;
  std::ostringstream v;
  v << "module ru_sta_harness (clk_i, a_i, y_o);\n  input clk_i;\n  input a_i;\n  output y_o;\n";
  for (int i = 0; i <= n; ++i) v << "  wire q" << i << ";\n";
  v << "  wire s1, s2, s3;\n  DFFPOSX1 r0 (.CLK(clk_i), .D(a_i), .Q(q0));\n";
  for (int i = 1; i < n - 1; ++i) v << "  DFFPOSX1 r" << i << " (.CLK(clk_i), .D(q" << i - 1 << "), .Q(q" << i << "));\n";
  v << "  INVX1 i0 (.A(q" << n - 2 << "), .Y(s1));\n  INVX1 i1 (.A(s1), .Y(s2));\n  INVX1 i2 (.A(s2), .Y(s3));\n"
    << "  DFFPOSX1 r" << n - 1 << " (.CLK(clk_i), .D(s3), .Q(y_o));\nendmodule\n";
  write_file_atomic(t.netlist, v.str());
  const StaResult r = run_sta(t.lib, "sta", t.netlist, "ru_sta_harness", 1000, 1, t.dir.path(), "sta", 120, true);
  EXPECT_EQ(r.path.end, "r" + std::to_string(n - 1)) << r.report.substr(0, 2000);
  EXPECT_EQ(r.path.segment, n - 1);
  ASSERT_EQ(r.level_ps.size(), static_cast<size_t>(n));
  EXPECT_NEAR(r.level_ps.at(n - 1), 550, 0.5);
  EXPECT_NEAR(r.level_ps.at(1), 250, 0.5);
}

TEST(CellSta, Osu018Fo4IsAnInverterDelay) {
  if (!have_sta() || !have_osu018()) GTEST_SKIP() << "sta or osu018 not installed";
  const double fo4 = measure_fo4_ps(cell_library("osu018"), "sta");
  // 180 nm: an FO4 delay of the order of 0.36 ns/um x 0.18 um = 65 ps .. 0.5 ns/um = 90 ps; the
  // typical-corner liberty gives 98 ps. A broken parse gives 0 or a path delay (hundreds of ps).
  EXPECT_GT(fo4, 50);
  EXPECT_LT(fo4, 150);
}

TEST(CellFlow, SmallUnitRowsAreConsistent) {
  if (!have_sta() || !have_osu018()) GTEST_SKIP() << "sta or osu018 not installed";
  FlowOptions o;
  o.flow = "osu018";
  o.clocks_ps = {1000, 20000};
  UnitConfig c;
  c.fmt = ru::num::Format::parse("e5m10");
  c.stages = 1;
  const SynthResult r = run_synth(find_unit("fp_cmp"), c, o);
  const auto rows = to_json_rows(r);
  ASSERT_EQ(rows.size(), 2u);
  for (const json& j : rows) {
    SCOPED_TRACE(j.dump());
    EXPECT_EQ(j["flow"], "osu018");
    EXPECT_EQ(j["unit"], "fp_cmp");
    const double period = j["sta_period_ps"], slack = j["slack_ps"], achieved = j["period_ps"];
    EXPECT_NEAR(achieved, period - slack, 0.2);
    EXPECT_NEAR(j["fmax_mhz"].get<double>(), 1e6 / achieved, 0.1);
    EXPECT_NEAR(j["area_um2"].get<double>(), j["area_comb_um2"].get<double>() + j["area_seq_um2"].get<double>(), 0.02);
    EXPECT_GT(j["area_seq_um2"].get<double>(), 0);  // Stages 1: the unit has registers
    EXPECT_EQ(j["critical_path"]["segments"], 2);
    EXPECT_GE(j["critical_path"]["segment"].get<int>(), 1);
    EXPECT_LE(j["critical_path"]["segment"].get<int>(), 2);
    EXPECT_FALSE(j.contains("area_nand2")) << "a cell row carries no generic estimate";
  }
  // 1 GHz is out of reach for this unit in 180 nm: negative slack, not met; 50 MHz is met.
  EXPECT_LT(rows[0]["slack_ps"].get<double>(), 0);
  EXPECT_FALSE(rows[0]["met"].get<bool>());
  EXPECT_GT(rows[1]["slack_ps"].get<double>(), 0);
  EXPECT_TRUE(rows[1]["met"].get<bool>());
}

// Register placement by measured delays: the characterization has one delay per segment, the
// weights are those delays scaled into 1..255, the stage periods of the placed unit are
// consistent with the critical path of report_checks (two independent OpenSTA queries).
TEST(CellFlow, DelayPlacementRows) {
  if (!have_sta() || !have_osu018()) GTEST_SKIP() << "sta or osu018 not installed";
  const UnitSpec& u = find_unit("fp_add");
  UnitConfig c;
  c.fmt = ru::num::Format::parse("e5m10");
  c.stages = 2;
  FlowOptions o;
  o.flow = "osu018";
  o.clocks_ps = {200};
  o.placement = "delay";
  const SynthResult r = run_synth(u, c, o);
  const json j = to_json(r);
  SCOPED_TRACE(j.dump());
  const size_t nseg = static_cast<size_t>(u.max_stages(c)) + 1;
  EXPECT_EQ(j["placement"], "delay");
  EXPECT_EQ(j["top"], "ru_fp_add_e5m10_s2_dly");
  ASSERT_EQ(j["segment_delays_ps"].size(), nseg);
  ASSERT_EQ(j["seg_weights"].size(), nseg);
  int wmax = 0;
  for (const json& w : j["seg_weights"]) {
    EXPECT_GE(w.get<int>(), 1);
    EXPECT_LE(w.get<int>(), 255);
    wmax = std::max(wmax, w.get<int>());
  }
  EXPECT_GE(wmax, 128);  // the largest delay uses the weights' range
  ASSERT_EQ(j["stage_periods_ps"].size(), 3u);
  double worst = 0;
  for (const json& p : j["stage_periods_ps"]) worst = std::max(worst, p.get<double>());
  EXPECT_NEAR(worst, j["period_ps"].get<double>(), 0.2);
  EXPECT_EQ(j["stage_periods_ps"][j["critical_path"]["segment"].get<int>() - 1].get<double>(), worst);
  // Depth placement: no weights, stage periods only when asked for.
  o.placement = "depth";
  const json d = to_json(run_synth(u, c, o));
  EXPECT_EQ(d["placement"], "depth");
  EXPECT_TRUE(d["seg_weights"].is_null());
  EXPECT_TRUE(d["stage_periods_ps"].is_null());
}

// The weights reach the RTL's placement: a front-heavy and a back-heavy weighting put Stages 1's
// one register at opposite ends of fp_add (after segment 0 / before the last), which register
// different signals (generic flow, no timing involved). Equal weights of the wrong count: error.
TEST(CellFlow, SegWeightsMoveTheRegisters) {
  const UnitSpec& u = find_unit("fp_add");
  UnitConfig c;
  c.fmt = ru::num::Format::parse("e5m10");
  c.stages = 1;
  FlowOptions o;
  o.ice40 = o.xilinx = false;
  const size_t nseg = static_cast<size_t>(u.max_stages(c)) + 1;
  c.seg_weights.assign(nseg, 1);
  c.seg_weights.front() = 250;
  const SynthResult front = run_synth(u, c, o);
  c.seg_weights.assign(nseg, 1);
  c.seg_weights.back() = 250;
  const SynthResult back = run_synth(u, c, o);
  EXPECT_NE(front.generic.reg_bits, back.generic.reg_bits);
  EXPECT_NE(wrapper_verilog(u, c).find(".SegW(48'hfa0101010101)"), std::string::npos) << wrapper_verilog(u, c);
  c.seg_weights.assign(nseg - 1, 1);
  EXPECT_THROW(run_synth(u, c, o), SynthError);
  c.seg_weights.assign(nseg, 0);
  EXPECT_THROW(wrapper_verilog(u, c), SynthError);
}

TEST(CellFlow, ClockValues) {
  EXPECT_DOUBLE_EQ(parse_clock_ps("--clock", "400MHz"), 2500);
  EXPECT_DOUBLE_EQ(parse_clock_ps("--clock", "1GHz"), 1000);
  EXPECT_DOUBLE_EQ(parse_clock_ps("--clock", "2.5ns"), 2500);
  EXPECT_DOUBLE_EQ(parse_clock_ps("--clock", "1500ps"), 1500);
  EXPECT_EQ(parse_clock_list("--clock", "2ns,400MHz").size(), 2u);
  for (const char* bad : {"400", "fast", "-2ns", "0MHz", "2ns,", "3 MHz"})
    EXPECT_THROW(parse_clock_ps("--clock", bad), SynthError) << bad;
}

// ---- error lines of the command ----

struct CliRun {
  int code;
  std::string out, err;
};

// `env` is prepended to the command (e.g. "RU_CELL_LIB_DIR=/x").
CliRun rayunits(const std::string& args, const std::string& env = "") {
  TempDir t("ru-test-cellcli-");
  const std::string o = t.path() + "/out", e = t.path() + "/err";
  const std::string cmd =
      env + " '" + std::string(RU_BINARY_DIR) + "/model/cli/rayunits' " + args + " >" + o + " 2>" + e;
  const int st = std::system(cmd.c_str());
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, read_file(o), read_file(e)};
}

void expect_error(const std::string& args, const std::string& want, const std::string& env = "") {
  SCOPED_TRACE(args);
  const CliRun r = rayunits(args, env);
  EXPECT_NE(r.code, 0);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "rayunits synth: error: " + want + "\n");
}

TEST(CellFlowCli, ErrorLines) {
  expect_error("synth fp_add --format e5m10 --stages 1 --flow tsmc7",
               "unknown flow 'tsmc7' (flows: generic, osu018, osu035, osu050)");
  expect_error("synth fp_add --format e5m10 --stages 1 --clock 400",
               "--clock expects a clock with its unit (400MHz, 1.2GHz, 2.5ns, 2500ps; 1 ps .. 100 us), got '400'");
  expect_error("synth fp_add --format e5m10 --stages 1 --flow generic --clock 2ns",
               "--clock needs a cell-library flow (--flow osu018, osu035 or osu050), not --flow generic");
  expect_error("synth fp_add --format e5m10 --stages 1 --flow osu018 --sta /nonexistent/sta",
               "OpenSTA not found ('/nonexistent/sta'): install the Debian package opensta or pass --sta PATH");
  expect_error("synth fp_add --format e5m10 --stages 1 --flow osu018 --fpga",
               "--fpga applies to the generic flow, not to a cell-library flow (--flow osu018)");
  expect_error("synth fp_add --format e5m10 --stages 1 --clock 3ns --device up5k",
               "--device applies to the generic flow, not to a cell-library flow (--flow osu018)");
  expect_error("synth fp_add --format e5m10 --stages 1 --netlist x.v",
               "--netlist needs a cell-library flow (--flow osu018, osu035 or osu050)");
  expect_error("synth fp_add --format e5m10 --stages 1 --flow osu018 --placement fast",
               "--placement expects depth or delay, got 'fast'");
  expect_error("synth fp_add --format e5m10 --stages 1 --placement delay",
               "--placement needs a cell-library flow (--flow osu018, osu035 or osu050)");
  expect_error("synth fp_add --format e5m10 --stages 1 --stage-periods",
               "--stage-periods needs a cell-library flow (--flow osu018, osu035 or osu050)");
  expect_error("synth ray_tri_exact --format e5m10 --stages 2 --flow osu018 --stage-periods",
               "--stage-periods: ray_tri_exact has a handshake (variable latency, registers outside its Stages "
               "pipeline); per-stage periods need a fixed-latency pipeline (the critical path and period still apply)");
  // The list names the registry's units with their own placement (a unit added to the registry
  // joins it without touching this test); the FP units that have one are among them.
  std::string own;
  for (const UnitSpec& x : units())
    if (x.seg_weights_param) own += (own.empty() ? "" : ", ") + x.name;
  for (const char* u : {"fp_add", "fp_mul", "fp_div", "fp_sqrt", "fp_fma", "fp_cmp"})
    EXPECT_NE(own.find(u), std::string::npos) << u;
  EXPECT_EQ((", " + own + ", ").find(", fp_dot3, "), std::string::npos);  // fp_dot3_fused has its own
  expect_error("synth fp_dot3 --format e5m10 --stages 3 --flow osu018 --placement delay",
               "--placement delay: fp_dot3 places its registers through its sub-units' chain (units with their own "
               "placement: " + own + ")");
  TempDir empty("ru-test-nolib-");
  expect_error("synth fp_add --format e5m10 --stages 1 --flow osu018",
               "cell library osu018 not found: no " + empty.path() +
                   "/osu018/osu018_stdcells.lib (install the Debian package qflow-tech-osu018, or set RU_CELL_LIB_DIR)",
               "RU_CELL_LIB_DIR=" + empty.path());
}

TEST(CellFlowCli, GenFindsTheSmallestStagesMeetingTheClock) {
  if (!have_sta() || !have_osu018()) GTEST_SKIP() << "sta or osu018 not installed";
  TempDir t("ru-test-genclk-");
  const std::string out = t.path() + "/g";
  const CliRun r = rayunits("gen fp_cmp --format e5m10 --clock 2.2ns --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const json ds = json::parse(read_file(out + "/datasheet.json"));
  const int chosen = ds["latency"];
  EXPECT_EQ(ds["flow"], "osu018");
  EXPECT_TRUE(ds["met"].get<bool>());
  EXPECT_GE(ds["slack_ps"].get<double>(), 0);
  EXPECT_EQ(ds["target_clock_ps"].get<double>(), 2200);
  // The smallest: either the unit's minimum, or one fewer stage was tried and missed.
  bool fewer_missed = chosen == 0;
  bool chosen_met = false;
  for (const json& p : ds["clock_search"]["probes"]) {
    if (p["stages"] == chosen - 1 && !p["met"].get<bool>()) fewer_missed = true;
    if (p["stages"] == chosen) chosen_met = p["met"].get<bool>();
  }
  EXPECT_TRUE(fewer_missed) << ds["clock_search"].dump();
  EXPECT_TRUE(chosen_met) << ds["clock_search"].dump();
  const std::string md = read_file(out + "/datasheet.md");
  EXPECT_NE(md.find("| target clock | 454.5 MHz (2200 ps): met"), std::string::npos) << md;
  EXPECT_NE(md.find("smallest meeting: " + std::to_string(chosen)), std::string::npos) << md;
}

// gen at a given Stages runs the flow on the generated directory itself: its datasheet must count
// the pipeline segments as synth does (Stages + 1; it said "of 1" for every Stages).
TEST(CellFlowCli, GenAtGivenStagesCountsTheSegments) {
  if (!have_sta() || !have_osu018()) GTEST_SKIP() << "sta or osu018 not installed";
  TempDir t("ru-test-genseg-");
  const std::string out = t.path() + "/g";
  const CliRun r = rayunits("gen fp_cmp --format e5m10 --stages 1 --flow osu018 --clock 2.2ns --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const json ds = json::parse(read_file(out + "/datasheet.json"));
  EXPECT_EQ(ds["synthesis"]["critical_path"]["segments"], 2) << ds["synthesis"].dump();
  const std::string md = read_file(out + "/datasheet.md");
  EXPECT_NE(md.find(" of 2 |"), std::string::npos) << md;
}

// synth/cell/exact_path_area.sh maps ru_exact_path (a submodule, not a registry unit) with the cell flow's
// untargeted ABC script written out in shell; it must be cell_abc_script(0), the one the flow runs.
TEST(CellFlow, ExactPathAreaScriptUsesTheFlowsAbcScript) {
  const std::string sh = read_file(std::string(RU_SOURCE_DIR) + "/synth/cell/exact_path_area.sh");
  std::string abc = cell_abc_script(0), escaped;
  for (char ch : abc) escaped += ch == '\n' ? std::string("\\n") : std::string(1, ch);
  EXPECT_NE(sh.find("printf '" + escaped + "' > "), std::string::npos)
      << "the script's ABC commands differ from cell_abc_script(0): " << escaped;
  EXPECT_NE(abc.find("dnsize"), std::string::npos);
}

TEST(CellFlowCli, GenUnreachableClockIsOneLine) {
  if (!have_sta() || !have_osu018()) GTEST_SKIP() << "sta or osu018 not installed";
  TempDir t("ru-test-genclk-");
  const std::string out = t.path() + "/g";
  const CliRun r = rayunits("gen fp_cmp --format e5m10 --clock 10GHz --out " + out + " 2>&1 >/dev/null | tail -1");
  // stderr: one progress line per probe, then the error line.
  EXPECT_EQ(r.out.rfind("rayunits gen: error: fp_cmp does not reach 10000.0 MHz (100 ps) in osu018: at its maximum "
                        "useful Stages 2 it reaches ",
                        0),
            0u)
      << r.out;
  EXPECT_FALSE(std::filesystem::exists(out)) << "nothing half-written";
}

}  // namespace
