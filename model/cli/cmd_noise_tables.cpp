// rayunits noise tables: runs the noise table generator (--check / --write the generated
// model header and RTL case tables). See docs/NOISE.md.
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

// ---- noise tables --------------------------------------------------------------------------
int run_noise_tables(int argc, char** argv) {
  CLI::App app{
      "Run the table generator (per-axis permutations, relaxed 256- and 64-entry gradient tables; docs/NOISE.md) "
      "and print its statistics. --check compares the generated files with the checked-in ones (exit 1 if they "
      "differ); --write rewrites them.",
      "rayunits noise tables"};
  bool write = false, check = false;
  std::string root = RU_SOURCE_DIR;
  app.add_flag("--write", write, "write " + std::string(kGeneratedHeaderPath) + " and " + kGeneratedSvhPath);
  app.add_flag("--check", check, "compare with the checked-in files");
  app.add_option("--root", root, "repository root (default: the source tree this binary was built from)");
  if (!parse_args(app, argc, argv)) return 0;
  TableSet t = generate_tables();
  std::printf("seed 0x%016llx\n", static_cast<unsigned long long>(t.seed));
  for (const RelaxStats* r : {&t.relax256, &t.relax64})
    std::printf("relaxed %3d gradients, %d steps: Coulomb energy %.6f -> %.6f, min chord %.4f -> %.4f, max "
                "tangential force %.2e (relative)\n",
                r->points, r->steps, r->energy_initial, r->energy_final, r->min_dist_initial, r->min_dist_final,
                r->max_tangential_force);
  const std::pair<std::string, std::string> files[] = {{kGeneratedHeaderPath, render_cpp_header(t)},
                                                       {kGeneratedSvhPath, render_svh(t)}};
  int rc = 0;
  for (const auto& [rel, text] : files) {
    std::string path = root + "/" + rel;
    if (check) {
      std::ifstream in(path, std::ios::binary);
      if (!in) {
        std::printf("%s: MISSING (%s)\n", rel.c_str(), path.c_str());
        rc = 1;
      } else {
        std::stringstream ss;
        ss << in.rdbuf();
        const bool same = ss.str() == text;
        std::printf("%s: %s\n", rel.c_str(), same ? "up to date" : "DIFFERS from the generator");
        if (!same) rc = 1;
      }
    }
    if (write) {
      std::ofstream out(path, std::ios::binary);
      out << text;
      if (!out) throw UsageError("cannot write " + path);
      std::printf("wrote %s\n", path.c_str());
    }
  }
  return rc;
}

}  // namespace

RU_COMMAND("noise tables", "run the noise table generator; --check / --write the generated files", run_noise_tables);

}  // namespace ru::cli
