// Elaboration time of the one cut-placement mechanism (rtl/ru_pipe_pkg.sv) in Yosys: every
// registered-output unit at Stages 0 and 1 elaborates in seconds. Regression: Yosys 0.23 evaluates
// both arms of a conditional inside a constant function, and cut_mask_reg_out's `stages - 1` at
// Stages 0 (unsigned: 2^32 - 1) made cut_mask's splitting loop run 2^32 times -- `synth noise
// --stages 0` never finished (planted back, this test times out after 120 s and fails).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rayunits/synth/process.hpp"
#include "rayunits/synth/units.hpp"

namespace {
using namespace ru::synth;

TEST(PipeElab, RegisteredOutputUnitAtStages0ElaboratesInYosys) {
  const std::string yosys = find_program("yosys");
  if (yosys.empty()) GTEST_SKIP() << "yosys not installed";
  const UnitSpec& u = find_unit("noise");
  const Sources src = resolve_sources(u, default_rtl_dir());
  std::string script = "read_verilog -sv -I" + default_rtl_dir();
  for (const auto& f : src.files) script += " " + f;
  for (int stages : {0, 1}) {
    SCOPED_TRACE(stages);
    TempDir t("ru-test-pipe-elab-");
    const std::string s = script + "; chparam -set Stages " + std::to_string(stages) + " " + u.top +
                          "; hierarchy -check -top " + u.top;
    const ProcResult r = run_process({yosys, "-q", "-p", s}, t.path(), t.path() + "/yosys.log", 120);
    EXPECT_FALSE(r.timed_out) << "Yosys elaboration of " << u.top << " at Stages " << stages << " took > 120 s";
    EXPECT_EQ(r.exit_code, 0) << read_file(t.path() + "/yosys.log");
  }
}

}  // namespace
