// rayunits units: cheaper variants of ray_tri_robust (issue 14 §3), golden models only.
//
// Fig. 3.6 taken literally (ray_tri.hpp) divides three times: t = Va/V, beta = V1/V,
// gamma = V2/V, each correctly rounded. Both variants below keep its volumes bit for bit (the
// same operations in the same order, so per-edge consistency and the sign test are unchanged)
// and change only what follows them:
//
//   ray_tri_robust_recip:    inv = 1/V; t = Va*inv; beta = V1*inv; gamma = V2*inv
//                            (1 division + 3 multiplications, as Moller-Trumbore)
//   ray_tri_robust_deferred: the interval test without a division,
//                              V > 0:  t_min*V < Va  and  Va < t_max*V
//                              V < 0:  t_min*V > Va  and  Va > t_max*V
//                              V = 0 or NaN: miss
//                            (2 multiplications and 2 compares); t, beta, gamma are then the
//                            three correctly rounded divisions of Fig. 3.6, which a deferred
//                            design performs once per ray, for the closest hit only (the outputs
//                            here are those of that final division).
// Decisions differ from Fig. 3.6 only through rounding: recip's t carries two roundings instead
// of one; deferred rounds the products t_min*V and t_max*V instead of Va/V. Both are measured
// against exact rationals by `rayunits study tri-outputs` (docs/UNITS.md).
#pragma once

#include "rayunits/units/ray_tri.hpp"

namespace ru::units {

namespace detail {

// Fig. 3.6's volumes and its sign / tie-break / eps decisions (everything before the division).
template <class T>
struct RobustVolumes {
  TriResult<T> r;
  bool mixed = false, tie = false, small = false;
};

template <class T>
RobustVolumes<T> robust_volumes(const Vec3<T>& a, const Vec3<T>& d, const Vec3<T>& p0, const Vec3<T>& p1,
                                const Vec3<T>& p2, const TriOptions& opt) {
  using namespace ru::num;
  RobustVolumes<T> o;
  TriResult<T>& r = o.r;
  const Vec3<T> e0 = vsub(p1, p2);
  const Vec3<T> e1 = vsub(p2, p0);
  const Vec3<T> e2 = vsub(p0, p1);
  const bool s0 = lex_first_is_min(p1, p2);
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
  const T zero = fp_from_bits<T>(0);
  const bool any_neg = r.V0 < zero || r.V1 < zero || r.V2 < zero;
  const bool any_pos = r.V0 > zero || r.V1 > zero || r.V2 > zero;
  o.mixed = any_neg && any_pos;
  if (opt.tie_break) o.tie = (r.V0 == zero && s0) || (r.V1 == zero && s1) || (r.V2 == zero && s2);
  if (opt.eps_test) o.small = fp_abs(r.V) < fp_cast<T>(opt.eps);
  return o;
}

template <class T>
void robust_finish(RobustVolumes<T>& o, bool in_range) {
  using namespace ru::num;
  TriResult<T>& r = o.r;
  r.why = o.mixed ? TriMiss::Sign
          : o.tie ? TriMiss::TieBreak
          : o.small ? TriMiss::Eps
          : !in_range ? TriMiss::Interval
                      : TriMiss::None;
  r.hit = r.why == TriMiss::None;
  r.t = fp_canon(r.t);
  r.beta = fp_canon(r.beta);
  r.gamma = fp_canon(r.gamma);
  r.V = fp_canon(r.V), r.Va = fp_canon(r.Va);
  r.V0 = fp_canon(r.V0), r.V1 = fp_canon(r.V1), r.V2 = fp_canon(r.V2);
}

}  // namespace detail

template <class T>
TriResult<T> ray_tri_robust_recip(const Vec3<T>& a, const Vec3<T>& d, const Vec3<T>& p0, const Vec3<T>& p1,
                                  const Vec3<T>& p2, T t_min, T t_max, const TriOptions& opt = {}) {
  using namespace ru::num;
  detail::RobustVolumes<T> o = detail::robust_volumes(a, d, p0, p1, p2, opt);
  TriResult<T>& r = o.r;
  const T inv = fp_cast<T>(1.0) / r.V;
  r.t = r.Va * inv;
  r.beta = r.V1 * inv;
  r.gamma = r.V2 * inv;
  detail::robust_finish(o, t_min < r.t && r.t < t_max);
  return o.r;
}

template <class T>
TriResult<T> ray_tri_robust_deferred(const Vec3<T>& a, const Vec3<T>& d, const Vec3<T>& p0, const Vec3<T>& p1,
                                     const Vec3<T>& p2, T t_min, T t_max, const TriOptions& opt = {}) {
  using namespace ru::num;
  detail::RobustVolumes<T> o = detail::robust_volumes(a, d, p0, p1, p2, opt);
  TriResult<T>& r = o.r;
  const T zero = fp_from_bits<T>(0);
  const T lo = t_min * r.V, hi = t_max * r.V;
  const bool in_range = (r.V > zero && lo < r.Va && r.Va < hi) || (r.V < zero && lo > r.Va && r.Va > hi);
  r.t = r.Va / r.V;  // the deferred division (once per ray, closest hit)
  r.beta = r.V1 / r.V;
  r.gamma = r.V2 / r.V;
  detail::robust_finish(o, in_range);
  return o.r;
}

}  // namespace ru::units
