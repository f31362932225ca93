// rayunits units: golden model of the ray-box unit (Williams et al. slab test as in Mirth's
// ray_box_int, dissertation §2.1), one function template for double, float and Soft.
//
// Inputs: origin o, reciprocal direction inv (= 1/d, per component; +-INF for a zero
// direction component), the interval [t_min, t_max], box [lo, hi]. Outputs: hit, t_enter,
// t_exit.
//
// Dataflow per axis k (docs/UNITS.md "Dataflow" is the contract):
//   neg_k  = sign bit of inv_k                       (bit select, not an FP op)
//   near_k = neg_k ? hi_k : lo_k;  far_k = neg_k ? lo_k : hi_k   (mux)
//   plain:        tn_k = (near_k - o_k) * inv_k;  tf_k = (far_k - o_k) * inv_k
//   conservative: tn_k = RDN( (near_k - o_k)[neg_k ? RUP : RDN] * inv_k )
//                 tf_k = RUP( (far_k  - o_k)[neg_k ? RDN : RUP] * inv_k )
//                 i.e. the subtraction is rounded so the product is a lower (upper) bound:
//                 with inv_k >= 0 a smaller difference gives a smaller product, with
//                 inv_k < 0 a larger one. FTZ formats only: a directed result flushed to a
//                 zero on the wrong side becomes +-min_normal (ftz_bound below).
//   t_enter = max(max(max(t_min, tn_x), tn_y), tn_z)   (maxNum: NaN operands ignored)
//   t_exit  = min(min(min(t_max, tf_x), tf_y), tf_z)   (minNum)
//   hit = (t_enter <= t_exit) & (t_enter != +INF) & (t_exit != -INF) & !any_nan_input
//
// Defined special cases:
//   * 0*INF: origin exactly on a slab plane of a ray parallel to that plane (d_k = 0, so
//     inv_k = +-INF, and near_k - o_k = 0) gives tn_k or tf_k = NaN, which min/max ignore: the
//     ray lies in the boundary plane of the CLOSED slab and that plane does not constrain t.
//     This is also what Mirth's min/max do with a NaN.
//   * an axis-parallel ray outside a slab gets tn = tf = +INF (or -INF): t_enter = +INF or
//     t_exit = -INF, which the two INF terms reject even when t_max = +INF (t_min = -INF).
//   * a NaN input (o, inv, lo, hi, t_min or t_max): miss. (NaN detection = exponent all ones
//     and fraction != 0 on each input; a bit test, not an FP op.)
// Conservative mode never misses a box that the exact slab test (units/exact.hpp,
// exact_slab) hits for the same input values: every tn_k is <= the exact value, every tf_k
// >= it, a NaN term only widens the interval, and RDN/RUP never round a finite bound across
// the wrong infinity (proof in docs/UNITS.md; property tests in tests/units).
#pragma once

#include <algorithm>
#include <cstring>
#include <limits>
#include <type_traits>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "rayunits/num/fp.hpp"
#include "rayunits/units/vec.hpp"

