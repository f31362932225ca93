// The oracle is checked before it is trusted:
//   * against native float/double hardware (x86 SSE/FMA: tininess after rounding, FTZ+DAZ) in
//     every rounding mode, with and without subnormals;
//   * against exact_ref.cpp (GMP integers + docs/FORMAT.md's rounding steps, written
//     separately) exhaustively on tiny formats and on random operands of the whole grid;
//   * on hand-computed cases, including the double-rounding trap below the normal range.
#include <mpfr.h>

#include <cmath>
#include <thread>

#include "exact_ref.hpp"
#include "harness.hpp"

namespace ru::num::testing {
namespace {

OpFn exact_fn() {
  return
      [](const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) { return exact_apply(f, op, a, b, c); };
}

// Native hardware as an OpFn: e8m23 -> float, e11m52 -> double.
OpFn native_fn() {
  return [](const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) {
    return native_spec_op(f, op, a, b, c);
  };
}

void oracle_vs_native(int E, int M, uint64_t count) {
  if (!native_supported(false)) GTEST_SKIP() << "no native FMA on this host";
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      for (Op op : kArithOps) {
        Checker chk("oracle vs native", NanMatch::AnyNan);
        run_specials(chk, f, op, native_fn(), oracle_op);
        run_random(chk, f, op, count, 0x0BAC1E + static_cast<uint64_t>(op), native_fn(), oracle_op);
        EXPECT_TRUE(chk.ok()) << chk.report();
      }
    }
  }
}

TEST(OracleNative, Float) { oracle_vs_native(8, 23, scaled(20000)); }
TEST(OracleNative, Double) { oracle_vs_native(11, 52, scaled(20000)); }
TEST(LongOracleNative, Float) { oracle_vs_native(8, 23, scaled(1000000)); }
TEST(LongOracleNative, Double) { oracle_vs_native(11, 52, scaled(1000000)); }

// ---- vs the exact-integer reference -------------------------------------------------------

class OracleExhaustive : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(OracleExhaustive, ArithVsExact) {
  const auto [E, M] = GetParam();
  const int width = 1 + E + M;
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      for (Op op : kArithOps) {
        Checker chk("oracle vs exact_ref");
        if (op == Op::Fma && width > 5) {
          run_random(chk, f, op, scaled(20000), 77, exact_fn(), oracle_op);
        } else {
          run_exhaustive(chk, f, op, exact_fn(), oracle_op);
        }
        EXPECT_TRUE(chk.ok()) << chk.report();
      }
    }
  }
}
INSTANTIATE_TEST_SUITE_P(Small, OracleExhaustive, ::testing::ValuesIn(small_formats(4, 8)), em_param_name);

class LongOracleExhaustive : public ::testing::TestWithParam<std::pair<int, int>> {};
TEST_P(LongOracleExhaustive, FmaVsExact) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      Checker chk("oracle vs exact_ref");
      run_exhaustive(chk, f, Op::Fma, exact_fn(), oracle_op);
      EXPECT_TRUE(chk.ok()) << chk.report();
    }
  }
}
INSTANTIATE_TEST_SUITE_P(LongSmall, LongOracleExhaustive, ::testing::ValuesIn(small_formats(6, 7)),
                         em_param_name);

class OracleGrid : public ::testing::TestWithParam<std::pair<int, int>> {};
void oracle_grid(int E, int M, uint64_t count) {
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      for (Op op : kArithOps) {
        Checker chk("oracle vs exact_ref");
        run_random(chk, f, op, count, 0xE4AC7 + static_cast<uint64_t>(op), exact_fn(), oracle_op);
        EXPECT_TRUE(chk.ok()) << chk.report();
      }
    }
  }
}
TEST_P(OracleGrid, ArithVsExact) { oracle_grid(GetParam().first, GetParam().second, scaled(2000)); }
INSTANTIATE_TEST_SUITE_P(Grid, OracleGrid, ::testing::ValuesIn(grid_formats()), em_param_name);
INSTANTIATE_TEST_SUITE_P(Edges, OracleGrid, ::testing::ValuesIn(edge_formats()), em_param_name);

class LongOracleGrid : public ::testing::TestWithParam<std::pair<int, int>> {};
TEST_P(LongOracleGrid, ArithVsExact) { oracle_grid(GetParam().first, GetParam().second, scaled(50000)); }
INSTANTIATE_TEST_SUITE_P(LongGrid, LongOracleGrid, ::testing::ValuesIn(grid_formats()), em_param_name);

// ---- hand-computed cases --------------------------------------------------------------------

constexpr uint8_t X = kInexact, U = kUnderflow, O = kOverflow, Z = kDivZero, I = kInvalid;

