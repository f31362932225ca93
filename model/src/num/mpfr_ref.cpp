// Independent MPFR oracle (see mpfr_ref.hpp). Written from docs/FORMAT.md and IEEE 754 only:
// it does not call the model (softfloat.cpp), it decodes/encodes the bit patterns itself.
#include "rayunits/num/mpfr_ref.hpp"

#include <mpfr.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <limits>

namespace ru::num {

namespace {

// Format parameters, derived here from (E, M) alone.
struct Fmt {
  int E, M;
  int64_t bias, emin, emax;      // value exponents: smallest normal 2^emin, largest finite < 2^(emax+1)
  uint64_t sign, fmask, efield;  // efield: the all-ones exponent field (INF/NaN)
  bool sub;
  Round rnd;
  explicit Fmt(const Format& f)
      : E(f.exp_bits),
        M(f.frac_bits),
        bias((int64_t{1} << (E - 1)) - 1),
        emin(1 - bias),
        emax(bias),
        sign(uint64_t{1} << (E + M)),
        fmask((uint64_t{1} << M) - 1),
        efield((uint64_t{1} << E) - 1),
        sub(f.subnormals),
        rnd(f.round) {}
  uint64_t inf(bool neg) const { return (neg ? sign : 0) | (efield << M); }
  uint64_t qnan() const { return (efield << M) | (uint64_t{1} << (M - 1)); }
  uint64_t max_finite(bool neg) const { return inf(neg) - 1; }
  uint64_t zero(bool neg) const { return neg ? sign : 0; }
};

enum class Kind { Zero, Finite, Inf, QNaN, SNaN };

struct Val {
  Kind kind;
  bool neg;
  uint64_t sig;  // Finite: value = (-1)^neg * sig * 2^exp2
  int64_t exp2;
  uint64_t bits;  // the pattern after flush-to-zero (a flushed subnormal becomes +-0)
  bool nan() const { return kind == Kind::QNaN || kind == Kind::SNaN; }
  // Exact value as a double (every value of these formats is one); NaN for NaNs.
  double value() const {
    switch (kind) {
      case Kind::Zero:
        return neg ? -0.0 : 0.0;
      case Kind::Inf:
        return neg ? -HUGE_VAL : HUGE_VAL;
      case Kind::Finite: {
        const double v = std::ldexp(static_cast<double>(sig), static_cast<int>(exp2));
        return neg ? -v : v;
      }
      default:
        return std::numeric_limits<double>::quiet_NaN();
    }
  }
};

Val decode(const Fmt& F, uint64_t x) {
  const bool neg = (x & F.sign) != 0;
  const uint64_t e = (x >> F.M) & F.efield;
  const uint64_t fr = x & F.fmask;
  if (e == F.efield) {
    if (fr == 0) return {Kind::Inf, neg, 0, 0, x};
    const bool quiet = (fr >> (F.M - 1)) & 1;  // M == 1: the only NaN fraction is 1 = quiet
    return {quiet ? Kind::QNaN : Kind::SNaN, neg, 0, 0, x};
  }
  if (e == 0) {
    if (fr == 0 || !F.sub) return {Kind::Zero, neg, 0, 0, F.zero(neg)};
    return {Kind::Finite, neg, fr, F.emin - F.M, x};
  }
  return {Kind::Finite, neg, fr | (uint64_t{1} << F.M), static_cast<int64_t>(e) - F.bias - F.M, x};
}

[[noreturn]] void oracle_bug(const char* what, double v, int E, int M) {
  std::fprintf(stderr, "mpfr_ref: internal error: %s (value %a, format e%dm%d)\n", what, v, E, M);
  std::abort();
}

// Bit pattern of a value that is exactly representable in F (finite or +-0 or +-inf). Works on
// the bits of the double (every value of these formats is a double).
uint64_t encode(const Fmt& F, double d) {
  uint64_t u;
  std::memcpy(&u, &d, sizeof u);
  const bool neg = (u >> 63) != 0;
  const uint64_t de = (u >> 52) & 0x7ff, dm = u & ((uint64_t{1} << 52) - 1);
  if (de == 0x7ff) {
    if (dm != 0) oracle_bug("encode: NaN", d, F.E, F.M);
    return F.inf(neg);
  }
  if (de == 0 && dm == 0) return F.zero(neg);
  // value = sig * 2^e2, sig with its leading one at bit 52 (or fewer bits for a double subnormal)
  const uint64_t sig = de ? (dm | (uint64_t{1} << 52)) : dm;
  const int64_t e2 = de ? static_cast<int64_t>(de) - 1075 : -1074;
  const int64_t lead = e2 + 63 - __builtin_clzll(sig);
  uint64_t pat;
  if (lead >= F.emin) {
    if (lead > F.emax || !de) oracle_bug("encode: above the format range", d, F.E, F.M);
    const int sh = 52 - F.M;  // keep M fraction bits
    if (sig & ((uint64_t{1} << sh) - 1)) oracle_bug("encode: more than M+1 bits", d, F.E, F.M);
    pat = (static_cast<uint64_t>(lead + F.bias) << F.M) | ((sig >> sh) & F.fmask);
  } else {
    const int64_t sh = (F.emin - F.M) - e2;  // units of 2^(emin-M)
    if (sh < 0 || sh >= 64 || (sig & ((uint64_t{1} << sh) - 1)))
      oracle_bug("encode: not a subnormal of the format", d, F.E, F.M);
    pat = sig >> sh;
    if (pat == 0 || pat > F.fmask) oracle_bug("encode: not a subnormal of the format", d, F.E, F.M);
  }
  return (neg ? F.sign : 0) | pat;
}

mpfr_rnd_t to_mpfr(Round r) {
  switch (r) {
    case Round::RNE:
      return MPFR_RNDN;
    case Round::RTZ:
      return MPFR_RNDZ;
    case Round::RDN:
      return MPFR_RNDD;
    case Round::RUP:
      return MPFR_RNDU;
  }
  return MPFR_RNDN;
}

// Per-thread MPFR variables, reused across calls (re-precisioned when M changes).
struct State {
  mpfr_t a, b, c, r;
  mpfr_t i0, i1;  // 64-bit scratch for to_int
  mpfr_prec_t prec = 0;
  State() {
    mpfr_inits2(2, a, b, c, r, static_cast<mpfr_ptr>(nullptr));
    mpfr_inits2(64, i0, i1, static_cast<mpfr_ptr>(nullptr));
  }
  ~State() { mpfr_clears(a, b, c, r, i0, i1, static_cast<mpfr_ptr>(nullptr)); }
  void set_prec(int M) {
    const mpfr_prec_t p = M + 1;
    if (p == prec) return;
    mpfr_set_prec(a, p);
    mpfr_set_prec(b, p);
    mpfr_set_prec(c, p);
    mpfr_set_prec(r, p);
    prec = p;
  }
};

State& state() {
  thread_local State s;
  return s;
}

// Sets an exponent range for the lifetime of the object, restoring the caller's afterwards.
class ExpRange {
 public:
  ExpRange() : emin_(mpfr_get_emin()), emax_(mpfr_get_emax()) {
    if (emin_ != kWideMin || emax_ != kWideMax) wide();
  }
  ~ExpRange() {
    if (emin_ != kWideMin || emax_ != kWideMax) {
      mpfr_set_emin(emin_);
      mpfr_set_emax(emax_);
    }
  }
  // Far wider than any intermediate result of these formats (|exponents| < 2^12).
  static constexpr mpfr_exp_t kWideMin = -(mpfr_exp_t{1} << 24), kWideMax = mpfr_exp_t{1} << 24;
  static void wide() {
    mpfr_set_emin(kWideMin);
    mpfr_set_emax(kWideMax);
  }
  // The format's range in MPFR's convention (x = 0.1b... * 2^e): the smallest subnormal
  // 2^(emin-M) has MPFR exponent emin-M+1, the largest finite value has exponent emax+1.
  static void format(const Fmt& F) {
    mpfr_set_emin(F.emin - F.M + 1);
    mpfr_set_emax(F.emax + 1);
  }

