// The batch API (num/batch.hpp) against the scalar functions, bit for bit and flag for flag:
// every operand pair (sqrt: operand; fma: triple up to 6 bits) of every format of 4..8 bits
// (4..6 for fma) in all four roundings, with and without subnormals; random and special operands
// at e8m23, e7m16, e5m10 (the compile-time-width dispatch), e6m12, e11m52 and e8m23-ftz (the
// dynamic one); the OR of the flags returned; flags = null accepted; y aliasing a. A planted
// error (one element's result bit flipped) is reported by the same comparison.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "harness.hpp"  // small_formats
#include "rayunits/num/batch.hpp"
#include "rayunits/num/patterns.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::num {
namespace {

using testing::small_formats;

enum class BOp { Add, Sub, Mul, Div, Sqrt, Fma };
constexpr BOp kOps[] = {BOp::Add, BOp::Sub, BOp::Mul, BOp::Div, BOp::Sqrt, BOp::Fma};

Result scalar(const Format& f, BOp op, uint64_t a, uint64_t b, uint64_t c) {
  switch (op) {
    case BOp::Add: return add(f, a, b);
    case BOp::Sub: return sub(f, a, b);
    case BOp::Mul: return mul(f, a, b);
    case BOp::Div: return div(f, a, b);
    case BOp::Sqrt: return sqrt(f, a);
    default: return fma(f, a, b, c);
  }
}
uint8_t batch(const Format& f, BOp op, const std::vector<uint64_t>& a, const std::vector<uint64_t>& b,
              const std::vector<uint64_t>& c, std::vector<uint64_t>& y, std::vector<uint8_t>* fl) {
  const size_t n = a.size();
  y.assign(n, 0);
  if (fl) fl->assign(n, 0xff);
  uint8_t* p = fl ? fl->data() : nullptr;
  switch (op) {
    case BOp::Add: return add_n(f, a.data(), b.data(), y.data(), p, n);
    case BOp::Sub: return sub_n(f, a.data(), b.data(), y.data(), p, n);
    case BOp::Mul: return mul_n(f, a.data(), b.data(), y.data(), p, n);
    case BOp::Div: return div_n(f, a.data(), b.data(), y.data(), p, n);
    case BOp::Sqrt: return sqrt_n(f, a.data(), y.data(), p, n);
    default: return fma_n(f, a.data(), b.data(), c.data(), y.data(), p, n);
  }
}

// Elements whose bits or flags differ from the scalar function, and whether the returned OR is
// the OR of the scalar flags.
struct Check {
  uint64_t differ = 0;
  bool or_ok = true;
  std::string first;
};
Check compare(const Format& f, BOp op, const std::vector<uint64_t>& a, const std::vector<uint64_t>& b,
              const std::vector<uint64_t>& c, const std::vector<uint64_t>& y, const std::vector<uint8_t>& fl,
              uint8_t all) {
  Check k;
  uint8_t want_all = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const Result r = scalar(f, op, a[i], b[i], c[i]);
    want_all |= r.flags;
    if (r.bits != y[i] || r.flags != fl[i]) {
      if (!k.differ++)
        k.first = f.name() + " op " + std::to_string(static_cast<int>(op)) + " element " + std::to_string(i) +
                  ": batch " + std::to_string(y[i]) + "/" + std::to_string(fl[i]) + ", scalar " +
                  std::to_string(r.bits) + "/" + std::to_string(r.flags);
    }
  }
  k.or_ok = all == want_all;
  return k;
}

// Every vector path the CPU has (set_batch_isa: scalar, AVX2, AVX-512) against the scalar functions.
void check_all(const Format& f, BOp op, const std::vector<uint64_t>& a, const std::vector<uint64_t>& b,
               const std::vector<uint64_t>& c) {
  for (BatchIsa isa : {BatchIsa::Scalar, BatchIsa::Avx2, BatchIsa::Avx512}) {
    if (!set_batch_isa(isa)) continue;
    SCOPED_TRACE("isa " + std::to_string(static_cast<int>(isa)));
    std::vector<uint64_t> y, y2;
    std::vector<uint8_t> fl;
    const uint8_t all = batch(f, op, a, b, c, y, &fl);
    const Check k = compare(f, op, a, b, c, y, fl, all);
    set_batch_isa(BatchIsa::Auto);
    ASSERT_EQ(k.differ, 0u) << k.first;
    ASSERT_TRUE(k.or_ok) << f.name();
    set_batch_isa(isa);
    ASSERT_EQ(batch(f, op, a, b, c, y2, nullptr), all);  // flags = null: same bits, same OR
    set_batch_isa(BatchIsa::Auto);
    ASSERT_EQ(y2, y);
  }
}

