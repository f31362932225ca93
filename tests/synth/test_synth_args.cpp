// The command lines of `synth`, `gen` and `synth-sweep` (CLI11, model/cli/synth_options.hpp):
// help texts, the error line of every bad argument, flow flags in command-line order. No tool
// runs here except `yosys -V`.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rayunits/synth/process.hpp"
#include "rayunits/synth/units.hpp"

namespace {

struct ArgsRun {
  int code;
  std::string out, err;
};

std::string read_all(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// `rayunits <args>` (plain words, no quoting needed) with stdout and stderr captured.
ArgsRun rayunits(const std::string& args) {
  ru::synth::TempDir t("ru-test-args-");
  const std::string o = t.path() + "/out", e = t.path() + "/err";
#ifdef RU_RAYUNITS_EXE
  const std::string exe = RU_RAYUNITS_EXE;
#else
  const std::string exe = std::string(RU_BINARY_DIR) + "/model/cli/rayunits";
#endif
  const std::string cmd = "'" + exe + "' " + args + " >" + o + " 2>" + e;
  const int st = std::system(cmd.c_str());
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, read_all(o), read_all(e)};
}

// Every bad request: exit 2, nothing on stdout, exactly `want` as the one stderr line.
void expect_error(const std::string& args, const std::string& want) {
  SCOPED_TRACE(args);
  const ArgsRun r = rayunits(args);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, want + "\n");
}

TEST(SynthCli, HelpTextsKeepTheirLayout) {
  for (const std::string cmd : {"synth", "gen", "synth-sweep"}) {
    SCOPED_TRACE(cmd);
    for (const char* h : {" --help", " -h"}) {
      const ArgsRun r = rayunits(cmd + h);
      EXPECT_EQ(r.code, 0);
      EXPECT_EQ(r.err, "");
      EXPECT_EQ(r.out.rfind("usage: rayunits " + cmd + " ", 0), 0u) << r.out;
      EXPECT_NE(r.out.find("\nflow options:\n  --flow NAME "), std::string::npos) << r.out;
      EXPECT_NE(r.out.find("\n  --fpga "), std::string::npos) << r.out;
      EXPECT_NE(r.out.find("  --keep              keep the temp directory"), std::string::npos) << r.out;
      EXPECT_EQ(r.out.find("OPTIONS"), std::string::npos) << r.out;  // not CLI11's own layout
    }
  }
  EXPECT_NE(rayunits("synth --help").out.find("\nunits: fp_add, fp_mul"), std::string::npos);
  EXPECT_NE(rayunits("gen --help").out.find("  --no-synth    do not run the flow"), std::string::npos);
  EXPECT_NE(rayunits("synth-sweep --help").out.find("defaults: --units fp_add,fp_mul,fp_div"), std::string::npos);
}

TEST(SynthCli, UnknownAndSurplusArguments) {
  expect_error("synth fp_mul --format e5m10 --stages 1 --bogus",
               "rayunits synth: error: unknown option '--bogus' (see rayunits synth --help)");
  expect_error("synth fp_mul --format e5m10 --stages 1 --bogus=3",
               "rayunits synth: error: unknown option '--bogus' (see rayunits synth --help)");
  expect_error("synth fp_mul --format e5m10 --stages 1 -x",
               "rayunits synth: error: unknown option '-x' (see rayunits synth --help)");
  expect_error("synth fp_mul fp_add --format e5m10 --stages 1",
               "rayunits synth: error: unexpected argument 'fp_add' (one unit per run)");
  expect_error("gen fp_mul --format e5m10 --stages 1 --out x --bogus",
               "rayunits gen: error: unknown option '--bogus' (see rayunits gen --help)");
  expect_error("gen fp_mul fp_add --format e5m10 --stages 1",
               "rayunits gen: error: unexpected argument 'fp_add' (one unit per run)");
  expect_error("synth-sweep --out x --bogus",
               "rayunits synth-sweep: error: unknown argument '--bogus' (see rayunits synth-sweep --help)");
  expect_error("synth-sweep extra --out x",
               "rayunits synth-sweep: error: unknown argument 'extra' (see rayunits synth-sweep --help)");
  expect_error("gen", "rayunits gen: error: missing unit (units: " + ru::synth::unit_names() + ")");
}

