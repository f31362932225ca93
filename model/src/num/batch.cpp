// The batch API of the format model (num/batch.hpp): the vector paths below for the blocks of
// lanes they can take (AVX-512 / AVX2), then one format dispatch and the scalar fast paths
// (detail/fast_paths.hpp, detail/double_paths.hpp) element by element with the general path as
// fallback -- the same code as the scalar functions, so the same bits and flags.
#include "rayunits/num/batch.hpp"

#include <atomic>
#include <cstring>
#include <type_traits>

#if defined(__GNUC__) && defined(__x86_64__) && !defined(RU_NUM_NO_SIMD)
#define RU_NUM_SIMD 1
#include <immintrin.h>
#endif

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
               uint64_t bxor, Result (*general)(const Format&, uint64_t, uint64_t), size_t start = 0,
               uint8_t start_flags = 0) {
  return with_consts(f, [&](const auto& c) {
    using C = std::decay_t<decltype(c)>;
    uint8_t all = start_flags;
    for (size_t i = start; i < n; ++i) {
      const uint64_t x = a[i], z = b[i];
      Result r;
      if (!Op<C>::run(c, r, x, z ^ bxor)) r = general(f, x, z);
      all |= put(y, flags, i, r);
    }
    return all;
  });
}

#if RU_NUM_SIMD
// The vector paths (issue 16 §3: the model at or above a double-backed emulator's rate): 8 lanes
// with AVX-512 (F, DQ), 4 with AVX2, picked at run time from the CPU (set_batch_isa), for
// round-to-nearest-even and M <= 24 (2(M+1)+2 <= 53). Each lane decodes its bit patterns into
// doubles (integer shifts), does one double operation and rounds the double into the format with
// integer operations, giving bits and the inexact flag:
//   add/sub  exact in double when the exponents differ by <= 51 - M; farther apart the smaller
//            operand lies below a quarter ulp of the result (result: the larger, inexact);
//   mul      exact (two <= 25-bit significands);
//   div/sqrt one rounding in double; lanes whose dropped bits are exactly 0 or half leave the
//            path (the unknown tail could matter; as detail/double_paths.hpp);
//   fma      the product exact (E <= 9: no overflow or underflow in double), TwoSum for the sum:
//            the tail's sign decides ties and the inexact flag.
// A lane also leaves the path ("bad") when an operand is zero, subnormal, INF or NaN (sqrt:
// negative) or when the result before or after rounding is outside the format's normal range
// (zero, underflow, overflow; tininess is detected after rounding, so a result that rounds up to
// 2^emin is normal); bad lanes are recomputed by the scalar functions from their saved operands.
// The kept lanes equal the scalar model bit for bit and flag for flag: tests/num/test_batch.cpp
// runs every path the CPU has against the scalar functions (RU_NUM_NO_SIMD switches them off).
enum class VOp { Add, Mul, Div, Sqrt, Fma };
static_assert(kInexact == 1, "the SIMD path packs the inexact flag as bit 0 of each lane byte");
BatchIsa cpu_best() {
  static const BatchIsa best = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") ? BatchIsa::Avx512
                               : __builtin_cpu_supports("avx2") ? BatchIsa::Avx2
                                                                : BatchIsa::Scalar;
  return best;
}
std::atomic<BatchIsa> g_isa{BatchIsa::Auto};
BatchIsa simd_isa(const Format& f) {
  if (f.round != Round::RNE || f.frac_bits > 24) return BatchIsa::Scalar;
  return batch_isa();
}

