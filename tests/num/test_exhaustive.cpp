// Exhaustive against MPFR for every format of <= 8 bits total (e2m1 ... e6m1, e4m3, e5m2,
// e3m4, e2m5): every operand pair of every op (add sub mul div min max lt le eq, every sqrt
// operand), all four rounding modes, subnormals on and off.
//   fast: every pair for every format (8-bit formats take about a second each), fma: every
//     triple for formats of <= 6 bits, 2*10^4 random triples otherwise;
//   long: fma over every triple of the 7- and 8-bit formats too.
#include "harness.hpp"

namespace ru::num::testing {
namespace {

class Exhaustive : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(Exhaustive, EveryPairEveryOp) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      for (Op op : kAllOps) {
        Checker chk("model vs MPFR (exhaustive)");
        if (op == Op::Fma && f.width() > 6) {
          run_random(chk, f, op, scaled(20000), 0xF3A, oracle_op, model_op);
        } else {
          run_exhaustive(chk, f, op, oracle_op, model_op);
          const uint64_t n = 1ull << f.width();
          EXPECT_EQ(chk.checks(), op == Op::Sqrt ? n : op == Op::Fma ? n * n * n : n * n);
        }
        EXPECT_TRUE(chk.ok()) << chk.report();
      }
    }
  }
}
INSTANTIATE_TEST_SUITE_P(Small, Exhaustive, ::testing::ValuesIn(small_formats(4, 8)), em_param_name);

class LongExhaustiveFma : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(LongExhaustiveFma, EveryTriple) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      Checker chk("model vs MPFR (exhaustive fma)");
      run_exhaustive(chk, f, Op::Fma, oracle_op, model_op);
      EXPECT_TRUE(chk.ok()) << chk.report();
    }
  }
}
INSTANTIATE_TEST_SUITE_P(LongSmall, LongExhaustiveFma, ::testing::ValuesIn(small_formats(7, 8)),
                         em_param_name);

}  // namespace
}  // namespace ru::num::testing
