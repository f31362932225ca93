// FFT, power spectra and the spectral measures of the noise study; and the spectral claims of
// Kensler sec. 4.5-4.7 measured on the reference noises.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <functional>
#include <map>
#include <random>

#include "rayunits/noise/spectrum.hpp"
#include "rayunits/noise/study.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::noise {
namespace {

using cd = std::complex<double>;

std::vector<cd> naive_dft(const std::vector<cd>& x) {
  const size_t n = x.size();
  std::vector<cd> X(n);
  for (size_t k = 0; k < n; ++k)
    for (size_t j = 0; j < n; ++j) X[k] += x[j] * std::polar(1.0, -2 * M_PI * static_cast<double>(j * k % n) / n);
  return X;
}

TEST(NoiseSpectrum, FftMatchesNaiveDft) {
  std::mt19937_64 g(1);
  std::normal_distribution<double> nd;
  for (size_t n : {1u, 2u, 8u, 64u, 256u}) {
    std::vector<cd> x(n);
    for (auto& v : x) v = {nd(g), nd(g)};
    std::vector<cd> X = x;
    fft(X);
    std::vector<cd> R = naive_dft(x);
    for (size_t k = 0; k < n; ++k) EXPECT_LT(std::abs(X[k] - R[k]), 1e-10 * std::sqrt(double(n))) << n << " " << k;
    fft(X, true);
    for (size_t k = 0; k < n; ++k) EXPECT_LT(std::abs(X[k] / double(n) - x[k]), 1e-12);
  }
  std::vector<cd> bad(12);
  EXPECT_THROW(fft(bad), std::invalid_argument);
}

TEST(NoiseSpectrum, Fft2MatchesNaiveAndParseval) {
  std::mt19937_64 g(2);
  std::normal_distribution<double> nd;
  const int w = 16, h = 8;
  std::vector<cd> a(w * h);
  for (auto& v : a) v = nd(g);
  std::vector<cd> A = a;
  fft2(A, w, h);
  double e_time = 0, e_freq = 0;
  for (int ky = 0; ky < h; ++ky)
    for (int kx = 0; kx < w; ++kx) {
      cd s = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          s += a[y * w + x] * std::polar(1.0, -2 * M_PI * (double(kx * x) / w + double(ky * y) / h));
      EXPECT_LT(std::abs(s - A[ky * w + kx]), 1e-10);
    }
  for (int i = 0; i < w * h; ++i) {
    e_time += std::norm(a[i]);
    e_freq += std::norm(A[i]);
  }
  EXPECT_NEAR(e_freq, e_time * w * h, 1e-9 * e_freq);
}

Image make(int n, const std::function<double(int, int)>& f) {
  Image im(n, n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) im.at(x, y) = f(x, y);
  return im;
}

TEST(NoiseSpectrum, BandFractionsOfSinusoids) {
  const int n = 256;  // 4 px per lattice: bin k <-> k/64 cycles per lattice spacing
  SpectrumParams p;
  // 0.375 cycles per lattice = bin 24: inside the band
  Image in_band = make(n, [](int x, int) { return std::sin(2 * M_PI * 24 * x / 256.0); });
  SpectrumStats s = spectrum_stats(power_spectrum(in_band, false), p);
  EXPECT_GT(s.band_frac, 0.999);
  EXPECT_NEAR(s.q10, 0.375, 1e-12);
  EXPECT_NEAR(s.q90, 0.375, 1e-12);
  EXPECT_EQ(s.octaves, 0.0);
  EXPECT_GT(s.anisotropy, 2.0);  // all power at one angle
  // 0.125 cycles per lattice: low; 1.25: high
  Image low = make(n, [](int, int y) { return std::cos(2 * M_PI * 8 * y / 256.0); });
  EXPECT_GT(spectrum_stats(power_spectrum(low), p).low_frac, 0.99);
  Image high = make(n, [](int x, int y) { return std::cos(2 * M_PI * (80 * x + 5 * y) / 256.0); });
  EXPECT_GT(spectrum_stats(power_spectrum(high), p).high_frac, 0.99);
  // two tones an octave apart, equal power: q10 at the lower, q90 at the upper, 1 octave
  Image two = make(n, [](int x, int y) { return std::cos(2 * M_PI * 16 * x / 256.0) + std::cos(2 * M_PI * 32 * y / 256.0); });
  SpectrumStats t = spectrum_stats(power_spectrum(two, false), p);
  EXPECT_NEAR(t.octaves, 1.0, 1e-12);
}

TEST(NoiseSpectrum, WhiteNoiseIsIsotropicAndUnstriated) {
  std::mt19937_64 g(3);
  std::normal_distribution<double> nd;
  Image w = make(512, [&](int, int) { return nd(g); });
  SpectrumStats s = spectrum_stats(power_spectrum(w, false), {});
  // sampling floor: ~1/sqrt(bins per angle bin) and ~1 for the striation index
  EXPECT_LT(s.anisotropy, 0.1);
  EXPECT_NEAR(s.striation_x, 1.0, 0.3);
  EXPECT_NEAR(s.striation_y, 1.0, 0.3);
}

TEST(NoiseSpectrum, ShiftedColumnsAreStriated) {
  // Planted structure: every column is a cyclic shift of one random sequence (what Perlin's
  // hash does along an axis): the lines of constant ky must stand out.
  std::mt19937_64 g(4);
  std::normal_distribution<double> nd;
  std::vector<double> seq(256);
  for (double& v : seq) v = nd(g);
  std::vector<int> shift(256);
  for (int& s : shift) s = static_cast<int>(g() % 256);
  Image im = make(256, [&](int x, int y) { return seq[(y + shift[x]) % 256]; });
  SpectrumStats s = spectrum_stats(power_spectrum(im, false), {});
  EXPECT_GT(s.striation_y, 3 * s.striation_x);
  // transposed: the other index
  Image tr = make(256, [&](int x, int y) { return seq[(x + shift[y]) % 256]; });
  SpectrumStats u = spectrum_stats(power_spectrum(tr, false), {});
  EXPECT_GT(u.striation_x, 3 * u.striation_y);
}

// Kensler Fig. 4.5: the single-table hash striates the spectrum, the xor hash does not.
TEST(NoiseSpectrum, XorHashRemovesStriation) {
  auto noises = study_noises(FixedNoise());
  const NoiseSpec *perlin = nullptr, *xorh = nullptr;
  for (const auto& s : noises) {
    if (s.name == "perlin_hash_256") perlin = &s;
    if (s.name == "xor_hash_256") xorh = &s;
  }
  ASSERT_TRUE(perlin && xorh);
  SpectrumParams p;
  p.px_per_lattice = 2;  // 512 px = 256 lattice spacings: one table period
  SpectrumStats sp = spectrum_stats(power_spectrum(render_slice(*perlin, 512, 2), false), p);
  SpectrumStats sx = spectrum_stats(power_spectrum(render_slice(*xorh, 512, 2), false), p);
  EXPECT_GT(sp.striation_y, 2.5 * sx.striation_y);
  EXPECT_GT(sp.striation_y, 2 * sp.striation_x);
  EXPECT_LT(sx.striation_y, 1.5 * sx.striation_x);
}

// Kensler Fig. 4.8/4.10: a diagonal slice of 3D noise leaks low frequencies; projection
// removes them. And the radial kernel band-limits better than Perlin's (Fig. 4.7).
TEST(NoiseSpectrum, ProjectionRemovesLowFrequencies) {
  auto noises = study_noises(FixedNoise());
  std::map<std::string, SpectrumStats> st;
  for (const auto& s : noises)
    if (s.name == "kensler_full_diag" || s.name == "kensler_projected" || s.name == "perlin_improved")
      st[s.name] = spectrum_stats(power_spectrum(render_slice(s, 256, 4)), {});
  EXPECT_LT(st["kensler_projected"].low_frac, 0.5 * st["kensler_full_diag"].low_frac);
  // and the projected noise is the most band-limited of the three
  EXPECT_LT(st["kensler_projected"].octaves, 0.7 * st["kensler_full_diag"].octaves);
  EXPECT_LT(st["kensler_full_diag"].octaves, st["perlin_improved"].octaves);
}

TEST(NoiseSpectrum, PngViewsHaveTheRequestedSize) {
  Image im = make(64, [](int x, int y) { return std::sin(x * 0.3) * std::cos(y * 0.2); });
  EXPECT_EQ(gray_linear(im, 1.0).size(), 64u * 64u);
  EXPECT_EQ(spectrum_view(power_spectrum(im), 32).size(), 32u * 32u);
  EXPECT_THROW(spectrum_view(power_spectrum(im), 128), std::invalid_argument);
  EXPECT_THROW(write_png_gray("/nonexistent-dir/x.png", 64, 64, gray_linear(im, 1.0)), std::runtime_error);
}

TEST(NoiseBounds, HalfResolutionBoundHoldsAndIsTight) {
  Bound b = bound_half_cell(24);
  EXPECT_GT(b.value, 0.17);
  EXPECT_LT(b.value, 0.19);
  // the bound holds on a dense sample of the float noise
  NoiseRef r(builtin_tables(), 64);
  std::mt19937_64 g(5);
  std::uniform_real_distribution<double> u(-128, 128);
  double mx = 0;
  for (int i = 0; i < 200000; ++i) mx = std::max(mx, std::fabs(r.half_cell(u(g), u(g), u(g))));
  EXPECT_LE(mx, b.value);
  EXPECT_GT(mx, 0.8 * b.value);
}

TEST(NoiseBounds, FixedBoundIsRigorousForSmallB) {
  // B = 5: the exhaustive bound, checked against every input of the first 4 x 4 x 4 cells, for
  // both datapaths (a bound that assumed the truncated dot product's former width failed here).
  for (const NoiseDatapath dp : {NoiseDatapath::kFull, NoiseDatapath::kTrunc}) {
    FixedConfig c{5, 8, 16};
    c.datapath = dp;
    FixedNoise f(c);
    double b = bound_fixed(f);
    double mx = 0;
    for (std::int64_t x = 0; x < 128; ++x)
      for (std::int64_t y = 0; y < 128; ++y)
        for (std::int64_t z = 0; z < 128; ++z) mx = std::max(mx, std::fabs(f.to_real(f.eval(x, y, z))));
    EXPECT_LE(mx, b) << c.describe();
    EXPECT_GT(mx, 0.5 * b) << c.describe();  // and not loose
    EXPECT_LT(b, 0.5);
  }
}

}  // namespace
}  // namespace ru::noise

