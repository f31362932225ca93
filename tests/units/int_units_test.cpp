// The integer units' golden models (units/int_units.hpp) against native integer arithmetic: at
// the native widths 8, 16, 32, 64 every op on edge and random operands is computed a second way
// with int8_t..int64_t / uint8_t..uint64_t (C++20 two's complement, shifts by the native type);
// at 2..7 bits every operand pair against arithmetic on int64_t reduced to w bits. A planted
// error (sra computed as srl) shows that the comparison catches a wrong model.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <random>
#include <type_traits>
#include <vector>

#include "rayunits/units/int_units.hpp"

using namespace ru::units;

namespace {

// The oracle of one op at a native width: S/U the signed/unsigned type of w bits.
template <class S>
uint64_t native(unsigned op, uint64_t a64, uint64_t b64) {
  using U = std::make_unsigned_t<S>;
  constexpr int w = 8 * sizeof(S);
  const U a = static_cast<U>(a64), b = static_cast<U>(b64);
  const S sa = static_cast<S>(a), sb = static_cast<S>(b);
  unsigned s = static_cast<unsigned>(b) & (w - 1);  // the low clog2(w) bits
  switch (op) {
    case 0: return static_cast<U>(a + b);
    case 1: return static_cast<U>(a - b);
    case 2: return static_cast<U>(a & b);
    case 3: return static_cast<U>(a | b);
    case 4: return static_cast<U>(a ^ b);
    case 5: return static_cast<U>(a << s);
    case 6: return static_cast<U>(a >> s);
    case 7: return static_cast<U>(static_cast<S>(sa >> s));
    case 8: return sa < sb;
    case 9: return a < b;
    case 10: return sa < sb ? a : b;
    case 11: return sa < sb ? b : a;
    default: return a;
  }
}

std::vector<uint64_t> operands(int w, std::mt19937_64& rng) {
  const uint64_t m = int_mask(w);
  std::vector<uint64_t> v = {0, 1, 2, m, m - 1, m >> 1, (m >> 1) + 1, static_cast<uint64_t>(w - 1),
                             static_cast<uint64_t>(w), static_cast<uint64_t>(w + 1)};
  for (int k = 0; k < w; ++k) v.push_back((1ull << k) & m);
  for (int i = 0; i < 60; ++i) v.push_back(rng() & m);
  for (auto& x : v) x &= m;
  return v;
}

using Alu = std::function<uint64_t(int, unsigned, uint64_t, uint64_t)>;

// Mismatches of `alu` against the native oracle at width w (8, 16, 32 or 64).
template <class S>
uint64_t native_mismatches(const Alu& alu) {
  constexpr int w = 8 * sizeof(S);
  std::mt19937_64 rng(w);
  const auto v = operands(w, rng);
  uint64_t bad = 0;
  for (unsigned op = 0; op < 16; ++op)
    for (uint64_t a : v)
      for (uint64_t b : v) bad += alu(w, op, a, b) != native<S>(op, a, b);
  return bad;
}

}  // namespace

TEST(IntAlu, EqualsNativeArithmetic) {
  const Alu model = [](int w, unsigned op, uint64_t a, uint64_t b) { return int_alu(w, op, a, b); };
  EXPECT_EQ(native_mismatches<int8_t>(model), 0u);
  EXPECT_EQ(native_mismatches<int16_t>(model), 0u);
  EXPECT_EQ(native_mismatches<int32_t>(model), 0u);
  EXPECT_EQ(native_mismatches<int64_t>(model), 0u);
  // planted: sra as srl
  const Alu planted = [](int w, unsigned op, uint64_t a, uint64_t b) { return int_alu(w, op == 7 ? 6 : op, a, b); };
  EXPECT_GT(native_mismatches<int32_t>(planted), 0u);
}

// Widths 2..7: every operand pair, against int64_t arithmetic reduced to w bits; shift amounts
// >= w shift everything out (sra: sign fill), as the RTL's Verilog shifts do.
TEST(IntAlu, SmallWidthsExhaustive) {
  for (int w = 2; w < 8; ++w) {
    const uint64_t m = int_mask(w);
    const int sb = int_shift_bits(w);
    for (unsigned op = 0; op < 16; ++op)
      for (uint64_t a = 0; a <= m; ++a)
        for (uint64_t b = 0; b <= m; ++b) {
          const int64_t sa = int_signed(a, w), sbv = int_signed(b, w);
          const uint64_t s = b & ((1u << sb) - 1);
          uint64_t want = 0;
          switch (op) {
            case 0: want = static_cast<uint64_t>(sa + sbv) & m; break;
            case 1: want = static_cast<uint64_t>(sa - sbv) & m; break;
            case 2: want = a & b; break;
            case 3: want = a | b; break;
            case 4: want = a ^ b; break;
            case 5: want = (a << s) & m; break;  // s < 8: a << s fits in 64 bits; >= w leaves 0 after the mask
            case 6: want = a >> s; break;
            case 7: want = static_cast<uint64_t>(sa >> (s > 62 ? 62 : s)) & m; break;
            case 8: want = sa < sbv; break;
            case 9: want = a < b; break;
            case 10: want = sa < sbv ? a : b; break;
            case 11: want = sa < sbv ? b : a; break;
            default: want = a; break;
          }
          ASSERT_EQ(int_alu(w, op, a, b), want) << "w " << w << " op " << op << " a " << a << " b " << b;
        }
  }
}

TEST(Branch, ConditionsAndNextPc) {
  std::mt19937_64 rng(7);
  uint64_t bad_planted = 0;
  for (int w : {8, 16, 32, 64}) {
    const auto v = operands(w, rng);
    for (unsigned op = 0; op < 8; ++op)
      for (uint64_t a : v)
        for (uint64_t b : v) {
          const int64_t sa = int_signed(a, w), sbv = int_signed(b, w);
          const bool want = op == 0 ? a == b : op == 1 ? a != b : op == 2 ? sa < sbv : op == 3 ? sa >= sbv
                          : op == 4 ? a < b : op == 5 ? a >= b : true;
          const uint64_t pc = rng() & int_mask(w), off = rng() & int_mask(w);
          const BranchResult r = branch(w, w, op, a, b, pc, off);
          ASSERT_EQ(r.taken, want) << "w " << w << " op " << op;
          ASSERT_EQ(r.next, ((want ? pc + off : pc + 1) & int_mask(w))) << "w " << w << " op " << op;
          // planted: bltu/bgeu read as signed
          const BranchResult p = branch(w, w, op == 4 ? 2 : op == 5 ? 3 : op, a, b, pc, off);
          bad_planted += p.taken != want;
        }
  }
  EXPECT_GT(bad_planted, 0u);
  // pc width apart from the register width: next pc wraps at 2^PcW
  EXPECT_EQ(branch(32, 4, 6, 0, 0, 15, 3).next, 2u);
  EXPECT_EQ(branch(32, 4, 1, 5, 5, 15, 3).next, 0u);
}