// The vector paths take the common case: normal operands and results (the operands of `rayunits
// bench fp`, exponents -8..8) at e8m23 and e7m16, lengths not a multiple of the lane count (the
// scalar tail), every path the CPU has, against the scalar functions. On a CPU with AVX2 both
// paths are there to test (the AVX-512 one only with AVX-512F and DQ).
TEST(NumBatch, VectorPathsEqualScalarOnNormalOperands) {
  EXPECT_TRUE(set_batch_isa(BatchIsa::Scalar));
  EXPECT_EQ(batch_isa(), BatchIsa::Scalar);
  set_batch_isa(BatchIsa::Auto);
  if (__builtin_cpu_supports("avx2")) {
    EXPECT_TRUE(set_batch_isa(BatchIsa::Avx2));
    EXPECT_EQ(batch_isa(), BatchIsa::Avx2);
    set_batch_isa(BatchIsa::Auto);
  }
  util::Xoshiro256ss rng(7);
  for (const char* name : {"e8m23", "e7m16", "e5m10", "e8m23-ftz"}) {
    const Format f = Format::parse(name);
    std::vector<uint64_t> a, b, c;
    const int span = std::min(8, f.emax() / 2 - 1);
    for (int i = 0; i < 40003; ++i)
      for (auto* v : {&a, &b, &c}) {
        const int e = static_cast<int>(rng.next() % (2 * span + 1)) - span;
        v->push_back((rng.next() & f.sign_bit()) | (static_cast<uint64_t>(e + f.bias()) << f.frac_bits) |
                     (rng.next() & f.frac_mask()));
      }
    for (BOp op : kOps) check_all(f, op, a, b, c);
  }
}

TEST(NumBatch, SmallFormatsExhaustiveEqualScalar) {
  for (auto [e, m] : small_formats(4, 8))
    for (int r = 0; r < 4; ++r)
      for (bool sub : {true, false}) {
        Format f{e, m};
        f.round = static_cast<Round>(r);
        f.subnormals = sub;
        const uint64_t n = 1ull << f.width();
        for (BOp op : kOps) {
          if (op == BOp::Fma && f.width() > 6) continue;
          std::vector<uint64_t> a, b, c;
          if (op == BOp::Sqrt) {
            for (uint64_t x = 0; x < n; ++x) a.push_back(x);
          } else if (op == BOp::Fma) {
            for (uint64_t x = 0; x < n; ++x)
              for (uint64_t z = 0; z < n; ++z)
                for (uint64_t w = 0; w < n; ++w) a.push_back(x), b.push_back(z), c.push_back(w);
          } else {
            for (uint64_t x = 0; x < n; ++x)
              for (uint64_t z = 0; z < n; ++z) a.push_back(x), b.push_back(z);
          }
          b.resize(a.size());
          c.resize(a.size());
          check_all(f, op, a, b, c);
        }
      }
}

TEST(NumBatch, WideFormatsRandomAndSpecialEqualScalar) {
  util::Xoshiro256ss rng(16);
  for (const char* name : {"e8m23", "e7m16", "e5m10", "e6m12", "e11m52", "e8m23-ftz"})
    for (int r = 0; r < 4; ++r) {
      Format f = Format::parse(name);
      f.round = static_cast<Round>(r);
      const std::vector<uint64_t> sv = special_values(f);
      std::vector<uint64_t> a, b, c;
      for (int i = 0; i < 20000; ++i) {
        auto pick = [&] { return (rng.next() & 3) == 0 ? sv[rng.next() % sv.size()] : rng.next() & f.mask(); };
        a.push_back(pick());
        b.push_back(pick());
        c.push_back(pick());
      }
      for (BOp op : kOps) check_all(f, op, a, b, c);
      std::vector<uint64_t> y = a;  // y aliasing a
      add_n(f, y.data(), b.data(), y.data(), nullptr, y.size());
      for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(y[i], add(f, a[i], b[i]).bits) << name;
    }
}

// The planted error: one element's result with a bit flipped (as a batch kernel that skipped an
// element would give) -- the comparison the tests above use reports it.
TEST(NumBatch, PlantedErrorIsReported) {
  const Format f = Format::parse("e7m16");
  util::Xoshiro256ss rng(3);
  std::vector<uint64_t> a(1000), b(1000), c(1000), y;
  for (size_t i = 0; i < a.size(); ++i) a[i] = rng.next() & f.mask(), b[i] = rng.next() & f.mask();
  std::vector<uint8_t> fl;
  const uint8_t all = batch(f, BOp::Mul, a, b, c, y, &fl);
  EXPECT_EQ(compare(f, BOp::Mul, a, b, c, y, fl, all).differ, 0u);
  y[517] ^= 1;
  EXPECT_EQ(compare(f, BOp::Mul, a, b, c, y, fl, all).differ, 1u);
  y[517] ^= 1;
  fl[3] ^= kInexact;
  EXPECT_EQ(compare(f, BOp::Mul, a, b, c, y, fl, all).differ, 1u);
  EXPECT_FALSE(compare(f, BOp::Mul, a, b, c, y, fl, all ^ kInvalid).or_ok);
}

}  // namespace
}  // namespace ru::num
