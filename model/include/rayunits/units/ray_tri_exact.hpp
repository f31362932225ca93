// rayunits units: ray_tri_exact, the exactly-once watertight variant of Kensler's robust test.
//
// Same dataflow as ray_tri_robust (Fig. 3.6, lexicographic-min edge operands, Kensler §3.10):
// t, beta, gamma, V, Va, V0..V2 are bit for bit those of ray_tri_robust (no tie-break). Only
// the hit decision differs: it is EXACT for the symbolically perturbed ray
//
//     a(eps) = a + (eps, eps^2, eps^3),  eps -> 0+          (d unchanged)
//
// i.e. hit  <=>  the three perturbed edge signs agree  and  t_min < Va/V < t_max  (exact t of the
// unperturbed ray, strict). The perturbation is a property of the RAY, the same for every
// triangle, so the hit set is that of a generic ray: it passes through no vertex and meets no
// edge line except those parallel to d (whose triangles contain d and are never hit), so on a
// closed mesh the triangles reporting a hit are exactly the crossings of one line with the
// surface. The triangle-edge quantity is, with e_k = p_{k+1} - p_{k+2} and m_k = lexmin of the
// edge's end points (both neighbours use the same operands in the same order):
//     S_k(eps) = ((a(eps) - m_k) x d) . e_k = S_k + (eps, eps^2, eps^3) . (d x e_k)
// so sign S_k(eps) = sign of the first non-zero of S_k, (d x e_k).x, (d x e_k).y, (d x e_k).z
// (simulation of simplicity); the neighbour has -e_k and gets the opposite sign, exactly.
//
// Filtered predicate (the fast path, what the pipeline computes every cycle):
//   V_k (the unit's rounded volume) and its permanent P_k = the same expression with every
//   operand replaced by its absolute value and every subtraction in the cross product and the
//   dot product by an addition (same rounding, same order; the cross product's six products are
//   shared: |fl(x y)| in place of fl(|x||y|)). Each of the six terms +-s_i d_j e_l of V_k passes
//   through at most n = 7 roundings (a - m, e, product, cross subtraction, product, two
//   additions), so, without underflow or overflow,
//       |fl(V_k) - V_k| <= ((1+u)^7 - 1) sum|s_i d_j e_l| <= ((1+u)^7 - 1)/(1-u)^7 * fl(P_k)
//   (fl(P_k) has at most 7 roundings per term too, all of positive terms, so
//   fl(P_k) >= (1-u)^7 sum|s_i d_j e_l|), u = 2^-(M+1) for RNE, 2^-M for directed modes.
//   The constant is rounded up to a power of two 2^K (K = -M+2 for RNE at M >= 6), so the test
//       |fl(V_k)| > 2^K fl(P_k)           (an exponent-shifted comparison, exact: certified())
//   certifies sign(V_k) = sign(fl(V_k)). Underflow is excluded: an operation of the volume or of
//   its permanent that raises the underflow flag (an inexact tiny result, or a flushed one in
//   -ftz formats) sends the edge to the exact path (exact results, even subnormal ones, carry no
//   error); overflow/NaN does too (fl(V_k), fl(P_k) must be finite, and normal: certified()
//   gives up on subnormal ones). Edges are only sent to the exact
//   path when the certified ones do not already decide a miss (one certified +, one certified -).
//   The interval test t_min < t < t_max uses the unit's t = fl(Va/V) with a proven absolute
//   bound (V: n = 7, Va: n = 8 roundings per term, the same permanent argument, plus the division):
//       |t - t_fp| <= (Ba + |t_q| BV) / (|fl(V)| (1 - BV/|fl(V)|)) + u |t_q|,  |t_q| <= |t_fp|/(1-u)
//   (BV = 2^K7 fl(P_V), Ba = 2^K8 fl(P_a); exact_detail::fast_interval), and goes to the exact
//   path when [t_fp - err, t_fp + err] straddles t_min or t_max, or V's sign is not certified.
// Exact path (the slow side path): S_k, (d x e_k), Va and V in exact integer arithmetic (GMP in
// the model). Bits needed (docs/UNITS.md): every value of eXmY is an integer multiple of
// 2^(emin-M) of magnitude < 2^L, L = 2^E + M - 2; a - m and e are < 2^(L+1); each of the six
// terms < 2^(3L+2); S_k < 2^(3L+5): 3L+6 bits two's complement (e5m10: 126, e6m12: 228,
// e7m16: 432, e8m23: 837, e11m52: 6300); the tie terms (d x e_k) need 2L+3 bits.
//
// Non-finite operands (INF/NaN in a, d, p0..p2): miss (the exact decision is undefined).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "rayunits/num/fp.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/vec.hpp"