TEST(SynthCli, MissingAndBadValues) {
  expect_error("synth fp_mul --stages 1 --format", "rayunits synth: error: --format needs a value");
  expect_error("synth fp_mul --format e5m10 --stages", "rayunits synth: error: --stages needs a value");
  expect_error("gen fp_mul --format e5m10 --stages 1 --out", "rayunits gen: error: --out needs a value");
  expect_error("synth-sweep --out", "rayunits synth-sweep: error: --out needs a value");
  for (const char* s : {"x", "-1", "1001", "2.5", "''"})
    expect_error(std::string("synth fp_mul --format e5m10 --stages ") + s,
                 std::string("rayunits synth: error: --stages expects an integer in 0..1000, got '") +
                     (s[0] == '\'' ? "" : s) + "'");
  expect_error("gen fp_mul --format e5m10 --out x --stages=y",
               "rayunits gen: error: --stages expects an integer in 0..1000, got 'y'");
  expect_error("synth noise --stages 2 --param Bogus",
               "rayunits synth: error: --param expects Name=Value, got 'Bogus'");
  expect_error("synth noise --stages 2 --param =3", "rayunits synth: error: --param expects Name=Value, got '=3'");
  expect_error("gen noise --stages 2 --out x --param FracBits=abc",
               "rayunits gen: error: --param FracBits expects an integer in -1000000..1000000, got 'abc'");
  // --param is repeatable and takes one value: the unit may follow it.
  expect_error("synth --param FracBits=3 noise --stages 2 --param IntBits=x",
               "rayunits synth: error: --param IntBits expects an integer in -1000000..1000000, got 'x'");
  expect_error("synth fp_mul --format e5m10 --stages 1 --timeout 0",
               "rayunits synth: error: --timeout expects an integer in 1..1000000, got '0'");
  expect_error("synth fp_mul --format e5m10 --stages 1 --device ecp5",
               "rayunits synth: error: --device expects hx8k or up5k, got 'ecp5'");
  expect_error("synth-sweep --out x -j 0", "rayunits synth-sweep: error: -j expects an integer in 1..256, got '0'");
  expect_error("synth-sweep --out x -jx", "rayunits synth-sweep: error: -j expects an integer in 1..256, got 'x'");
  expect_error("synth-sweep --out x --stages 1,x",
               "rayunits synth-sweep: error: --stages expects an integer in 0..1000, got 'x'");
  expect_error("synth-sweep --out x --device foo",
               "rayunits synth-sweep: error: --device expects hx8k or up5k, got 'foo'");
  expect_error("synth-sweep --out x --units ,,",
               "rayunits synth-sweep: error: empty sweep: give at least one unit, format and stage count");
  // A repeated option keeps its last value.
  const ArgsRun r = rayunits("synth fp_mul --format e5m10 --stages 1 --stages 99");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("supports --stages 0.."), std::string::npos) << r.err;
  expect_error("synth fp_mul --format e5m10 --stages 1 --device=up5k --device ecp5",
               "rayunits synth: error: --device expects hx8k or up5k, got 'ecp5'");
}

// --fpga turns place and route on, --no-ice40 and --generic-only turn it off, the last one
// given wins. Seen without running a tool: with place and route a missing nextpnr is reported
// first, without it the missing RTL directory.
TEST(SynthCli, FlowFlagsApplyInCommandLineOrder) {
  ru::synth::TempDir t("ru-test-args-");
  const std::string base = "synth-sweep --units fp_add --out " + t.path() + "/sw --nextpnr /nonexistent/nextpnr "
                           "--rtl /nonexistent/rtl ";
  const std::string pnr = "rayunits synth-sweep: error: nextpnr-ice40 not found ('/nonexistent/nextpnr'): "
                          "install it or drop --fpga";
  const std::string no_pnr = "rayunits synth-sweep: error: RTL directory '/nonexistent/rtl' not found";
  expect_error(base + "--fpga", pnr);
  expect_error(base + "--fpga --no-ice40", no_pnr);
  expect_error(base + "--no-ice40 --fpga", pnr);
  expect_error(base + "--generic-only --fpga", pnr);
  expect_error(base + "--fpga --generic-only", no_pnr);
  expect_error(base + "--fpga --no-xilinx --device up5k --timeout=5 -j3 --keep", pnr);
}

}  // namespace