// One loop for L lanes (4: AVX2, 8: AVX-512), written once as a macro because the two differ in
// their target attribute and two intrinsics (lane mask, square root). The loop runs over m (a
// multiple of L) elements; bad lanes are recomputed by scalar(a, b) from the operands as loaded
// (y may alias a or b).
#define RU_SIMD_LOOP(NAME, TARGET, L, MOVEMASK, SQRT)                                                          \
  template <VOp op, class Scalar>                                                                             \
  __attribute__((target(TARGET))) void NAME(const Format& f, const uint64_t* pa, const uint64_t* pb,          \
                                            const uint64_t* pc, uint64_t bxor, uint64_t* py, uint8_t* pfl,    \
                                            size_t m, uint8_t* all, Scalar& scalar) {                         \
    using uv = uint64_t __attribute__((vector_size(8 * L)));                                                  \
    using iv = int64_t __attribute__((vector_size(8 * L)));                                                   \
    using fv = double __attribute__((vector_size(8 * L)));                                                    \
    const int M = f.frac_bits, EM = f.exp_bits + f.frac_bits, d = 52 - M;                                     \
    const uint64_t emaxf = f.exp_field_max();                                                                 \
    const int64_t off = 1023 - f.bias(); /* double exponent field - format exponent field */                 \
    const uv low = uv{} + ((1ull << d) - 1), half = uv{} + (1ull << (d - 1)), one_ulp = half + half;          \
    const uv vfmask = uv{} + f.frac_mask(), vemaxf = uv{} + emaxf, voff = uv{} + static_cast<uint64_t>(off);  \
    const iv vlo = iv{} + (off + 1), vhi = iv{} + (off + static_cast<int64_t>(emaxf) - 1), hv = (iv)half;      \
    uint8_t flags_or = 0;                                                                                     \
    for (size_t i = 0; i < m; i += L) {                                                                       \
      uv a, b = {}, c = {};                                                                                   \
      std::memcpy(&a, pa + i, 8 * L);                                                                         \
      if (op != VOp::Sqrt) std::memcpy(&b, pb + i, 8 * L);                                                    \
      if (op == VOp::Fma) std::memcpy(&c, pc + i, 8 * L);                                                     \
      const uv b2 = b ^ bxor;                                                                                 \
      iv bad = {};                                                                                            \
      /* the format's normal value as a double (zero, subnormal, INF, NaN: bad) */                          \
      const uv ea = (a >> M) & vemaxf, eb = (b2 >> M) & vemaxf;                                               \
      bad |= (iv)(ea == 0) | (iv)(ea == vemaxf);                                                              \
      const fv da = (fv)(((a >> EM) << 63) | ((ea + voff) << 52) | ((a & vfmask) << d));                      \
      const fv db = (fv)(((b2 >> EM) << 63) | ((eb + voff) << 52) | ((b2 & vfmask) << d));                    \
      if (op != VOp::Sqrt) bad |= (iv)(eb == 0) | (iv)(eb == vemaxf);                                         \
      fv r, err = {};                                                                                         \
      iv far = {};                                                                                            \
      if constexpr (op == VOp::Add) {                                                                         \
        /* exact in double when the exponents differ by <= 51 - M (M + 1 + 51 - M + 1 carry = 53 bits); */  \
        /* farther apart the smaller is below a quarter ulp of the result: result = the larger, inexact */   \
        r = da + db;                                                                                          \
        const iv de = (iv)ea - (iv)eb;                                                                        \
        far = (de > 51 - M) | (de < M - 51);                                                                  \
      } else if constexpr (op == VOp::Mul) {                                                                  \
        r = da * db; /* exact: two <= 25-bit significands */                                                 \
      } else if constexpr (op == VOp::Div) {                                                                  \
        r = da / db;                                                                                          \
      } else if constexpr (op == VOp::Sqrt) {                                                                 \
        bad |= (iv)((a >> EM) & 1) != 0; /* negative (zero is already bad) */                                \
        r = SQRT(da);                                                                                         \
      } else { /* fma: the product is exact (E <= 9: no overflow or underflow in double), TwoSum */          \
        const uv ec = (c >> M) & vemaxf;                                                                      \
        bad |= (iv)(ec == 0) | (iv)(ec == vemaxf);                                                            \
        const fv dc = (fv)(((c >> EM) << 63) | ((ec + voff) << 52) | ((c & vfmask) << d));                    \
        const fv p = da * db;                                                                                 \
        r = p + dc;                                                                                           \
        const fv bb = r - p;                                                                                  \
        err = (p - (r - bb)) + (dc - bb); /* r + err is the exact a b + c */                                 \
      }                                                                                                       \
      const uv u = (uv)r, ue = (uv)err;                                                                       \
      const iv rem = (iv)(u & low);                                                                           \
      const iv lsb = (iv)(((u >> d) & 1) != 0);                                                               \
      const iv errnz = (iv)((ue << 1) != 0); /* fma only: the tail below the double */                       \
      const iv same = (iv)(((ue ^ u) >> 63) == 0) & errnz; /* ... pointing away from zero */                 \
      const iv up = (rem > hv) | ((rem == hv) & (same | (~errnz & lsb)));                                     \
      if constexpr (op == VOp::Div || op == VOp::Sqrt) bad |= (rem == 0) | (rem == hv);                       \
      const iv inexact = (rem != 0) | far | errnz;                                                            \
      const uv ur = (u & ~low) + ((uv)up & one_ulp);                                                          \
      const iv ev = (iv)((u >> 52) & 0x7ff), er = (iv)((ur >> 52) & 0x7ff);                                   \
      bad |= (ev < vlo) | (ev > vhi) | (er < vlo) | (er > vhi);                                               \
      const uv y = ((u >> 63) << EM) | ((uv)(er - (iv)voff) << M) | ((ur >> d) & vfmask);                     \
      const unsigned mask = MOVEMASK(bad);                                                                    \
      uint64_t sa[L], sb[L], sc[L];                                                                           \
      if (mask) { /* keep the operands of the lanes to redo */                                               \
        std::memcpy(sa, &a, 8 * L);                                                                           \
        std::memcpy(sb, &b, 8 * L);                                                                           \
        std::memcpy(sc, &c, 8 * L);                                                                           \
      }                                                                                                       \
      std::memcpy(py + i, &y, 8 * L);                                                                         \
      const unsigned inx = MOVEMASK(inexact);                                                                 \
      if (pfl)                                                                                                \
        for (int k = 0; k < L; ++k) pfl[i + k] = static_cast<uint8_t>((inx >> k) & 1u); /* kInexact */       \
      if (inx & ~mask) flags_or |= kInexact;                                                                  \
      for (unsigned k = 0, bits = mask; bits; ++k, bits >>= 1)                                                \
        if (bits & 1) flags_or |= put(py, pfl, i + k, scalar(sa[k], sb[k], sc[k]));                           \
    }                                                                                                         \
    *all |= flags_or;                                                                                         \
  }

