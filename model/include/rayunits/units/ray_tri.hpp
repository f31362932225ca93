// rayunits units: golden models of the ray-triangle units.
//
//   ray_tri_robust: Kensler's robust algorithm (dissertation Fig. 3.6, Eq. 3.3-3.6).
//   ray_tri_mt:     Moller-Trumbore (Eq. 3.2), one reciprocal of the determinant.
//
// Each is ONE function template, run with double, float or ru::num::Soft (the runtime format).
// Every arithmetic operation below is one operation of an FP unit of the format, in exactly
// the order written (vec.hpp fixes the order inside vsub/cross/dot); docs/UNITS.md "Dataflow"
// is the contract the RTL follows. There is no early exit: every output is computed for every
// input (as the pipelined RTL does); t, beta, gamma are meaningful when hit is true.
//
// Ray: a + t*d, hit only when t_min < t < t_max (strict). Barycentrics: the hit point is
// (1-beta-gamma)*p0 + beta*p1 + gamma*p2.
//
// Defined results for special inputs (tested in tests/units):
//   * NaN anywhere: ordered comparisons with NaN are false, so the sign test does not reject,
//     but t is NaN and t_min < t fails: miss.
//   * degenerate triangles (zero area), rays parallel to the plane: V = 0 (or V0..2 all 0),
//     t = Va/V is +-INF or NaN and fails the strict interval test: miss. (With t_max = +INF
//     too, since INF < INF is false.)
//   * overflow inside the volumes gives INF/NaN and the same rules apply.
#pragma once

#include <cstdint>

#include "rayunits/num/fp.hpp"
#include "rayunits/units/vec.hpp"

