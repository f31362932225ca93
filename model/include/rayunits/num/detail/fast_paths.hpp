// Fast paths of add/sub and mul, and min/max/lt/le of non-NaN operands (included by
// format.hpp; do not include directly); the double-backed paths of add/sub, mul, div, sqrt
// and fma for M <= 24 are in double_paths.hpp.
//
// They apply when both operands are normal, the result is normal and not next to overflow,
// and M is small enough for 64-bit arithmetic; they compute exactly the bits and flags of the
// general path in softfloat.cpp (the MPFR / native / exhaustive suites exercise both paths:
// every test that hits a normal result goes through here). Everything else falls through.
// They are inline so that renders and sweeps in the emulated format pay no call overhead:
// the general path alone is about 3-4x slower.
#pragma once
#include <utility>

#include "rayunits/num/detail/double_paths.hpp"

namespace ru::num {
namespace detail {

Result add_general(const Format& f, uint64_t a, uint64_t b);
Result sub_general(const Format& f, uint64_t a, uint64_t b);
Result mul_general(const Format& f, uint64_t a, uint64_t b);
Result div_general(const Format& f, uint64_t a, uint64_t b);
Result sqrt_general(const Format& f, uint64_t a);
Result fma_general(const Format& f, uint64_t a, uint64_t b, uint64_t c);
Result min_general(const Format& f, uint64_t a, uint64_t b);  // every operand, NaNs included
Result max_general(const Format& f, uint64_t a, uint64_t b);
Result lt_general(const Format& f, uint64_t a, uint64_t b);
Result le_general(const Format& f, uint64_t a, uint64_t b);

// FTZ formats read a subnormal operand as a zero of its sign.
inline uint64_t flush_operand(const Format& f, uint64_t a) {
  if (!f.subnormals && ((a >> f.frac_bits) & f.exp_field_max()) == 0) return a & f.sign_bit();
  return a;
}
// Integer keys of non-NaN values (after flushing): total_key orders -0 < +0 (min/max),
// value_key makes them equal (comparisons).
inline int64_t total_key(const Format& f, uint64_t a) {
  a = flush_operand(f, a);
  const int64_t m = static_cast<int64_t>(a & ~f.sign_bit());
  return (a & f.sign_bit()) ? -m - 1 : m;
}
inline int64_t value_key(const Format& f, uint64_t a) {
  a = flush_operand(f, a);
  const int64_t m = static_cast<int64_t>(a & ~f.sign_bit());
  return (a & f.sign_bit()) ? -m : m;
}
// minNum/maxNum of two non-NaN operands: the flushed operand that is smaller / larger in the
// total order (a on a tie), no flags. The general path uses it too.
inline uint64_t minmax_ordered(const Format& f, uint64_t a, uint64_t b, bool is_max) {
  const int64_t ka = total_key(f, a), kb = total_key(f, b);
  const bool pick_b = is_max ? kb > ka : kb < ka;
  return flush_operand(f, pick_b ? b : a);
}

// Round-up decision for a kept value q with `rem` dropped bits whose half-way value is `half`
// (see the truth table in docs/FORMAT.md). Branch-free for the data-dependent parts.
inline uint64_t round_inc(Round rm, bool neg, uint64_t q, uint64_t rem, uint64_t half) {
  switch (rm) {
    case Round::RNE: return static_cast<uint64_t>(rem > half) | (static_cast<uint64_t>(rem == half) & q & 1);
    case Round::RTZ: return 0;
    case Round::RDN: return static_cast<uint64_t>(neg) & static_cast<uint64_t>(rem != 0);
    case Round::RUP: return static_cast<uint64_t>(!neg) & static_cast<uint64_t>(rem != 0);
  }
  return 0;
}

// Format constants for the fast paths: DynConsts reads them from a runtime Format;
// FixedConsts<E, M> makes them compile-time constants (shifts and masks become immediates),
// used for the formats sweeps and renders use most. Both instantiate the same code below.
struct DynConsts {
  int M, E;
  int64_t bias;
  Round rm;
  bool subn;
  static constexpr int plant = 0;  // tests/num/test_fast_paths.cpp plants errors with a non-zero value
  explicit DynConsts(const Format& f)
      : M(f.frac_bits), E(f.exp_bits), bias(f.bias()), rm(f.round), subn(f.subnormals) {}
};
template <int kE, int kM>
struct FixedConsts {
  static constexpr int M = kM, E = kE;
  static constexpr int64_t bias = (1 << (kE - 1)) - 1;
  Round rm;
  bool subn;
  static constexpr int plant = 0;
  explicit FixedConsts(const Format& f) : rm(f.round), subn(f.subnormals) {}
};

template <class C>
inline bool exp_is_normal(const C& c, uint64_t e) {
  return e - 1 < (1ull << c.E) - 2;
}

template <class C>
inline bool mul_fast(const C& c, uint64_t a, uint64_t b, Result& out) {
  const int M = c.M;
  if (M > 31) return false;
  const uint64_t emask = (1ull << c.E) - 1;
  const uint64_t ea = (a >> M) & emask, eb = (b >> M) & emask;
  if (!exp_is_normal(c, ea) || !exp_is_normal(c, eb)) return false;
  const uint64_t hidden = 1ull << M, fmask = hidden - 1;
  const uint64_t p = ((a & fmask) | hidden) * ((b & fmask) | hidden);  // [2^2M, 2^(2M+2))
  const int hi = static_cast<int>(p >> (2 * M + 1));
  const int64_t e = static_cast<int64_t>(ea + eb) - c.bias + hi;  // biased, before rounding
  if (e <= 0 || e >= static_cast<int64_t>(emask) - 1) return false;
  const bool neg = ((a ^ b) >> (M + c.E)) & 1;
  const int shift = M + hi;
  const uint64_t q = p >> shift, rem = p & ((1ull << shift) - 1);
  const uint64_t up = round_inc(c.rm, neg, q, rem, 1ull << (shift - 1));
  // (e-1) << M plus q (hidden bit included): a rounding carry ripples into the exponent.
  out.bits = (static_cast<uint64_t>(neg) << (M + c.E)) | ((static_cast<uint64_t>(e - 1) << M) + q + up);
  out.flags = rem ? kInexact : 0;
  return true;
}

// M <= 29: the significands are aligned high in a 64-bit word (leading one at bit 62, so
// L = 62 - M >= M + 33 zero bits below the smaller operand's last bit). A right shift by the
// exponent difference d <= L is then exact; for d > L the shifted value is below 2^M, far
// under the result's half-ulp (>= 2^(L-2) even after a one-bit cancellation), so it is
// replaced by any nonzero value below 2^M (the shifted bits with bit 0 forced to one): no
// rounding boundary lies between the two, so q, the round decision and inexact are the same.
// The result is normalised with one count-leading-zeros and constant shifts; the dropped bits
// end up left-aligned in `rem` (half-way = 2^63).
template <class C>
inline bool add_fast_narrow(const C& c, uint64_t a, uint64_t b, Result& out) {
  const int M = c.M;
  const int L = 62 - M;
  const uint64_t sign = 1ull << (M + c.E), mag = sign - 1, emask = (1ull << c.E) - 1;
  const uint64_t hidden = 1ull << M, fmask = hidden - 1, inf = emask << M;
  const uint64_t am = a & mag, bm = b & mag;
  // Magnitude order as selects (no branch to mispredict on random operands).
  const bool swap = am < bm;
  const uint64_t hi = swap ? bm : am, lo = swap ? am : bm;
  if (hi >= inf || lo < hidden) return false;  // both normal (lo <= hi)
  const uint64_t s = (swap ? b : a) & sign;    // sign of the larger magnitude
  const uint64_t ea = hi >> M, d = ea - (lo >> M);
  const uint64_t X = ((hi & fmask) | hidden) << L;
  const uint64_t Yb = ((lo & fmask) | hidden) << L;
  const uint64_t Y = (Yb >> (d > 63 ? 63 : d)) | static_cast<uint64_t>(d > static_cast<uint64_t>(L));
  // X + Y (< 2^64) or X - Y: a conditional negation of Y (m = all ones for a subtraction).
  const uint64_t m = -(((a ^ b) >> (M + c.E)) & 1);
  const uint64_t S = X + ((Y ^ m) - m);
  if (S == 0) return false;  // exact zero: its sign depends on the mode (general path)
  const int lz = __builtin_clzll(S);  // 0 (carry), 1, or more after a cancellation
  const uint64_t N = S << lz;           // leading one at bit 63
  const int64_t e = static_cast<int64_t>(ea) + 1 - lz;  // biased, before rounding
  if (e <= 0 || e >= static_cast<int64_t>(emask) - 1) return false;
  const uint64_t q = N >> (63 - M), rem = N << (M + 1);
  const uint64_t up = round_inc(c.rm, s != 0, q, rem, 1ull << 63);
  out.bits = s | ((static_cast<uint64_t>(e - 1) << M) + q + up);
  out.flags = static_cast<uint8_t>(rem != 0) * kInexact;
  return true;
}

template <class C>
inline bool add_fast(const C& c, uint64_t a, uint64_t b, Result& out) {
  const int M = c.M;
  if (M <= 29) return add_fast_narrow(c, a, b, out);
  if (M > 44) return false;
  const uint64_t sign = 1ull << (M + c.E), mag = sign - 1, emask = (1ull << c.E) - 1;
  if ((a & mag) < (b & mag)) std::swap(a, b);  // |a| >= |b|
  const uint64_t ea = (a >> M) & emask, eb = (b >> M) & emask;
  if (!exp_is_normal(c, ea) || !exp_is_normal(c, eb)) return false;
  const uint64_t hidden = 1ull << M, fmask = hidden - 1;
  const int d = static_cast<int>(ea - eb);
  // Three extra low bits (guard, round, sticky) below both significands.
  const uint64_t X = ((a & fmask) | hidden) << 3;
  const uint64_t yb = ((b & fmask) | hidden) << 3;
  const int ds = d > M + 4 ? M + 4 : d;  // beyond M+4 only a sticky bit remains
  const uint64_t Y = (yb >> ds) | static_cast<uint64_t>((yb & ((1ull << ds) - 1)) != 0);
  int64_t e = static_cast<int64_t>(ea);
  uint64_t S;
  if (((a ^ b) & sign) == 0) {
    S = X + Y;  // < 2^(M+5)
    const int carry = static_cast<int>(S >> (M + 4));
    S = (S >> carry) | (S & static_cast<uint64_t>(carry));
    e += carry;
  } else {
    S = X - Y;
    if (S == 0) return false;  // exact zero: its sign depends on the mode (general path)
    const int lz = (M + 3) - (63 - __builtin_clzll(S));  // > 1 only if d <= 1: then S is exact
    S <<= lz;
    e -= lz;
  }
  if (e <= 0 || e >= static_cast<int64_t>(emask) - 1) return false;
  const bool neg = (a & sign) != 0;
  const uint64_t q = S >> 3, rem = S & 7;
  const uint64_t up = round_inc(c.rm, neg, q, rem, 4);
  out.bits = (a & sign) | ((static_cast<uint64_t>(e - 1) << M) + q + up);
  out.flags = rem ? kInexact : 0;
  return true;
}

// Dispatch to a compile-time-constant instance for the common formats.
template <template <class> class Op, class... A>
inline bool dispatch_fast_n(const Format& f, Result& out, A... args) {
  if (f.exp_bits == 8 && f.frac_bits == 23) return Op<FixedConsts<8, 23>>::run(FixedConsts<8, 23>(f), out, args...);
  if (f.exp_bits == 7 && f.frac_bits == 16) return Op<FixedConsts<7, 16>>::run(FixedConsts<7, 16>(f), out, args...);
  if (f.exp_bits == 5 && f.frac_bits == 10) return Op<FixedConsts<5, 10>>::run(FixedConsts<5, 10>(f), out, args...);
  return Op<DynConsts>::run(DynConsts(f), out, args...);
}
template <template <class> class Op>
inline bool dispatch_fast(const Format& f, uint64_t a, uint64_t b, Result& out) {
  return dispatch_fast_n<Op>(f, out, a, b);
}
// The 64-bit integer paths (normal operands and results) first, then the double-backed paths
// (detail/double_paths.hpp: subnormal operands and results, tiny results, overflow).
template <class C>
struct AddFastOp {
  static bool run(const C& c, Result& out, uint64_t a, uint64_t b) {
    return add_fast(c, a, b, out) || (kDoublePaths && add_double(c, c.subn, a, b, out));
  }
};
template <class C>
struct MulFastOp {
  static bool run(const C& c, Result& out, uint64_t a, uint64_t b) {
    return mul_fast(c, a, b, out) || (kDoublePaths && mul_double(c, c.subn, a, b, out));
  }
};
// The integer paths alone (tests: the double paths are compared with them and the general path).
template <class C>
struct AddIntOp {
  static bool run(const C& c, Result& out, uint64_t a, uint64_t b) { return add_fast(c, a, b, out); }
};
template <class C>
struct MulIntOp {
  static bool run(const C& c, Result& out, uint64_t a, uint64_t b) { return mul_fast(c, a, b, out); }
};
// The double-backed paths alone.
template <class C>
struct AddDoubleOp {
  static bool run(const C& c, Result& out, uint64_t a, uint64_t b) { return add_double(c, c.subn, a, b, out); }
};
template <class C>
struct MulDoubleOp {
  static bool run(const C& c, Result& out, uint64_t a, uint64_t b) { return mul_double(c, c.subn, a, b, out); }
};
template <class C>
struct DivDoubleOp {
  static bool run(const C& c, Result& out, uint64_t a, uint64_t b) {
    return kDoublePaths && div_double(c, c.subn, a, b, out);
  }
};
template <class C>
struct SqrtDoubleOp {
  static bool run(const C& c, Result& out, uint64_t a) { return kDoublePaths && sqrt_double(c, c.subn, a, out); }
};
template <class C>
struct FmaDoubleOp {
  static bool run(const C& c, Result& out, uint64_t a, uint64_t b, uint64_t z) {
    return kDoublePaths && fma_double(c, c.subn, a, b, z, out);
  }
};

}  // namespace detail

inline Result add(const Format& f, uint64_t a, uint64_t b) {
  Result r;
  if (detail::dispatch_fast<detail::AddFastOp>(f, a, b, r)) return r;
  return detail::add_general(f, a, b);
}
inline Result sub(const Format& f, uint64_t a, uint64_t b) {
  Result r;
  if (detail::dispatch_fast<detail::AddFastOp>(f, a, b ^ f.sign_bit(), r)) return r;
  return detail::sub_general(f, a, b);
}
inline Result mul(const Format& f, uint64_t a, uint64_t b) {
  Result r;
  if (detail::dispatch_fast<detail::MulFastOp>(f, a, b, r)) return r;
  return detail::mul_general(f, a, b);
}
inline Result div(const Format& f, uint64_t a, uint64_t b) {
  Result r;
  if (detail::dispatch_fast_n<detail::DivDoubleOp>(f, r, a, b)) return r;
  return detail::div_general(f, a, b);
}
inline Result sqrt(const Format& f, uint64_t a) {
  Result r;
  if (detail::dispatch_fast_n<detail::SqrtDoubleOp>(f, r, a)) return r;
  return detail::sqrt_general(f, a);
}
inline Result fma(const Format& f, uint64_t a, uint64_t b, uint64_t c) {
  Result r;
  if (detail::dispatch_fast_n<detail::FmaDoubleOp>(f, r, a, b, c)) return r;
  return detail::fma_general(f, a, b, c);
}
inline Result min(const Format& f, uint64_t a, uint64_t b) {
  if (!is_nan(f, a) && !is_nan(f, b)) return {detail::minmax_ordered(f, a, b, false), 0};
  return detail::min_general(f, a, b);
}
inline Result max(const Format& f, uint64_t a, uint64_t b) {
  if (!is_nan(f, a) && !is_nan(f, b)) return {detail::minmax_ordered(f, a, b, true), 0};
  return detail::max_general(f, a, b);
}
inline Result lt(const Format& f, uint64_t a, uint64_t b) {
  if (!is_nan(f, a) && !is_nan(f, b)) return {detail::value_key(f, a) < detail::value_key(f, b) ? 1u : 0u, 0};
  return detail::lt_general(f, a, b);
}
inline Result le(const Format& f, uint64_t a, uint64_t b) {
  if (!is_nan(f, a) && !is_nan(f, b)) return {detail::value_key(f, a) <= detail::value_key(f, b) ? 1u : 0u, 0};
  return detail::le_general(f, a, b);
}

}  // namespace ru::num
