// Double-precision reference noises; see rayunits/noise/reference.hpp and docs/NOISE.md.
#include "rayunits/noise/reference.hpp"

#include <cmath>
#include <stdexcept>

namespace ru::noise {

namespace {

// Perlin 2002: written in the reference implementation's operation order so the values
// agree to the last bit (e.g. noise(3.14, 42, 7) = 0.13691995878400012).
double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
double lerp(double t, double a, double b) { return a + t * (b - a); }
double grad12(int hash, double x, double y, double z) {
  int h = hash & 15;
  double u = h < 8 ? x : y;
  double v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
  return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}
int perm512(int i) { return kPerlinPermutation[i & 255]; }

long lfloor(double v) { return static_cast<long>(std::floor(v)); }

}  // namespace

double perlin_improved(double x, double y, double z) {
  int X = static_cast<int>(std::floor(x)) & 255, Y = static_cast<int>(std::floor(y)) & 255,
      Z = static_cast<int>(std::floor(z)) & 255;
  x -= std::floor(x);
  y -= std::floor(y);
  z -= std::floor(z);
  double u = fade(x), v = fade(y), w = fade(z);
  int A = perm512(X) + Y, AA = perm512(A) + Z, AB = perm512(A + 1) + Z;
  int B = perm512(X + 1) + Y, BA = perm512(B) + Z, BB = perm512(B + 1) + Z;
  return lerp(w,
              lerp(v, lerp(u, grad12(perm512(AA), x, y, z), grad12(perm512(BA), x - 1, y, z)),
                   lerp(u, grad12(perm512(AB), x, y - 1, z), grad12(perm512(BB), x - 1, y - 1, z))),
              lerp(v, lerp(u, grad12(perm512(AA + 1), x, y, z - 1), grad12(perm512(BA + 1), x - 1, y, z - 1)),
                   lerp(u, grad12(perm512(AB + 1), x, y - 1, z - 1), grad12(perm512(BB + 1), x - 1, y - 1, z - 1))));
}

double kensler_kernel(double d) {
  if (!(d < 4)) return 0;
  double t = 1 - d / 4;
  double t2 = t * t, t4 = t2 * t2;
  return 4 * t4 * t - 3 * t4;
}

NoiseRef::NoiseRef(const TableSet& t, int grad_size)
    : t_(&t), size_(grad_size), grad_(grad_size == 64 ? t.grad64 : t.grad256) {
  if (grad_size != 256 && grad_size != 64)
    throw std::invalid_argument("noise: gradient table size must be 256 or 64, got " + std::to_string(grad_size));
  if (static_cast<int>(grad_.size()) != grad_size) throw std::invalid_argument("noise: gradient table not filled");
}

int NoiseRef::hash_xor(long i, long j, long k) const {
  return (t_->perm_x[i & 255] ^ t_->perm_y[j & 255] ^ t_->perm_z[k & 255]) & (size_ - 1);
}

int NoiseRef::hash_perlin(long i, long j, long k) const {
  const auto& P = t_->perm_x;
  return P[(P[(P[i & 255] + j) & 255] + k) & 255] & (size_ - 1);
}

double NoiseRef::separable(double x, double y, double z, Hash hash) const {
  long I = lfloor(x), J = lfloor(y), K = lfloor(z);
  double F[3] = {x - I, y - J, z - K};
  double s[3] = {fade(F[0]), fade(F[1]), fade(F[2])};
  double v = 0;
  for (int c = 0; c < 8; ++c) {
    int cx = c & 1, cy = (c >> 1) & 1, cz = c >> 2;
    int h = hash == Hash::kXor ? hash_xor(I + cx, J + cy, K + cz) : hash_perlin(I + cx, J + cy, K + cz);
    Vec3 D{F[0] - cx, F[1] - cy, F[2] - cz};
    double wgt = (cx ? s[0] : 1 - s[0]) * (cy ? s[1] : 1 - s[1]) * (cz ? s[2] : 1 - s[2]);
    v += dot(D, grad_[h]) * wgt;
  }
  return v;
}

double NoiseRef::full(double x, double y, double z) const {
  long I = lfloor(x), J = lfloor(y), K = lfloor(z);
  Vec3 F{x - I, y - J, z - K};
  double v = 0;
  for (int k = -1; k <= 2; ++k)
    for (int j = -1; j <= 2; ++j)
      for (int i = -1; i <= 2; ++i) {
        Vec3 D{F.x - i, F.y - j, F.z - k};
        double d = dot(D, D);
        if (d < 4) v += dot(D, grad_[hash_xor(I + i, J + j, K + k)]) * kensler_kernel(d);
      }
  return v;
}

double NoiseRef::projected(Vec3 X, Vec3 N, bool fig411_stencil) const {
  long I = lfloor(X.x), J = lfloor(X.y), K = lfloor(X.z);
  Vec3 F{X.x - I, X.y - J, X.z - K};
  const int lo = fig411_stencil ? -1 : -2, hi = fig411_stencil ? 2 : 3;
  double v = 0;
  for (int k = lo; k <= hi; ++k)
    for (int j = lo; j <= hi; ++j)
      for (int i = lo; i <= hi; ++i) {
        Vec3 D{F.x - i, F.y - j, F.z - k};
        double o = dot(D, N);
        Vec3 A = D - o * N;
        double d = dot(A, A);
        o = 1 - std::fabs(o);
        if (d < 4 && o > 0) {
          double a = 3 * o * o - 2 * o * o * o;
          v += dot(A, grad_[hash_xor(I + i, J + j, K + k)]) * kensler_kernel(d) * a;
        }
      }
  return v;
}

double NoiseRef::half(double x, double y, double z) const {
  long I = lfloor(x / 2), J = lfloor(y / 2), K = lfloor(z / 2);  // cell index = lattice point / 2
  Vec3 F{x - 2 * I, y - 2 * J, z - 2 * K};                       // in [0, 2)
  double v = 0;
  for (int c = 0; c < 8; ++c) {
    int cx = c & 1, cy = (c >> 1) & 1, cz = c >> 2;
    Vec3 D{F.x - 2 * cx, F.y - 2 * cy, F.z - 2 * cz};
    double d = dot(D, D);
    if (d < 4) v += dot(D, grad_[hash_xor(I + cx, J + cy, K + cz)]) * kensler_kernel(d);
  }
  return v;
}

double NoiseRef::half_cell(double u, double v, double w) const {
  long I = lfloor(u), J = lfloor(v), K = lfloor(w);
  Vec3 F{u - I, v - J, w - K};
  double s = 0;
  for (int c = 0; c < 8; ++c) {
    int cx = c & 1, cy = (c >> 1) & 1, cz = c >> 2;
    Vec3 D{F.x - cx, F.y - cy, F.z - cz};
    double d = dot(D, D);
    if (d < 1) {
      double t = 1 - d, t2 = t * t, t4 = t2 * t2;
      s += dot(D, grad_[hash_xor(I + cx, J + cy, K + cz)]) * (4 * t4 * t - 3 * t4);
    }
  }
  return s;
}

}  // namespace ru::noise
