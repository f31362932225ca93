// rayunits bench noise: noise evaluations/s in software vs the hardware unit's one result per
// clock. See docs/NOISE.md.
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

// ---- bench noise ---------------------------------------------------------------------------
double find_fmax(const nlohmann::json& j) {
  if (j.is_object()) {
    for (const char* k : {"fmax_mhz", "fmax_est_mhz"})
      if (j.contains(k) && j[k].is_number()) return j[k].get<double>();
    for (const auto& [k, v] : j.items()) {
      double f = find_fmax(v);
      if (f > 0) return f;
    }
  } else if (j.is_array()) {
    for (const auto& v : j) {
      double f = find_fmax(v);
      if (f > 0) return f;
    }
  }
  return 0;
}

// CPU time of the calling thread: robust on the shared, loaded machine (wall clock is not).
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

int run_bench_noise(int argc, char** argv) {
  CLI::App app{
      "Software noise evaluations per second on this machine (one thread, median of --reps timed runs over the "
      "same random points): Perlin improved (double), Kensler full (4-point radial kernel, 256 gradients), "
      "Kensler projected, half-resolution (float), and the bit-accurate fixed-point model; then the hardware "
      "unit's one result per clock at its estimated Fmax and the speedup over each.",
      "rayunits bench noise"};
  size_t n = 1 << 16;
  int reps = 7;
  double min_time = 0.05, fmax = 0;
  int depth = 48;
  std::string synth_json;
  std::uint64_t seed = 1;
  app.add_option("--n", n, "points per pass (default 65536)");
  app.add_option("--reps", reps, "timed runs; the median is reported (default 7)");
  app.add_option("--min-time", min_time, "seconds per timed run, at least (default 0.05)");
  app.add_option("--seed", seed, "point seed (default 1)");
  app.add_option("--fmax-mhz", fmax, "the unit's clock for the hardware line");
  app.add_option("--synth-json", synth_json, "read fmax_mhz from `rayunits synth noise --stages N --json F` output");
  app.add_option("--depth", depth,
                 "else: worst-stage logic depth for the delay model (default 48, ru_noise Stages=4 measured with "
                 "Yosys 0.23, docs/NOISE.md)");
  if (!parse_args(app, argc, argv)) return 0;
  if (n < 1 || n > (1u << 24)) throw UsageError("--n must be 1..16777216");
  if (reps < 1 || reps > 1000) throw UsageError("--reps must be 1..1000");
  if (!(min_time > 0 && min_time <= 10)) throw UsageError("--min-time must be in (0, 10]");
  std::string fmax_src;
  if (!synth_json.empty()) {
    std::ifstream in(synth_json);
    if (!in) throw UsageError("cannot read " + synth_json);
    nlohmann::json j;
    try {
      in >> j;
    } catch (const std::exception& e) {
      throw UsageError(synth_json + ": not JSON (" + e.what() + ")");
    }
    fmax = find_fmax(j);
    if (!(fmax > 0)) throw UsageError(synth_json + ": no fmax_mhz field");
    fmax_src = synth_json;
  } else if (fmax > 0) {
    fmax_src = "--fmax-mhz";
  } else {
    if (depth < 1 || depth > 10000) throw UsageError("--depth must be 1..10000");
    fmax = ru::synth::DelayModel::fmax_mhz(depth);
    fmax_src = "delay model " + std::string(ru::synth::DelayModel::kName) + " at depth " + std::to_string(depth);
  }

  NoiseRef r256(builtin_tables(), 256), r64(builtin_tables(), 64);
  FixedNoise fx;
  std::vector<double> px(n), py(n), pz(n);
  std::vector<std::int64_t> wx(n), wy(n), wz(n);
  std::uint64_t s = seed;
  for (size_t i = 0; i < n; ++i) {
    double* q[3] = {&px[i], &py[i], &pz[i]};
    for (double* v : q) *v = util::unit_double(util::splitmix64(s)) * 256 - 128;
    wx[i] = fx.quantize(px[i] / 2);
    wy[i] = fx.quantize(py[i] / 2);
    wz[i] = fx.quantize(pz[i] / 2);
  }
  const Vec3 N = (1.0 / std::sqrt(3.0)) * Vec3{1, 1, 1};
  volatile double sink = 0;
  struct Case {
    const char* name;
    std::function<double()> pass;
  };
  std::vector<Case> cases = {
      {"perlin_improved (double)",
       [&] {
         double a = 0;
         for (size_t i = 0; i < n; ++i) a += perlin_improved(px[i], py[i], pz[i]);
         return a;
       }},
      {"kensler_full (double)",
       [&] {
         double a = 0;
         for (size_t i = 0; i < n; ++i) a += r256.full(px[i], py[i], pz[i]);
         return a;
       }},
      {"kensler_projected (double)",
       [&] {
         double a = 0;
         for (size_t i = 0; i < n; ++i) a += r256.projected({px[i], py[i], pz[i]}, N);
         return a;
       }},
      {"half_res (double)",
       [&] {
         double a = 0;
         for (size_t i = 0; i < n; ++i) a += r64.half(px[i], py[i], pz[i]);
         return a;
       }},
      {"fixed-point model B=8",
       [&] {
         std::int64_t a = 0;
         for (size_t i = 0; i < n; ++i) a += fx.eval(wx[i], wy[i], wz[i]);
         return static_cast<double>(a);
       }},
  };
  std::printf("bench noise: one thread, %zu random points in [-128, 128)^3, million evaluations per CPU-second "
              "(thread CPU time), median of %d runs (>= %.2f s each)\n\n",
              n, reps, min_time);
  std::printf("%-28s %12s %12s %10s\n", "implementation", "Meval/s", "ns/eval", "hw speedup");
  const double hw = fmax * 1e6;  // evaluations per second: one per clock
  for (const Case& c : cases) {
    std::vector<double> t;
    for (int r = 0; r < reps; ++r) {
      const double t0 = thread_cpu_seconds();
      size_t passes = 0;
      double el = 0;
      do {
        sink = sink + c.pass();
        ++passes;
        el = thread_cpu_seconds() - t0;
      } while (el < min_time);
      t.push_back(el / static_cast<double>(passes * n));
    }
    std::sort(t.begin(), t.end());
    double sec = t[t.size() / 2];
    std::printf("%-28s %12.2f %12.1f %9.0fx\n", c.name, 1e-6 / sec, sec * 1e9, hw * sec);
    std::fflush(stdout);
  }
  std::printf("%-28s %12.2f %12.3f %10s\n", "hardware ru_noise (1/clock)", fmax, 1e3 / fmax, "1x");
  std::printf("\nhardware clock %.1f MHz from %s. Dissertation: 16.7 M evaluations/s (Perlin, 2.8 GHz Core 2) vs "
              "1 G/s for the unit (60x).\n",
              fmax, fmax_src.c_str());
  return 0;
}

}  // namespace

RU_COMMAND("bench noise", "noise evaluations/s in software vs the hardware unit's one result per clock", run_bench_noise);

}  // namespace ru::cli
