// rayunits bench trax: simulated thread-instructions per second of the TRaX model on one host
// core (issue 7 section 6; target >= 5 M/s without co-simulation) and the slowdown factor of
// --cosim, measured on the same frame in one run; medians over repeats.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "cli_util.hpp"
#include "render_common.hpp"
#include "rayunits/trax/cosim.hpp"
#include "rayunits/trax/trax.hpp"

namespace ru::cli {
namespace {

int run_bench_trax(int argc, char** argv) {
  CLI::App app{"TRaX model benchmark: simulated thread-instructions/s on one host core (functional execution in "
               "the emulated format included) and the --cosim slowdown on the same frame, medians over repeats"};
  SceneArgs sa;
  sa.add(app, "default");
  std::string size = "64x64", cosim_size = "32x32", format;
  int repeats = 5, cosim_repeats = 3;
  bool no_cosim = false;
  app.add_option("--size", size, "image size of the timing runs");
  app.add_option("--repeats", repeats, "runs timed (median)")->check(CLI::Range(1, 100));
  app.add_option("--format", format, "number format (default: the default configuration's, e8m23)");
  app.add_option("--cosim-size", cosim_size, "image size of the with/without --cosim comparison");
  app.add_option("--cosim-repeats", cosim_repeats, "co-simulated runs timed (median)")->check(CLI::Range(1, 20));
  app.add_flag("--no-cosim", no_cosim, "skip the co-simulation comparison");
  if (!parse_args(app, argc, argv)) return 0;
  trax::Config cfg = trax::default_config();
  if (!format.empty()) cfg.format = format;
  try {
    cfg.validate();
  } catch (const trax::ConfigError& e) {
    throw UsageError(e.what());
  }
  const scene::Scene s = sa.load();
  int w, h;
  parse_size(size, &w, &h);
  auto timed = [&](int ww, int hh, int n, bool cosim, uint64_t* instr) {
    std::vector<double> t;
    for (int i = 0; i < n; ++i) {
      // wall clock of the whole run: scene preparation, simulation, and with --cosim the
      // companion's start and its draining of the stream (it runs in parallel on the other core)
      const auto t0 = std::chrono::steady_clock::now();
      std::unique_ptr<trax::cosim::Client> cl;
      if (cosim) {
        cl = std::make_unique<trax::cosim::Client>(trax::cosim::default_executable());
        try {
          cl->start(trax::resolve_config(cfg));
        } catch (const std::runtime_error& e) {
          throw UsageError(e.what());
        }
      }
      const trax::TraxResult r = trax::run_trax(s, cfg, ww, hh, false, cl.get());
      if (cl) {
        const trax::cosim::Outcome o = cl->finish(r.sim.cycles);
        if (!o.ok) throw UsageError("co-simulation failed: " + o.summary.substr(0, o.summary.find('\n')));
      }
      const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      *instr = r.sim.instructions;
      t.push_back(sec);
    }
    return median(t);
  };
  uint64_t instr = 0;
  std::fprintf(stderr, "bench trax: %s %dx%d, %d runs\n", s.name.c_str(), w, h, repeats);
  timed(w, h, 1, false, &instr);  // warm-up
  const double t = timed(w, h, repeats, false, &instr);
  std::printf("scene %s %dx%d, %s, %d TMs x %d TPs: %llu thread-instructions, median %.3f s over %d runs = %.2f M "
              "thread-instructions/s on one host core (wall clock incl. scene preparation; target >= 5)\n",
              s.name.c_str(), w, h, cfg.format.c_str(), cfg.tms, cfg.tps_per_tm, (unsigned long long)instr, t, repeats,
              instr / t / 1e6);
  if (!no_cosim) {
    int cw, ch;
    parse_size(cosim_size, &cw, &ch);
    uint64_t ci = 0;
    std::fprintf(stderr, "bench trax: --cosim comparison at %dx%d\n", cw, ch);
    const double tp = timed(cw, ch, repeats, false, &ci);
    const double tc = timed(cw, ch, cosim_repeats, true, &ci);
    std::printf("--cosim at %dx%d: median %.3f s (%d runs) vs %.3f s without (%d runs): slowdown x%.1f "
                "(%.2f M thread-instructions/s co-simulated)\n",
                cw, ch, tc, cosim_repeats, tp, repeats, tc / tp, ci / tc / 1e6);
  }
  return 0;
}

}  // namespace

RU_COMMAND("bench trax", "TRaX model speed: simulated thread-instructions/s and the --cosim slowdown", run_bench_trax);

}  // namespace ru::cli
