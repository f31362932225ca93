// The bit-accurate fixed-point model of the noise unit against an independent implementation
// of the specification in docs/NOISE.md (written with doubles and std::floor instead of integer
// shifts, and indexing the permutation tables directly instead of the packed hash entries).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "rayunits/noise/fixed.hpp"
#include "rayunits/noise/reference.hpp"

namespace ru::noise {
namespace {

// docs/NOISE.md, "Fixed-point datapath", steps (1)-(13). Every quantity is an exact double.
std::int64_t spec_eval(const FixedConfig& c, std::int64_t x, std::int64_t y, std::int64_t z) {
  const TableSet& T = builtin_tables();
  const int B = c.frac_bits;
  const double S = std::ldexp(1.0, B);
  auto q = [S](double v) { return std::floor(v * S) / S; };  // floor to B fraction bits
  std::int64_t in[3] = {x, y, z};
  double f[3];
  long cell[3];
  for (int a = 0; a < 3; ++a) {
    // the low in_w bits as a two's complement number
    std::int64_t m = (std::int64_t{1} << c.in_w()) - 1, w = in[a] & m;
    if (w >> (c.in_w() - 1)) w -= std::int64_t{1} << c.in_w();
    double u = std::ldexp(static_cast<double>(w), -B);
    cell[a] = static_cast<long>(std::floor(u));
    f[a] = u - std::floor(u);
  }
  double sum = 0;
  for (int k = 0; k < 8; ++k) {
    int b[3] = {k & 1, (k >> 1) & 1, k >> 2};
    double d = 0, a3[3];
    for (int a = 0; a < 3; ++a) {
      a3[a] = f[a] - b[a];
      d += q(a3[a] * a3[a]);
    }
    double t = std::max(0.0, 1 - d);
    double t2 = q(t * t), t4 = q(t2 * t2), t5 = q(t4 * t);
    double w = 4 * t5 - 3 * t4;
    int h = (T.perm_x[(cell[0] + b[0]) & 255] ^ T.perm_y[(cell[1] + b[1]) & 255] ^ T.perm_z[(cell[2] + b[2]) & 255]) % 64;
    double p = 0;
    for (int a = 0; a < 3; ++a) {
      double g = std::floor(T.grad64_q16[h][a] / 65536.0 * S + 0.5) / S;  // round, ties up
      p += a3[a] * g;
    }
    sum += w * q(p);
  }
  double v = std::floor(std::ldexp(sum, c.out_w + 1));
  double hi = std::ldexp(1.0, c.out_w - 1) - 1, lo = -std::ldexp(1.0, c.out_w - 1);
  return static_cast<std::int64_t>(std::clamp(v, lo, hi));
}

std::int64_t random_word(std::mt19937_64& g, int bits) { return static_cast<std::int64_t>(g() & ((1ull << bits) - 1)); }

TEST(NoiseFixed, MatchesSpecificationRandom) {
  std::mt19937_64 g(11);
  for (int B = 4; B <= 16; ++B)
    for (int ib : {1, 3, 8, 9, 16}) {
      for (int ow : {2, B + 2, 2 * B - 1, 2 * B + 6}) {
        FixedConfig c{B, ib, ow};
        FixedNoise f(c);
        for (int n = 0; n < 1500; ++n) {
          std::int64_t x = random_word(g, c.in_w()), y = random_word(g, c.in_w()), z = random_word(g, c.in_w());
          ASSERT_EQ(f.eval(x, y, z), spec_eval(c, x, y, z)) << c.describe() << " x=" << x << " y=" << y << " z=" << z;
        }
      }
    }
}

TEST(NoiseFixed, MatchesSpecificationExhaustiveCellB5) {
  // every fractional input of one cell (and of a cell across the table wrap)
  for (std::int64_t base : {std::int64_t{0}, std::int64_t{-1}}) {
    FixedConfig c{5, 8, 12};
    FixedNoise f(c);
    for (std::int64_t x = 0; x < 32; ++x)
      for (std::int64_t y = 0; y < 32; ++y)
        for (std::int64_t z = 0; z < 32; ++z) {
          std::int64_t wx = base * 32 + x, wy = 127 * 32 + y, wz = -128 * 32 + z;
          ASSERT_EQ(f.eval(wx, wy, wz), spec_eval(c, wx, wy, wz));
        }
  }
}

TEST(LongNoiseFixed, MatchesSpecificationExhaustiveCellB8) {
  FixedConfig c{8, 8, 10};
  FixedNoise f(c);
  for (std::int64_t x = 0; x < 256; ++x)
    for (std::int64_t y = 0; y < 256; ++y)
      for (std::int64_t z = 0; z < 256; ++z) {
        std::int64_t wx = 37 * 256 + x, wy = -5 * 256 + y, wz = 255 * 256 + z;  // cell 255: the wrap
        ASSERT_EQ(f.eval(wx, wy, wz), spec_eval(c, wx, wy, wz)) << x << " " << y << " " << z;
      }
}

TEST(NoiseFixed, SpecificationCatchesPlantedErrors) {
  // The comparison above must fail for a datapath that differs in one rounding decision.
  FixedConfig c{8, 8, 15};
  FixedNoise f(c);
  std::mt19937_64 g(12);
  // planted error 1: one gradient component off by one LSB (B = 8: 2^8 in Q1.16)
  TableSet t = builtin_tables();
  t.grad64_q16[5][0] += 256;
  FixedNoise bad(c, t);
  int diff_table = 0, diff_sum = 0;
  for (int n = 0; n < 20000; ++n) {
    std::int64_t x = random_word(g, 16), y = random_word(g, 16), z = random_word(g, 16);
    std::int64_t good = spec_eval(c, x, y, z);
    EXPECT_EQ(f.eval(x, y, z), good);
    diff_table += bad.eval(x, y, z) != good;
    // planted error 2: one LSB in the sum
    diff_sum += (f.eval(x, y, z) + 1) != good;
  }
  EXPECT_GT(diff_table, 0);
  EXPECT_EQ(diff_sum, 20000);
}

TEST(NoiseFixed, InternalRangesHoldForEveryT) {
  // The RTL widths: t, t^2, t^4, t^5 in [0, 2^B] (B+1 bits unsigned), w in B+2 bits signed.
  for (int B = 4; B <= 16; ++B) {
    const std::int64_t one = 1ll << B;
    std::int64_t wmin = 0, wmax = 0;
    for (std::int64_t d = 0; d <= 3 * one; ++d) {
      std::int64_t t = d < one ? one - d : 0, t2 = (t * t) >> B, t4 = (t2 * t2) >> B, t5 = (t4 * t) >> B;
      ASSERT_LE(t5, t4);
      ASSERT_LE(t4, one);
      std::int64_t w = 4 * t5 - 3 * t4;
      wmin = std::min(wmin, w);
      wmax = std::max(wmax, w);
    }
    EXPECT_EQ(wmax, one) << B;
    EXPECT_GE(wmin, -(one << 1)) << B;
    EXPECT_LT(wmin, 0) << B;
  }
}

TEST(NoiseFixed, AccuracyAgainstFloatHalfResolution) {
  NoiseRef r(builtin_tables(), 64);
  std::mt19937_64 g(13);
  double prev_rms = 1;
  for (int B : {6, 8, 10, 12}) {
    FixedNoise f({B, 8, 2 * B - 1});
    double se = 0, mx = 0;
    const int n = 40000;
    for (int i = 0; i < n; ++i) {
      std::int64_t w[3] = {random_word(g, B + 8), random_word(g, B + 8), random_word(g, B + 8)};
      double e = f.to_real(f.eval(w[0], w[1], w[2])) -
                 r.half_cell(f.input_real(w[0]), f.input_real(w[1]), f.input_real(w[2]));
      se += e * e;
      mx = std::max(mx, std::fabs(e));
    }
    double rms = std::sqrt(se / n);
    // about 1.3 * 2^-B RMS: every 2 bits divide the error by about 4
    EXPECT_LT(rms, 1.6 * std::ldexp(1.0, -B)) << B;
    EXPECT_LT(mx, 12 * std::ldexp(1.0, -B)) << B;
    EXPECT_LT(rms, prev_rms / 3) << B;
    prev_rms = rms;
  }
}

TEST(NoiseFixed, CoordinatesWrapWithTheTables) {
  std::mt19937_64 g(14);
  FixedNoise wide({8, 12, 10}), narrow({8, 8, 10});
  for (int n = 0; n < 5000; ++n) {
    std::int64_t x = random_word(g, 16) - 32768, y = random_word(g, 16) - 32768, z = random_word(g, 16) - 32768;
    // 256 cells further on: the same value (12 integer bits hold x + 256 cells)
    EXPECT_EQ(wide.eval(x + (256 << 8), y, z - (256 << 8)), wide.eval(x, y, z));
    // 8 integer bits: the same as the wide unit on the same coordinates
    EXPECT_EQ(narrow.eval(x, y, z), wide.eval(x, y, z));
  }
}

TEST(NoiseFixed, NarrowIntegerPartIsSignExtended) {
  // IntBits < 8: the integer part is sign-extended to the 8-bit cell index, so the unit agrees
  // with a wider one on every coordinate it can represent.
  std::mt19937_64 g(15);
  for (int ib = 1; ib < 8; ++ib) {
    FixedNoise n({6, ib, 14}), w({6, 8, 14});
    for (int k = 0; k < 3000; ++k) {
      std::int64_t x = random_word(g, ib + 6), y = random_word(g, ib + 6), z = random_word(g, ib + 6);
      auto sx = [&](std::int64_t v) { return (v >> (ib + 5)) ? v - (std::int64_t{1} << (ib + 6)) : v; };
      ASSERT_EQ(n.eval(x, y, z), w.eval(sx(x), sx(y), sx(z))) << ib;
    }
  }
}

TEST(NoiseFixed, OutputWidthIsFloorOfExactSumThenSaturation) {
  std::mt19937_64 g(16);
  for (int B : {4, 6, 8}) {
    FixedNoise exact({B, 8, 2 * B - 1});
    for (int ow = 2; ow <= 2 * B + 6; ++ow) {
      FixedNoise f({B, 8, ow});
      for (int n = 0; n < 2000; ++n) {
        std::int64_t x = random_word(g, B + 8), y = random_word(g, B + 8), z = random_word(g, B + 8);
        FixedTrace t;
        exact.eval(x, y, z, &t);
        std::int64_t s = t.sum;  // the exact sum (2B fraction bits)
        double v = std::floor(std::ldexp(static_cast<double>(s), ow + 1 - 2 * B));
        double lim = std::ldexp(1.0, ow - 1);
        ASSERT_EQ(f.eval(x, y, z), static_cast<std::int64_t>(std::clamp(v, -lim, lim - 1))) << B << " " << ow;
      }
    }
  }
}

TEST(NoiseFixed, TraceAgreesWithResult) {
  FixedNoise f;
  FixedTrace t;
  std::int64_t v = f.eval(0x1234, -0x0567, 0x7fff, &t);
  EXPECT_EQ(t.value, v);
  std::int64_t s = 0;
  for (int c = 0; c < 8; ++c) {
    EXPECT_EQ(t.contrib[c], std::int64_t{t.w[c]} * t.dot[c]);
    EXPECT_EQ(t.h[c], t.hash[0][c & 1] ^ t.hash[1][(c >> 1) & 1] ^ t.hash[2][c >> 2]);
    s += t.contrib[c];
  }
  EXPECT_EQ(t.sum, s);
  EXPECT_EQ(t.cell[0], 0x12);
  EXPECT_EQ(t.frac[0], 0x34);
  EXPECT_EQ(t.cell[2], 0x7f);
}

TEST(NoiseFixed, QuantizeAndInputReal) {
  FixedNoise f({8, 8, 10});
  EXPECT_EQ(f.quantize(1.5), 384);
  EXPECT_EQ(f.quantize(-0.001), -1);
  EXPECT_EQ(f.input_real(f.quantize(-3.25)), -3.25);
  EXPECT_EQ(f.quantize(128.0), -32768);  // wraps to in_w = 16 bits
}

TEST(NoiseFixed, BadConfigurationsAreRejected) {
  EXPECT_THROW(FixedNoise({3, 8, 10}), std::invalid_argument);
  EXPECT_THROW(FixedNoise({17, 8, 10}), std::invalid_argument);
  EXPECT_THROW(FixedNoise({8, 0, 10}), std::invalid_argument);
  EXPECT_THROW(FixedNoise({8, 25, 10}), std::invalid_argument);
  EXPECT_THROW(FixedNoise({8, 8, 1}), std::invalid_argument);
  EXPECT_THROW(FixedNoise({8, 8, 23}), std::invalid_argument);
  EXPECT_NO_THROW(FixedNoise({8, 8, 22}));
}

}  // namespace
}  // namespace ru::noise
