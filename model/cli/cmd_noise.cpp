// rayunits noise ...: the gradient noise unit (Kensler ch. 4): `noise study`, `noise tables`,
// `noise eval` and `bench noise`. See docs/NOISE.md.
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

FixedConfig make_fixed(int b, int ib, int ow) {
  FixedConfig c{b, ib, ow};
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  return c;
}

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

// ---- noise eval ----------------------------------------------------------------------------
int run_noise_eval(int argc, char** argv) {
  CLI::App app{
      "Evaluate every noise at one point X = (x, y, z) in full-resolution lattice units: Perlin improved, Kensler "
      "full (256 gradients), projected (with --normal), half-resolution (64 gradients), and the fixed-point unit "
      "at u = X/2 (its input is in half-resolution cells). --trace prints the unit's intermediate values.",
      "rayunits noise eval"};
  std::vector<double> p, n;
  int b = 8, ib = 8, ow = 10;
  bool trace = false;
  app.add_option("point", p, "x y z")->required()->expected(3);
  app.add_option("--normal", n, "surface normal for the projected noise (normalized here)")->expected(3);
  app.add_option("--frac-bits", b, "fixed point: fraction bits (4..16, default 8)");
  app.add_option("--int-bits", ib, "fixed point: input integer bits incl. sign (1..24, default 8)");
  app.add_option("--out-w", ow, "fixed point: output width (2..2B+6, default 10)");
  app.add_flag("--trace", trace, "print the fixed-point datapath values");
  if (!parse_args(app, argc, argv)) return 0;
  for (double v : p)
    if (!std::isfinite(v) || std::fabs(v) > 1e9) throw UsageError("coordinates must be finite and |x| <= 1e9");
  FixedNoise fx(make_fixed(b, ib, ow));
  Vec3 N{};
  if (!n.empty()) {
    double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0) || !std::isfinite(len)) throw UsageError("--normal must be a finite non-zero vector");
    N = {n[0] / len, n[1] / len, n[2] / len};
  }
  NoiseRef r256(builtin_tables(), 256), r64(builtin_tables(), 64);
  std::printf("perlin_improved   %.17g\n", perlin_improved(p[0], p[1], p[2]));
  std::printf("kensler_full      %.17g\n", r256.full(p[0], p[1], p[2]));
  if (!n.empty()) std::printf("kensler_projected %.17g\n", r256.projected({p[0], p[1], p[2]}, N));
  std::printf("half_res          %.17g   (N(u) = half/2 = %.17g)\n", r64.half(p[0], p[1], p[2]),
              r64.half_cell(p[0] / 2, p[1] / 2, p[2] / 2));
  std::int64_t w[3];
  for (int a = 0; a < 3; ++a) w[a] = fx.quantize(p[a] / 2);
  FixedTrace t;
  std::int64_t v = fx.eval(w[0], w[1], w[2], &t);
  const int iw = fx.config().in_w();
  const std::uint64_t im = iw >= 64 ? ~0ull : (1ull << iw) - 1, om = (1ull << fx.config().out_w) - 1;
  std::printf("fixed (%s)  x_i=0x%llx y_i=0x%llx z_i=0x%llx -> value_o=0x%llx (%lld) = N %.9g%s\n",
              fx.config().describe().c_str(), static_cast<unsigned long long>(w[0] & im),
              static_cast<unsigned long long>(w[1] & im), static_cast<unsigned long long>(w[2] & im),
              static_cast<unsigned long long>(static_cast<std::uint64_t>(v) & om), static_cast<long long>(v),
              fx.to_real(v), t.saturated ? " (saturated)" : "");
  if (trace) {
    for (int a = 0; a < 3; ++a)
      std::printf("  axis %c: cell %3d frac %5d hash {%2d,%2d} sq {%d,%d}\n", "xyz"[a], t.cell[a], t.frac[a],
                  t.hash[a][0], t.hash[a][1], t.sq[a][0], t.sq[a][1]);
    for (int c = 0; c < 8; ++c)
      std::printf("  corner %d%d%d: d %d t %d t2 %d t4 %d t5 %d w %d | h %2d g (%d %d %d) dot %lld | w*dot %lld\n",
                  c & 1, (c >> 1) & 1, c >> 2, t.d[c], t.t[c], t.t2[c], t.t4[c], t.t5[c], t.w[c], t.h[c], t.g[c][0],
                  t.g[c][1], t.g[c][2], static_cast<long long>(t.dot[c]), static_cast<long long>(t.contrib[c]));
    std::printf("  sum %lld (2B fraction bits)\n", static_cast<long long>(t.sum));
  }
  return 0;
}

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
}  // namespace ru::cli

RU_COMMAND("noise study", "noise unit quality: spectra, fixed-point error vs fraction bits, output range", ru::cli::run_noise_study);
RU_COMMAND("noise tables", "run the noise table generator; --check / --write the generated files", ru::cli::run_noise_tables);
RU_COMMAND("noise eval", "evaluate every noise (and the fixed-point unit) at one point", ru::cli::run_noise_eval);
RU_COMMAND("bench noise", "noise evaluations/s in software vs the hardware unit's one result per clock", ru::cli::run_bench_noise);