struct Case {
  const char* fmt;
  Round r;
  Op op;
  uint64_t a, b, c;
  uint64_t bits;
  uint8_t flags;
};

Format named(const char* name, Round r) {
  // Parsed here (not with Format::parse) to keep the oracle tests independent of the model.
  int E = 0, M = 0;
  char ftz[8] = "";
  std::sscanf(name, "e%dm%d%7s", &E, &M, ftz);
  return make_format(E, M, ftz[0] == 0, r);
}

TEST(OracleHand, KnownResults) {
  // e5m10 (binary16): 1.0 = 0x3c00, min subnormal 0x0001 = 2^-24, min normal 0x0400 = 2^-14,
  // max 0x7bff = 65504. e2m1: values 0, 0.5(sub), 1, 1.5, 2, 3, inf; emin = 0, emax = 1.
  const Case cases[] = {
      {"e5m10", Round::RNE, Op::Add, 0x3c00, 0x1000, 0, 0x3c00, X},  // 1 + 2^-11: tie -> even
      {"e5m10", Round::RNE, Op::Add, 0x3c01, 0x1000, 0, 0x3c02, X},  // odd + half ulp -> up
      {"e5m10", Round::RUP, Op::Add, 0x3c00, 0x0001, 0, 0x3c01, X},
      {"e5m10", Round::RDN, Op::Sub, 0x3c00, 0x3c00, 0, 0x8000, 0},  // x - x = -0 under RDN
      {"e5m10", Round::RNE, Op::Sub, 0x3c00, 0x3c00, 0, 0x0000, 0},
      {"e5m10", Round::RNE, Op::Mul, 0x7bff, 0x4000, 0, 0x7c00, O | X},
      {"e5m10", Round::RTZ, Op::Mul, 0x7bff, 0x4000, 0, 0x7bff, O | X},
      {"e5m10", Round::RDN, Op::Mul, 0xfbff, 0x4000, 0, 0xfc00, O | X},
      {"e5m10", Round::RUP, Op::Mul, 0xfbff, 0x4000, 0, 0xfbff, O | X},
      {"e5m10", Round::RNE, Op::Mul, 0x0001, 0x3800, 0, 0x0000, U | X},  // 2^-25: tie -> 0
      {"e5m10", Round::RNE, Op::Mul, 0x0003, 0x3800, 0, 0x0002, U | X},  // 1.5 units: tie -> 2
      {"e5m10", Round::RUP, Op::Mul, 0x0001, 0x3800, 0, 0x0001, U | X},
      {"e5m10", Round::RNE, Op::Mul, 0x0400, 0x3800, 0, 0x0200, 0},          // exact subnormal: no flag
      {"e5m10-ftz", Round::RNE, Op::Mul, 0x0400, 0x3800, 0, 0x0000, U | X},  // exact but tiny: flushed
      {"e5m10-ftz", Round::RNE, Op::Add, 0x0001, 0x0000, 0, 0x0000, 0},      // subnormal input = 0
      {"e5m10-ftz", Round::RNE, Op::Add, 0x8001, 0x8000, 0, 0x8000, 0},      // -0 + -0
      {"e5m10", Round::RNE, Op::Div, 0x3c00, 0x0000, 0, 0x7c00, Z},
      {"e5m10", Round::RNE, Op::Div, 0x8000, 0x0000, 0, 0x7e00, I},
      {"e5m10-ftz", Round::RNE, Op::Div, 0x3c00, 0x0001, 0, 0x7c00, Z},  // b flushed to +0
      {"e5m10", Round::RNE, Op::Sqrt, 0x8000, 0, 0, 0x8000, 0},
      {"e5m10", Round::RNE, Op::Sqrt, 0xbc00, 0, 0, 0x7e00, I},
      {"e5m10", Round::RNE, Op::Sqrt, 0x7d00, 0, 0, 0x7e00, I},  // sNaN
      {"e5m10", Round::RNE, Op::Add, 0x7e00, 0x7d00, 0, 0x7e00, I},
      {"e5m10", Round::RNE, Op::Add, 0xfe01, 0x3c00, 0, 0x7e00, 0},       // qNaN -> canonical
      {"e5m10", Round::RNE, Op::Fma, 0x0000, 0x7c00, 0x7e00, 0x7e00, I},  // 0*inf + qNaN
      {"e5m10", Round::RNE, Op::Fma, 0x7c00, 0x3c00, 0xfc00, 0x7e00, I},  // inf - inf
      {"e5m10", Round::RDN, Op::Fma, 0x3c00, 0x0000, 0x8000, 0x8000, 0},  // +0 + -0 under RDN
      {"e5m10", Round::RNE, Op::Fma, 0x3c00, 0x0000, 0x8000, 0x0000, 0},
      {"e5m10", Round::RNE, Op::Fma, 0xbc00, 0x0000, 0x8000, 0x8000, 0},  // -0 + -0
      // Max finite + half ulp: RNE rounds to 2^16 -> overflow.
      {"e5m10", Round::RNE, Op::Add, 0x7bff, 0x4c00, 0, 0x7c00, O | X},
      {"e5m10", Round::RNE, Op::Add, 0x7bff, 0x4bff, 0, 0x7bff, X},
      // (2-2^-10)^2 * 2^-16 = (1 - 2^-10 + 2^-22) * 2^-14: tiny, 1023.0002 units -> 1023.
      {"e5m10", Round::RNE, Op::Mul, 0x07ff, 0x37ff, 0, 0x03ff, U | X},
      {"e2m1", Round::RNE, Op::Add, 0x2, 0x3, 0, 0x4, X},      // 1 + 1.5 = 2.5: tie -> 2 (even)
      {"e2m1", Round::RUP, Op::Add, 0x2, 0x3, 0, 0x5, X},      // -> 3
      {"e2m1", Round::RNE, Op::Mul, 0x3, 0x3, 0, 0x4, X},      // 1.5*1.5 = 2.25 -> 2
      {"e2m1", Round::RNE, Op::Mul, 0x5, 0x5, 0, 0x6, O | X},  // 3*3 = 9 -> inf
      {"e2m1", Round::RTZ, Op::Mul, 0x5, 0x5, 0, 0x5, O | X},
      {"e2m1", Round::RNE, Op::Mul, 0x1, 0x1, 0, 0x0, U | X},  // 0.25: tie between 0 and 0.5 -> 0
      {"e2m1", Round::RUP, Op::Mul, 0x1, 0x1, 0, 0x1, U | X},
      {"e2m1-ftz", Round::RNE, Op::Mul, 0x2, 0x2, 0, 0x2, 0},  // 1*1
  };
  for (const Case& k : cases) {
    const Format f = named(k.fmt, k.r);
    const Result got = mpfr_apply(f, k.op, k.a, k.b, k.c);
    const Result ex = exact_apply(f, k.op, k.a, k.b, k.c);
    Checker chk("hand");
    chk.check(f, k.op, k.a, k.b, k.c, {k.bits, k.flags}, got);
    chk.check(f, k.op, k.a, k.b, k.c, {k.bits, k.flags}, ex);
    EXPECT_TRUE(chk.ok()) << chk.report();
  }
}