namespace ru::noise {
namespace {

// 10^7 samples of the float half-resolution noise and of the fixed-point unit (B = 8): both
// stay within their derived bounds (the fixed-point one is rigorous, exhaustive over a cell).
TEST(LongNoiseBounds, RangeOver1e7Samples) {
  FixedNoise f({8, 8, 15});
  const double bf = bound_fixed(f), bh = bound_half_cell().value;
  NoiseRef r(builtin_tables(), 64);
  std::uint64_t s = 99;
  double mf = 0, mh = 0;
  for (long i = 0; i < 10000000; ++i) {
    std::int64_t w[3];
    for (auto& v : w) v = static_cast<std::int64_t>(util::splitmix64(s) & 0xffff);
    mf = std::max(mf, std::fabs(f.to_real(f.eval(w[0], w[1], w[2]))));
    mh = std::max(mh, std::fabs(r.half_cell(f.input_real(w[0]), f.input_real(w[1]), f.input_real(w[2]))));
  }
  EXPECT_LE(mf, bf);
  EXPECT_LE(mh, bh);
  EXPECT_GT(mh, 0.95 * bh);  // the Cauchy-Schwarz bound is nearly attained
  std::printf("max |fixed| %.6f (bound %.6f), max |half| %.6f (bound %.6f)\n", mf, bf, mh, bh);
}

}  // namespace
}  // namespace ru::noise
