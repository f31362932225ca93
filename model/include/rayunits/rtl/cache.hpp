// rayunits rtl: one unit configuration run under the cycle-by-cycle scoreboard, with its Verilator
// build cached by content (issue 17 §1; `rayunits rtl`, the sweep kind `rtl`, docs/SWEEPS.md).
//
// A configuration (unit, format, rounding, Stages, unit parameters) becomes one test executable:
// the unit's own test plan from tb/ (the same plan `tb_<unit>` runs in ctest) linked with one
// Verilated model of the RTL. The executable is stored in the cache under a key that covers
// everything it is built from:
//   - the unit and its tb configuration string (tb/cmake/RuTb.cmake syntax, "e5m10-ftz:s2:rtz"),
//   - the unit's RTL sources (synth::sources_hash: names and contents),
//   - the harness and golden-model sources (every file under tb/ and model/ and the top-level
//     CMakeLists.txt, by content),
//   - the Verilator and C++ compiler versions.
// So a configuration is built once and shared by every job and sweep that needs it, and any
// change to what it is built from makes a new key. Layout of the cache directory:
//   bin/<key>/tb, bin/<key>/manifest.json   the executable and what it was built from
//   trees/<id>/build/                        one CMake build tree per source checkout, configured
//                                            with -DRU_TB_JOBS_ONLY=ON (the model library and the
//                                            harness are compiled once; each new configuration
//                                            adds one Verilated model and a link)
//   trees/<id>/.lock                         builds in a tree are serialized (flock); runs are not
//   logs/<key>.build.log                     the build's output
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayunits/synth/units.hpp"

namespace ru::rtl {

// A request that cannot be served (missing tool, failed build): one line. The CLI exits 2.
struct RtlError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Where the cache is and what it builds from (every request).
struct CacheOptions {
  std::string rtl_dir;            // "" : synth::default_rtl_dir()
  std::string cache_dir;          // "" : default_cache_dir()
  std::string source_dir;         // "" : the checkout rayunits was built from
  // Progress lines (cache hit or miss, build steps); may be empty.
  std::function<void(const std::string&)> progress;
};

struct Request : CacheOptions {
  const synth::UnitSpec* unit = nullptr;
  synth::UnitConfig cfg;
  std::uint64_t vectors = 20000;  // random vectors per test of the plan (the tb's --vectors)
  std::uint64_t seed = 1;         // the tb's --seed
  double timeout_s = 0;           // > 0: the test run is killed after that long (status "timeout")
  bool build_only = false;        // build (or find) the executable, run nothing
  bool long_tests = false;        // also the plan's Long_* tests (ctest label long)
};

// The TRaX co-simulation companion (tb/trax/cosim_main.cpp) with exactly these unit
// configurations (`rayunits trax --cosim-build`): cached like a test executable, keyed by every
// unit's configuration and RTL plus the harness, model and tools.
struct CosimRequest : CacheOptions {
  std::vector<std::pair<const synth::UnitSpec*, synth::UnitConfig>> units;
};

// $RU_RTL_CACHE, else $XDG_CACHE_HOME/rayunits/rtl, else $HOME/.cache/rayunits/rtl.
std::string default_cache_dir();

// The configuration in tb/cmake/RuTb.cmake's syntax: "e5m10-ftz:s2:rtz:FracBits=8" (format and
// rounding only for units with a format; parameters given explicitly, in name order).
std::string tb_config(const synth::UnitSpec& u, const synth::UnitConfig& c);

struct Key {
  std::string hash;        // 16 hex digits: util::fnv1a64_hex of parts.dump()
  nlohmann::json parts;    // unit, config, rtl_hash, tb_hash, verilator, compiler
};
// Throws RtlError (missing RTL file, missing verilator or compiler).
Key build_key(const Request& r);

struct Build {
  std::string exe;      // <cache>/bin/<key>/tb
  std::string key;
  bool hit = false;     // found in the cache (no build by this call)
  double seconds = 0;   // this call's build time (0 on a hit)
};
// Returns the cached test executable or builds it (serialized per build tree; a build that another
// process finished while this one waited for the lock counts as a hit). Throws RtlError with the
// build log's path on failure; nothing is left in bin/ for a failed build.
Build ensure_built(const Request& r);
Build ensure_cosim(const CosimRequest& r);  // the same, for a co-simulation companion

// One typed result row (the sweep's `rtl` kind stores it; to_json is its one serializer).
struct Row {
  std::string unit, format, round;  // format/round empty for units without a format
  bool ftz = false;
  int stages = 0;
  nlohmann::json params = nlohmann::json::object();  // unit parameters given explicitly
  std::string config;                                // tb_config()
  std::string key, rtl_hash;
  std::uint64_t vectors = 0, seed = 0;
  std::string status;            // "pass", "fail", "timeout", "built" (build_only)
  int tests = 0, failed = 0;     // gtest cases of the plan
  std::vector<std::string> failed_tests;  // up to 20 names
  std::string first_failure;     // first line of the first failure message
  bool cache_hit = false;
  double build_s = 0, run_s = 0;
  std::string verilator;
};
nlohmann::json to_json(const Row& r);

// ensure_built, then runs the executable (its output goes to this process's stdout) and reads
// its gtest JSON report into a Row. Throws RtlError when the executable cannot report (crash
// without a report).
Row run(const Request& r);

}  // namespace ru::rtl
