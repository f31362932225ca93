// Exact integer-significand arithmetic for every Format (E <= 11, M <= 52).
//
// Every operation reduces to: an exact (or exact-plus-sticky) integer significand `sig` and a
// binary exponent `exp` with value = sig * 2^exp, handed to the single rounding routine
// round_pack(). The sticky bit stands for a non-zero tail strictly below bit 0 of sig; callers
// guarantee that whenever it is set, sig has at least M+3 significant bits, so the guard bit is
// always an exact bit of sig and the tail only feeds the sticky bit. Semantics: docs/FORMAT.md.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include <gmpxx.h>

#include "rayunits/num/detail/bits.hpp"
#include "rayunits/num/format.hpp"

namespace ru::num {
namespace {

using u128 = unsigned __int128;

inline int msb64(uint64_t x) { return 63 - __builtin_clzll(x); }
inline int msb128(u128 x) {
  const uint64_t hi = static_cast<uint64_t>(x >> 64);
  return hi ? 127 - __builtin_clzll(hi) : msb64(static_cast<uint64_t>(x));
}

struct Unpacked {
  enum Kind : uint8_t { Zero, Finite, Inf, NaN } kind = Zero;
  bool neg = false;
  bool snan = false;
  uint64_t sig = 0;  // value = sig * 2^exp (Finite only)
  int exp = 0;
};

// Decodes a bit pattern. FTZ formats read subnormals as zero of the same sign.
inline Unpacked unpack(const Format& f, uint64_t a) {
  Unpacked u;
  const int M = f.frac_bits;
  u.neg = (a & f.sign_bit()) != 0;
  const uint64_t e = (a >> M) & f.exp_field_max();
  const uint64_t fr = a & f.frac_mask();
  if (e == f.exp_field_max()) {
    if (fr) {
      u.kind = Unpacked::NaN;
      u.snan = ((fr >> (M - 1)) & 1) == 0;  // M = 1: the only NaN is quiet
    } else {
      u.kind = Unpacked::Inf;
    }
  } else if (e == 0) {
    if (fr == 0 || !f.subnormals) {
      u.kind = Unpacked::Zero;
    } else {
      u.kind = Unpacked::Finite;
      u.sig = fr;
      u.exp = f.emin() - M;
    }
  } else {
    u.kind = Unpacked::Finite;
    u.sig = fr | (1ull << M);
    u.exp = static_cast<int>(e) - f.bias() - M;
  }
  return u;
}

inline uint64_t signed_zero(const Format& f, bool neg) { return neg ? f.sign_bit() : 0; }

struct Shifted {
  u128 q;
  bool inexact;
};

// Drops `shift` low bits of sig (plus the sticky tail) and rounds toward the mode.
// Rounding truth table (g = first dropped bit, s = OR of the rest, l = kept LSB):
//   RNE: up = g & (s | l);  RTZ: never;  RDN: up = (g | s) & neg;  RUP: up = (g | s) & !neg.
inline Shifted round_shift(u128 sig, bool sticky, int shift, bool neg, Round rm) {
  u128 q;
  bool g, s;
  if (shift <= 0) {  // exact (sticky is never set on this path, see file comment)
    q = sig << -shift;
    g = false;
    s = sticky;
  } else if (shift > 128) {
    q = 0;
    g = false;
    s = sig != 0 || sticky;
  } else if (shift == 128) {
    q = 0;
    g = (sig >> 127) != 0;
    s = (sig << 1) != 0 || sticky;
  } else {
    q = sig >> shift;
    g = ((sig >> (shift - 1)) & 1) != 0;
    s = (sig & ((static_cast<u128>(1) << (shift - 1)) - 1)) != 0 || sticky;
  }
  bool up = false;
  switch (rm) {
    case Round::RNE: up = g && (s || (q & 1)); break;
    case Round::RTZ: up = false; break;
    case Round::RDN: up = (g || s) && neg; break;
    case Round::RUP: up = (g || s) && !neg; break;
  }
  return {q + (up ? 1 : 0), g || s};
}

// Rounds the non-zero value (-1)^neg * (sig + tail) * 2^exp into the format (docs/FORMAT.md).
Result round_pack(const Format& f, bool neg, int exp, u128 sig, bool sticky) {
  const int M = f.frac_bits;
  const Round rm = f.round;
  const int n = msb128(sig);
  const int e_unb = exp + n;
  // 1. Round to M+1 bits with unbounded exponent.
  const Shifted r = round_shift(sig, sticky, n - M, neg, rm);
  const int carry = static_cast<int>(r.q >> (M + 1));  // rounded up to 2^(M+1)
  const int e_r = e_unb + carry;
  const uint64_t sbit = neg ? f.sign_bit() : 0;
  if (e_r >= f.emin()) {  // 2. not tiny (tininess after rounding)
    if (e_r > f.emax()) {  // 3. overflow
      const bool to_inf = rm == Round::RNE || (rm == Round::RUP && !neg) || (rm == Round::RDN && neg);
      return {to_inf ? f.inf(neg) : f.max_finite(neg), static_cast<uint8_t>(kOverflow | kInexact)};
    }
    const uint64_t q = static_cast<uint64_t>(r.q >> carry);
    return {sbit | (static_cast<uint64_t>(e_r + f.bias()) << M) | (q & f.frac_mask()),
            static_cast<uint8_t>(r.inexact ? kInexact : 0)};
  }
  if (!f.subnormals) return {sbit, static_cast<uint8_t>(kUnderflow | kInexact)};  // 5. flush
  // 4. Round to a multiple of 2^(emin-M); q <= 2^M, and q == 2^M encodes the min normal.
  const Shifted r2 = round_shift(sig, sticky, (f.emin() - M) - exp, neg, rm);
  return {sbit | static_cast<uint64_t>(r2.q), static_cast<uint8_t>(r2.inexact ? (kUnderflow | kInexact) : 0)};
}

inline Result nan_result(const Format& f, bool invalid) {
  return {f.qnan(), static_cast<uint8_t>(invalid ? kInvalid : 0)};
}

inline Result exact_zero_sum(const Format& f, bool neg_a, bool neg_b) {
  const bool n = neg_a == neg_b ? neg_a : f.round == Round::RDN;
  return {signed_zero(f, n), 0};
}

// Adds two non-zero finite significands with signs, aligned at 128-bit window positions.
// X is the operand with the larger top bit. Bits of Y below the window go into `st`.
Result add_aligned(const Format& f, bool xneg, u128 X, bool yneg, u128 Y, bool st, int base) {
  if (xneg == yneg) return round_pack(f, xneg, base, X + Y, st);
  if (X > Y) return round_pack(f, xneg, base, X - Y - (st ? 1 : 0), st);
  if (Y > X) return round_pack(f, yneg, base, Y - X, st);  // st is false here
  return {signed_zero(f, f.round == Round::RDN), 0};
}

// Shifts v right by s >= 0 into a u128 and reports the dropped bits.
inline u128 shr_sticky(u128 v, int s, bool& st) {
  if (s <= 0) return v << -s;
  if (s >= 128) {
    st = st || v != 0;
    return 0;
  }
  st = st || (v & ((static_cast<u128>(1) << s) - 1)) != 0;
  return v >> s;
}

Result add_impl(const Format& f, uint64_t a, uint64_t b, bool negate_b) {
  Unpacked x = unpack(f, a), y = unpack(f, b);
  if (x.kind == Unpacked::NaN || y.kind == Unpacked::NaN) return nan_result(f, x.snan || y.snan);
  if (negate_b) y.neg = !y.neg;
  if (x.kind == Unpacked::Inf) {
    if (y.kind == Unpacked::Inf && x.neg != y.neg) return nan_result(f, true);
    return {f.inf(x.neg), 0};
  }
  if (y.kind == Unpacked::Inf) return {f.inf(y.neg), 0};
  if (x.kind == Unpacked::Zero) {
    if (y.kind == Unpacked::Zero) return exact_zero_sum(f, x.neg, y.neg);
    return {(b & ~f.sign_bit()) | signed_zero(f, y.neg), 0};
  }
  if (y.kind == Unpacked::Zero) return {a, 0};
  if (x.exp < y.exp) std::swap(x, y);
  // x has the larger (or equal) exponent; its significand sits at bit 64 of the window.
  const int d = x.exp - y.exp;
  bool st = false;
  const u128 X = static_cast<u128>(x.sig) << 64;
  const u128 Y = shr_sticky(static_cast<u128>(y.sig) << 64, d, st);
  return add_aligned(f, x.neg, X, y.neg, Y, st, x.exp - 64);
}

// Significand normalized so that its MSB is bit M.
inline void normalize(const Format& f, Unpacked& u) {
  const int s = f.frac_bits - msb64(u.sig);
  u.sig <<= s;
  u.exp -= s;
}

uint64_t flush(const Format& f, uint64_t a) { return detail::flush_operand(f, a); }
using detail::value_key;  // key for comparing non-NaN values (detail/fast_paths.hpp)

Result minmax(const Format& f, uint64_t a, uint64_t b, bool is_max) {
  const Unpacked x = unpack(f, a), y = unpack(f, b);
  const uint8_t fl = (x.snan || y.snan) ? kInvalid : 0;
  const bool xn = x.kind == Unpacked::NaN, yn = y.kind == Unpacked::NaN;
  if (xn && yn) return {f.qnan(), fl};
  if (xn) return {flush(f, b), fl};
  if (yn) return {flush(f, a), fl};
  return {detail::minmax_ordered(f, a, b, is_max), fl};
}

enum class Rel { Lt, Le, Eq, Unord };
Result compare(const Format& f, uint64_t a, uint64_t b, Rel rel) {
  const Unpacked x = unpack(f, a), y = unpack(f, b);
  if (x.kind == Unpacked::NaN || y.kind == Unpacked::NaN) {
    const bool signaling = rel == Rel::Lt || rel == Rel::Le;
    return {rel == Rel::Unord ? 1u : 0u, static_cast<uint8_t>((signaling || x.snan || y.snan) ? kInvalid : 0)};
  }
  const int64_t ka = value_key(f, a), kb = value_key(f, b);
  bool r = false;
  switch (rel) {
    case Rel::Lt: r = ka < kb; break;
    case Rel::Le: r = ka <= kb; break;
    case Rel::Eq: r = ka == kb; break;
    case Rel::Unord: r = false; break;
  }
  return {r ? 1u : 0u, 0};
}

// Integer square root of a u128 (floor).
u128 isqrt128(u128 v) {
  if (v == 0) return 0;
  u128 r = static_cast<u128>(std::sqrt(static_cast<long double>(v)));
  while (r * r > v) --r;
  while ((r + 1) * (r + 1) <= v) ++r;
  return r;
}


}  // namespace

namespace detail {
Result add_general(const Format& f, uint64_t a, uint64_t b) { return add_impl(f, a, b, false); }
Result sub_general(const Format& f, uint64_t a, uint64_t b) { return add_impl(f, a, b, true); }

Result mul_general(const Format& f, uint64_t a, uint64_t b) {
  const Unpacked x = unpack(f, a), y = unpack(f, b);
  if (x.kind == Unpacked::NaN || y.kind == Unpacked::NaN) return nan_result(f, x.snan || y.snan);
  const bool neg = x.neg != y.neg;
  if (x.kind == Unpacked::Inf || y.kind == Unpacked::Inf) {
    if (x.kind == Unpacked::Zero || y.kind == Unpacked::Zero) return nan_result(f, true);
    return {f.inf(neg), 0};
  }
  if (x.kind == Unpacked::Zero || y.kind == Unpacked::Zero) return {signed_zero(f, neg), 0};
  return round_pack(f, neg, x.exp + y.exp, static_cast<u128>(x.sig) * y.sig, false);
}
}  // namespace detail

Result detail::div_general(const Format& f, uint64_t a, uint64_t b) {
  Unpacked x = unpack(f, a), y = unpack(f, b);
  if (x.kind == Unpacked::NaN || y.kind == Unpacked::NaN) return nan_result(f, x.snan || y.snan);
  const bool neg = x.neg != y.neg;
  if (x.kind == Unpacked::Inf) {
    if (y.kind == Unpacked::Inf) return nan_result(f, true);
    return {f.inf(neg), 0};
  }
  if (y.kind == Unpacked::Inf) return {signed_zero(f, neg), 0};
  if (y.kind == Unpacked::Zero) {
    if (x.kind == Unpacked::Zero) return nan_result(f, true);
    return {f.inf(neg), kDivZero};
  }
  if (x.kind == Unpacked::Zero) return {signed_zero(f, neg), 0};
  normalize(f, x);
  normalize(f, y);
  const int M = f.frac_bits;
  // Quotient of (M+1)-bit significands scaled by 2^(M+3): M+3 or M+4 bits, remainder -> sticky.
  const u128 num = static_cast<u128>(x.sig) << (M + 3);
  const u128 q = num / y.sig;
  const bool st = (num % y.sig) != 0;
  return round_pack(f, neg, x.exp - y.exp - (M + 3), q, st);
}

Result detail::sqrt_general(const Format& f, uint64_t a) {
  Unpacked x = unpack(f, a);
  if (x.kind == Unpacked::NaN) return nan_result(f, x.snan);
  if (x.kind == Unpacked::Zero) return {signed_zero(f, x.neg), 0};
  if (x.neg) return nan_result(f, true);
  if (x.kind == Unpacked::Inf) return {f.inf(false), 0};
  normalize(f, x);
  const int M = f.frac_bits;
  u128 s = x.sig;
  int e = x.exp;
  if (e & 1) {
    s <<= 1;
    e -= 1;
  }
  const int k = (M + 6) / 2;  // root gets >= M+3 bits
  const u128 rad = s << (2 * k);
  const u128 root = isqrt128(rad);
  return round_pack(f, false, (e - 2 * k) / 2, root, root * root != rad);
}

Result detail::fma_general(const Format& f, uint64_t a, uint64_t b, uint64_t c) {
  const Unpacked x = unpack(f, a), y = unpack(f, b), z = unpack(f, c);
  const bool prod_inf = x.kind == Unpacked::Inf || y.kind == Unpacked::Inf;
  const bool prod_zero = x.kind == Unpacked::Zero || y.kind == Unpacked::Zero;
  if (x.kind == Unpacked::NaN || y.kind == Unpacked::NaN || z.kind == Unpacked::NaN) {
    const bool inv = x.snan || y.snan || z.snan ||
                     (prod_inf && prod_zero && x.kind != Unpacked::NaN && y.kind != Unpacked::NaN);
    return nan_result(f, inv);
  }
  const bool pneg = x.neg != y.neg;
  if (prod_inf) {
    if (prod_zero) return nan_result(f, true);
    if (z.kind == Unpacked::Inf && z.neg != pneg) return nan_result(f, true);
    return {f.inf(pneg), 0};
  }
  if (z.kind == Unpacked::Inf) return {f.inf(z.neg), 0};
  if (prod_zero) {
    if (z.kind == Unpacked::Zero) return exact_zero_sum(f, pneg, z.neg);
    return {c, 0};
  }
  const u128 P = static_cast<u128>(x.sig) * y.sig;
  const int pe = x.exp + y.exp;
  if (z.kind == Unpacked::Zero) return round_pack(f, pneg, pe, P, false);
  // Align: the operand with the higher top bit goes to bit 125 of the window.
  const int top_p = pe + msb128(P), top_c = z.exp + msb64(z.sig);
  u128 A = P, B = z.sig;
  int ae = pe, be = z.exp;
  bool an = pneg, bn = z.neg;
  if (top_c > top_p) {
    std::swap(A, B);
    std::swap(ae, be);
    std::swap(an, bn);
  }
  const int sa = 125 - msb128(A);
  const int base = ae - sa;
  bool st = false;
  const u128 Bw = shr_sticky(B, base - be, st);
  return add_aligned(f, an, A << sa, bn, Bw, st, base);
}

Result dot3(const Format& f, const uint64_t a[3], const uint64_t b[3]) {
  const Result p0 = mul(f, a[0], b[0]), p1 = mul(f, a[1], b[1]), p2 = mul(f, a[2], b[2]);
  const Result s = add(f, p0.bits, p1.bits);
  Result y = add(f, s.bits, p2.bits);
  y.flags |= p0.flags | p1.flags | p2.flags | s.flags;
  return y;
}

// Fused: the exact sum of the three exact products, rounded once (docs/FORMAT.md). The sum is
// formed exactly in a GMP integer over the lowest product exponent; its top 125 bits (the rest
// as sticky) go to round_pack.
Result dot3_fused(const Format& f, const uint64_t a[3], const uint64_t b[3]) {
  Unpacked x[3], y[3];
  bool any_nan = false, any_snan = false, itz = false, pos_inf = false, neg_inf = false;
  for (int i = 0; i < 3; ++i) {
    x[i] = unpack(f, a[i]);
    y[i] = unpack(f, b[i]);
    any_nan = any_nan || x[i].kind == Unpacked::NaN || y[i].kind == Unpacked::NaN;
    any_snan = any_snan || x[i].snan || y[i].snan;
    const bool inf = x[i].kind == Unpacked::Inf || y[i].kind == Unpacked::Inf;
    const bool zero = x[i].kind == Unpacked::Zero || y[i].kind == Unpacked::Zero;
    itz = itz || (inf && zero);
    if (inf && !zero) (x[i].neg != y[i].neg ? neg_inf : pos_inf) = true;
  }
  // A NaN operand: NaN, invalid for a signaling NaN or an inf*0 product (as fma); inf*0, or
  // infinite products of both signs: NaN, invalid; one infinite sign: that infinity.
  if (any_nan) return nan_result(f, any_snan || itz);
  if (itz || (pos_inf && neg_inf)) return nan_result(f, true);
  if (pos_inf || neg_inf) return {f.inf(neg_inf), 0};
  int lo = 0;
  bool first = true, all_zero = true, zsign_same = true;
  const bool zneg0 = x[0].neg != y[0].neg;
  for (int i = 0; i < 3; ++i) {
    const bool neg = x[i].neg != y[i].neg;
    zsign_same = zsign_same && neg == zneg0;
    if (x[i].kind == Unpacked::Zero || y[i].kind == Unpacked::Zero) continue;
    all_zero = false;
    const int e = x[i].exp + y[i].exp;
    lo = first ? e : std::min(lo, e);
    first = false;
  }
  if (all_zero) return {signed_zero(f, zsign_same ? zneg0 : f.round == Round::RDN), 0};
  mpz_class sum = 0, t;
  for (int i = 0; i < 3; ++i) {
    if (x[i].kind == Unpacked::Zero || y[i].kind == Unpacked::Zero) continue;
    mpz_class p(static_cast<unsigned long>(x[i].sig));
    p *= static_cast<unsigned long>(y[i].sig);
    mpz_mul_2exp(t.get_mpz_t(), p.get_mpz_t(), static_cast<mp_bitcnt_t>(x[i].exp + y[i].exp - lo));
    if (x[i].neg != y[i].neg) sum -= t; else sum += t;
  }
  const int sgn = mpz_sgn(sum.get_mpz_t());
  if (sgn == 0) return {signed_zero(f, f.round == Round::RDN), 0};  // opposite signs cancelled
  mpz_abs(sum.get_mpz_t(), sum.get_mpz_t());
  const long bits = static_cast<long>(mpz_sizeinbase(sum.get_mpz_t(), 2));
  const long drop = std::max(0L, bits - 125);
  const bool sticky = drop > 0 && static_cast<long>(mpz_scan1(sum.get_mpz_t(), 0)) < drop;
  mpz_tdiv_q_2exp(t.get_mpz_t(), sum.get_mpz_t(), static_cast<mp_bitcnt_t>(drop));
  u128 sig = 0;
  for (size_t w = mpz_size(t.get_mpz_t()); w-- > 0;)
    sig = (sig << 64) | static_cast<uint64_t>(mpz_getlimbn(t.get_mpz_t(), static_cast<mp_size_t>(w)));
  return round_pack(f, sgn < 0, lo + static_cast<int>(drop), sig, sticky);
}

Result detail::min_general(const Format& f, uint64_t a, uint64_t b) { return minmax(f, a, b, false); }
Result detail::max_general(const Format& f, uint64_t a, uint64_t b) { return minmax(f, a, b, true); }
Result detail::lt_general(const Format& f, uint64_t a, uint64_t b) { return compare(f, a, b, Rel::Lt); }
Result detail::le_general(const Format& f, uint64_t a, uint64_t b) { return compare(f, a, b, Rel::Le); }
Result eq(const Format& f, uint64_t a, uint64_t b) { return compare(f, a, b, Rel::Eq); }
Result unordered(const Format& f, uint64_t a, uint64_t b) { return compare(f, a, b, Rel::Unord); }
uint64_t abs(const Format& f, uint64_t a) { return a & f.mask() & ~f.sign_bit(); }
uint64_t neg(const Format& f, uint64_t a) { return (a ^ f.sign_bit()) & f.mask(); }

Result from_double(const Format& f, double d) {
  const uint64_t bits = detail::double_bits(d);
  const bool neg = bits >> 63;
  const int e = static_cast<int>((bits >> 52) & 0x7ff);
  const uint64_t fr = bits & ((1ull << 52) - 1);
  if (e == 0x7ff) {
    if (fr) return nan_result(f, ((fr >> 51) & 1) == 0);
    return {f.inf(neg), 0};
  }
  if (e == 0 && fr == 0) return {signed_zero(f, neg), 0};
  if (e == 0) return round_pack(f, neg, -1074, fr, false);
  return round_pack(f, neg, e - 1075, fr | (1ull << 52), false);
}

double to_double(const Format& f, uint64_t a) {
  const Unpacked u = unpack(f, a);
  switch (u.kind) {
    case Unpacked::NaN: return std::nan("");
    case Unpacked::Inf: return u.neg ? -HUGE_VAL : HUGE_VAL;
    case Unpacked::Zero: return u.neg ? -0.0 : 0.0;
    case Unpacked::Finite: break;
  }
  const double v = std::ldexp(static_cast<double>(u.sig), u.exp);
  return u.neg ? -v : v;
}

namespace detail {
// Rounds the exact decimal (-1)^neg * digits * 10^exp10 once into the format: the value is a
// rational N/D (GMP), and the integer quotient with M+3..M+4 bits plus the remainder as sticky
// feeds round_pack. |exp10| is clamped to 1200: beyond that every format over- or underflows
// the same way (2^1024 ~ 1.8e308, 2^-1074 ~ 4.9e-324).
Result from_decimal(const Format& f, bool neg, const std::string& digits, long exp10) {
  mpz_class N(digits, 10);
  if (N == 0) return {signed_zero(f, neg), 0};
  const long e10 = exp10 > 1200 ? 1200 : (exp10 < -1200 ? -1200 : exp10);
  mpz_class D = 1, p;
  mpz_ui_pow_ui(p.get_mpz_t(), 10, static_cast<unsigned long>(e10 < 0 ? -e10 : e10));
  if (e10 < 0) D = p; else N *= p;
  // Choose s so that q = floor(N * 2^s / D) has M+3 or M+4 bits.
  const long nb = static_cast<long>(mpz_sizeinbase(N.get_mpz_t(), 2));
  const long db = static_cast<long>(mpz_sizeinbase(D.get_mpz_t(), 2));
  const long s = (f.frac_bits + 4) - (nb - db);
  if (s >= 0) N <<= static_cast<mp_bitcnt_t>(s); else D <<= static_cast<mp_bitcnt_t>(-s);
  mpz_class q, r;
  mpz_tdiv_qr(q.get_mpz_t(), r.get_mpz_t(), N.get_mpz_t(), D.get_mpz_t());
  const uint64_t q64 = mpz_get_ui(q.get_mpz_t());  // < 2^(M+5) <= 2^57
  return round_pack(f, neg, static_cast<int>(-s), q64, r != 0);
}
}  // namespace detail

Result from_int(const Format& f, int64_t x) {
  if (x == 0) return {0, 0};
  const bool neg = x < 0;
  const uint64_t mag = neg ? 0 - static_cast<uint64_t>(x) : static_cast<uint64_t>(x);
  return round_pack(f, neg, 0, mag, false);
}

IntResult to_int(const Format& f, uint64_t a, Round r) {
  const Unpacked u = unpack(f, a);
  const IntResult sat_pos{INT64_MAX, kInvalid}, sat_neg{INT64_MIN, kInvalid};
  if (u.kind == Unpacked::NaN) return sat_pos;
  if (u.kind == Unpacked::Inf) return u.neg ? sat_neg : sat_pos;
  if (u.kind == Unpacked::Zero) return {0, 0};
  u128 mag;
  bool inexact = false;
  if (u.exp >= 0) {
    if (msb64(u.sig) + u.exp > 63) return u.neg ? sat_neg : sat_pos;
    mag = static_cast<u128>(u.sig) << u.exp;
  } else {
    const Shifted s = round_shift(u.sig, false, -u.exp, u.neg, r);
    mag = s.q;
    inexact = s.inexact;
  }
  const u128 lim = static_cast<u128>(1) << 63;
  if (u.neg) {
    if (mag > lim) return sat_neg;
    return {mag == lim ? INT64_MIN : -static_cast<int64_t>(mag), static_cast<uint8_t>(inexact ? kInexact : 0)};
  }
  if (mag >= lim) return sat_pos;
  return {static_cast<int64_t>(mag), static_cast<uint8_t>(inexact ? kInexact : 0)};
}

IntResult to_int(const Format& f, uint64_t a, Round r, int int_w) {
  if (int_w < 1 || int_w > 64) throw std::invalid_argument("ru::num::to_int: int_w must be 1..64");
  const IntResult x = to_int(f, a, r);
  if (int_w == 64) return x;
  const int64_t hi = static_cast<int64_t>((1ull << (int_w - 1)) - 1), lo = -hi - 1;
  if (x.value > hi) return {hi, kInvalid};  // NaN and +INF included (INT64_MAX)
  if (x.value < lo) return {lo, kInvalid};
  return x;
}

Result convert(const Format& to, const Format& from, uint64_t a) {
  const Unpacked u = unpack(from, a);
  switch (u.kind) {
    case Unpacked::NaN: return nan_result(to, u.snan);
    case Unpacked::Inf: return {to.inf() | (u.neg ? to.sign_bit() : 0), 0};
    case Unpacked::Zero: return {signed_zero(to, u.neg), 0};
    case Unpacked::Finite: break;
  }
  return round_pack(to, u.neg, u.exp, u.sig, false);
}

Class classify(const Format& f, uint64_t a) {
  const bool n = (a & f.sign_bit()) != 0;
  const uint64_t e = (a >> f.frac_bits) & f.exp_field_max();
  const uint64_t fr = a & f.frac_mask();
  if (e == f.exp_field_max()) {
    if (!fr) return n ? Class::NegInf : Class::PosInf;
    return ((fr >> (f.frac_bits - 1)) & 1) ? Class::QNaN : Class::SNaN;
  }
  if (e == 0) {
    if (!fr) return n ? Class::NegZero : Class::PosZero;
    return n ? Class::NegSubnormal : Class::PosSubnormal;
  }
  return n ? Class::NegNormal : Class::PosNormal;
}

const char* class_name(Class c) {
  static const char* names[] = {"-inf", "-normal", "-subnormal", "-zero", "+zero",
                                "+subnormal", "+normal", "+inf", "snan", "qnan"};
  return names[static_cast<int>(c)];
}

}  // namespace ru::num
