// Double-precision reference noises (Kensler ch. 4) against published values and brute-force sums.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rayunits/noise/reference.hpp"

namespace ru::noise {
namespace {

TEST(NoiseReference, PerlinImprovedPublishedValue) {
  // Ken Perlin's reference implementation (ImprovedNoise.java): noise(3.14, 42, 7).
  EXPECT_EQ(perlin_improved(3.14, 42, 7), 0.13691995878400012);
}

TEST(NoiseReference, PerlinImprovedZeroAtLatticePoints) {
  for (int i = -3; i < 300; i += 7) EXPECT_EQ(perlin_improved(i, 2 * i + 1, -i), 0.0);
}

TEST(NoiseReference, KernelMatchesBothFormsOfSec46) {
  // s(x) = (2-x)^4 (2+x)^4 (1-x)(1+x) / 256 = 4(1-x^2/4)^5 - 3(1-x^2/4)^4, zero beyond |x| = 2.
  for (double x = -2.5; x <= 2.5; x += 1.0 / 64) {
    double f = std::fabs(x) < 2 ? std::pow(2 - x, 4) * std::pow(2 + x, 4) * (1 - x) * (1 + x) / 256 : 0.0;
    EXPECT_NEAR(kensler_kernel(x * x), f, 1e-14) << x;
  }
  EXPECT_EQ(kensler_kernel(0), 1.0);
  EXPECT_EQ(kensler_kernel(4), 0.0);
  // secondary lobe: s(x) x has opposite-sign lobes; s < 0 for 1 < |x| < 2
  EXPECT_LT(kensler_kernel(1.5 * 1.5), 0.0);
}

// Brute force: every lattice point of a wide window, kernel where d < 4.
double brute_full(const NoiseRef& r, double x, double y, double z) {
  double v = 0;
  for (long k = std::lround(std::floor(z)) - 4; k <= std::lround(std::floor(z)) + 5; ++k)
    for (long j = std::lround(std::floor(y)) - 4; j <= std::lround(std::floor(y)) + 5; ++j)
      for (long i = std::lround(std::floor(x)) - 4; i <= std::lround(std::floor(x)) + 5; ++i) {
        Vec3 D{x - i, y - j, z - k};
        double d = dot(D, D);
        if (d < 4) {
          double t = 1 - d / 4;
          v += dot(D, r.gradient(r.hash_xor(i, j, k))) * (4 * std::pow(t, 5) - 3 * std::pow(t, 4));
        }
      }
  return v;
}

TEST(NoiseReference, FullEqualsBruteForceSum) {
  NoiseRef r(builtin_tables(), 256);
  std::mt19937_64 g(3);
  std::uniform_real_distribution<double> u(-300, 300);
  for (int n = 0; n < 2000; ++n) {
    double x = u(g), y = u(g), z = u(g);
    EXPECT_NEAR(r.full(x, y, z), brute_full(r, x, y, z), 1e-13);
  }
}

TEST(NoiseReference, HalfResolutionUsesEvenLatticePoints) {
  NoiseRef r(builtin_tables(), 64);
  std::mt19937_64 g(4);
  std::uniform_real_distribution<double> u(-600, 600);
  for (int n = 0; n < 2000; ++n) {
    double x = u(g), y = u(g), z = u(g);
    // every even lattice point (2a, 2b, 2c) of a window; its table index is the cell (a, b, c)
    double v = 0;
    long a0 = std::lround(std::floor(x / 2)), b0 = std::lround(std::floor(y / 2)), c0 = std::lround(std::floor(z / 2));
    for (long c = c0 - 2; c <= c0 + 3; ++c)
      for (long b = b0 - 2; b <= b0 + 3; ++b)
        for (long a = a0 - 2; a <= a0 + 3; ++a) {
          Vec3 D{x - 2.0 * a, y - 2.0 * b, z - 2.0 * c};
          double d = dot(D, D);
          if (d < 4) v += dot(D, r.gradient(r.hash_xor(a, b, c))) * kensler_kernel(d);
        }
    EXPECT_NEAR(r.half(x, y, z), v, 1e-13);
    EXPECT_NEAR(r.half_cell(x / 2, y / 2, z / 2), v / 2, 1e-13);
  }
}

TEST(NoiseReference, ProjectedEqualsBruteForceAndFig411Truncates) {
  NoiseRef r(builtin_tables(), 256);
  std::mt19937_64 g(5);
  std::uniform_real_distribution<double> u(-100, 100), s(-1, 1);
  double max_trunc = 0;
  for (int n = 0; n < 1500; ++n) {
    Vec3 X{u(g), u(g), u(g)}, N{s(g), s(g), s(g)};
    N = (1.0 / std::sqrt(dot(N, N))) * N;
    double v = 0;
    long I = std::lround(std::floor(X.x)), J = std::lround(std::floor(X.y)), K = std::lround(std::floor(X.z));
    for (long k = K - 4; k <= K + 5; ++k)
      for (long j = J - 4; j <= J + 5; ++j)
        for (long i = I - 4; i <= I + 5; ++i) {
          Vec3 D{X.x - i, X.y - j, X.z - k};
          double o = dot(D, N);
          Vec3 A = D - o * N;
          double d = dot(A, A), a = 1 - std::fabs(o);
          if (d < 4 && a > 0) v += dot(A, r.gradient(r.hash_xor(i, j, k))) * kensler_kernel(d) * (3 * a * a - 2 * a * a * a);
        }
    EXPECT_NEAR(r.projected(X, N), v, 1e-13);
    max_trunc = std::max(max_trunc, std::fabs(r.projected(X, N, true) - v));
  }
  // The pseudocode's 4-point stencil misses lattice points two cells away; the difference is
  // real but small (docs/NOISE.md).
  EXPECT_GT(max_trunc, 0.0);
  EXPECT_LT(max_trunc, 0.002);
}

TEST(NoiseReference, ProjectionAlongAxisOfAxisSlice) {
  // With N = z and X on the plane z = k (integer), the lattice points of that plane have
  // offset 0 (full weight) and the neighbouring planes offset 1 (weight 0): projected noise is
  // the 2D noise of the lattice plane.
  NoiseRef r(builtin_tables(), 256);
  for (double x = -3; x < 3; x += 0.37)
    for (double y = -2; y < 2; y += 0.41) {
      double v = 0;
      for (int j = -2; j <= 3; ++j)
        for (int i = -2; i <= 3; ++i) {
          long I = std::lround(std::floor(x)) + i, J = std::lround(std::floor(y)) + j;
          Vec3 A{x - I, y - J, 0};
          v += dot(A, r.gradient(r.hash_xor(I, J, 5))) * kensler_kernel(dot(A, A));
        }
      EXPECT_NEAR(r.projected({x, y, 5}, {0, 0, 1}), v, 1e-13);
    }
}

TEST(NoiseReference, ContinuousAcrossCellFacesAndTableWrap) {
  NoiseRef r(builtin_tables(), 256), h(builtin_tables(), 64);
  std::mt19937_64 g(6);
  std::uniform_real_distribution<double> u(0, 1);
  const double e = 1e-9;
  for (int k : {-1, 0, 1, 17, 255, 256, 257}) {
    for (int n = 0; n < 50; ++n) {
      double y = 10 * u(g), z = 10 * u(g);
      EXPECT_NEAR(r.full(k - e, y, z), r.full(k + e, y, z), 1e-7);
      EXPECT_NEAR(r.separable(k - e, y, z, Hash::kXor), r.separable(k + e, y, z, Hash::kXor), 1e-7);
      EXPECT_NEAR(h.half_cell(k - e, y, z), h.half_cell(k + e, y, z), 1e-7);
      EXPECT_NEAR(h.half(2 * k - e, y, z), h.half(2 * k + e, y, z), 1e-7);
    }
  }
}

TEST(NoiseReference, PeriodicWithTheTables) {
  NoiseRef r(builtin_tables(), 256), h(builtin_tables(), 64);
  for (double x = -5.25; x < 5; x += 0.625) {  // dyadic: x + 256 is exact
    EXPECT_EQ(r.full(x, 1.5, -2.125), r.full(x + 256, 1.5, -2.125 - 512));
    EXPECT_EQ(h.half(x, 1.5, 3.0625), h.half(x + 512, 1.5 - 1024, 3.0625));
    EXPECT_EQ(h.half_cell(x, 1.5, 3.0625), h.half_cell(x - 256, 1.5, 3.0625 + 256));
    EXPECT_EQ(perlin_improved(x, 1.5, 0.75), perlin_improved(x + 256, 1.5, 0.75));
  }
}

TEST(NoiseReference, SeparableZeroAtLatticePoints) {
  NoiseRef r(builtin_tables(), 256);
  for (int i = -5; i < 20; i += 3) {
    EXPECT_EQ(r.separable(i, 3 - i, 2 * i, Hash::kPerlin), 0.0);
    EXPECT_EQ(r.separable(i, 3 - i, 2 * i, Hash::kXor), 0.0);
  }
}

TEST(NoiseReference, PerlinHashColumnsAreShiftedCopiesXorIsNot) {
  // Sec. 4.5: with H = P[P[P[i]+j]+k], if P[i2] = P[i] + s then column i2 is column i shifted by
  // s (the cause of the striations). The xor hash has no such relation.
  NoiseRef r(builtin_tables(), 256);
  const auto& P = builtin_tables().perm_x;
  int perlin_equal = 0, xor_equal = 0, total = 0;
  for (int i = 0; i < 256; i += 5) {
    int i2 = (i * 7 + 3) % 256;
    int s = (P[i2] - P[i] + 256) % 256;
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 256; ++j) {
        perlin_equal += r.hash_perlin(i2, j, k) == r.hash_perlin(i, j + s, k);
        xor_equal += r.hash_xor(i2, j, k) == r.hash_xor(i, j + s, k);
        ++total;
      }
  }
  EXPECT_EQ(perlin_equal, total);
  EXPECT_LT(xor_equal, total / 50);  // chance level is 1/256
}

TEST(NoiseReference, BadGradientTableSize) {
  EXPECT_THROW(NoiseRef(builtin_tables(), 128), std::invalid_argument);
}

}  // namespace
}  // namespace ru::noise
