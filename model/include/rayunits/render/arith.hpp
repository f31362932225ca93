// Arithmetic vocabulary of the renderer on top of rayunits/num/fp.hpp: square root and floor
// in every type, and `Probe`, a double that records the binary exponent of every value it
// computes (the scene profile, Fig. 3.5). The golden models of units/ run with Probe too:
// the overloads below are found by argument-dependent lookup, the fp_cast / fp_from_bits /
// fp_format specialisations by the templates' explicit arguments.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "rayunits/num/fp.hpp"

namespace ru::render {

// ------------------------------------------------------------------ value histogram
// Counts of finite non-zero values by binary exponent e = floor(log2 |x|) (x = m 2^e, 1 <= m < 2).
struct ExpHistogram {
  static constexpr int kMinExp = -1080, kMaxExp = 1030;
  std::array<uint64_t, kMaxExp - kMinExp + 1> counts{};
  uint64_t zeros = 0, infs = 0, nans = 0;
  double min_abs = std::numeric_limits<double>::infinity(), max_abs = 0;

  void add(double x) {
    if (x == 0) {
      ++zeros;
      return;
    }
    if (std::isnan(x)) {
      ++nans;
      return;
    }
    const double a = std::fabs(x);
    if (std::isinf(a)) {
      ++infs;
      return;
    }
    ++counts[std::ilogb(a) - kMinExp];
    if (a < min_abs) min_abs = a;
    if (a > max_abs) max_abs = a;
  }
  void merge(const ExpHistogram& o) {
    for (size_t i = 0; i < counts.size(); ++i) counts[i] += o.counts[i];
    zeros += o.zeros;
    infs += o.infs;
    nans += o.nans;
    min_abs = std::min(min_abs, o.min_abs);
    max_abs = std::max(max_abs, o.max_abs);
  }
  uint64_t finite_nonzero() const {
    uint64_t s = 0;
    for (auto c : counts) s += c;
    return s;
  }
  int min_exp() const {  // smallest exponent present (kMaxExp + 1 when none)
    for (size_t i = 0; i < counts.size(); ++i)
      if (counts[i]) return static_cast<int>(i) + kMinExp;
    return kMaxExp + 1;
  }
  int max_exp() const {
    for (size_t i = counts.size(); i-- > 0;)
      if (counts[i]) return static_cast<int>(i) + kMinExp;
    return kMinExp - 1;
  }
  uint64_t count_above(int e) const {  // values with exponent > e
    uint64_t s = 0;
    for (int k = std::max(e + 1, kMinExp); k <= kMaxExp; ++k) s += counts[k - kMinExp];
    return s;
  }
  uint64_t count_below(int e) const {  // values with exponent < e
    uint64_t s = 0;
    for (int k = kMinExp; k < std::min(e, kMaxExp + 1); ++k) s += counts[k - kMinExp];
    return s;
  }
};

namespace detail {
// Where Probe results go on this thread (nullptr: not recorded). `inputs` receives the
// operands the renderer hands to the ray-box / ray-triangle units (Fig. 3.5's population).
struct ProbeSink {
  ExpHistogram all, inputs;
};
inline thread_local ProbeSink* probe_sink = nullptr;
inline void probe_note(double x) {
  if (probe_sink) probe_sink->all.add(x);
}
}  // namespace detail

// A double whose every arithmetic result (and every conversion into it) is recorded.
struct Probe {
  double v = 0;
  Probe() = default;
  static Probe make(double x) {
    detail::probe_note(x);
    Probe p;
    p.v = x;
    return p;
  }
  friend Probe operator+(Probe a, Probe b) { return make(a.v + b.v); }
  friend Probe operator-(Probe a, Probe b) { return make(a.v - b.v); }
  friend Probe operator*(Probe a, Probe b) { return make(a.v * b.v); }
  friend Probe operator/(Probe a, Probe b) { return make(a.v / b.v); }
  friend Probe operator-(Probe a) {
    Probe p;
    p.v = -a.v;
    return p;
  }
  friend bool operator<(Probe a, Probe b) { return a.v < b.v; }
  friend bool operator<=(Probe a, Probe b) { return a.v <= b.v; }
  friend bool operator>(Probe a, Probe b) { return a.v > b.v; }
  friend bool operator>=(Probe a, Probe b) { return a.v >= b.v; }
  friend bool operator==(Probe a, Probe b) { return a.v == b.v; }
  friend bool operator!=(Probe a, Probe b) { return a.v != b.v; }
};

// Overloads for Probe (found by argument-dependent lookup from the units' templates).
inline uint64_t fp_bits(Probe x) { return ru::num::fp_bits(x.v); }
inline bool fp_isnan(Probe x) { return std::isnan(x.v); }
inline Probe fp_abs(Probe x) {
  Probe p;
  p.v = std::fabs(x.v);
  return p;
}
inline Probe fp_canon(Probe x) {
  Probe p;
  p.v = ru::num::fp_canon(x.v);
  return p;
}
inline Probe fp_min(Probe a, Probe b) {
  Probe p;
  p.v = ru::num::fp_min(a.v, b.v);
  return p;
}
inline Probe fp_max(Probe a, Probe b) {
  Probe p;
  p.v = ru::num::fp_max(a.v, b.v);
  return p;
}
inline double fp_to_double(Probe x) { return x.v; }

// ------------------------------------------------------------------ sqrt, floor
// Correctly rounded square root in the type (Soft: the format model's sqrt, one FP op).
inline float fp_sqrt(float x) { return std::sqrt(x); }
inline double fp_sqrt(double x) { return std::sqrt(x); }
inline ru::num::Soft fp_sqrt(ru::num::Soft x) {
  return ru::num::Soft::wrap(ru::num::sqrt(ru::num::soft_format(), x.bits));
}
inline Probe fp_sqrt(Probe x) { return Probe::make(std::sqrt(x.v)); }

// Fused multiply-add a*b + c and multiply-subtract a*b - c, one rounding in the type (Soft: the
// format model's fma, ru_fp_fma's op 0 and 1; native: std::fma, the same IEEE operation, so an
// e8m23 render with fma equals a float render with fma bit for bit).
inline float fp_fma(float a, float b, float c) { return std::fma(a, b, c); }
inline double fp_fma(double a, double b, double c) { return std::fma(a, b, c); }
inline float fp_fms(float a, float b, float c) { return std::fma(a, b, -c); }
inline double fp_fms(double a, double b, double c) { return std::fma(a, b, -c); }
inline ru::num::Soft fp_fma(ru::num::Soft a, ru::num::Soft b, ru::num::Soft c) {
  return ru::num::Soft::wrap(ru::num::fma(ru::num::soft_format(), a.bits, b.bits, c.bits));
}
inline ru::num::Soft fp_fms(ru::num::Soft a, ru::num::Soft b, ru::num::Soft c) { return fp_fma(a, b, -c); }
inline Probe fp_fma(Probe a, Probe b, Probe c) { return Probe::make(std::fma(a.v, b.v, c.v)); }
inline Probe fp_fms(Probe a, Probe b, Probe c) { return Probe::make(std::fma(a.v, b.v, -c.v)); }

// floor: exact in every type (Soft: float-to-int conversion toward -inf and back, the two
// conversions a hardware shader would issue; values >= 2^52 are already integers).
inline float fp_floor(float x) { return std::floor(x); }
inline double fp_floor(double x) { return std::floor(x); }
inline Probe fp_floor(Probe x) { return Probe::make(std::floor(x.v)); }
inline ru::num::Soft fp_floor(ru::num::Soft x) {
  using namespace ru::num;
  const Format& f = soft_format();
  const double d = to_double(f, x.bits);
  if (!(std::fabs(d) < 0x1p52)) return x;  // NaN, INF, or already an integer
  IntResult i = to_int(f, x.bits, Round::RDN);
  ru::num::detail::note(i.flags);
  Soft r = Soft::wrap(from_int(f, i.value));
  // Keep the sign of a zero result that came from a negative input (floor(-0.3) is -1 anyway;
  // floor(-0) = -0).
  if (i.value == 0 && (x.bits & f.sign_bit())) r.bits = f.neg_zero();
  return r;
}

}  // namespace ru::render

namespace ru::num {
template <>
inline Format fp_format<ru::render::Probe>() { return Format{11, 52, true, Round::RNE}; }
template <>
inline ru::render::Probe fp_from_bits<ru::render::Probe>(uint64_t b) {
  ru::render::Probe p;
  p.v = fp_from_bits<double>(b);
  return p;
}
template <>
inline ru::render::Probe fp_cast<ru::render::Probe>(double x) {
  return ru::render::Probe::make(fp_cast<double>(x));
}
}  // namespace ru::num
