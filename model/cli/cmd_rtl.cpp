// `rayunits rtl`: one unit configuration under the cycle-by-cycle scoreboard, its Verilator build
// cached by content (rayunits/rtl/cache.hpp, docs/SWEEPS.md "rtl jobs").
#include <cstdio>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/rtl/cache.hpp"
#include "rayunits/synth/process.hpp"
#include "synth_options.hpp"

namespace ru::cli {
namespace {

std::string rtl_help() {
  return "usage: rayunits rtl <unit> [--format eXmY] --stages N|max [--round rne|rtz|rdn|rup] [--ftz]\n"
         "                    [--param Name=V]... [--vectors N] [--seed S] [--rtl DIR] [--cache DIR]\n"
         "                    [--json FILE|-] [--timeout S] [--build-only] [--long] [--quiet]\n\n"
         "Runs the unit's test plan (the one tb_<unit> runs in ctest: random, special and burst\n"
         "traffic, mid-stream resets) for one configuration on its Verilated RTL, every output bit of\n"
         "every cycle against the golden model. The test executable is cached by content (unit,\n"
         "configuration, RTL sources, harness and model sources, Verilator and compiler versions) and\n"
         "shared by every run and sweep that needs it. Exit status: 0 every test passed, 1 a test\n"
         "failed or timed out, 2 bad options or a failed build.\n\n"
         "units: " +
         synth::unit_names() +
         "\n\n"
         "  --format eXmY[-ftz]  number format (units with a format); --ftz: flush to zero\n"
         "  --round MODE  rounding mode (default rne)\n"
         "  --stages N    latency in cycles, 0..the unit's useful maximum, or max\n"
         "  --param N=V   a unit-specific parameter (e.g. noise: FracBits)\n"
         "  --vectors N   random vectors per test of the plan (default 20000)\n"
         "  --seed S      seed of the random vectors (default 1)\n"
         "  --rtl DIR     RTL source directory (default <repo>/rtl or $RU_RTL_DIR)\n"
         "  --cache DIR   build cache (default $RU_RTL_CACHE, else ~/.cache/rayunits/rtl)\n"
         "  --json FILE   write the result row as JSON (\"-\": on stdout)\n"
         "  --timeout S   stop the test run after S seconds (status timeout, exit 1)\n"
         "  --build-only  build (or find) the executable, run nothing\n"
         "  --long        also the plan's Long_ tests (10^6 vectors each unless --vectors)\n"
         "  --quiet       no cache/build progress lines\n";
}

}  // namespace

bool parse_rtl_command(int argc, char** argv, RtlCommand& r) {
  CLI::App app{"", "rayunits rtl"};
  synth_app(app, rtl_help);
  std::string unit, vectors, seed, timeout;
  ConfigArgs ca;
  app.add_option("unit", unit, "the unit");
  add_config_options(app, ca);
  app.add_option("--vectors", vectors, "random vectors per test");
  app.add_option("--seed", seed, "seed");
  app.add_option("--rtl", r.req.rtl_dir, "RTL directory");
  app.add_option("--cache", r.req.cache_dir, "build cache directory");
  app.add_option("--json", r.json_out, "write the row as JSON");
  app.add_option("--timeout", timeout, "stop the run after S seconds");
  app.add_flag("--build-only", r.req.build_only, "build only");
  app.add_flag("--long", r.req.long_tests, "also the Long_ tests");
  app.add_flag("--quiet", r.quiet, "no progress lines");
  if (!parse_synth_args(app, argc, argv, unit_command_surplus("rtl"))) return false;
  if (unit.empty()) throw UsageError("missing unit (units: " + synth::unit_names() + ")");
  r.req.unit = &synth::find_unit(unit);
  const bool max = ca.stages == "max";
  if (max) ca.stages = "0";
  r.req.cfg = make_config(*r.req.unit, app, ca);
  if (max) r.req.cfg.stages = r.req.unit->max_stages(r.req.cfg);
  synth::check_config(*r.req.unit, r.req.cfg);
  if (!vectors.empty()) r.req.vectors = synth::parse_int("--vectors", vectors, 1, 1000000000);
  if (!seed.empty()) r.req.seed = synth::parse_int("--seed", seed, 0, 2000000000);
  if (!timeout.empty()) r.req.timeout_s = synth::parse_int("--timeout", timeout, 1, 1000000);
  if (!r.req.rtl_dir.empty() && !std::filesystem::is_directory(r.req.rtl_dir))
    throw UsageError("--rtl: no such directory '" + r.req.rtl_dir + "'");
  return true;
}

namespace {

int run_rtl_cmd(int argc, char** argv) {
  RtlCommand rc;
  if (!parse_rtl_command(argc, argv, rc)) return 0;
  if (!rc.quiet) rc.req.progress = [](const std::string& l) { std::fprintf(stderr, "%s\n", l.c_str()); };
  synth::install_interrupt_handler();
  std::fflush(stdout);
  const rtl::Row row = rtl::run(rc.req);
  const std::string line = rtl::to_json(row).dump() + "\n";
  if (rc.json_out == "-") {
    std::fputs(line.c_str(), stdout);
  } else {
    if (!rc.json_out.empty()) synth::write_file_atomic(rc.json_out, line);
    std::printf("rtl %s %s: %s, %d/%d tests passed (%s, build %.1f s, run %.1f s, key %s)\n", row.unit.c_str(),
                row.config.c_str(), row.status.c_str(), row.tests - row.failed, row.tests,
                row.cache_hit ? "cache hit" : "built", row.build_s, row.run_s, row.key.c_str());
    if (!row.first_failure.empty()) std::printf("first failure: %s\n", row.first_failure.c_str());
  }
  return row.status == "pass" || row.status == "built" ? 0 : 1;
}

}  // namespace

RU_COMMAND("rtl", "run one unit configuration under the RTL scoreboard (Verilator build cached by content)",
           run_rtl_cmd);

}  // namespace ru::cli