namespace ru::units {

// Planted errors, for the tests that must show their checkers fail (never used otherwise).
enum class ExactPlant : uint8_t {
  None = 0,
  NoExactPath,      // trust the rounded V_k always (zero -> neither sign, plain Fig. 3.6)
  VertexOrderTie,   // exact zeros broken by the edge's vertex order (lexmin -> lexmax), not the ray
  ShrunkBound,      // filter bound 2^-24 times too small (certifies wrong signs)
  NoTinyCheck,      // underflow not detected (the bound is then unsound for subnormal/flushed results)
};

// The filter's bound on |fl(V) - V| (all three sound; the hit bit does not depend on it, only
// which path decides): Permanent, 2^K fl(P) with P the permanent computed beside the volume (15
// multiplications and 22 additions per test in hardware, the cross products' products shared); Exponent, 2^K 2^(Es+Ed+Ee+3+g) from the
// largest exponents Es, Ed, Ee of the three factor vectors' components (exponent fields only: a
// subnormal counts as emin, an overestimate; about a dozen small exponent adders and comparators).
// Sum |s_i d_j e_l| <= 6 max|s| max|d| max|e| <= 6/(1-u)^3 2^(Es+Ed+Ee+3) <= 2^(Es+Ed+Ee+3+g)
// (a (1-u) for each rounded difference: s = fl(a - m), e = fl(q1 - q2); the interval's V and Va
// likewise with e1, e0 and d or f = p2 - a; g the smallest with 6/(1-u)^3 <= 2^g: 3 from M = 5 on
// with round-to-nearest).
// PermanentFormat: Permanent's bounds, with the interval test's error evaluated the way hardware
// can, in the format with directed rounding (exact_detail::fast_interval_format, about a dozen FP
// operations) instead of in double arithmetic; the specification of the RTL's filter
// (ru_ray_tri_exact) and the default.
enum class ExactFilter : uint8_t { Permanent, Exponent, PermanentFormat };

struct ExactTriOptions {
  ExactPlant plant = ExactPlant::None;
  ExactFilter filter = ExactFilter::PermanentFormat;  // the RTL's (ru_ray_tri_exact)
};

// Which path decided (statistics for the cost of the side path).
struct ExactPathInfo {
  uint8_t slow_edges = 0;      // edges whose sign came from the exact path (0..3)
  uint8_t edge_mask = 0;       // which ones (bit k: edge k), asked in the order 0, 1, 2
  bool slow_interval = false;  // the interval test came from the exact path
  bool slow() const { return slow_edges != 0 || slow_interval; }
};

template <class T>
struct TriExactResult : TriResult<T> {
  ExactPathInfo path;
};

namespace exact_detail {

// Exponent K with ((1+u)^n - 1)/(1-u)^n <= 2^K for the format (u from its rounding mode).
int bound_exp(const ru::num::Format& f, int n);
// |v| > 2^k * p exactly, for finite doubles p >= 0 (v any finite double).
bool abs_greater_scaled(double v, double p, int k);
// The certification |v| > 2^k p of the RTL's filter on bit patterns of format f: false when v is
// zero, subnormal or not finite, or p is subnormal or not finite (the filter gives up: the exact
// path decides); p = 0 and v normal: true; both normal: the exponent-shifted comparison, exact
// (abs_greater_scaled on the same values).
bool certified(const ru::num::Format& f, uint64_t v, uint64_t p, int k);
// Exact sign of the perturbed edge quantity ((a(eps) - m) x d) . e, e = q1 - q2 (doubles: the
// format values, exactly). plant VertexOrderTie: the zero case uses e oriented lexmin -> lexmax.
int exact_edge_sign(const Vec3d& a, const Vec3d& d, const Vec3d& m, const Vec3d& q1, const Vec3d& q2,
                    bool vertex_order_tie);
// Exact strict interval test of t = Va / V, Va = ((p2-p0) x (p1-p2)) . (p2 - a),
// V = ((p2-p0) x (p1-p2)) . d (V != 0 assumed; false if V == 0 or t_min/t_max NaN).
bool exact_interval(const Vec3d& a, const Vec3d& d, const Vec3d& p0, const Vec3d& p1, const Vec3d& p2,
                    double t_min, double t_max);
// The certified-interval test: returns 1 (t in the interval), 0 (not), -1 (undecided).
int fast_interval(double t_fp, double V, double PV, int kV, double Va, double Pa, int ka, double u,
                  double minnorm, double t_min, double t_max);
// The same decision as fast_interval from format arithmetic only (f's bit patterns; the values
// must be finite format values, V's sign certified by the caller's certified(V, PV, kV)), the
// specification of ru_ray_tri_exact's interval filter:
//   R = RUP(2 RUP(Ba + RUP(tq BV)) + z),  z = u RUP(tq |V|), or 2 minnorm |V| when |t| < minnorm
//   (z >= u tq |V| + minnorm |V| then: the division's absolute error), BV = PV 2^kV, Ba = Pa 2^ka,
//   tq = RUP(|t| (1+2u)), and 2 BV < |V| required (rho < 1/2, so 1/(1-rho) < 2): R >= err |V|
//   for fast_interval's err. A side of the interval is decided
//   when RTZ(RTZ(|t - bound|) |V|) > R (then t is on t_fp's side of that bound). The products by
//   powers of two (2^kV, 2^ka, 2, u, 2 minnorm) are scale2 (an exponent addition); every RUP operation that
//   underflows or overflows, and every scale2 that gives up, gives "undecided". Returns 1, 0, -1
//   as fast_interval.
int fast_interval_format(const ru::num::Format& f, uint64_t t, uint64_t V, uint64_t PV, int kV, uint64_t Va,
                         uint64_t Pa, int ka, uint64_t t_min, uint64_t t_max);
// x 2^k by an exponent addition: exact for +-0 and for a normal x with a normal result; otherwise
// (x subnormal, INF or NaN, or the result outside the normal range) flags != 0: the filter gives up.
ru::num::Result scale2(const ru::num::Format& f, uint64_t x, int k);
double unit_roundoff(const ru::num::Format& f);

template <class T>
bool fin(const T& x) {
  const double v = ru::num::fp_to_double(x);
  return std::isfinite(v);
}

// Tiny-result detection: the underflow flag (tiny after rounding and inexact, docs/FORMAT.md) of
// an operation, ORed over every operation of a volume and of its permanent. An exact result, even
// a subnormal one, has no rounding error and does not need the flag; an inexact tiny result (or a
// flushed one in an -ftz format) has an absolute, not a relative, error and sets it. In hardware
// this is the OR of the FP units' flags_o[1] (ru_ray_tri_exact).
template <class T>
struct Checked {
  bool tiny = false;
  T mul(T x, T y) { return op(x, y, 2); }
  T sub(T x, T y) { return op(x, y, 1); }
  T add(T x, T y) { return op(x, y, 0); }

