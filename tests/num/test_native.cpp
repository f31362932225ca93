// Bit-exact against the hardware: e8m23 == float and e11m52 == double (x86-64 SSE/FMA, one
// inline-asm instruction per operation with its own MXCSR: rounding mode, FTZ+DAZ for -ftz).
// Results are compared bit for bit (NaN as NaN: the hardware propagates payloads, the format
// returns the canonical NaN), flags exactly. Operands: special x special, then half uniformly
// random bit patterns, half OperandGen sets.
//   fast: 10^5 random sets per op (RNE, subnormals), 2*10^4 in the other seven configurations;
//   long: 10^7 per op (RNE, subnormals), 10^6 in the other configurations.
#include "harness.hpp"

namespace ru::num::testing {
namespace {

OpFn native_ref() {
  return [](const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) {
    return native_spec_op(f, op, a, b, c);
  };
}

void native_suite(int E, int M, Op op, Round r, bool sub, uint64_t count) {
  if (!native_supported(!sub)) GTEST_SKIP() << "native FMA/FTZ not available on this host";
  const Format f = make_format(E, M, sub, r);
  Checker chk("model vs native", NanMatch::AnyNan);
  const uint64_t seed = (static_cast<uint64_t>(E) << 32) ^ (static_cast<uint64_t>(op) << 8) ^
                        (static_cast<uint64_t>(r) << 4) ^ (sub ? 1 : 0);
  run_specials(chk, f, op, native_ref(), model_op);
  run_uniform(chk, f, op, count / 2, seed, native_ref(), model_op);
  run_random(chk, f, op, count - count / 2, seed, native_ref(), model_op);
  EXPECT_TRUE(chk.ok()) << chk.report();
  EXPECT_GE(chk.checks(), count);
}

std::string op_param_name(const ::testing::TestParamInfo<Op>& info) { return op_str(info.param); }

class NativeFloat : public ::testing::TestWithParam<Op> {};
class NativeDouble : public ::testing::TestWithParam<Op> {};
class LongNativeFloat : public ::testing::TestWithParam<Op> {};
class LongNativeDouble : public ::testing::TestWithParam<Op> {};

void other_modes(int E, int M, Op op, uint64_t count) {
  for (bool sub : {true, false})
    for (Round r : kRounds)
      if (!(sub && r == Round::RNE)) native_suite(E, M, op, r, sub, count);
}

TEST_P(NativeFloat, RneSubnormals) { native_suite(8, 23, GetParam(), Round::RNE, true, scaled(100000)); }
TEST_P(NativeFloat, OtherModes) { other_modes(8, 23, GetParam(), scaled(20000)); }
TEST_P(NativeDouble, RneSubnormals) { native_suite(11, 52, GetParam(), Round::RNE, true, scaled(100000)); }
TEST_P(NativeDouble, OtherModes) { other_modes(11, 52, GetParam(), scaled(20000)); }
TEST_P(LongNativeFloat, RneSubnormals) {
  native_suite(8, 23, GetParam(), Round::RNE, true, scaled(10000000));
}
TEST_P(LongNativeFloat, OtherModes) { other_modes(8, 23, GetParam(), scaled(1000000)); }
TEST_P(LongNativeDouble, RneSubnormals) {
  native_suite(11, 52, GetParam(), Round::RNE, true, scaled(10000000));
}
TEST_P(LongNativeDouble, OtherModes) { other_modes(11, 52, GetParam(), scaled(1000000)); }

INSTANTIATE_TEST_SUITE_P(Native, NativeFloat, ::testing::ValuesIn(kArithOps), op_param_name);
INSTANTIATE_TEST_SUITE_P(Native, NativeDouble, ::testing::ValuesIn(kArithOps), op_param_name);
INSTANTIATE_TEST_SUITE_P(LongNative, LongNativeFloat, ::testing::ValuesIn(kArithOps), op_param_name);
INSTANTIATE_TEST_SUITE_P(LongNative, LongNativeDouble, ::testing::ValuesIn(kArithOps), op_param_name);

// The harness itself: the wrappers really execute in the requested mode (a wrong MXCSR would
// make every native comparison meaningless).
TEST(NativeHarness, ModesAndFlagsTakeEffect) {
  if (!native_supported(true)) GTEST_SKIP();
  const uint64_t one = 0x3f800000, three = 0x40400000;  // 1/3 rounds up in RNE, down in RTZ
  const Result rne = native_op(32, Op::Div, one, three, 0, Round::RNE, false);
  const Result rtz = native_op(32, Op::Div, one, three, 0, Round::RTZ, false);
  const Result rup = native_op(32, Op::Div, one, three, 0, Round::RUP, false);
  EXPECT_EQ(rne.bits, 0x3eaaaaabu);
  EXPECT_EQ(rtz.bits, 0x3eaaaaaau);
  EXPECT_EQ(rup.bits, 0x3eaaaaabu);
  EXPECT_EQ(rne.flags, kInexact);
  // FTZ: 2^-126 * 0.5 is an exact subnormal; flushed to 0 with underflow+inexact under FTZ.
  EXPECT_EQ(native_op(32, Op::Mul, 0x00800000, 0x3f000000, 0, Round::RNE, false).bits, 0x00400000u);
  EXPECT_EQ(native_op(32, Op::Mul, 0x00800000, 0x3f000000, 0, Round::RNE, false).flags, 0);
  const Result ftz = native_op(32, Op::Mul, 0x00800000, 0x3f000000, 0, Round::RNE, true);
  EXPECT_EQ(ftz.bits, 0u);
  EXPECT_EQ(ftz.flags, kUnderflow | kInexact);
  // DAZ: a subnormal input reads as zero.
  EXPECT_EQ(native_op(32, Op::Add, 0x00000001, 0, 0, Round::RNE, true).bits, 0u);
  EXPECT_EQ(native_op(64, Op::Fma, 0x3ff0000000000000ull, 0x3ff0000000000000ull, 0x3ca0000000000000ull,
                      Round::RNE, false)
                .bits,
            0x3ff0000000000000ull);  // 1 + 2^-53: tie -> 1
  EXPECT_EQ(native_op(64, Op::Sqrt, 0x4000000000000000ull, 0, 0, Round::RTZ, false).bits,
            0x3ff6a09e667f3bccull);  // sqrt(2) truncated
  EXPECT_EQ(native_op(64, Op::Div, 0x3ff0000000000000ull, 0, 0, Round::RNE, false).flags, kDivZero);
  EXPECT_EQ(native_op(64, Op::Sub, 0x7ff0000000000000ull, 0x7ff0000000000000ull, 0, Round::RNE, false).flags,
            kInvalid);
}

}  // namespace
}  // namespace ru::num::testing
