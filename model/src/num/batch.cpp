// The batch API of the format model (num/batch.hpp): one format dispatch per call, then the
// scalar fast paths (detail/fast_paths.hpp, detail/double_paths.hpp) element by element with the
// general path as fallback -- the same code as the scalar functions, so the same bits and flags.
#include "rayunits/num/batch.hpp"

#include <type_traits>

namespace ru::num {
namespace {

using detail::DynConsts;
using detail::FixedConsts;

// Calls fn with the format's constants: compile-time widths for the common formats.
template <class F>
uint8_t with_consts(const Format& f, F&& fn) {
  if (f.exp_bits == 8 && f.frac_bits == 23) return fn(FixedConsts<8, 23>(f));
  if (f.exp_bits == 7 && f.frac_bits == 16) return fn(FixedConsts<7, 16>(f));
  if (f.exp_bits == 5 && f.frac_bits == 10) return fn(FixedConsts<5, 10>(f));
  return fn(DynConsts(f));
}

inline uint8_t put(uint64_t* y, uint8_t* flags, size_t i, const Result& r) {
  y[i] = r.bits;
  if (flags) flags[i] = r.flags;
  return r.flags;
}

// Two operands: Op<C>::run on (a, b ^ bxor), else general(f, a, b).
template <template <class> class Op>
uint8_t binary(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n,
               uint64_t bxor, Result (*general)(const Format&, uint64_t, uint64_t)) {
  return with_consts(f, [&](const auto& c) {
    using C = std::decay_t<decltype(c)>;
    uint8_t all = 0;
    for (size_t i = 0; i < n; ++i) {
      const uint64_t x = a[i], z = b[i];
      Result r;
      if (!Op<C>::run(c, r, x, z ^ bxor)) r = general(f, x, z);
      all |= put(y, flags, i, r);
    }
    return all;
  });
}

}  // namespace

uint8_t add_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n) {
  return binary<detail::AddFastOp>(f, a, b, y, flags, n, 0, detail::add_general);
}
uint8_t sub_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n) {
  return binary<detail::AddFastOp>(f, a, b, y, flags, n, f.sign_bit(), detail::sub_general);
}
uint8_t mul_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n) {
  return binary<detail::MulFastOp>(f, a, b, y, flags, n, 0, detail::mul_general);
}
uint8_t div_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n) {
  return binary<detail::DivDoubleOp>(f, a, b, y, flags, n, 0, detail::div_general);
}
uint8_t sqrt_n(const Format& f, const uint64_t* a, uint64_t* y, uint8_t* flags, size_t n) {
  return with_consts(f, [&](const auto& c) {
    using C = std::decay_t<decltype(c)>;
    uint8_t all = 0;
    for (size_t i = 0; i < n; ++i) {
      const uint64_t x = a[i];
      Result r;
      if (!detail::SqrtDoubleOp<C>::run(c, r, x)) r = detail::sqrt_general(f, x);
      all |= put(y, flags, i, r);
    }
    return all;
  });
}
uint8_t fma_n(const Format& f, const uint64_t* a, const uint64_t* b, const uint64_t* c3, uint64_t* y, uint8_t* flags,
              size_t n) {
  return with_consts(f, [&](const auto& c) {
    using C = std::decay_t<decltype(c)>;
    uint8_t all = 0;
    for (size_t i = 0; i < n; ++i) {
      const uint64_t x = a[i], z = b[i], w = c3[i];
      Result r;
      if (!detail::FmaDoubleOp<C>::run(c, r, x, z, w)) r = detail::fma_general(f, x, z, w);
      all |= put(y, flags, i, r);
    }
    return all;
  });
}

}  // namespace ru::num