namespace ru::units {

struct TriOptions {
  // Fig. 3.6 optional test: when V_i is exactly zero, only the triangle that sees the
  // edge's lexicographically smaller end point first (p_{i+1} = min(p_{i+1}, p_{i+2})) misses,
  // so a ray through a shared edge is taken by exactly one of the two triangles.
  bool tie_break = false;
  // |V| < eps -> miss (grazing rays). eps is rounded into the arithmetic type.
  bool eps_test = false;
  double eps = 0.0;
};

enum class TriMiss : uint8_t {
  None = 0,      // hit
  Sign = 1,      // robust: V0, V1, V2 of mixed signs / MT: beta < 0, gamma < 0 or beta+gamma > 1
  TieBreak = 2,  // robust: the optional zero-volume tie-break rejected
  Eps = 3,       // |V| < eps
  Interval = 4,  // t not in (t_min, t_max) (also NaN t)
};
const char* tri_miss_name(TriMiss m);

template <class T>
struct TriResult {
  bool hit = false;
  TriMiss why = TriMiss::None;  // first failing condition in the order listed in TriMiss
  T t{}, beta{}, gamma{};
  // Intermediate volumes (diagnostics, testbench dumps). MT does not compute V0 (left +0).
  T V{}, Va{}, V0{}, V1{}, V2{};
};

// Kensler Fig. 3.6. Dataflow (every line: FP unit operations in this order):
//   e0 = p1 - p2;  e1 = p2 - p0;  e2 = p0 - p1                    (9 sub)
//   m0 = lexmin(p1, p2); m1 = lexmin(p2, p0); m2 = lexmin(p0, p1) (compares only)
//   V0 = dot(cross(a - m0, d), e0)                                  (Eq. 3.5/3.6 by m0)
//   V1 = dot(cross(a - m1, d), e1)
//   V2 = dot(cross(a - m2, d), e2)
//   N  = cross(e1, e0)          = (p2 - p0) x (p1 - p2)             (Eq. 3.3)
//   V  = dot(N, d)
//   Va = dot(N, p2 - a)         = [(p2-p0) x (p2-p1)] . (a-p2)      (Eq. 3.4)
//   t = Va / V;  beta = V1 / V;  gamma = V2 / V                     (3 div, correctly rounded)
//   mixed = (V0 < 0 | V1 < 0 | V2 < 0) & (V0 > 0 | V1 > 0 | V2 > 0)
//   hit = !mixed & !tiebreak & !(|V| < eps) & (t_min < t) & (t < t_max)
template <class T>
TriResult<T> ray_tri_robust(const Vec3<T>& a, const Vec3<T>& d, const Vec3<T>& p0,
                            const Vec3<T>& p1, const Vec3<T>& p2, T t_min, T t_max,
                            const TriOptions& opt = {}) {
  using namespace ru::num;
  TriResult<T> r;
  const Vec3<T> e0 = vsub(p1, p2);
  const Vec3<T> e1 = vsub(p2, p0);
  const Vec3<T> e2 = vsub(p0, p1);
  const bool s0 = lex_first_is_min(p1, p2);  // true: min(p1, p2) = p1
  const bool s1 = lex_first_is_min(p2, p0);
  const bool s2 = lex_first_is_min(p0, p1);
  const Vec3<T>& m0 = s0 ? p1 : p2;
  const Vec3<T>& m1 = s1 ? p2 : p0;
  const Vec3<T>& m2 = s2 ? p0 : p1;
  r.V0 = dot(cross(vsub(a, m0), d), e0);
  r.V1 = dot(cross(vsub(a, m1), d), e1);
  r.V2 = dot(cross(vsub(a, m2), d), e2);
  const Vec3<T> N = cross(e1, e0);
  r.V = dot(N, d);
  r.Va = dot(N, vsub(p2, a));
  r.t = r.Va / r.V;
  r.beta = r.V1 / r.V;
  r.gamma = r.V2 / r.V;

  const T zero = fp_from_bits<T>(0);  // +0
  const bool any_neg = r.V0 < zero || r.V1 < zero || r.V2 < zero;
  const bool any_pos = r.V0 > zero || r.V1 > zero || r.V2 > zero;
  const bool mixed = any_neg && any_pos;
  bool tie = false;
  if (opt.tie_break)
    tie = (r.V0 == zero && s0) || (r.V1 == zero && s1) || (r.V2 == zero && s2);
  bool small = false;
  if (opt.eps_test) small = fp_abs(r.V) < fp_cast<T>(opt.eps);
  const bool in_range = t_min < r.t && r.t < t_max;

  r.why = mixed ? TriMiss::Sign
          : tie ? TriMiss::TieBreak
          : small ? TriMiss::Eps
          : !in_range ? TriMiss::Interval
                      : TriMiss::None;
  r.hit = r.why == TriMiss::None;
  r.t = fp_canon(r.t);
  r.beta = fp_canon(r.beta);
  r.gamma = fp_canon(r.gamma);
  r.V = fp_canon(r.V), r.Va = fp_canon(r.Va);
  r.V0 = fp_canon(r.V0), r.V1 = fp_canon(r.V1), r.V2 = fp_canon(r.V2);
  return r;
}

// Moller-Trumbore as Eq. 3.2 (the published algorithm: one reciprocal, three multiplies).
// Dataflow:
//   e1 = p1 - p0;  e2 = p2 - p0;  s = a - p0                        (9 sub)
//   q = cross(d, e2);  r = cross(s, e1)                             (12 mul, 6 sub)
//   V  = dot(q, e1)   = (d x (p2-p0)) . (p1-p0)
//   V1 = dot(q, s)    = (d x (p2-p0)) . (a-p0)
//   V2 = dot(r, d)    = ((a-p0) x (p1-p0)) . d
//   Va = dot(r, e2)   = ((a-p0) x (p1-p0)) . (p2-p0)
//   inv = 1 / V;  beta = V1 * inv;  gamma = V2 * inv;  t = Va * inv  (1 div, 3 mul)
//   sum = beta + gamma                                              (1 add)
//   hit = (beta >= 0) & (gamma >= 0) & (sum <= 1) & !(|V| < eps) & (t_min < t) & (t < t_max)
template <class T>
TriResult<T> ray_tri_mt(const Vec3<T>& a, const Vec3<T>& d, const Vec3<T>& p0,
                        const Vec3<T>& p1, const Vec3<T>& p2, T t_min, T t_max,
                        const TriOptions& opt = {}) {
  using namespace ru::num;
  TriResult<T> r;
  const Vec3<T> e1 = vsub(p1, p0);
  const Vec3<T> e2 = vsub(p2, p0);
  const Vec3<T> s = vsub(a, p0);
  const Vec3<T> q = cross(d, e2);
  const Vec3<T> rr = cross(s, e1);
  r.V = dot(q, e1);
  r.V1 = dot(q, s);
  r.V2 = dot(rr, d);
  r.Va = dot(rr, e2);
  const T one = fp_cast<T>(1.0);
  const T inv = one / r.V;
  r.beta = r.V1 * inv;
  r.gamma = r.V2 * inv;
  r.t = r.Va * inv;
  const T sum = r.beta + r.gamma;

  const T zero = fp_from_bits<T>(0);  // +0
  const bool inside = r.beta >= zero && r.gamma >= zero && sum <= one;
  bool small = false;
  if (opt.eps_test) small = fp_abs(r.V) < fp_cast<T>(opt.eps);
  const bool in_range = t_min < r.t && r.t < t_max;
  r.why = !inside ? TriMiss::Sign
          : small ? TriMiss::Eps
          : !in_range ? TriMiss::Interval
                      : TriMiss::None;
  r.hit = r.why == TriMiss::None;
  r.t = fp_canon(r.t);
  r.beta = fp_canon(r.beta);
  r.gamma = fp_canon(r.gamma);
  r.V = fp_canon(r.V), r.Va = fp_canon(r.Va);
  r.V1 = fp_canon(r.V1), r.V2 = fp_canon(r.V2);
  return r;
}

}  // namespace ru::units
