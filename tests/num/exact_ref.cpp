// Exact-integer reference (see exact_ref.hpp).
#include "exact_ref.hpp"

#include <gmp.h>

#include <algorithm>
#include <stdexcept>

namespace ru::num::testing {

namespace {

// RAII mpz.
struct Z {
  mpz_t v;
  Z() { mpz_init(v); }
  explicit Z(uint64_t x) {
    mpz_init(v);
    mpz_import(v, 1, 1, sizeof x, 0, 0, &x);
  }
  ~Z() { mpz_clear(v); }
  Z(const Z&) = delete;
  Z& operator=(const Z&) = delete;
};

enum Kind { kZero, kFinite, kInf, kQNaN, kSNaN };

struct Spec {
  int E, M;
  long bias, emin, emax;
  bool sub;
  Round rnd;
  uint64_t sign_bit() const { return uint64_t{1} << (E + M); }
  uint64_t exp_ones() const { return (uint64_t{1} << E) - 1; }
  uint64_t inf(bool neg) const { return (neg ? sign_bit() : 0) | (exp_ones() << M); }
  uint64_t nan() const { return (exp_ones() << M) | (uint64_t{1} << (M - 1)); }
  uint64_t zero(bool neg) const { return neg ? sign_bit() : 0; }
};

struct Num {
  Kind kind = kZero;
  bool neg = false;
  uint64_t sig = 0;  // value = sig * 2^exp
  long exp = 0;
};

Num unpack(const Spec& s, uint64_t x) {
  Num n;
  n.neg = (x >> (s.E + s.M)) & 1;
  const uint64_t e = (x >> s.M) & s.exp_ones();
  const uint64_t fr = x & ((uint64_t{1} << s.M) - 1);
  if (e == s.exp_ones()) {
    n.kind = fr == 0 ? kInf : ((fr >> (s.M - 1)) & 1 ? kQNaN : kSNaN);
  } else if (e == 0) {
    if (fr == 0 || !s.sub) {
      n.kind = kZero;
    } else {
      n.kind = kFinite;
      n.sig = fr;
      n.exp = s.emin - s.M;
    }
  } else {
    n.kind = kFinite;
    n.sig = fr | (uint64_t{1} << s.M);
    n.exp = static_cast<long>(e) - s.bias - s.M;
  }
  return n;
}

bool round_up(Round r, bool neg, bool g, bool st, bool l) {
  switch (r) {
    case Round::RNE:
      return g && (st || l);
    case Round::RTZ:
      return false;
    case Round::RDN:
      return (g || st) && neg;
    case Round::RUP:
      return (g || st) && !neg;
  }
  return false;
}

// q = round(N * 2^-drop) with the truth table; returns whether anything nonzero was dropped.
bool round_drop(const Spec& s, bool neg, const mpz_t N, bool sticky, long drop, mpz_t q) {
  bool g = false, st = sticky;
  if (drop <= 0) {
    mpz_mul_2exp(q, N, static_cast<unsigned long>(-drop));
  } else {
    mpz_fdiv_q_2exp(q, N, static_cast<unsigned long>(drop));
    g = mpz_tstbit(N, static_cast<unsigned long>(drop - 1));
    // any bit below the guard bit
    if (!st && drop >= 2) {
      const mp_bitcnt_t low = mpz_scan1(N, 0);
      st = low != ~mp_bitcnt_t{0} && low < static_cast<mp_bitcnt_t>(drop - 1);
    }
  }
  if (round_up(s.rnd, neg, g, st, mpz_tstbit(q, 0))) mpz_add_ui(q, q, 1);
  return g || st;
}

uint64_t to_u64(const mpz_t q) {
  uint64_t out = 0;
  size_t count = 0;
  if (mpz_sizeinbase(q, 2) > 64) throw std::logic_error("exact_ref: too wide");
  mpz_export(&out, &count, 1, sizeof out, 0, 0, q);
  return count ? out : 0;
}

// Rounds (-1)^neg * (N + sticky*eps) * 2^k, N > 0 (or N == 0 with sticky set), into s.
Result round_value(const Spec& s, bool neg, const mpz_t N, long k, bool sticky) {
  if (mpz_sgn(N) == 0) throw std::logic_error("exact_ref: not enough quotient bits");
  // Step 1: round to M+1 significant bits, unbounded exponent.
  const long bits = static_cast<long>(mpz_sizeinbase(N, 2));
  Z q;
  const long drop = bits - (s.M + 1);
  const bool inexact = round_drop(s, neg, N, sticky, drop, q.v);
  long exp1 = k + drop;
  if (mpz_sizeinbase(q.v, 2) > static_cast<size_t>(s.M + 1)) {  // carried into 2^(M+1)
    mpz_fdiv_q_2exp(q.v, q.v, 1);
    exp1 += 1;
  }
  const long lead = exp1 + s.M;  // |r| in [2^lead, 2^(lead+1))
  // Step 2: tininess after rounding.
  if (lead >= s.emin) {
    // Step 3: overflow, or the normal result.
    if (lead > s.emax) {
      bool to_inf;
      switch (s.rnd) {
        case Round::RNE:
          to_inf = true;
          break;
        case Round::RTZ:
          to_inf = false;
          break;
        case Round::RUP:
          to_inf = !neg;
          break;
        default:
          to_inf = neg;
          break;
      }
      return {to_inf ? s.inf(neg) : s.inf(neg) - 1, kOverflow | kInexact};
    }
    const uint64_t frac = to_u64(q.v) & ((uint64_t{1} << s.M) - 1);
    return {(neg ? s.sign_bit() : 0) | (static_cast<uint64_t>(lead + s.bias) << s.M) | frac,
            static_cast<uint8_t>(inexact ? kInexact : 0)};
  }
  // Step 5: flush to zero.
  if (!s.sub) return {s.zero(neg), kUnderflow | kInexact};
  // Step 4: round v to a multiple of 2^(emin-M); the count of units is the bit pattern
  // (2^M units = the smallest normal).
  Z q2;
  const bool inexact2 = round_drop(s, neg, N, sticky, (s.emin - s.M) - k, q2.v);
  return {(neg ? s.sign_bit() : 0) | to_u64(q2.v),
          static_cast<uint8_t>(inexact2 ? kUnderflow | kInexact : 0)};
}

// Sets z = (-1)^neg * sig * 2^(exp - k)  (exp >= k).
void scaled(mpz_t z, const Num& n, long k) {
  Z s(n.sig);
  mpz_mul_2exp(z, s.v, static_cast<unsigned long>(n.exp - k));
  if (n.neg) mpz_neg(z, z);
}

// Exact sum of two exact terms (x = ±X*2^kx); zero results get the IEEE sign.
Result sum(const Spec& s, const mpz_t X, long kx, bool xzero, bool xneg, const Num& y) {
  const bool yzero = y.kind == kZero;
  if (xzero && yzero) {
    const bool neg = (xneg == y.neg) ? xneg : s.rnd == Round::RDN;
    return {s.zero(neg), 0};
  }
  Z T;
  long k;
  if (xzero) {
    k = y.exp;
    scaled(T.v, y, k);
  } else if (yzero) {
    k = kx;
    mpz_set(T.v, X);
  } else {
    k = std::min(kx, y.exp);
    Z t2;
    mpz_mul_2exp(T.v, X, static_cast<unsigned long>(kx - k));
    scaled(t2.v, y, k);
    mpz_add(T.v, T.v, t2.v);
  }
  if (mpz_sgn(T.v) == 0) return {s.zero(s.rnd == Round::RDN), 0};
  const bool neg = mpz_sgn(T.v) < 0;
  mpz_abs(T.v, T.v);
  return round_value(s, neg, T.v, k, false);
}

}  // namespace

Result exact_apply(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) {
  Spec s;
  s.E = f.exp_bits;
  s.M = f.frac_bits;
  s.bias = (1L << (s.E - 1)) - 1;
  s.emin = 1 - s.bias;
  s.emax = s.bias;
  s.sub = f.subnormals;
  s.rnd = f.round;
  const int n = op == Op::Sqrt ? 1 : op == Op::Fma ? 3 : 2;
  Num x = unpack(s, a), y = n >= 2 ? unpack(s, b) : Num{}, z = n >= 3 ? unpack(s, c) : Num{};
  if (op == Op::Sub) y.neg = !y.neg;
  auto isnan = [](const Num& v) { return v.kind == kQNaN || v.kind == kSNaN; };
  const bool snan = x.kind == kSNaN || y.kind == kSNaN || z.kind == kSNaN;
  const bool zero_inf = (x.kind == kZero && y.kind == kInf) || (x.kind == kInf && y.kind == kZero);
  if (isnan(x) || isnan(y) || isnan(z)) {
    return {s.nan(), static_cast<uint8_t>(snan || (op == Op::Fma && zero_inf) ? kInvalid : 0)};
  }
  const Result invalid{s.nan(), kInvalid};
  switch (op) {
    case Op::Add:
    case Op::Sub: {
      if (x.kind == kInf || y.kind == kInf) {
        if (x.kind == kInf && y.kind == kInf && x.neg != y.neg) return invalid;
        return {s.inf(x.kind == kInf ? x.neg : y.neg), 0};
      }
      Z X;
      if (x.kind == kFinite) scaled(X.v, x, x.exp);
      return sum(s, X.v, x.exp, x.kind == kZero, x.neg, y);
    }
    case Op::Mul:
    case Op::Fma: {
      const bool pneg = x.neg != y.neg;
      if (zero_inf) return invalid;
      const bool pinf = x.kind == kInf || y.kind == kInf;
      if (op == Op::Mul) {
        if (pinf) return {s.inf(pneg), 0};
        if (x.kind == kZero || y.kind == kZero) return {s.zero(pneg), 0};
        Z P, B(y.sig);
        Z A(x.sig);
        mpz_mul(P.v, A.v, B.v);
        return round_value(s, pneg, P.v, x.exp + y.exp, false);
      }
      if (pinf) {
        if (z.kind == kInf && z.neg != pneg) return invalid;
        return {s.inf(pneg), 0};
      }
      if (z.kind == kInf) return {s.inf(z.neg), 0};
      const bool pzero = x.kind == kZero || y.kind == kZero;
      Z P;
      long kp = 0;
      if (!pzero) {
        Z A(x.sig), B(y.sig);
        mpz_mul(P.v, A.v, B.v);
        if (pneg) mpz_neg(P.v, P.v);
        kp = x.exp + y.exp;
      }
      return sum(s, P.v, kp, pzero, pneg, z);
    }
    case Op::Div: {
      const bool qneg = x.neg != y.neg;
      if ((x.kind == kZero && y.kind == kZero) || (x.kind == kInf && y.kind == kInf)) return invalid;
      if (x.kind == kInf) return {s.inf(qneg), 0};
      if (y.kind == kZero) return {s.inf(qneg), kDivZero};
      if (x.kind == kZero || y.kind == kInf) return {s.zero(qneg), 0};
      Z A(x.sig), B(y.sig), Q, R;
      const long la = static_cast<long>(mpz_sizeinbase(A.v, 2));
      const long lb = static_cast<long>(mpz_sizeinbase(B.v, 2));
      const long sh = std::max(0L, (s.M + 4) + lb - la);  // >= M+3 quotient bits
      mpz_mul_2exp(A.v, A.v, static_cast<unsigned long>(sh));
      mpz_fdiv_qr(Q.v, R.v, A.v, B.v);
      return round_value(s, qneg, Q.v, x.exp - y.exp - sh, mpz_sgn(R.v) != 0);
    }
    case Op::Sqrt: {
      if (x.kind == kZero) return {s.zero(x.neg), 0};
      if (x.neg) return invalid;
      if (x.kind == kInf) return {s.inf(false), 0};
      Z A(x.sig), Rt, Rm;
      long e = x.exp;
      if (e & 1) {
        mpz_mul_2exp(A.v, A.v, 1);
        e -= 1;
      }
      const long la = static_cast<long>(mpz_sizeinbase(A.v, 2));
      const long t = std::max(0L, (2 * s.M + 9 - la + 1) / 2);  // root >= M+4 bits
      mpz_mul_2exp(A.v, A.v, static_cast<unsigned long>(2 * t));
      mpz_sqrtrem(Rt.v, Rm.v, A.v);
      return round_value(s, false, Rt.v, (e - 2 * t) / 2, mpz_sgn(Rm.v) != 0);
    }
    default:
      break;
  }
  throw std::logic_error("exact_apply: unsupported op");
}

}  // namespace ru::num::testing
