// A second, deliberately naive reference for the arithmetic ops, used to check the MPFR oracle
// itself: exact integer arithmetic with GMP (value = N * 2^k, plus a sticky bit for the
// remainder of div/sqrt) followed by the rounding steps of docs/FORMAT.md transcribed literally
// (round to M+1 bits with unbounded exponent, tininess after rounding, overflow, subnormal or
// flush-to-zero). Slow; shares no code with mpfr_ref.cpp or the model.
#pragma once

#include <cstdint>

#include "rayunits/num/format.hpp"

namespace ru::num::testing {

// add, sub, mul, div, sqrt, fma only.
Result exact_apply(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c);

}  // namespace ru::num::testing
