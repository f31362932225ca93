// Independent MPFR oracle for the number formats (docs/FORMAT.md).
//
// Shares nothing with the model but the Format/Result/Op declarations: bit patterns are decoded
// and encoded here, NaN-ness and the flags are derived here, and every rounding is done by MPFR
// at precision M+1:
//   1. the operation is computed with an (effectively) unbounded exponent range, giving r and
//      its ternary value: r = v rounded to M+1 bits; tiny <=> |r| < 2^emin (tininess after
//      rounding); |r| > max finite <=> overflow;
//   2. a tiny result with subnormals is recomputed with emin/emax set for the format followed by
//      mpfr_subnormalize(ternary), which rounds once to the subnormal grid (no double rounding);
//   3. flush-to-zero: subnormal operands read as zero of the same sign; a tiny result becomes
//      zero of the sign of v with underflow+inexact.
// Flags: inexact from the ternary values, underflow = tiny && inexact (with subnormals) or tiny
// (flush-to-zero), overflow, invalid (sNaN operands, inf-inf, 0*inf, 0/0, inf/inf, sqrt(<0)),
// divzero (finite nonzero / 0). NaN results are the canonical quiet NaN.
// min/max/lt/le/eq are plain comparisons of the exact operand values.
//
// Thread-safe (per-thread MPFR state); the caller's MPFR exponent range is preserved.
#pragma once

#include <cstdint>

#include "rayunits/num/format.hpp"

namespace ru::num {

// op(a, b, c) in f (f.round, f.subnormals). Unused operands are ignored.
Result mpfr_apply(const Format& f, Op op, uint64_t a, uint64_t b = 0, uint64_t c = 0);
// Correctly rounded conversion of a double / an int64 into f.
Result mpfr_from_double(const Format& f, double x);
Result mpfr_from_int(const Format& f, int64_t x);
// Correctly rounded conversion of a decimal (or C99 hexadecimal-float, "inf", "nan") string,
// rounded once from its exact value (mpfr_strtofr). *ok = false if text is not a number.
Result mpfr_from_string(const Format& f, const char* text, bool* ok);
// Exact value of a (FTZ formats read subnormals as zero); NaN gives a quiet NaN.
double mpfr_to_double(const Format& f, uint64_t a);
// Rounds a to an integer with mode r. NaN -> INT64_MAX, +-INF / out of range -> saturated,
// both with invalid only; an in-range non-integer raises inexact.
IntResult mpfr_to_int(const Format& f, uint64_t a, Round r);
// The RTL's dot3: round(round(round(a0*b0) + round(a1*b1)) + round(a2*b2)), flags ORed.
Result mpfr_dot3(const Format& f, const uint64_t a[3], const uint64_t b[3]);
// The fused dot3: the exact a0*b0 + a1*b1 + a2*b2 rounded once (mpfr_sum of exact products).
Result mpfr_dot3_fused(const Format& f, const uint64_t a[3], const uint64_t b[3]);

}  // namespace ru::num