#define RU_MASK4(x) static_cast<unsigned>(_mm256_movemask_pd((__m256d)(x)))
#define RU_SQRT4(x) (fv) _mm256_sqrt_pd((__m256d)(x))
#define RU_MASK8(x) static_cast<unsigned>(_mm512_movepi64_mask((__m512i)(x)))
#define RU_SQRT8(x) (fv) _mm512_maskz_sqrt_pd(static_cast<__mmask8>(0xff), (__m512d)(x))
RU_SIMD_LOOP(simd_loop4, "avx2", 4, RU_MASK4, RU_SQRT4)
RU_SIMD_LOOP(simd_loop8, "avx512f,avx512dq", 8, RU_MASK8, RU_SQRT8)
#undef RU_SIMD_LOOP
#undef RU_MASK4
#undef RU_SQRT4
#undef RU_MASK8
#undef RU_SQRT8

template <VOp op, class Scalar>
size_t simd_blocks(const Format& f, const uint64_t* a, const uint64_t* b, const uint64_t* c, uint64_t bxor, uint64_t* y,
                   uint8_t* flags, size_t n, uint8_t* all, Scalar&& scalar) {
  if (op == VOp::Fma && f.exp_bits > 9) return 0;  // products must stay normal doubles
  switch (simd_isa(f)) {
    case BatchIsa::Avx512: simd_loop8<op>(f, a, b, c, bxor, y, flags, n & ~size_t(7), all, scalar); return n & ~size_t(7);
    case BatchIsa::Avx2: simd_loop4<op>(f, a, b, c, bxor, y, flags, n & ~size_t(3), all, scalar); return n & ~size_t(3);
    default: return 0;
  }
}
#endif

}  // namespace

