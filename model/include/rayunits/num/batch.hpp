// The format model on arrays (issue 16 §3: "a batch API, arrays in, arrays out, that sweeps and
// the renderer can use"): y[i] = op(a[i], b[i]) with exactly the bits and flags of the scalar
// ru::num::add/sub/mul/div/sqrt/fma (format.hpp) -- the same fast paths and general fallback,
// with the format's dispatch (e8m23, e7m16, e5m10 compiled with constant widths, others
// dynamic) done once per call instead of once per operation, and vector paths (AVX-512 / AVX2,
// round to nearest even, M <= 24; batch.cpp) for the common case of normal operands and
// results. flags may be null; the return value is the OR of every element's flags. Arrays may
// alias y only element for element (y == a is fine). Checked against the scalar functions bit
// for bit on every path the CPU has (tests/num/test_batch.cpp); speed: `rayunits bench fp`
// (column "batch", --batch-isa).
#pragma once
#include <cstddef>
#include <cstdint>

#include "rayunits/num/format.hpp"

namespace ru::num {

uint8_t add_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n);
uint8_t sub_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n);
uint8_t mul_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n);
uint8_t div_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n);
uint8_t sqrt_n(const Format& f, const uint64_t* a, uint64_t* y, uint8_t* flags, size_t n);
uint8_t fma_n(const Format& f, const uint64_t* a, const uint64_t* b, const uint64_t* c, uint64_t* y, uint8_t* flags,
              size_t n);

// The vector paths of add/sub/mul/div/sqrt (round to nearest even, M <= 24; batch.cpp): 8 lanes
// with AVX-512, 4 with AVX2, chosen at run time from the CPU. set_batch_isa restricts them (the
// tests run every path against the scalar functions; `bench fp` can time each): Auto = the best
// the CPU has, Scalar = none. Returns false, changing nothing, when the CPU lacks the ISA.
enum class BatchIsa { Auto, Scalar, Avx2, Avx512 };
bool set_batch_isa(BatchIsa isa);
BatchIsa batch_isa();  // the path in use (never Auto)

}  // namespace ru::num
