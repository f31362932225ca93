// Double-backed fast paths of add/sub, mul, div, sqrt and fma for formats with M <= 24
// (2(M+1)+2 <= 53), included by fast_paths.hpp; do not include directly.
//
// The operands are decoded into doubles (exact: every value of such a format is a double), the
// operation is done once in double, and the double result is rounded into the format with the
// model's full semantics (exponent range, subnormals or FTZ, four roundings, five flags) by
// round_double() below. What round_double needs to know besides the double s is where the exact
// result lies relative to s:
//   * tail known (add/sub, mul, fma): the exact result is s + t, t from an error-free
//     transformation (TwoSum: exact for doubles without overflow; a product of two <= 25-bit
//     significands is exact in a normal double), and only the sign of t matters: |t| <= ulp(s)/2
//     and every rounding boundary of the format (a representable value or a midpoint, at the
//     normal or the subnormal scale) is a multiple of ulp(s) (M+1 < 53), so no boundary lies
//     strictly between s and s + t; s + t is then rounded as "s nudged by an infinitesimal".
//   * tail unknown (div, sqrt: s = RN(exact), |exact - s| <= ulp(s)/2): if the bits of s dropped
//     by the rounding are neither 0 nor exactly half (at the scale that decides the result),
//     s and the exact value are strictly on the same side of every boundary (the distance to the
//     nearest boundary is >= 1 ulp(s)) and round alike; otherwise (an exact or near-tie quotient
//     or root) the path gives up and the general path decides.
// Every case the path does not handle (NaN/INF operands, zero or non-normal double results,
// ambiguity above) returns false and falls through to the general integer path in
// softfloat.cpp, which is the reference: tests/num/test_fast_paths.cpp compares the two bit
// for bit (value and flags) exhaustively for every format of <= 8 bits and on random and
// special operands for every format, and shows a planted error in round_double is caught.
#pragma once
#include <cmath>
#include <cstring>

#include "rayunits/num/detail/bits.hpp"