bool set_batch_isa(BatchIsa isa) {
#if RU_NUM_SIMD
  const BatchIsa best = cpu_best();
  if (isa == BatchIsa::Avx512 && best != BatchIsa::Avx512) return false;
  if (isa == BatchIsa::Avx2 && best == BatchIsa::Scalar) return false;
  g_isa = isa;
  return true;
#else
  return isa == BatchIsa::Auto || isa == BatchIsa::Scalar;
#endif
}
BatchIsa batch_isa() {
#if RU_NUM_SIMD
  const BatchIsa i = g_isa;
  return i == BatchIsa::Auto ? cpu_best() : i;
#else
  return BatchIsa::Scalar;
#endif
}

#if RU_NUM_SIMD
#define RU_SIMD_PREFIX(OP, B, C, XOR, CALL)                                                                      \
  uint8_t all = 0;                                                                                            \
  const size_t done = simd_blocks<OP>(f, a, B, C, XOR, y, flags, n, &all, [&](uint64_t x, uint64_t z, uint64_t w) { \
    (void)z;                                                                                                  \
    (void)w;                                                                                                  \
    return CALL;                                                                                              \
  });
#else
#define RU_SIMD_PREFIX(OP, B, C, XOR, CALL) \
  uint8_t all = 0;                       \
  const size_t done = 0;
#endif

uint8_t add_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n) {
  RU_SIMD_PREFIX(VOp::Add, b, nullptr, 0, add(f, x, z))
  return binary<detail::AddFastOp>(f, a, b, y, flags, n, 0, detail::add_general, done, all);
}
uint8_t sub_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n) {
  RU_SIMD_PREFIX(VOp::Add, b, nullptr, f.sign_bit(), sub(f, x, z))
  return binary<detail::AddFastOp>(f, a, b, y, flags, n, f.sign_bit(), detail::sub_general, done, all);
}
uint8_t mul_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n) {
  RU_SIMD_PREFIX(VOp::Mul, b, nullptr, 0, mul(f, x, z))
  return binary<detail::MulFastOp>(f, a, b, y, flags, n, 0, detail::mul_general, done, all);
}
uint8_t div_n(const Format& f, const uint64_t* a, const uint64_t* b, uint64_t* y, uint8_t* flags, size_t n) {
  RU_SIMD_PREFIX(VOp::Div, b, nullptr, 0, div(f, x, z))
  return binary<detail::DivDoubleOp>(f, a, b, y, flags, n, 0, detail::div_general, done, all);
}
uint8_t sqrt_n(const Format& f, const uint64_t* a, uint64_t* y, uint8_t* flags, size_t n) {
  RU_SIMD_PREFIX(VOp::Sqrt, static_cast<const uint64_t*>(nullptr), nullptr, 0, sqrt(f, x))
  return with_consts(f, [&](const auto& c) {
    using C = std::decay_t<decltype(c)>;
    for (size_t i = done; i < n; ++i) {
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
  RU_SIMD_PREFIX(VOp::Fma, b, c3, 0, fma(f, x, z, w))
  return with_consts(f, [&](const auto& c) {
    using C = std::decay_t<decltype(c)>;
    for (size_t i = done; i < n; ++i) {
      const uint64_t x = a[i], z = b[i], w = c3[i];
      Result r;
      if (!detail::FmaDoubleOp<C>::run(c, r, x, z, w)) r = detail::fma_general(f, x, z, w);
      all |= put(y, flags, i, r);
    }
    return all;
  });
}

}  // namespace ru::num