namespace ru::units {

// DConservative (issue 14 §4): conservative against the ray direction d itself, when inv is the
// round-to-nearest reciprocal of d in the format (as the renderer computes it): per axis the true
// 1/d lies in [a, b] = reciprocal_bounds(inv), and each product takes the end of [a, b] that gives
// the bound (the sign of the rounded difference selects it: two incrementers and a mux per axis
// in hardware, no extra multiplier). Proof in docs/UNITS.md.
enum class BoxMode : uint8_t { Plain = 0, Conservative = 1, DConservative = 2 };

// The interval [a, b] that holds the exact 1/d when inv = RNE(1/d) in T's format (d in the
// format, subnormals or FTZ): inv's neighbours in the format, each clamped at inv's own signed
// zero (the true 1/d has d's sign) and at infinity. Why it holds: a finite nonzero inv is within
// half an ulp of 1/d (the neighbour below a power of two is half an ulp away too); inv = +-INF
// means 1/d overflowed (|1/d| >= max + ulp/2 > max) or d = +-0; inv = +-0 means |1/d| <=
// min_subnormal / 2 (with FTZ: below min_normal). A NaN gives [NaN, NaN].
template <class T>
void reciprocal_bounds(T inv, T& a, T& b) {
  using namespace ru::num;
  const Format f = fp_format<T>();
  const uint64_t bits = fp_bits(inv), sign = bits & f.sign_bit(), mag = bits & ~f.sign_bit();
  if (fp_isnan(inv)) {
    a = b = inv;
    return;
  }
  const uint64_t inf = f.inf(false), minn = f.min_normal(false);
  // magnitude one step away from zero / towards zero, in the format's set of values
  const uint64_t away = mag == inf ? inf : (mag == 0 && !f.subnormals) ? minn : mag + 1;
  const uint64_t toward = mag == 0 ? 0 : (mag == minn && !f.subnormals) ? 0 : mag - 1;
  a = fp_from_bits<T>(sign | (sign ? away : toward));
  b = fp_from_bits<T>(sign | (sign ? toward : away));
}


template <class T>
struct BoxResult {
  bool hit = false;
  T t_enter{}, t_exit{};
};

// Flush-to-zero formats flush a tiny result to zero of its sign whatever the rounding mode,
// which is not a bound in the wrong direction (RUP of a tiny positive value gives +0). The
// conservative unit replaces such a result by the smallest normal of the same sign: selected
// by the operation's underflow flag, the zero result and its sign (a mux, no FP op). With
// subnormals a directed result is never a flushed zero, so this is a no-op there.
template <class T>
T ftz_bound(T x, uint8_t flags, ru::num::Round r) {
  using namespace ru::num;
  const Format f = fp_format<T>();
  const uint64_t b = fp_bits(x);
  const bool is_zero = (b & ~f.sign_bit()) == 0;
  const bool negz = (b & f.sign_bit()) != 0;
  if ((flags & kUnderflow) && is_zero && ((r == Round::RUP && !negz) || (r == Round::RDN && negz)))
    return fp_from_bits<T>(f.min_normal(negz));
  return x;
}

// The golden model exactly as specified above, for every T (the reference of the fast path
// below; ray_box() calls it for Soft, for conservative mode and whenever the fast path sees
// a NaN).
template <class T>
BoxResult<T> ray_box_reference(const Vec3<T>& o, const Vec3<T>& inv, const Vec3<T>& lo, const Vec3<T>& hi,
                     T t_min, T t_max, BoxMode mode = BoxMode::Plain) {
  using namespace ru::num;
  BoxResult<T> r;
  bool any_nan = fp_isnan(t_min) || fp_isnan(t_max);
  T tn[3], tf[3];
  for (int k = 0; k < 3; ++k) {
    any_nan = any_nan || fp_isnan(o[k]) || fp_isnan(inv[k]) || fp_isnan(lo[k]) || fp_isnan(hi[k]);
    const bool neg = fp_signbit(inv[k]);
    const T near_plane = neg ? hi[k] : lo[k];
    const T far_plane = neg ? lo[k] : hi[k];
    if (mode == BoxMode::Plain) {
      tn[k] = (near_plane - o[k]) * inv[k];
      tf[k] = (far_plane - o[k]) * inv[k];
    } else {
      const Round rn = neg ? Round::RUP : Round::RDN, rf = neg ? Round::RDN : Round::RUP;
      uint8_t fl[4] = {0, 0, 0, 0};
      T dn = fp_sub_round(near_plane, o[k], rn, &fl[0]);
      dn = ftz_bound(dn, fl[0], rn);
      T df = fp_sub_round(far_plane, o[k], rf, &fl[1]);
      df = ftz_bound(df, fl[1], rf);
      T r_n = inv[k], r_f = inv[k];
      if (mode == BoxMode::DConservative) {
        // r in [ra, rb] (same sign as inv): the product's lower bound takes ra for x > 0 and rb
        // for x < 0, its upper bound the opposite (x = the directed difference; its sign bit).
        // A zero x takes the end away from zero (rb for inv > 0, ra for inv < 0): its product
        // is then 0*INF = NaN (ignored) whenever the interval reaches infinity, as in the other
        // modes; with the sign of a zero selecting, -0 * max = -0 became a real bound for a ray
        // in a face plane (d_k = +-0; issue 14, found by the e3m2 long test).
        T ra, rb;
        reciprocal_bounds(inv[k], ra, rb);
        const T away = neg ? ra : rb;
        r_n = fp_is_zero(dn) ? away : fp_signbit(dn) ? rb : ra;
        r_f = fp_is_zero(df) ? away : fp_signbit(df) ? ra : rb;
      }
      tn[k] = fp_mul_round(dn, r_n, Round::RDN, &fl[2]);
      tn[k] = ftz_bound(tn[k], fl[2], Round::RDN);
      tf[k] = fp_mul_round(df, r_f, Round::RUP, &fl[3]);
      tf[k] = ftz_bound(tf[k], fl[3], Round::RUP);
    }
  }
  r.t_enter = fp_max(fp_max(fp_max(t_min, tn[0]), tn[1]), tn[2]);
  r.t_exit = fp_min(fp_min(fp_min(t_max, tf[0]), tf[1]), tf[2]);
  r.hit = !any_nan && r.t_enter <= r.t_exit && !fp_is_pos_inf(r.t_enter) && !fp_is_neg_inf(r.t_exit);
  r.t_enter = fp_canon(r.t_enter);
  r.t_exit = fp_canon(r.t_exit);
  return r;
}

namespace detail {

// Fast path for native float/double in plain mode; returns false (r not set) when any of
// tn_x..tf_z, t_min or t_max is a NaN or t_enter or t_exit would be a zero, and the golden
// model above then runs. Otherwise it
// gives the golden model's bits, for these reasons:
//   * tn_k and tf_k are the same two IEEE operations per value in the same order (4 lanes of
//     a vector = 4 independent scalar operations; -ffp-contract=off, no FMA);
//   * no NaN among the six products means no NaN input: each of o_k, inv_k, lo_k and hi_k
//     enters one of them, and sub/mul propagate a NaN (t_min, t_max are checked directly);
//     so any_nan = false and no min/max operand is a NaN;
//   * on non-NaN values minNum/maxNum are the minimum/maximum in the total order with
//     -0 < +0 (fp.hpp native_minmax), which is associative: the chains equal the plain
//     min/max over the four values. A nonzero extreme value has one bit pattern, so
//     "a > b ? a : b" (any order) gives the same bits; only a zero extreme could differ
//     (+0 vs -0), and then the golden model runs;
//   * hit uses the same float comparisons; fp_canon is the identity without NaNs.
// t_min / t_max ride in lane 3: (t - 0) * 1 == t exactly (also -0 - +0 = -0 in RNE).
template <class T, class I>
inline bool ray_box_native_plain(const Vec3<T>& o, const Vec3<T>& inv, const Vec3<T>& lo, const Vec3<T>& hi,
                                 T t_min, T t_max, BoxResult<T>& r) {
  static_assert(sizeof(T) == sizeof(I), "key type");
  typedef T VT __attribute__((vector_size(4 * sizeof(T))));
  typedef I VI __attribute__((vector_size(4 * sizeof(T))));
  const VT vo = {o.x, o.y, o.z, T(0)};
  const VT vi = {inv.x, inv.y, inv.z, T(1)};
  const VT vlo = {lo.x, lo.y, lo.z, t_min}, vhi = {hi.x, hi.y, hi.z, t_max};
  // Sign bit of inv_k (lane 3: inv = +1, so near = t_min, far = t_max).
  VI neg;
  std::memcpy(&neg, &vi, sizeof neg);
  neg = neg >> (8 * static_cast<int>(sizeof(T)) - 1);  // all ones when the sign bit is set
  VI blo, bhi;
  std::memcpy(&blo, &vlo, sizeof blo);
  std::memcpy(&bhi, &vhi, sizeof bhi);
  const VI bnear = (bhi & neg) | (blo & ~neg), bfar = (blo & neg) | (bhi & ~neg);
  VT near_plane, far_plane;
  std::memcpy(&near_plane, &bnear, sizeof near_plane);
  std::memcpy(&far_plane, &bfar, sizeof far_plane);
  const VT tn = (near_plane - vo) * vi;
  const VT tf = (far_plane - vo) * vi;
  // Horizontal maximum of tn and minimum of tf (lane 3: t_min / t_max): a > b ? a : b is the
  // exact maximum of two non-NaN values except for a +0/-0 pair, so a zero result is left
  // to the golden model (its sign is the only thing that could differ).
  VT s = __builtin_shufflevector(tn, tn, 2, 3, 0, 1);
  VT en = tn > s ? tn : s;
  s = __builtin_shufflevector(en, en, 1, 0, 3, 2);
  en = en > s ? en : s;
  s = __builtin_shufflevector(tf, tf, 2, 3, 0, 1);
  VT ex = tf < s ? tf : s;
  s = __builtin_shufflevector(ex, ex, 1, 0, 3, 2);
  ex = ex < s ? ex : s;
  // Any NaN among the eight lanes, or a zero t_enter / t_exit: golden model.
  bool nan;
#if defined(__SSE__)
  if constexpr (sizeof(T) == 4) {
    nan = _mm_movemask_ps(_mm_cmpunord_ps(tn, tf)) != 0;  // one compare for both vectors
  } else
#endif
  {
    VI bad = (tn != tn) | (tf != tf);
    bad |= __builtin_shufflevector(bad, bad, 2, 3, 0, 1);
    bad |= __builtin_shufflevector(bad, bad, 1, 0, 3, 2);
    nan = bad[0] != 0;
  }
  if (nan | (en[0] == T(0)) | (ex[0] == T(0))) return false;
  r.t_enter = en[0];
  r.t_exit = ex[0];
  r.hit = r.t_enter <= r.t_exit && r.t_enter != std::numeric_limits<T>::infinity() &&
          r.t_exit != -std::numeric_limits<T>::infinity();
  return true;
}

// Out of line, result through a pointer: keeps the inlined fast path's result in registers.
template <class T>
__attribute__((noinline)) void ray_box_slow(const Vec3<T>& o, const Vec3<T>& inv, const Vec3<T>& lo,
                                            const Vec3<T>& hi, T t_min, T t_max, BoxMode mode, BoxResult<T>* r) {
  *r = ray_box_reference(o, inv, lo, hi, t_min, t_max, mode);
}

}  // namespace detail

// The unit: the golden model above; native float/double in plain mode take the bit-identical
// fast path (detail::ray_box_native_plain) unless a NaN shows up.
template <class T>
BoxResult<T> ray_box(const Vec3<T>& o, const Vec3<T>& inv, const Vec3<T>& lo, const Vec3<T>& hi,
                     T t_min, T t_max, BoxMode mode = BoxMode::Plain) {
  if constexpr (std::is_same_v<T, float> || std::is_same_v<T, double>) {
    using I = std::conditional_t<std::is_same_v<T, float>, int32_t, int64_t>;
    BoxResult<T> r;
    if (mode == BoxMode::Plain && detail::ray_box_native_plain<T, I>(o, inv, lo, hi, t_min, t_max, r)) return r;
    detail::ray_box_slow(o, inv, lo, hi, t_min, t_max, mode, &r);
    return r;
  } else {
    return ray_box_reference(o, inv, lo, hi, t_min, t_max, mode);
  }
}

}  // namespace ru::units
