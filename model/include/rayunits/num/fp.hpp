// rayunits: one arithmetic vocabulary for the golden models, so each unit is ONE function
// template that runs in native `double`, native `float` and the emulated runtime format `Soft`.
//
// Soft: a value of the thread's current runtime Format (a raw bit pattern; the format lives in
// a thread-local environment set by SoftScope). Every operator is exactly one call of the
// format model (add/sub/mul/div/lt/...: docs/FORMAT.md), so an expression written with Soft is
// the operation sequence an RTL datapath built from ru_fp_add/ru_fp_mul/ru_fp_div/ru_fp_cmp
// performs. Each operation also accumulates the IEEE flags of the thread (per-flag counts and
// the OR of all flags) in SoftStats, so a sweep can say "how often did e6 overflow".
//
// float/double: native arithmetic. The build uses -ffp-contract=off (no fused multiply-add is
// formed behind our back) and x86-64 SSE arithmetic (no excess precision), so a model run with
// float equals the same model run with Soft at e8m23 bit for bit (tests/units check this),
// except for NaN payloads: native NaNs are canonicalised by fp_canon() before a model returns.
//
// The generic helpers (fp_cast, fp_min, fp_max, fp_abs, fp_sub_round, ...) are overloaded for
// the three types and have the same semantics for all of them:
//   fp_min/fp_max: IEEE 754-2008 minNum/maxNum (a NaN operand is ignored, -0 < +0), the
//                  format's min/max (ru_fp_cmp ops 3/4);
//   fp_sub_round/fp_mul_round: one subtraction / multiplication rounded with an explicit
//                  rounding mode (RDN/RUP for conservative tests), whatever the default mode;
//                  optionally returns the operation's IEEE flags.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "rayunits/num/detail/bits.hpp"
#include "rayunits/num/format.hpp"

namespace ru::num {

// Per-thread flag statistics of Soft arithmetic: number of operations that raised each flag,
// and the OR of every flag raised. Reset by SoftScope (or reset_soft_stats()).
struct SoftStats {
  uint64_t ops = 0;
  uint64_t invalid = 0, divzero = 0, overflow = 0, underflow = 0, inexact = 0;
  uint8_t flags = 0;  // OR of all flags (FlagBit)

  void add(const SoftStats& o) {
    ops += o.ops;
    invalid += o.invalid;
    divzero += o.divzero;
    overflow += o.overflow;
    underflow += o.underflow;
    inexact += o.inexact;
    flags |= o.flags;
  }
};

namespace detail {
struct SoftEnv {
  Format fmt{};  // e8m23, RNE, subnormals until a SoftScope says otherwise
  SoftStats stats{};
};
inline thread_local SoftEnv soft_env;

inline void note(uint8_t fl) {
  SoftEnv& e = soft_env;
  ++e.stats.ops;
  if (!fl) return;
  e.stats.flags |= fl;
  e.stats.invalid += (fl & kInvalid) != 0;
  e.stats.divzero += (fl & kDivZero) != 0;
  e.stats.overflow += (fl & kOverflow) != 0;
  e.stats.underflow += (fl & kUnderflow) != 0;
  e.stats.inexact += (fl & kInexact) != 0;
}
}  // namespace detail

inline const Format& soft_format() { return detail::soft_env.fmt; }
inline const SoftStats& soft_stats() { return detail::soft_env.stats; }
inline void reset_soft_stats() { detail::soft_env.stats = SoftStats{}; }

// Sets the thread's Soft format (validated) and resets the flag statistics; the previous
// format and statistics come back when the scope ends.
class SoftScope {
 public:
  explicit SoftScope(const Format& f) : saved_(detail::soft_env) {
    f.validate();
    detail::soft_env.fmt = f;
    detail::soft_env.stats = SoftStats{};
  }
  ~SoftScope() { detail::soft_env = saved_; }
  SoftScope(const SoftScope&) = delete;
  SoftScope& operator=(const SoftScope&) = delete;

