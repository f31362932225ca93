// rayunits noise: double-precision reference noises (Kensler's dissertation, chapter 4).
//
//   perlin_improved      Perlin's improved noise (2002), bit-for-bit the published algorithm
//   NoiseRef::separable  Perlin's separable quintic kernel with a relaxed gradient table and a
//                        choice of hash (single-table Perlin hash or per-axis xor hash, sec. 4.5)
//   NoiseRef::full       Kensler's noise: xor hash, relaxed gradients, radial kernel
//                        s = 4t^5 - 3t^4 (t = 1 - d/4, d = squared distance < 4) over the 4-point
//                        stencil (sec. 4.6)
//   NoiseRef::projected  the same with the stencil projected onto the plane through X with unit
//                        normal N and the Hermite falloff 3o^2 - 2o^3 (sec. 4.7, Fig. 4.11)
//   NoiseRef::half       the half-resolution grid (sec. 4.8): only lattice points with even
//                        coordinates, 8 per evaluation (the form the hardware computes)
//   NoiseRef::half_cell  the same in the hardware's coordinates (one unit = one half-res cell):
//                        half_cell(u) = half(2u) / 2
// Lattice coordinates wrap modulo 256 (the permutation tables); gradient indices modulo the
// gradient table size (256 or 64). Everything is defined in docs/NOISE.md.
#pragma once

#include "rayunits/noise/tables.hpp"

namespace ru::noise {

double perlin_improved(double x, double y, double z);

// The radial kernel of sec. 4.6 as a function of the squared distance d (0 for d >= 4).
double kensler_kernel(double d);

enum class Hash { kPerlin, kXor };

class NoiseRef {
 public:
  // grad_size: 256 or 64 (which relaxed table of `t` to use).
  explicit NoiseRef(const TableSet& t = builtin_tables(), int grad_size = 256);

  int grad_size() const { return size_; }
  // Gradient index of lattice point (i, j, k).
  int hash_xor(long i, long j, long k) const;
  int hash_perlin(long i, long j, long k) const;  // P[P[P[i] + j] + k] with P = perm_x
  const Vec3& gradient(int h) const { return grad_[h]; }

  double separable(double x, double y, double z, Hash h) const;
  double full(double x, double y, double z) const;
  // Fig. 4.11 uses the 4-point stencil -1..2 on every axis; with projection a lattice point
  // two cells away can still lie inside the support (radial distance < 2, offset < 1), so by
  // default the stencil is widened to -2..3 (the exact sum). fig411_stencil = true reproduces
  // the pseudocode's truncated stencil.
  double projected(Vec3 X, Vec3 N, bool fig411_stencil = false) const;
  double half(double x, double y, double z) const;
  double half_cell(double u, double v, double w) const;

 private:
  const TableSet* t_;
  int size_;
  const std::vector<Vec3>& grad_;
};

}  // namespace ru::noise