 private:
  T op(T x, T y, int which) {
    if constexpr (std::is_same_v<T, ru::num::Soft>) {
      const uint64_t before = ru::num::soft_stats().underflow;
      const T z = which == 2 ? x * y : which == 1 ? x - y : x + y;
      if (ru::num::soft_stats().underflow != before) tiny = true;
      return z;
    } else {  // native arithmetic; its flag from the bit-exact format model of the same format
      const ru::num::Format f = ru::num::fp_format<T>();
      const uint64_t a = ru::num::fp_bits(x), b = ru::num::fp_bits(y);
      const ru::num::Result r =
          which == 2 ? ru::num::mul(f, a, b) : which == 1 ? ru::num::sub(f, a, b) : ru::num::add(f, a, b);
      if (r.flags & ru::num::kUnderflow) tiny = true;
      return which == 2 ? x * y : which == 1 ? x - y : x + y;
    }
  }
};

// dot(cross(u, w), z) with the order of vec.hpp, and its permanent, every operation checked:
// the cross product's six products l_i = u_j w_k, r_i = u_k w_j are shared (|fl(l_i)| in place of
// fl(|u_j||w_k|): the same relative error bound in every rounding mode, and no second set of
// multipliers in hardware), pc_i = |l_i| + |r_i|, perm = (pc.x |z.x| + pc.y |z.y|) + pc.z |z.z|.
template <class T>
void vol_perm(Checked<T>& c, const Vec3<T>& u, const Vec3<T>& w, const Vec3<T>& z, T& vol, T& perm) {
  using ru::num::fp_abs;
  const Vec3<T> l{c.mul(u.y, w.z), c.mul(u.z, w.x), c.mul(u.x, w.y)};
  const Vec3<T> r{c.mul(u.z, w.y), c.mul(u.x, w.z), c.mul(u.y, w.x)};
  const Vec3<T> cr{c.sub(l.x, r.x), c.sub(l.y, r.y), c.sub(l.z, r.z)};
  vol = c.add(c.add(c.mul(cr.x, z.x), c.mul(cr.y, z.y)), c.mul(cr.z, z.z));
  const Vec3<T> pc{c.add(fp_abs(l.x), fp_abs(r.x)), c.add(fp_abs(l.y), fp_abs(r.y)), c.add(fp_abs(l.z), fp_abs(r.z))};
  perm = c.add(c.add(c.mul(pc.x, fp_abs(z.x)), c.mul(pc.y, fp_abs(z.y))), c.mul(pc.z, fp_abs(z.z)));
}

template <class T>
Vec3<T> vsub_chk(Checked<T>& c, const Vec3<T>& u, const Vec3<T>& v) {
  return {c.sub(u.x, v.x), c.sub(u.y, v.y), c.sub(u.z, v.z)};
}

// 2^(Ex+Ey+Ez+3+g) >= sum of |x_i y_j z_l| over the six terms of (x cross y) . z (see ExactFilter),
// Ev = the largest exponent of v's components (a subnormal counts as emin; a zero vector gives a
// tiny bound, harmless: its volume is 0 and never certified). A power of two; infinite when it
// leaves the double range (never certifies).
inline int exponent_bound_g(double u) {
  const double c = 6.0 / ((1 - u) * (1 - u) * (1 - u)) * (1 + 0x1p-40);  // 1-u exact (u a power of two)
  int g = 0;
  while (std::ldexp(1.0, g) < c) ++g;
  return g;
}
template <class T>
double exponent_bound(const Vec3<T>& x, const Vec3<T>& y, const Vec3<T>& z, int emin, int g) {
  auto ex = [&](const Vec3<T>& v) {
    int e = -100000;
    for (int k = 0; k < 3; ++k) {
      const double c = ru::num::fp_to_double(v[k]);
      if (c != 0) e = std::max(e, std::max(std::ilogb(c), emin));
    }
    return e;
  };
  const long sum = static_cast<long>(ex(x)) + ex(y) + ex(z) + 3 + g;
  if (sum > 1023) return std::numeric_limits<double>::infinity();
  return sum < -1074 ? 0x1p-1074 : std::ldexp(1.0, static_cast<int>(sum));
}

template <class T>
int sgn_fp(const T& x) {
  const double v = ru::num::fp_to_double(x);
  return v > 0 ? 1 : v < 0 ? -1 : 0;
}

}  // namespace exact_detail

// The exactly-once unit. Outputs as ray_tri_robust (tie_break/eps options do not apply); hit is
// the exact decision for the perturbed ray; r.path says which path decided.
template <class T>
TriExactResult<T> ray_tri_exact(const Vec3<T>& a, const Vec3<T>& d, const Vec3<T>& p0, const Vec3<T>& p1,
                                const Vec3<T>& p2, T t_min, T t_max, const ExactTriOptions& opt = {}) {
  using namespace ru::num;
  using namespace exact_detail;
  TriExactResult<T> r;
  static_cast<TriResult<T>&>(r) = ray_tri_robust(a, d, p0, p1, p2, t_min, t_max);
  r.hit = false;
  const Format f = fp_format<T>();
  const double minnorm = to_double(f, f.min_normal());
  const double u = unit_roundoff(f);
  const int shrink = opt.plant == ExactPlant::ShrunkBound ? 24 : 0;
  const int k7 = bound_exp(f, 7) - shrink, k8 = bound_exp(f, 8) - shrink;
  const int gx = exponent_bound_g(u);

  const Vec3d ad = vdouble(a), dd = vdouble(d), P[3] = {vdouble(p0), vdouble(p1), vdouble(p2)};
  for (const Vec3d* v : {&ad, &dd, &P[0], &P[1], &P[2]})
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite((*v)[k])) {
        r.why = TriMiss::Sign;
        return r;
      }