namespace ru::num {
namespace detail {

// Off switch: -DRU_NUM_NO_DOUBLE_PATHS builds the model without these paths (general path only
// for div/sqrt/fma, the 64-bit integer paths for add/mul).
#ifdef RU_NUM_NO_DOUBLE_PATHS
inline constexpr bool kDoublePaths = false;
#else
inline constexpr bool kDoublePaths = true;
#endif

inline constexpr int kDoubleMaxM = 24;  // 2(M+1)+2 <= 53

// Decodes a finite operand into the double of the same value (FTZ: subnormals read as zero of
// the same sign). Returns false for INF and NaN.
template <class C>
inline bool decode_double(const C& c, bool subn, uint64_t a, double& x) {
  const int M = c.M;
  const uint64_t emask = (1ull << c.E) - 1;
  const uint64_t e = (a >> M) & emask;
  const uint64_t fr = a & ((1ull << M) - 1);
  const uint64_t s = ((a >> (M + c.E)) & 1) << 63;
  if (e - 1 < emask - 1) {  // normal
    x = double_from_bits(s | ((e - static_cast<uint64_t>(c.bias) + 1023) << 52) | (fr << (52 - M)));
    return true;
  }
  if (e == emask) return false;
  if (fr == 0 || !subn) {
    x = double_from_bits(s);
    return true;
  }
  // Subnormal: fr * 2^(emin - M), exact (the scale is a double, normal or subnormal, >= 2^-1046).
  const int k = static_cast<int>(1 - c.bias) - M;
  const double scale = k >= -1022 ? double_from_bits(static_cast<uint64_t>(k + 1023) << 52) : double_from_bits(1ull << (k + 1074));
  const double v = static_cast<double>(fr) * scale;
  x = s ? -v : v;
  return true;
}

// Round-up decision for the kept value q, dropped bits rem (half-way value half) and a tail
// of sign tm relative to the magnitude (-1: the exact magnitude is below q*2^k + rem by an
// infinitesimal, +1: above, 0: exact). down = (tm < 0 && rem == 0): the exact magnitude is then
// just below the kept value, i.e. kept value q - 1 with dropped bits just below a full unit.
// Branch-free in the data (bitwise & | on 0/1 values): a mispredicted branch per operation
// costs more than the whole rounding.
template <int kPlant = 0>
[[gnu::always_inline]] inline uint64_t round_up_tail(Round rm, bool neg, uint64_t q, uint64_t rem, uint64_t half,
                                                     int tm, bool down) {
  const uint64_t nonzero = static_cast<uint64_t>(rem != 0) | static_cast<uint64_t>(tm != 0);
  switch (rm) {
    case Round::RNE: {
      // planted error 4 (tests only): a tail above an exact half-way point is ignored
      const uint64_t at_half = static_cast<uint64_t>(rem == half);
      const uint64_t gt = static_cast<uint64_t>(rem > half) |
                          (static_cast<uint64_t>(kPlant != 4 && tm > 0) & at_half) | static_cast<uint64_t>(down);
      const uint64_t tie = static_cast<uint64_t>(tm == 0) & at_half;
      return gt | (tie & q & 1);
    }
    case Round::RTZ: return 0;
    case Round::RDN: return static_cast<uint64_t>(neg) & nonzero;
    case Round::RUP: return static_cast<uint64_t>(!neg) & nonzero;
  }
  return 0;
}

// Rounds the exact value "double s (bits sb) nudged by a tail of sign tm" into the format (see
// the file comment; known = false: tm is 0 and the tail's sign is unknown). Returns false if s is
// zero, subnormal, INF or NaN as a double, or (tail unknown) if the tail could change the result.
template <class C>
[[gnu::always_inline]] inline bool round_double(const C& c, bool subn, uint64_t sb, int tm, bool known, Result& out) {
  const int M = c.M;
  if constexpr (C::plant == 1) tm = 0;  // planted error (tests only): the tail / sticky is lost
  const uint64_t de = (sb >> 52) & 0x7ff;
  if (de - 1 >= 2046) return false;
  const uint64_t sig = (sb & ((1ull << 52) - 1)) | (1ull << 52);
  const bool neg = (sb >> 63) != 0;
  const int64_t e_s = static_cast<int64_t>(de) - 1023;
  const uint64_t sgn = static_cast<uint64_t>(neg) << (M + c.E);
  const int shift = 52 - M;
  uint64_t q = sig >> shift, rem = sig & ((1ull << shift) - 1), half = 1ull << (shift - 1);
  if (!known && (rem == 0 || rem == half)) return false;
  bool down = (tm < 0) & (rem == 0);
  if constexpr (C::plant == 3) down = false;  // planted error (tests only): no step below q
  uint64_t up = round_up_tail<C::plant>(c.rm, neg, q, rem, half, tm, down);
  // 1. Rounded to M+1 bits with unbounded exponent; the hidden bit sits at bit M of q, so a
  // carry (q + 1 = 2^(M+1)) or a borrow (q - 1 = 2^M - 1) moves the exponent field by one.
  constexpr int64_t kB = 1100;  // exponent offset: e_s >= -1022 keeps the field positive
  const uint64_t P = (static_cast<uint64_t>(e_s + kB - 1) << M) + q + up - static_cast<uint64_t>(down);
  const int64_t e_r = static_cast<int64_t>(P >> M) - kB;
  const bool inexact = (rem != 0) | (tm != 0);
  if (e_r >= 1 - c.bias) {     // 2. not tiny (tininess after rounding)
    if (e_r > c.bias) {        // 3. overflow
      const bool to_inf = c.rm == Round::RNE || (c.rm == Round::RUP && !neg) || (c.rm == Round::RDN && neg);
      const uint64_t inf = ((1ull << c.E) - 1) << M;
      out.bits = sgn | (to_inf ? inf : inf - 1);
      out.flags = kOverflow | kInexact;
      return true;
    }
    out.bits = sgn | (P - (static_cast<uint64_t>(kB - c.bias) << M));
    out.flags = static_cast<uint8_t>(inexact * kInexact);
    return true;
  }
  if (!subn) {  // 5. flush
    out.bits = sgn;
    out.flags = kUnderflow | kInexact;
    return true;
  }
  // 4. Rounded to a multiple of 2^(emin-M); beyond 54 dropped bits the value is below half
  // the quantum (sig < 2^53), which 54 already shows.
  int64_t shift2 = (1 - c.bias) - M - e_s + 52;  // >= shift: tiny implies e_s <= emin
  if (shift2 > 54) shift2 = 54;
  q = sig >> shift2;
  rem = sig & ((1ull << shift2) - 1);
  half = 1ull << (shift2 - 1);
  if (!known && (rem == 0 || rem == half)) return false;
  down = (tm < 0) & (rem == 0);
  up = round_up_tail<C::plant>(c.rm, neg, q, rem, half, tm, down);
  out.bits = sgn | (q + up - static_cast<uint64_t>(down));
  out.flags = static_cast<uint8_t>(((rem != 0) | (tm != 0)) * (kUnderflow | kInexact));
  if constexpr (C::plant == 2) out.flags &= ~kUnderflow;  // planted error (tests only)
  return true;
}

// Sign of the TwoSum tail t relative to the magnitude of s (branch-free).
inline int tail_sign(double s, double t) {
  const uint64_t tb = double_bits(t);
  const int nz = (tb << 1) != 0;
  const int opp = static_cast<int>((tb ^ double_bits(s)) >> 63);
  return nz * (1 - 2 * opp);
}

template <class C>
inline bool add_double(const C& c, bool subn, uint64_t a, uint64_t b, Result& out) {
  if (c.M > kDoubleMaxM) return false;
  double x, y;
  if (!decode_double(c, subn, a, x) || !decode_double(c, subn, b, y)) return false;
  const double s = x + y;  // TwoSum (Knuth): x + y = s + t exactly
  const double bb = s - x;
  const double t = (x - (s - bb)) + (y - bb);
  return round_double(c, subn, double_bits(s), tail_sign(s, t), true, out);
}

template <class C>
inline bool mul_double(const C& c, bool subn, uint64_t a, uint64_t b, Result& out) {
  if (c.M > kDoubleMaxM) return false;
  double x, y;
  if (!decode_double(c, subn, a, x) || !decode_double(c, subn, b, y)) return false;
  return round_double(c, subn, double_bits(x * y), 0, true, out);  // exact if normal
}

template <class C>
inline bool fma_double(const C& c, bool subn, uint64_t a, uint64_t b, uint64_t z, Result& out) {
  if (c.M > kDoubleMaxM) return false;
  double x, y, w;
  if (!decode_double(c, subn, a, x) || !decode_double(c, subn, b, y) || !decode_double(c, subn, z, w)) return false;
  const double p = x * y;  // exact if normal
  const uint64_t pe = (double_bits(p) >> 52) & 0x7ff;
  if (pe - 1 >= 2046) return false;
  const double s = p + w;
  const double bb = s - p;
  const double t = (p - (s - bb)) + (w - bb);
  return round_double(c, subn, double_bits(s), tail_sign(s, t), true, out);
}

template <class C>
inline bool div_double(const C& c, bool subn, uint64_t a, uint64_t b, Result& out) {
  if (c.M > kDoubleMaxM) return false;
  double x, y;
  if (!decode_double(c, subn, a, x) || !decode_double(c, subn, b, y)) return false;
  return round_double(c, subn, double_bits(x / y), 0, false, out);
}

template <class C>
inline bool sqrt_double(const C& c, bool subn, uint64_t a, Result& out) {
  if (c.M > kDoubleMaxM) return false;
  double x;
  if (!decode_double(c, subn, a, x) || !(x > 0)) return false;  // zeros and negatives: general path
  return round_double(c, subn, double_bits(__builtin_sqrt(x)), 0, false, out);
}

}  // namespace detail
}  // namespace ru::num
