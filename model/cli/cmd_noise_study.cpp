// rayunits noise study: quality of the noise unit (spectra, fixed-point error vs fraction bits,
// output range). See docs/NOISE.md.
#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/noise/fixed.hpp"
#include "rayunits/noise/reference.hpp"
#include "rayunits/noise/study.hpp"
#include "rayunits/noise/tables.hpp"
#include "rayunits/util/rng.hpp"
#include "rayunits/synth/flow.hpp"

namespace ru::cli {
namespace {

using namespace ru::noise;

// ---- noise study ---------------------------------------------------------------------------
int run_noise_study(int argc, char** argv) {
  CLI::App app{
      "Quality study of the noise unit (docs/NOISE.md): slices and power spectra of Perlin improved, the xor-hash "
      "and single-table-hash variants, Kensler full / projected / half-resolution and the fixed-point model, with "
      "band, anisotropy and striation numbers; the fixed-point error against the float half-resolution reference "
      "for fraction bits 4..12; the output range over random samples against the derived bounds. Writes CSV, "
      "PNG and noise_summary.md into --out.",
      "rayunits noise study"};
  StudyOptions o;
  bool long_run = false, quiet = false;
  app.add_option("--out", o.out_dir, "output directory (created)")->required();
  app.add_option("--size", o.spectrum_size, "pixels per side of the spectral images, power of two (default 1024)");
  app.add_option("--error-samples", o.error_samples, "random inputs per fraction width (default 200000)");
  app.add_option("--range-samples", o.range_samples, "output-range samples per noise (default 10^6)");
  app.add_option("--min-bits", o.min_bits, "smallest fraction width of the error curve (default 4)");
  app.add_option("--max-bits", o.max_bits, "largest fraction width of the error curve (default 12)");
  app.add_option("--seed", o.seed, "sampling seed (default 1)");
  app.add_flag("--long", long_run, "10^7 output-range samples per noise and 10^6 error samples per width");
  app.add_flag("!--no-plot", o.plot, "do not run scripts/plot_noise.py");
  app.add_flag("--quiet", quiet, "no progress lines");
  if (!parse_args(app, argc, argv)) return 0;
  if (long_run) {
    o.range_samples = std::max(o.range_samples, 10000000l);
    o.error_samples = std::max(o.error_samples, 1000000l);
  }
  if (o.error_samples < 1 || o.range_samples < 1) throw UsageError("sample counts must be >= 1");
  o.progress = !quiet;
  o.command = command_line("rayunits noise study", argc, argv);
  try {
    return run_study(o);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

}  // namespace

RU_COMMAND("noise study", "noise unit quality: spectra, fixed-point error vs fraction bits, output range", run_noise_study);

}  // namespace ru::cli
