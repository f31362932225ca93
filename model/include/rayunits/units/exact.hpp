// rayunits units: exact references with GMP rationals (mpq_class).
//
// Every finite double is a rational, and the signed volumes use only +, -, *, so the values
// below are exact ("gold standard", dissertation §3.7). Canonical definitions (the same
// volumes every equivalent scalar triple product computes, up to sign; units/formulas.hpp):
//   V   = [(p2 - p0) x (p1 - p2)] . d              (Eq. 3.3)
//   Va  = [(p2 - p0) x (p2 - p1)] . (a - p2)       (Eq. 3.4)
//   V_k = [(a - q2) x d] . (q1 - q2),  (q1, q2) = (p_{k+1}, p_{k+2}) indices mod 3  (Eq. 3.5)
// with V0 + V1 + V2 = V, t = Va / V, beta = V1 / V, gamma = V2 / V.
#pragma once

#include <gmpxx.h>

#include <optional>

#include "rayunits/units/vec.hpp"

namespace ru::units {

using Vec3q = Vec3<mpq_class>;

// Exact rational of a finite double. Throws std::domain_error for INF/NaN.
mpq_class to_q(double x);
Vec3q to_q(const Vec3d& v);

mpq_class dot_q(const Vec3q& u, const Vec3q& v);
Vec3q cross_q(const Vec3q& u, const Vec3q& v);
Vec3q sub_q(const Vec3q& u, const Vec3q& v);

struct ExactVolumes {
  mpq_class V, Va, V0, V1, V2;
};
// Inputs must be finite (throws std::domain_error otherwise).
ExactVolumes exact_volumes(const Vec3d& a, const Vec3d& d, const Vec3d& p0, const Vec3d& p1,
                           const Vec3d& p2);

// Exact ray-triangle hit (closed triangle, open interval): V != 0, V0..2 not of mixed signs
// (zeros allowed: edges and vertices belong to the triangle), and t_min < Va/V < t_max. The
// interval bounds may be +-INF; a, d, p_i must be finite.
struct ExactTriHit {
  bool hit = false;
  ExactVolumes vol;
  bool has_t = false;  // V != 0
  mpq_class t, beta, gamma;
};
ExactTriHit exact_tri(const Vec3d& a, const Vec3d& d, const Vec3d& p0, const Vec3d& p1,
                      const Vec3d& p2, double t_min, double t_max);

// An extended rational: finite value, +INF, -INF, or "none" (no constraint).
struct XQ {
  enum Kind : uint8_t { Finite, PosInf, NegInf, None } kind = None;
  mpq_class q;
  double to_double() const;  // finite values rounded toward zero by GMP
};

// Exact slab test with the semantics of ray_box (ray_box.hpp) on the same input values:
// per axis, with inv = +-INF allowed (a zero direction component): t = (plane - o) * inv is
// the exact product, +-INF when the difference is non-zero and inv infinite, and "no
// constraint" when the difference is zero and inv infinite (the ray lies in the plane).
// inv_k's sign bit chooses near/far planes as in the model. hit = t_enter <= t_exit,
// t_enter != +INF, t_exit != -INF. o, lo, hi must be finite; t_min/t_max may be +-INF.
// Any NaN input: no hit.
struct ExactBox {
  bool hit = false;
  XQ t_enter, t_exit;
};
ExactBox exact_slab(const Vec3d& o, const Vec3d& inv, const Vec3d& lo, const Vec3d& hi,
                    double t_min, double t_max);

// The same slab test on the ray direction d itself (not a reciprocal): per axis t = (plane - o)
// / d exactly; a zero component (either sign) is a ray parallel to the slab, as an infinite
// reciprocal of d's sign above (no constraint in the plane, +-INF outside). d's sign bit chooses
// near/far. The oracle of BoxMode::DConservative (issue 14 §4). d must not be NaN or INF.
ExactBox exact_slab_dir(const Vec3d& o, const Vec3d& d, const Vec3d& lo, const Vec3d& hi, double t_min,
                        double t_max);

}  // namespace ru::units