TEST(OracleHand, Conversions) {
  const Format h = make_format(5, 10);
  // Double rounding trap: v = (1.5 - 2^-20) * 2^-24 is just below 1.5 subnormal units. Rounding
  // to 11 bits first gives exactly 1.5 units (a false tie -> 2); the right answer is 1 unit.
  const double v = (1.5 - 0x1p-20) * 0x1p-24;
  Result r = mpfr_from_double(h, v);
  EXPECT_EQ(r.bits, 0x0001u);
  EXPECT_EQ(r.flags, U | X);
  r = mpfr_from_double(h, -v);
  EXPECT_EQ(r.bits, 0x8001u);
  // Just above the tie: 2 units.
  r = mpfr_from_double(h, (1.5 + 0x1p-20) * 0x1p-24);
  EXPECT_EQ(r.bits, 0x0002u);
  // Exactly 1.5 units: tie -> 2 (even).
  r = mpfr_from_double(h, 1.5 * 0x1p-24);
  EXPECT_EQ(r.bits, 0x0002u);
  EXPECT_EQ(r.flags, U | X);
  // Below the normal range but rounds up to the min normal (tiny after rounding? 2^-14 - 2^-26
  // rounds at 11 bits to 2^-14: not tiny -> no underflow).
  r = mpfr_from_double(h, 0x1p-14 - 0x1p-26);
  EXPECT_EQ(r.bits, 0x0400u);
  EXPECT_EQ(r.flags, X);
  // 2^-14 - 2^-25 is exactly representable at 11 bits (tiny), rounds (RNE) to 2^-14 on the
  // subnormal grid: underflow + inexact although the result is the min normal.
  r = mpfr_from_double(h, 0x1p-14 - 0x1p-25);
  EXPECT_EQ(r.bits, 0x0400u);
  EXPECT_EQ(r.flags, U | X);
  EXPECT_EQ(mpfr_from_double(h, 65520.0).bits, 0x7c00u);  // max + half ulp -> inf
  EXPECT_EQ(mpfr_from_double(h, 65519.99).bits, 0x7bffu);
  EXPECT_EQ(mpfr_from_double(h, -0.0).bits, 0x8000u);
  EXPECT_EQ(mpfr_from_double(h, HUGE_VAL).bits, 0x7c00u);
  EXPECT_EQ(mpfr_from_double(h, std::nan("")).bits, 0x7e00u);
  EXPECT_EQ(mpfr_from_double(h, std::nan("")).flags, 0);
  EXPECT_EQ(mpfr_from_int(h, 2049).bits, 0x6800u);  // 2049 -> tie -> 2048
  EXPECT_EQ(mpfr_from_int(h, 2051).bits, 0x6802u);  // 2051 -> tie -> 2052
  EXPECT_EQ(mpfr_from_int(h, 2049).flags, X);
  EXPECT_EQ(mpfr_from_int(h, INT64_MIN).bits, 0xfc00u);
  EXPECT_EQ(mpfr_to_double(h, 0x0001), 0x1p-24);
  EXPECT_EQ(mpfr_to_double(make_format(5, 10, false), 0x8001), 0.0);
  EXPECT_TRUE(std::signbit(mpfr_to_double(make_format(5, 10, false), 0x8001)));
  // to_int
  EXPECT_EQ(mpfr_to_int(h, 0x3e00, Round::RNE).value, 2);  // 1.5 -> 2
  EXPECT_EQ(mpfr_to_int(h, 0x4100, Round::RNE).value, 2);  // 2.5 -> 2
  EXPECT_EQ(mpfr_to_int(h, 0x4100, Round::RUP).value, 3);
  EXPECT_EQ(mpfr_to_int(h, 0xc100, Round::RDN).value, -3);
  EXPECT_EQ(mpfr_to_int(h, 0xc100, Round::RTZ).value, -2);
  EXPECT_EQ(mpfr_to_int(h, 0xc100, Round::RTZ).flags, X);
  EXPECT_EQ(mpfr_to_int(h, 0x7c00, Round::RNE).value, INT64_MAX);
  EXPECT_EQ(mpfr_to_int(h, 0x7c00, Round::RNE).flags, I);
  EXPECT_EQ(mpfr_to_int(h, 0x7e00, Round::RNE).value, INT64_MAX);
  const Format d = make_format(11, 52);
  EXPECT_EQ(mpfr_to_int(d, 0x43e0000000000000ull, Round::RNE).value, INT64_MAX);  // 2^63
  EXPECT_EQ(mpfr_to_int(d, 0x43e0000000000000ull, Round::RNE).flags, I);
  EXPECT_EQ(mpfr_to_int(d, 0xc3e0000000000000ull, Round::RNE).value, INT64_MIN);  // -2^63 fits
  EXPECT_EQ(mpfr_to_int(d, 0xc3e0000000000000ull, Round::RNE).flags, 0);
}

