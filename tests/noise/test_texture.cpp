// The procedural texture unit's model (noise::FixedTexture, rtl/ru_texture.sv; docs/NOISE.md "The
// procedural texture unit") against an independent specification: real coordinates, each
// octave's noise input by FixedNoise::quantize(2^(L o) u) (not the model's shifted words), the
// sums and transfer functions in long double (exact at these widths), the square root by
// sqrtl with an integer fix-up (not the model's recurrence). Planted changes to the specification
// must be caught.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>

#include "rayunits/noise/texture.hpp"

namespace ru::noise {
namespace {

struct Plant {
  bool no_abs = false;      // turbulence without |.|
  int gain_shift_delta = 0;  // wrong gain
  double wood_scale = 4;     // the rings' frequency
  double marble_turb = 1.5;  // the marble's turbulence weight
};

long double floor_to(long double v, int frac) { return std::floor(std::ldexp(v, frac)); }

std::int64_t spec_eval(const FixedTexture& t, TextureMode m, int n, std::int64_t x, std::int64_t y,
                       std::int64_t z, const Plant& p = {}) {
  const TextureConfig& C = t.config();
  const FixedNoise& N = t.noise();
  n = std::clamp(n, 1, C.octaves);
  auto real = [&](std::int64_t w) {  // the word as a coordinate u (two's complement, in_w bits)
    const std::int64_t m = (std::int64_t{1} << C.in_w()) - 1;
    std::int64_t v = w & m;
    if (v >> (C.in_w() - 1)) v -= m + 1;
    return std::ldexp(static_cast<long double>(v), -C.in_frac());
  };
  const long double ux = real(x), uy = real(y), uz = real(z);
  const bool absolute = m == TextureMode::kTurbulence || m == TextureMode::kGranite || m == TextureMode::kMarble;
  long double s = 0;
  for (int o = 0; o < n; ++o) {
    const double k = std::ldexp(1.0, C.lac_shift * o);
    const std::int64_t v = N.eval(N.quantize(static_cast<double>(k * ux)), N.quantize(static_cast<double>(k * uy)),
                                  N.quantize(static_cast<double>(k * uz)));
    const long double vr = std::ldexp(static_cast<long double>(v), -C.noise.out_w);
    s += std::ldexp(absolute && !p.no_abs ? std::fabs(vr) : vr, -(C.gain_shift + p.gain_shift_delta) * o);
  }
  long double f = s;
  switch (m) {
    case TextureMode::kFbm:
    case TextureMode::kTurbulence: break;
    case TextureMode::kGranite: f = std::min<long double>(1, 1.5L * s); break;
    case TextureMode::kMarble: {
      const long double a = ux + p.marble_turb * s;
      f = std::fabs(2 * (a - std::floor(a)) - 1);
      break;
    }
    case TextureMode::kWood: {
      const long double sc = std::ldexp(1.0L, C.in_frac());
      const std::int64_t X = static_cast<std::int64_t>(ux * sc), Y = static_cast<std::int64_t>(uy * sc);
      const std::int64_t q = X * X + Y * Y;
      std::int64_t r = static_cast<std::int64_t>(std::sqrt(static_cast<long double>(q)));
      while (r * r > q) --r;
      while ((r + 1) * (r + 1) <= q) ++r;
      const long double g = p.wood_scale * (static_cast<long double>(r) / sc) + s;
      const long double fr = g - std::floor(g);
      f = fr * fr;
      break;
    }
  }
  return static_cast<std::int64_t>(floor_to(f, C.out_frac));
}

TextureConfig config(int b, int octaves, int lac, int gain, int out_frac, NoiseDatapath dp) {
  TextureConfig c;
  c.noise = default_config(dp);
  c.noise.frac_bits = b;
  c.noise.out_w = std::min(10, 2 * b + 6);
  c.octaves = octaves;
  c.lac_shift = lac;
  c.gain_shift = gain;
  c.out_frac = out_frac;
  return c;
}

std::int64_t word(std::mt19937_64& g, const TextureConfig& c) {
  return static_cast<std::int64_t>(g() & ((1ull << c.in_w()) - 1));
}

const std::vector<TextureConfig>& configs() {
  static const std::vector<TextureConfig> v = {
      TextureConfig{},                                            // the default: B 8, 8 octaves, trunc
      config(8, 4, 1, 1, 12, NoiseDatapath::kFull),               // around ru_noise
      config(6, 8, 1, 2, 8, NoiseDatapath::kTrunc),               // 8 octaves, gain 1/4
      config(10, 3, 2, 1, 16, NoiseDatapath::kTrunc),             // lacunarity 4
      config(8, 1, 1, 1, 20, NoiseDatapath::kFull),               // one octave, wide output
  };
  return v;
}

TEST(Texture, MatchesSpecificationEveryModeAndOctaveCount) {
  std::mt19937_64 g(41);
  for (const TextureConfig& c : configs()) {
    const FixedTexture t(c);
    for (int mode = 0; mode < kTextureModes; ++mode)
      for (int n = 0; n <= c.octaves + 1; ++n)  // 0 and octaves + 1 are clamped
        for (int i = 0; i < 300; ++i) {
          const std::int64_t x = word(g, c), y = word(g, c), z = word(g, c);
          const TextureMode m = static_cast<TextureMode>(mode);
          ASSERT_EQ(t.eval(m, n, x, y, z), spec_eval(t, m, n, x, y, z))
              << c.describe() << " " << texture_mode_name(m) << " n=" << n << " at " << x << " " << y << " " << z;
        }
  }
}

TEST(Texture, OutputRangeAndWidth) {
  std::mt19937_64 g(43);
  for (const TextureConfig& c : configs()) {
    const FixedTexture t(c);
    const std::int64_t one = std::int64_t{1} << c.out_frac;
    for (int mode = 0; mode < kTextureModes; ++mode)
      for (int i = 0; i < 3000; ++i) {
        const std::int64_t v = t.eval(static_cast<TextureMode>(mode), c.octaves, word(g, c), word(g, c), word(g, c));
        if (mode == 0) {
          EXPECT_GT(v, -2 * one);
          EXPECT_LT(v, 2 * one);
        } else {
          EXPECT_GE(v, 0);
          EXPECT_LE(v, one) << texture_mode_name(static_cast<TextureMode>(mode));
        }
      }
  }
}

TEST(Texture, SpecificationCatchesPlantedErrors) {
  const FixedTexture t{TextureConfig{}};
  std::mt19937_64 g(47);
  auto differs = [&](TextureMode m, const Plant& p) {
    for (int i = 0; i < 200; ++i) {
      const std::int64_t x = word(g, t.config()), y = word(g, t.config()), z = word(g, t.config());
      if (t.eval(m, 4, x, y, z) != spec_eval(t, m, 4, x, y, z, p)) return true;
    }
    return false;
  };
  EXPECT_TRUE(differs(TextureMode::kTurbulence, {true, 0, 4, 1.5}));
  EXPECT_TRUE(differs(TextureMode::kFbm, {false, 1, 4, 1.5}));
  EXPECT_TRUE(differs(TextureMode::kWood, {false, 0, 2, 1.5}));
  EXPECT_TRUE(differs(TextureMode::kMarble, {false, 0, 4, 3.0}));
  EXPECT_FALSE(differs(TextureMode::kMarble, {}));
}

TEST(Texture, OctaveInputsAreTheNoiseUnitsQuantizedScaledPoints) {
  const FixedTexture t{TextureConfig{}};
  std::mt19937_64 g(53);
  for (int i = 0; i < 1000; ++i) {
    const std::int64_t x = word(g, t.config()), y = word(g, t.config()), z = word(g, t.config());
    TextureTrace tr{};
    t.eval(TextureMode::kFbm, 4, x, y, z, &tr);
    ASSERT_EQ(tr.n, 4);
    const int w = t.config().in_w();
    const double u = std::ldexp(static_cast<double>(x - ((x >> (w - 1)) & 1 ? (std::int64_t{1} << w) : 0)), -t.config().in_frac());
    for (int o = 0; o < 4; ++o) EXPECT_EQ(tr.in[o][0], t.noise().quantize(std::ldexp(u, o))) << o;
  }
}

TEST(Texture, SqrtFloorIsExact) {
  const FixedTexture t{TextureConfig{}};
  std::mt19937_64 g(59);
  for (int i = 0; i < 100000; ++i) {
    const std::int64_t v = static_cast<std::int64_t>(g() >> (2 + g() % 60));
    const std::int64_t r = t.sqrt_floor(v);
    ASSERT_LE(r * r, v);
    ASSERT_GT((r + 1) * (r + 1), v);
  }
}

TEST(Texture, BadConfigurationIsOneLine) {
  TextureConfig c;
  c.octaves = 9;
  try {
    FixedTexture t(c);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "texture: octaves must be 1..8, got 9");
  }
  c = TextureConfig{};
  c.noise.int_bits = 24;
  EXPECT_THROW(FixedTexture{c}, std::invalid_argument);  // input words wider than 31 bits
}

}  // namespace
}  // namespace ru::noise
