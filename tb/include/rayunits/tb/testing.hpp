// rayunits tb: command-line options, test plans and the GoogleTest glue of the RTL tests.
//
// Every test executable (tb_<unit>, tb_<unit>_long, ...) shares tb/src/tb_main.cpp:
//   tb_fp_mul [--seed=N|random] [--vectors=N] [--max-errors=N] [--trace] [--no-trace-on-fail]
//             [--trace-dir=DIR] [--vector-file=FILE]... [--progress] [gtest options]
// Environment: RU_SEED, RU_VECTORS, RU_TRACE_DIR, RU_VECTOR_FILE (command line wins).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rayunits/tb/dut.hpp"
#include "rayunits/tb/harness.hpp"

namespace ru::tb {

struct GlobalOptions {
  uint64_t seed = 1;            // base seed of every stream (printed in every report)
  int64_t vectors = -1;         // >= 0: overrides the random-vector count of every test
  int max_errors = 5;
  bool trace_always = false;    // --trace: FST of the whole run
  bool trace_on_fail = true;    // re-run a failing test with tracing (window around the errors)
  std::string trace_dir = "tb_traces";
  std::vector<std::string> vector_files;
  bool progress = false;
  std::string argv0 = "tb";
};
GlobalOptions& global_options();

// Parses and removes the options above from argv (gtest's own options stay). On a bad option
// prints one line to stderr and returns false.
bool parse_options(int& argc, char** argv);

// A unit's test plan: given one configuration, registers its GoogleTest cases.
using TestPlan = std::function<void(const ConfigDesc&)>;
std::vector<std::pair<std::string, TestPlan>>& registered_plans();
struct PlanRegistrar {
  PlanRegistrar(const std::string& unit, TestPlan p) { registered_plans().emplace_back(unit, std::move(p)); }
};

// Registers every configuration linked into the executable with its unit's plan.
// Returns false (and prints why) if a configuration's unit has no plan.
bool register_all_tests();

// Registers one GoogleTest case at run time.
void register_test(const std::string& suite, const std::string& name, std::function<void()> body);

// One scoreboard run as a test: builds a fresh Dut/adapter/source, runs, and if it failed
// re-runs the same seed with FST tracing over a window ending just after the last error.
struct ScoreboardTest {
  const ConfigDesc* cfg = nullptr;
  std::string name;  // "fp_mul_e8m23_s3.random" (rerun hints, trace file names)
  std::function<std::unique_ptr<UnitAdapter>()> adapter;
  std::function<std::unique_ptr<VectorSource>()> source;
  RunOptions opt;    // seed, stages, max_errors, ... (filled by make_options)
};
RunOptions make_options(const ConfigDesc& cfg, const std::string& test_name);
RunStats run_scoreboard(const ScoreboardTest& t, std::string* trace_file = nullptr);

// Vector-count helper: --vectors if given, else the configuration's n=<count> tag, else def.
uint64_t vector_count(const ConfigDesc& cfg, uint64_t def);

}  // namespace ru::tb