  // Edge volumes: the same operations as ray_tri_robust, with the tiny check and the permanent.
  const Vec3<T>* pv[3] = {&p0, &p1, &p2};
  int sign[3];
  bool certain[3];
  for (int k = 0; k < 3; ++k) {
    const Vec3<T>& q1 = *pv[(k + 1) % 3];
    const Vec3<T>& q2 = *pv[(k + 2) % 3];
    const Vec3<T>& m = lex_first_is_min(q1, q2) ? q1 : q2;
    Checked<T> c;
    const Vec3<T> e = vsub_chk(c, q1, q2);
    const Vec3<T> s = vsub_chk(c, a, m);
    T vol, perm;
    vol_perm(c, s, d, e, vol, perm);
    sign[k] = sgn_fp(vol);
    if (opt.plant == ExactPlant::NoTinyCheck) c.tiny = false;
    bool cert;
    if (opt.filter == ExactFilter::Exponent) {
      const double vd = fp_to_double(vol), pd = exponent_bound(s, d, e, f.emin(), gx);
      cert = std::isfinite(vd) && std::isfinite(pd) && abs_greater_scaled(vd, pd, k7);
    } else {
      cert = certified(f, fp_bits(vol), fp_bits(perm), k7);
    }
    certain[k] = opt.plant == ExactPlant::NoExactPath || (!c.tiny && cert);
  }
  auto decided_mixed = [&] {
    bool pos = false, neg = false;
    for (int k = 0; k < 3; ++k)
      if (certain[k]) pos |= sign[k] > 0, neg |= sign[k] < 0;
    return pos && neg;
  };
  if (!decided_mixed()) {
    for (int k = 0; k < 3; ++k) {
      if (certain[k]) continue;
      const Vec3d& q1 = P[(k + 1) % 3];
      const Vec3d& q2 = P[(k + 2) % 3];
      const Vec3d& m = lex_first_is_min(q1, q2) ? q1 : q2;
      sign[k] = exact_edge_sign(ad, dd, m, q1, q2, opt.plant == ExactPlant::VertexOrderTie);
      certain[k] = true;
      ++r.path.slow_edges;
      r.path.edge_mask |= static_cast<uint8_t>(1u << k);
      if (decided_mixed()) break;
    }
  }
  bool agree;
  if (opt.plant == ExactPlant::NoExactPath) {  // plain Fig. 3.6 rule: zeros count as either sign
    const bool any_neg = sign[0] < 0 || sign[1] < 0 || sign[2] < 0;
    const bool any_pos = sign[0] > 0 || sign[1] > 0 || sign[2] > 0;
    agree = !(any_neg && any_pos);
  } else {
    agree = (sign[0] > 0 && sign[1] > 0 && sign[2] > 0) || (sign[0] < 0 && sign[1] < 0 && sign[2] < 0);
  }
  if (!agree) {
    r.why = TriMiss::Sign;
    return r;
  }
  // Interval: V and Va recomputed with the same operations (bit-identical to r.V, r.Va).
  Checked<T> c;
  const Vec3<T> e0 = vsub_chk(c, p1, p2), e1 = vsub_chk(c, p2, p0);
  T V, PV, Va, Pa;
  vol_perm(c, e1, e0, d, V, PV);
  const bool tinyV = c.tiny && opt.plant != ExactPlant::NoTinyCheck;
  const Vec3<T> f2 = vsub_chk(c, p2, a);
  vol_perm(c, e1, e0, f2, Va, Pa);
  int in = -1;
  if (opt.plant == ExactPlant::NoTinyCheck) c.tiny = false;
  if (opt.plant == ExactPlant::NoExactPath) {
    in = t_min < r.t && r.t < t_max;
  } else if (!c.tiny && !tinyV && opt.filter == ExactFilter::PermanentFormat) {
    auto bits = [&](const T& x) { return ru::num::from_double(f, fp_to_double(x)).bits; };  // exact
    in = certified(f, fp_bits(V), fp_bits(PV), k7)
             ? fast_interval_format(f, bits(r.t), bits(V), bits(PV), k7, bits(Va), bits(Pa), k8, bits(t_min),
                                    bits(t_max))
             : -1;
  } else if (!c.tiny && !tinyV) {
    const bool ex = opt.filter == ExactFilter::Exponent;
    in = fast_interval(fp_to_double(r.t), fp_to_double(V), ex ? exponent_bound(e1, e0, d, f.emin(), gx) : fp_to_double(PV),
                       k7, fp_to_double(Va), ex ? exponent_bound(e1, e0, f2, f.emin(), gx) : fp_to_double(Pa), k8, u,
                       minnorm, fp_to_double(t_min), fp_to_double(t_max));
  }
  if (in < 0) {
    r.path.slow_interval = true;
    in = exact_interval(ad, dd, P[0], P[1], P[2], fp_to_double(t_min), fp_to_double(t_max));
  }
  r.why = in ? TriMiss::None : TriMiss::Interval;
  r.hit = in != 0;
  return r;
}

}  // namespace ru::units