 private:
  mpfr_exp_t emin_, emax_;
};

void set_val(mpfr_ptr x, const Val& v) {
  switch (v.kind) {
    case Kind::Zero:
      mpfr_set_zero(x, v.neg ? -1 : 1);
      break;
    case Kind::Inf:
      mpfr_set_inf(x, v.neg ? -1 : 1);
      break;
    case Kind::Finite:
      if (mpfr_set_ui_2exp(x, v.sig, static_cast<mpfr_exp_t>(v.exp2), MPFR_RNDN) != 0)
        oracle_bug("operand not exact", v.value(), 0, 0);
      if (v.neg) mpfr_neg(x, x, MPFR_RNDN);
      break;
    default:
      mpfr_set_nan(x);
      break;
  }
}

// Rounds the result of fn(r, rnd) (an MPFR computation returning its ternary value) into F.
// Must be called inside an ExpRange (wide range active).
// The part of round_into before the tiny case: r = v rounded to M+1 bits with ternary value t,
// unbounded exponent. Returns false (out untouched) if r is tiny after rounding.
bool pack_not_tiny(const Fmt& F, mpfr_srcptr r, int t, Result& out) {
  if (mpfr_nan_p(r)) return out = {F.qnan(), kInvalid}, true;
  const bool neg = mpfr_signbit(r) != 0;
  if (mpfr_inf_p(r)) return out = {F.inf(neg), 0}, true;
  if (mpfr_zero_p(r)) return out = {F.zero(neg), 0}, true;  // exact zero (no underflow to 0 in this range)
  const int64_t lead = static_cast<int64_t>(mpfr_get_exp(r)) - 1;  // |r| in [2^lead, 2^(lead+1))
  if (lead < F.emin) return false;
  if (lead > F.emax) {  // overflow
    const bool to_inf = F.rnd == Round::RNE || (F.rnd == Round::RUP && !neg) || (F.rnd == Round::RDN && neg);
    out = {to_inf ? F.inf(neg) : F.max_finite(neg), kOverflow | kInexact};
  } else {
    out = {encode(F, mpfr_get_d(r, MPFR_RNDN)), static_cast<uint8_t>(t != 0 ? kInexact : 0)};
  }
  return true;
}

template <class Fn>
Result round_into(const Fmt& F, mpfr_ptr r, Fn fn) {
  const mpfr_rnd_t rnd = to_mpfr(F.rnd);
  const int t = fn(r, rnd);  // r = v rounded to M+1 bits, unbounded exponent
  Result out;
  if (pack_not_tiny(F, r, t, out)) return out;
  // Tiny after rounding.
  const bool neg = mpfr_signbit(r) != 0;
  if (!F.sub) return {F.zero(neg), kUnderflow | kInexact};
  ExpRange::format(F);
  int t2 = fn(r, rnd);
  t2 = mpfr_subnormalize(r, t2, rnd);
  ExpRange::wide();
  const double d = mpfr_get_d(r, MPFR_RNDN);
  return {encode(F, d), static_cast<uint8_t>(t2 != 0 ? kUnderflow | kInexact : 0)};
}

int arity(Op op) {
  switch (op) {
    case Op::Sqrt:
      return 1;
    case Op::Fma:
      return 3;
    default:
      return 2;
  }
}

Result compare_op(const Fmt& F, Op op, uint64_t a, uint64_t b) {
  const Val x = decode(F, a), y = decode(F, b);
  const double xv = x.value(), yv = y.value();
  const bool snan = x.kind == Kind::SNaN || y.kind == Kind::SNaN;
  const bool nan = x.nan() || y.nan();
  // Total order on non-NaN values with -0 < +0 (for min/max).
  auto less = [](const Val& p, double pv, const Val& q, double qv) {
    return pv < qv || (pv == qv && p.neg && !q.neg);
  };
  switch (op) {
    case Op::Lt:
      if (nan) return {0, kInvalid};
      return {xv < yv ? 1u : 0u, 0};
    case Op::Le:
      if (nan) return {0, kInvalid};
      return {xv <= yv ? 1u : 0u, 0};
    case Op::Eq:
      if (nan) return {0, static_cast<uint8_t>(snan ? kInvalid : 0)};
      return {xv == yv ? 1u : 0u, 0};
    case Op::Min:
    case Op::Max: {
      const uint8_t fl = snan ? kInvalid : 0;
      if (x.nan() && y.nan()) return {F.qnan(), fl};
      if (x.nan()) return {y.bits, fl};
      if (y.nan()) return {x.bits, fl};
      const bool pick_y = op == Op::Min ? less(y, yv, x, xv) : less(x, xv, y, yv);
      return {pick_y ? y.bits : x.bits, fl};
    }
    default:
      break;
  }
  return {};
}

}  // namespace

Result mpfr_apply(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) {
  const Fmt F(f);
  switch (op) {
    case Op::Min:
    case Op::Max:
    case Op::Lt:
    case Op::Le:
    case Op::Eq:
      return compare_op(F, op, a, b);
    default:
      break;
  }
  const int n = arity(op);
  const Val va = decode(F, a);
  const Val vb = n >= 2 ? decode(F, b) : Val{Kind::Zero, false, 0, 0, 0};
  const Val vc = n >= 3 ? decode(F, c) : Val{Kind::Zero, false, 0, 0, 0};
  const bool any_snan = va.kind == Kind::SNaN || vb.kind == Kind::SNaN || vc.kind == Kind::SNaN;
  const bool any_nan = va.nan() || vb.nan() || vc.nan();
  // fma: 0*inf is invalid whatever c is (also a quiet NaN), per docs/FORMAT.md.
  const bool zero_times_inf = op == Op::Fma && ((va.kind == Kind::Zero && vb.kind == Kind::Inf) ||
                                                (va.kind == Kind::Inf && vb.kind == Kind::Zero));
  if (any_nan) return {F.qnan(), static_cast<uint8_t>(any_snan || zero_times_inf ? kInvalid : 0)};

  State& S = state();
  S.set_prec(F.M);
  ExpRange range;
  set_val(S.a, va);
  if (n >= 2) set_val(S.b, vb);
  if (n >= 3) set_val(S.c, vc);
  Result res;
  switch (op) {
    case Op::Add:
      res = round_into(F, S.r, [&](mpfr_ptr r, mpfr_rnd_t m) { return mpfr_add(r, S.a, S.b, m); });
      break;
    case Op::Sub:
      res = round_into(F, S.r, [&](mpfr_ptr r, mpfr_rnd_t m) { return mpfr_sub(r, S.a, S.b, m); });
      break;
    case Op::Mul:
      res = round_into(F, S.r, [&](mpfr_ptr r, mpfr_rnd_t m) { return mpfr_mul(r, S.a, S.b, m); });
      break;
    case Op::Div:
      res = round_into(F, S.r, [&](mpfr_ptr r, mpfr_rnd_t m) { return mpfr_div(r, S.a, S.b, m); });
      break;
    case Op::Sqrt:
      res = round_into(F, S.r, [&](mpfr_ptr r, mpfr_rnd_t m) { return mpfr_sqrt(r, S.a, m); });
      break;
    case Op::Fma:
      res = round_into(F, S.r, [&](mpfr_ptr r, mpfr_rnd_t m) { return mpfr_fma(r, S.a, S.b, S.c, m); });
      break;
    default:
      break;
  }
  if (op == Op::Div && vb.kind == Kind::Zero && va.kind == Kind::Finite) res.flags |= kDivZero;
  return res;
}

Result mpfr_from_double(const Format& f, double x) {
  const Fmt F(f);
  if (std::isnan(x)) {
    uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    const bool quiet = (u >> 51) & 1;
    return {F.qnan(), static_cast<uint8_t>(quiet ? 0 : kInvalid)};
  }
  State& S = state();
  S.set_prec(F.M);
  ExpRange range;
  return round_into(F, S.r, [&](mpfr_ptr r, mpfr_rnd_t m) { return mpfr_set_d(r, x, m); });
}

Result mpfr_from_int(const Format& f, int64_t x) {
  const Fmt F(f);
  State& S = state();
  S.set_prec(F.M);
  ExpRange range;
  return round_into(F, S.r, [&](mpfr_ptr r, mpfr_rnd_t m) { return mpfr_set_sj(r, x, m); });
}

Result mpfr_from_string(const Format& f, const char* text, bool* ok) {
  const Fmt F(f);
  State& S = state();
  S.set_prec(F.M);
  ExpRange range;
  char* end = nullptr;
  mpfr_strtofr(S.a, text, &end, 0, MPFR_RNDN);  // only to validate the syntax and spot NaNs
  *ok = end != text && *end == 0;
  if (!*ok) return {};
  if (mpfr_nan_p(S.a)) return {F.qnan(), 0};
  return round_into(F, S.r, [&](mpfr_ptr r, mpfr_rnd_t m) { return mpfr_strtofr(r, text, nullptr, 0, m); });
}

double mpfr_to_double(const Format& f, uint64_t a) { return decode(Fmt(f), a).value(); }

IntResult mpfr_to_int(const Format& f, uint64_t a, Round r) {
  const Fmt F(f);
  const Val v = decode(F, a);
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
  if (v.nan()) return {kMax, kInvalid};
  if (v.kind == Kind::Inf) return {v.neg ? kMin : kMax, kInvalid};
  if (v.kind == Kind::Zero) return {0, 0};
  State& S = state();
  ExpRange range;
  mpfr_set_ui_2exp(S.i0, v.sig, static_cast<mpfr_exp_t>(v.exp2), MPFR_RNDN);  // exact: 64 >= M+1 bits
  if (v.neg) mpfr_neg(S.i0, S.i0, MPFR_RNDN);
  mpfr_rint(S.i1, S.i0, to_mpfr(r));  // integer of magnitude <= 2^1024: exact in 64 bits
  if (mpfr_cmp_d(S.i1, 0x1p63) >= 0) return {kMax, kInvalid};
  if (mpfr_cmp_d(S.i1, -0x1p63) < 0) return {kMin, kInvalid};
  const int64_t iv = static_cast<int64_t>(mpfr_get_sj(S.i1, MPFR_RNDZ));
  return {iv, static_cast<uint8_t>(mpfr_equal_p(S.i0, S.i1) ? 0 : kInexact)};
}

Result mpfr_dot3(const Format& f, const uint64_t a[3], const uint64_t b[3]) {
  const Result p0 = mpfr_apply(f, Op::Mul, a[0], b[0]);
  const Result p1 = mpfr_apply(f, Op::Mul, a[1], b[1]);
  const Result p2 = mpfr_apply(f, Op::Mul, a[2], b[2]);
  const Result s = mpfr_apply(f, Op::Add, p0.bits, p1.bits);
  const Result y = mpfr_apply(f, Op::Add, s.bits, p2.bits);
  return {y.bits, static_cast<uint8_t>(p0.flags | p1.flags | p2.flags | s.flags | y.flags)};
}

// Fused dot3: the three products exactly (precision 2M+2), mpfr_sum rounds their exact sum once.
// Specials as docs/FORMAT.md states them for dot3_fused (written from the text, not the model).
Result mpfr_dot3_fused(const Format& f, const uint64_t a[3], const uint64_t b[3]) {
  const Fmt F(f);
  Val x[3], y[3];
  bool nan = false, snan = false, zero_times_inf = false, pinf = false, ninf = false;
  bool all_zero = true, zneg_all = true, zpos_all = true;
  for (int i = 0; i < 3; ++i) {
    x[i] = decode(F, a[i]);
    y[i] = decode(F, b[i]);
    nan = nan || x[i].nan() || y[i].nan();
    snan = snan || x[i].kind == Kind::SNaN || y[i].kind == Kind::SNaN;
    const bool inf = x[i].kind == Kind::Inf || y[i].kind == Kind::Inf;
    const bool zero = x[i].kind == Kind::Zero || y[i].kind == Kind::Zero;
    const bool neg = x[i].neg != y[i].neg;
    if (inf && zero) zero_times_inf = true;
    if (inf && !zero) (neg ? ninf : pinf) = true;
    if (!zero) all_zero = false;
    (neg ? zpos_all : zneg_all) = false;
  }
  if (nan) return {F.qnan(), static_cast<uint8_t>(snan || zero_times_inf ? kInvalid : 0)};
  if (zero_times_inf || (pinf && ninf)) return {F.qnan(), kInvalid};
  if (pinf || ninf) return {F.inf(ninf), 0};
  const bool rdn = F.rnd == Round::RDN;
  if (all_zero) return {F.zero(zneg_all || (!zpos_all && rdn)), 0};
  // The exact sum X at a precision that holds it (its terms span at most P - 2M - 4 binades);
  // then rounded like round_into, except on the subnormal grid: X's inputs lie outside the
  // format's exponent range, so the tiny case rounds X / 2^(emin-M) to an integer (mpfr_rint).
  State& S = state();
  S.set_prec(F.M);
  ExpRange range;
  mpfr_t p[3], X, q;
  mpfr_ptr tab[3];
  mpfr_exp_t hi = 0, lo = 0;
  bool any = false;
  for (int i = 0; i < 3; ++i) {
    mpfr_init2(p[i], 2 * (F.M + 1));
    set_val(S.a, x[i]);
    set_val(S.b, y[i]);
    if (mpfr_mul(p[i], S.a, S.b, MPFR_RNDN) != 0) oracle_bug("product not exact", x[i].value(), F.E, F.M);
    tab[i] = p[i];
    if (mpfr_zero_p(p[i])) continue;
    const mpfr_exp_t e = mpfr_get_exp(p[i]);
    hi = any ? std::max(hi, e) : e;
    lo = any ? std::min(lo, e) : e;
    any = true;
  }
  mpfr_init2(X, static_cast<mpfr_prec_t>(hi - lo) + 2 * (F.M + 1) + 4);
  mpfr_init2(q, 64);
  if (mpfr_sum(X, tab, 3, MPFR_RNDN) != 0) oracle_bug("sum not exact", mpfr_get_d(X, MPFR_RNDN), F.E, F.M);
  Result res;
  const mpfr_rnd_t rnd = to_mpfr(F.rnd);
  if (!pack_not_tiny(F, S.r, mpfr_set(S.r, X, rnd), res)) {
    const bool neg = mpfr_signbit(X) != 0;
    if (!F.sub) {
      res = {F.zero(neg), kUnderflow | kInexact};
    } else {
      mpfr_mul_2si(X, X, -(F.emin - F.M), MPFR_RNDN);  // exact
      const int t = mpfr_rint(q, X, rnd);                // |q| <= 2^M
      const double d = std::ldexp(mpfr_get_d(q, MPFR_RNDN), static_cast<int>(F.emin - F.M));
      res = {mpfr_zero_p(q) ? F.zero(neg) : encode(F, d), static_cast<uint8_t>(t != 0 ? kUnderflow | kInexact : 0)};
    }
  }
  mpfr_clears(X, q, static_cast<mpfr_ptr>(nullptr));
  for (auto& v : p) mpfr_clear(v);
  // An exact zero from non-zero terms: opposite signs cancelled, +0 (-0 under RDN).
  if (res.flags == 0 && (res.bits & ~F.sign) == 0) res.bits = F.zero(rdn);
  return res;
}

}  // namespace ru::num