 private:
  detail::SoftEnv saved_;
};

// Switches the thread's Soft format for a part of one computation and keeps the flag statistics
// (a mixed-precision evaluation: dp::evaluate runs a graph's wide nodes in its wide format); the
// previous format comes back when the scope ends. f must be valid (not checked here: hot path).
class SoftFormatSwitch {
 public:
  explicit SoftFormatSwitch(const Format& f) : saved_(detail::soft_env.fmt) { detail::soft_env.fmt = f; }
  ~SoftFormatSwitch() { detail::soft_env.fmt = saved_; }
  SoftFormatSwitch(const SoftFormatSwitch&) = delete;
  SoftFormatSwitch& operator=(const SoftFormatSwitch&) = delete;

 private:
  Format saved_;
};

class Soft {
 public:
  uint64_t bits = 0;  // +0

  Soft() = default;
  static Soft from_bits(uint64_t b) {
    Soft s;
    s.bits = b & soft_format().mask();
    return s;
  }
  // Rounds x into the current format with its rounding mode (flags counted).
  static Soft from_double(double x) { return wrap(ru::num::from_double(soft_format(), x)); }
  double to_double() const { return ru::num::to_double(soft_format(), bits); }

  friend Soft operator+(Soft a, Soft b) { return wrap(add(soft_format(), a.bits, b.bits)); }
  friend Soft operator-(Soft a, Soft b) { return wrap(sub(soft_format(), a.bits, b.bits)); }
  friend Soft operator*(Soft a, Soft b) { return wrap(mul(soft_format(), a.bits, b.bits)); }
  friend Soft operator/(Soft a, Soft b) { return wrap(div(soft_format(), a.bits, b.bits)); }
  friend Soft operator-(Soft a) { return from_bits(neg(soft_format(), a.bits)); }  // sign flip, no op
  Soft& operator+=(Soft b) { return *this = *this + b; }
  Soft& operator-=(Soft b) { return *this = *this - b; }
  Soft& operator*=(Soft b) { return *this = *this * b; }
  Soft& operator/=(Soft b) { return *this = *this / b; }

  // IEEE comparisons: < <= > >= are signaling (invalid on NaN, false), == != are quiet.
  friend bool operator<(Soft a, Soft b) { return cmp(lt(soft_format(), a.bits, b.bits)); }
  friend bool operator<=(Soft a, Soft b) { return cmp(le(soft_format(), a.bits, b.bits)); }
  friend bool operator>(Soft a, Soft b) { return b < a; }
  friend bool operator>=(Soft a, Soft b) { return b <= a; }
  friend bool operator==(Soft a, Soft b) { return cmp(eq(soft_format(), a.bits, b.bits)); }
  friend bool operator!=(Soft a, Soft b) { return !(a == b); }

  static Soft wrap(Result r) {
    detail::note(r.flags);
    Soft s;
    s.bits = r.bits;
    return s;
  }

