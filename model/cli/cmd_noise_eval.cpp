// rayunits noise eval: every noise (references and the fixed-point unit) at one point.
// See docs/NOISE.md.
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

// ---- noise eval ----------------------------------------------------------------------------
int run_noise_eval(int argc, char** argv) {
  CLI::App app{
      "Evaluate every noise at one point X = (x, y, z) in full-resolution lattice units: Perlin improved, Kensler "
      "full (256 gradients), projected (with --normal), half-resolution (64 gradients), and the fixed-point units "
      "(ru_noise; ru_noise_trunc for 5 or more fraction bits) at u = X/2 (their input is in half-resolution cells). "
      "--trace prints the units' intermediate values.",
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
  // The unit's datapaths: ru_noise, and ru_noise_trunc where it exists (B >= 5; docs/NOISE.md).
  auto show = [&](const FixedNoise& f) {
    std::int64_t w[3];
    for (int a = 0; a < 3; ++a) w[a] = f.quantize(p[a] / 2);
    FixedTrace t;
    std::int64_t v = f.eval(w[0], w[1], w[2], &t);
    const int iw = f.config().in_w();
    const std::uint64_t im = iw >= 64 ? ~0ull : (1ull << iw) - 1, om = (1ull << f.config().out_w) - 1;
    std::printf("fixed (%s)  x_i=0x%llx y_i=0x%llx z_i=0x%llx -> value_o=0x%llx (%lld) = N %.9g%s\n",
                f.config().describe().c_str(), static_cast<unsigned long long>(w[0] & im),
                static_cast<unsigned long long>(w[1] & im), static_cast<unsigned long long>(w[2] & im),
                static_cast<unsigned long long>(static_cast<std::uint64_t>(v) & om), static_cast<long long>(v),
                f.to_real(v), t.saturated ? " (saturated)" : "");
    if (!trace) return;
    const bool tr = f.config().datapath == NoiseDatapath::kTrunc;
    for (int a = 0; a < 3; ++a)
      std::printf("  axis %c: cell %3d frac %5d hash {%2d,%2d} sq {%d,%d}\n", "xyz"[a], t.cell[a], t.frac[a],
                  t.hash[a][0], t.hash[a][1], t.sq[a][0], t.sq[a][1]);
    for (int c = 0; c < 8; ++c) {
      std::printf("  corner %d%d%d: d %d ", c & 1, (c >> 1) & 1, c >> 2, t.d[c]);
      if (tr)
        std::printf("table[%d] w %d", t.t[c], t.w[c]);
      else
        std::printf("t %d t2 %d t4 %d t5 %d w %d", t.t[c], t.t2[c], t.t4[c], t.t5[c], t.w[c]);
      std::printf(" | h %2d g (%d %d %d) dot %lld | w*dot %lld\n", t.h[c], t.g[c][0], t.g[c][1], t.g[c][2],
                  static_cast<long long>(t.dot[c]), static_cast<long long>(t.contrib[c]));
    }
    std::printf("  sum %lld (%d fraction bits)\n", static_cast<long long>(t.sum), b + f.dot_frac_bits());
  };
  show(fx);
  if (b >= 5 && b <= 12) {  // the truncated datapath's range (its weight table)
    FixedConfig tc = fx.config();
    tc.datapath = NoiseDatapath::kTrunc;
    show(FixedNoise(tc));
  }
  return 0;
}

}  // namespace

RU_COMMAND("noise eval", "evaluate every noise (and the fixed-point units) at one point", run_noise_eval);

}  // namespace ru::cli