TEST(OracleHand, ThreadSafeAndPreservesTheCallersMpfrState) {
  std::vector<std::tuple<Format, Op, uint64_t, uint64_t, uint64_t>> work;
  for (auto [E, M] : {std::pair{5, 10}, {8, 23}, {3, 2}, {11, 52}}) {
    for (bool sub : {true, false}) {
      const Format f = make_format(E, M, sub, sub ? Round::RNE : Round::RDN);
      OperandGen g(f, 12);
      for (int i = 0; i < 3000; ++i) {
        uint64_t a, b, c;
        g.triple(a, b, c);
        work.emplace_back(f, kArithOps[i % 6], a, b, c);
      }
    }
  }
  auto run = [&](std::vector<Result>& out) {
    out.clear();
    for (const auto& [f, op, a, b, c] : work) out.push_back(mpfr_apply(f, op, a, b, c));
  };
  std::vector<Result> r0, r1, r2;
  const mpfr_exp_t emin = mpfr_get_emin(), emax = mpfr_get_emax();
  mpfr_set_emin(-100);  // a caller with its own exponent range
  mpfr_set_emax(100);
  run(r0);
  EXPECT_EQ(mpfr_get_emin(), -100);
  EXPECT_EQ(mpfr_get_emax(), 100);
  mpfr_set_emin(emin);
  mpfr_set_emax(emax);
  std::thread t1([&] { run(r1); }), t2([&] { run(r2); });
  t1.join();
  t2.join();
  ASSERT_EQ(r0.size(), work.size());
  for (size_t i = 0; i < work.size(); ++i) {
    EXPECT_TRUE(r0[i].bits == r1[i].bits && r0[i].flags == r1[i].flags && r0[i].bits == r2[i].bits &&
                r0[i].flags == r2[i].flags)
        << i;
  }
}

}  // namespace
}  // namespace ru::num::testing