 private:
  static bool cmp(Result r) {
    detail::note(r.flags);
    return r.bits != 0;
  }
};

// ------------------------------------------------------------------ generic helpers

// The Format a type computes in (Soft: the thread's current format).
template <class T>
Format fp_format();
template <>
inline Format fp_format<float>() { return Format{8, 23, true, Round::RNE}; }
template <>
inline Format fp_format<double>() { return Format{11, 52, true, Round::RNE}; }
template <>
inline Format fp_format<Soft>() { return soft_format(); }

// Bit patterns (float/double: the IEEE encoding, identical to e8m23/e11m52).
inline uint64_t fp_bits(float x) { return detail::float_bits(x); }
inline uint64_t fp_bits(double x) { return detail::double_bits(x); }
inline uint64_t fp_bits(Soft x) { return x.bits; }

template <class T>
T fp_from_bits(uint64_t b);
template <>
inline float fp_from_bits<float>(uint64_t b) { return detail::float_from_bits(static_cast<uint32_t>(b)); }
template <>
inline double fp_from_bits<double>(uint64_t b) { return detail::double_from_bits(b); }
template <>
inline Soft fp_from_bits<Soft>(uint64_t b) { return Soft::from_bits(b); }

// Conversion from double, rounded to nearest even (Soft: the format's mode) and to double (exact).
template <class T>
T fp_cast(double x);
template <>
inline float fp_cast<float>(double x) {
  return std::isnan(x) ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(x);
}
template <>
inline double fp_cast<double>(double x) {
  return std::isnan(x) ? std::numeric_limits<double>::quiet_NaN() : x;
}
template <>
inline Soft fp_cast<Soft>(double x) { return Soft::from_double(x); }

inline double fp_to_double(float x) { return x; }
inline double fp_to_double(double x) { return x; }
inline double fp_to_double(Soft x) { return x.to_double(); }

inline bool fp_isnan(float x) { return std::isnan(x); }
inline bool fp_isnan(double x) { return std::isnan(x); }
inline bool fp_isnan(Soft x) { return is_nan(soft_format(), x.bits); }

// +INF / -INF tests (bit patterns; no flushing, no flags).
template <class T>
bool fp_is_pos_inf(T x) { return fp_bits(x) == fp_format<T>().inf(false); }
template <class T>
bool fp_is_neg_inf(T x) { return fp_bits(x) == fp_format<T>().inf(true); }

// +0 or -0 (bit pattern: exponent and fraction zero; a subnormal is not zero here).
template <class T>
bool fp_is_zero(T x) { return (fp_bits(x) & ~fp_format<T>().sign_bit()) == 0; }

// Sign bit (also of zeros and NaNs).
template <class T>
bool fp_signbit(T x) { return (fp_bits(x) & fp_format<T>().sign_bit()) != 0; }

// |x|: clears the sign bit (a bit operation, no flags).
inline float fp_abs(float x) { return std::fabs(x); }
inline double fp_abs(double x) { return std::fabs(x); }
inline Soft fp_abs(Soft x) { return Soft::from_bits(abs(soft_format(), x.bits)); }

// Canonical NaN for native results (sign 0, quiet bit only); other values unchanged.
inline float fp_canon(float x) { return std::isnan(x) ? std::numeric_limits<float>::quiet_NaN() : x; }
inline double fp_canon(double x) { return std::isnan(x) ? std::numeric_limits<double>::quiet_NaN() : x; }
inline Soft fp_canon(Soft x) { return x; }  // the format model only produces canonical NaNs

// minNum / maxNum (IEEE 754-2008): NaN operand ignored, both NaN -> canonical NaN, -0 < +0.
namespace detail {
template <class T>
T native_minmax(T a, T b, bool is_max) {
  if (std::isnan(a)) return std::isnan(b) ? std::numeric_limits<T>::quiet_NaN() : b;
  if (std::isnan(b)) return a;
  if (a == b) {  // equal values; only the zeros can differ (by sign)
    const bool pick_a = is_max ? !std::signbit(a) : std::signbit(a);
    return pick_a ? a : b;
  }
  return ((a < b) != is_max) ? a : b;
}
}  // namespace detail
inline float fp_min(float a, float b) { return detail::native_minmax(a, b, false); }
inline double fp_min(double a, double b) { return detail::native_minmax(a, b, false); }
inline float fp_max(float a, float b) { return detail::native_minmax(a, b, true); }
inline double fp_max(double a, double b) { return detail::native_minmax(a, b, true); }
inline Soft fp_min(Soft a, Soft b) { return Soft::wrap(min(soft_format(), a.bits, b.bits)); }
inline Soft fp_max(Soft a, Soft b) { return Soft::wrap(max(soft_format(), a.bits, b.bits)); }

// One subtraction / multiplication with an explicit rounding mode. For float/double this is
// computed by the bit-exact format model at e8m23/e11m52 (native code cannot switch rounding
// modes reliably without -frounding-math); for Soft it is the current format with mode r.
template <class T>
T fp_sub_round(T a, T b, Round r, uint8_t* flags = nullptr) {
  Format f = fp_format<T>();
  f.round = r;
  const Result res = sub(f, fp_bits(a), fp_bits(b));
  if (flags) *flags = res.flags;
  if constexpr (std::is_same_v<T, Soft>) return Soft::wrap(res);
  return fp_from_bits<T>(res.bits);
}
template <class T>
T fp_mul_round(T a, T b, Round r, uint8_t* flags = nullptr) {
  Format f = fp_format<T>();
  f.round = r;
  const Result res = mul(f, fp_bits(a), fp_bits(b));
  if (flags) *flags = res.flags;
  if constexpr (std::is_same_v<T, Soft>) return Soft::wrap(res);
  return fp_from_bits<T>(res.bits);
}

}  // namespace ru::num
