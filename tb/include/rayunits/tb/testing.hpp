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

// A unit's test plan: given one configuration, registers its GoogleTest cases. The plan
// registered for unit "*" (tb/src/registry_plan.cpp) serves every unit without its own.
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

// "N results checked in C cycles (...)" for progress lines.
std::string run_summary(const RunStats& st);

// The verdict of a run without planted errors: no mismatch and (unless it stopped early)
// every one of expect_checked vectors checked exactly once; prints a summary line to stderr.
void expect_clean(const std::string& name, const RunStats& st, uint64_t expect_checked);

// The planted harness errors every unit's "selftest" configurations must catch. Each test is
// a clean control run, then the same run with one planted error that must be reported with
// the right kind at the right place:
//   inject_bitflip                 one bit of a random output field of expected item 700
//   inject_latency_late / _early   expectations one cycle late / early (early: Stages > 0)
//   inject_stale                   a reset at cycle 200 that the DUT does not see (Stages > 0):
//                                  its in-flight results are stale
struct SelftestPlan {
  std::string suite;
  int stages = 0;
  std::function<ScoreboardTest(const std::string& test)> make;  // test name -> test
  // test name, count -> a factory of `count` random vectors seeded from the test name
  std::function<std::function<std::unique_ptr<VectorSource>()>(const std::string& test, uint64_t n)> random;
  std::vector<int> out_bits;  // width of each output field (bit flips land in one of them)
  std::function<uint64_t(const std::string& test)> seed;
  // A unit with a handshake (in_ready_o), and whether its tests have a timing reference
  // (RunOptions::timing): inject_latency_early needs one; inject_stale accepts a stale
  // in_ready_o as the first symptom.
  bool handshake = false, timing = false;
};
void add_harness_selftests(const SelftestPlan& p);

// The generic plan of a registered unit (tb/src/registry_plan.cpp), for a unit's own plan to
// build on: `options` adjusts every run's options (a handshake unit: RunOptions::timing and
// max_latency; then `timing` = true), fast_random / long_random replace the random-vector counts
// (20,000 and 10^6) and reset_every the reset test's mean cycles between resets (40) when
// non-zero (a unit whose results may take hundreds of cycles needs longer: else hardly a result
// survives to be checked).
struct RegistryPlanHooks {
  std::function<void(RunOptions&)> options;
  bool timing = false;
  uint64_t fast_random = 0, long_random = 0;
  uint32_t reset_every = 0;
};
void registry_plan(const ConfigDesc& cfg, const RegistryPlanHooks& hooks = {});
// One test of that plan: `n` of the registry's random vectors, options as the plan's.
ScoreboardTest registry_test(const ConfigDesc& cfg, const std::string& test, uint64_t n,
                             const RegistryPlanHooks& hooks = {});

// Vector-count helper: --vectors if given, else the configuration's n=<count> tag, else def.
uint64_t vector_count(const ConfigDesc& cfg, uint64_t def);

}  // namespace ru::tb
