// Planted-error proof: every checker in this directory is shown to catch deliberately wrong
// results (a flipped LSB, a dropped flag, a wrong rounding mode, a wrong subnormal setting,
// double rounding below the normal range, a wrong sign of zero, an error on a single operand
// pair), to print what an engineer needs (format, rounding, op, operands in hex and decimal,
// expected, actual, flags) and to stop after a few errors.
#include <cmath>

#include "harness.hpp"

namespace ru::num::testing {
namespace {

// A deliberately wrong DUT built from the oracle.
OpFn planted(std::function<Result(const Format&, Op, uint64_t, uint64_t, uint64_t)> wrong) { return wrong; }

void expect_caught(const Checker& chk, const Format& f, Op op) {
  EXPECT_GT(chk.errors(), 0u) << "planted error not caught";
  const std::string rep = chk.report();
  for (const std::string& s :
       {fmt_name(f), std::string(rnd_name(f.round)), std::string(op_str(op)), std::string("0x"),
        std::string("expected"), std::string("actual"), std::string("flags"), std::string("MISMATCH")})
    EXPECT_NE(rep.find(s), std::string::npos) << "report lacks '" << s << "':\n" << rep;
}

TEST(Planted, FlippedLsbIsCaughtAndReported) {
  const Format f = make_format(5, 10);
  Checker chk("planted lsb");
  auto dut = planted([](const Format& g, Op op, uint64_t a, uint64_t b, uint64_t c) {
    Result r = mpfr_apply(g, op, a, b, c);
    if (!bits_are_nan(g, r.bits)) r.bits ^= 1;
    return r;
  });
  run_random(chk, f, Op::Mul, 100000, 1, oracle_op, dut);
  expect_caught(chk, f, Op::Mul);
  EXPECT_TRUE(chk.done());
  EXPECT_EQ(chk.errors(), 5u) << "stops after a few errors";
  EXPECT_LE(chk.checks(), 20u) << "keeps going after the error budget";
  // Operands are printed in hex and decimal (e.g. "0x3c00 = 1 (0x1p+0)").
  EXPECT_NE(chk.report().find(" = "), std::string::npos);
  EXPECT_NE(chk.report().find("(0x"), std::string::npos);
  std::cout << "example report:\n" << chk.report();
}

TEST(Planted, DroppedInexactFlag) {
  for (Op op : kArithOps) {
    const Format f = make_format(8, 23, true, Round::RUP);
    Checker chk("planted flag");
    auto dut = planted([](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
      Result r = mpfr_apply(g, o, a, b, c);
      r.flags &= ~kInexact;
      return r;
    });
    run_random(chk, f, op, 10000, 2, oracle_op, dut);
    expect_caught(chk, f, op);
    EXPECT_NE(chk.report().find("flags differ"), std::string::npos);
  }
}

// Tininess detected before rounding: a result that rounds up to the smallest normal gets
// underflow. Only products near a power of two reach it.
OpFn underflow_before_rounding() {
  return [](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
    Result r = mpfr_apply(g, o, a, b, c);
    Format z = g;
    z.round = Round::RTZ;  // |v| < 2^emin  <=>  v rounded toward zero is below the smallest normal
    const Result t = mpfr_apply(z, o, a, b, c);
    const bool tiny_before = (t.bits & ~g.sign_bit()) < g.min_normal();
    if ((r.bits & ~g.sign_bit()) == g.min_normal() && (r.flags & kInexact) && tiny_before)
      r.flags |= kUnderflow;
    return r;
  };
}

TEST(Planted, UnderflowBeforeRounding) {
  for (Round rm : kRounds) {
    for (Op op : {Op::Mul, Op::Fma}) {
      const Format f = make_format(5, 10, true, rm);
      Checker chk("planted tininess");
      run_random(chk, f, op, 200000, 3, oracle_op, underflow_before_rounding());
      if (rm == Round::RTZ) {
        EXPECT_EQ(chk.errors(), 0u) << "RTZ never rounds up to the smallest normal";
      } else {
        expect_caught(chk, f, op);
      }
    }
  }
}

TEST(Planted, TininessBeforeAndAfterRoundingAgreeForAddDivSqrt) {
  // Why the planted error above is only planted in mul and fma: sums near 2^emin are exact,
  // and a quotient or a square root of (M+1)-bit values never lies within half an ulp below a
  // power of two, so no input tells the two tininess rules apart. Shown exhaustively on e4m3.
  for (Round rm : kRounds) {
    for (Op op : {Op::Add, Op::Sub, Op::Div, Op::Sqrt}) {
      const Format f = make_format(4, 3, true, rm);
      Checker chk("tininess add/div/sqrt");
      run_exhaustive(chk, f, op, oracle_op, underflow_before_rounding());
      EXPECT_TRUE(chk.ok()) << chk.report();
    }
  }
}

TEST(Planted, WrongRoundingMode) {
  for (Round want : kRounds) {
    for (Op op : kArithOps) {
      const Format f = make_format(6, 9, true, want);
      Checker chk("planted rounding");
      auto dut = planted([](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
        // RNE->RTZ, RTZ->RUP, RDN->RNE, RUP->RDN (RTZ and RDN agree on sqrt's positive results)
        static const Round wrong[] = {Round::RTZ, Round::RUP, Round::RNE, Round::RDN};
        Format w = g;
        w.round = wrong[static_cast<int>(g.round)];
        return mpfr_apply(w, o, a, b, c);
      });
      run_random(chk, f, op, 10000, 4, oracle_op, dut);
      expect_caught(chk, f, op);
    }
  }
}

TEST(Planted, WrongSubnormalSetting) {
  for (bool sub : {true, false}) {
    for (Op op : kAllOps) {
      const Format f = make_format(4, 3, sub);
      Checker chk("planted ftz");
      auto dut = planted([](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
        Format w = g;
        w.subnormals = !g.subnormals;
        return mpfr_apply(w, o, a, b, c);
      });
      run_random(chk, f, op, 10000, 5, oracle_op, dut);
      expect_caught(chk, f, op);
    }
  }
}

TEST(Planted, DoubleRoundingBelowTheNormalRange) {
  // Round to M+1 bits in a format with one more exponent bit first, then into the target:
  // the classic double-rounding bug for results in the subnormal range.
  for (Op op : {Op::Mul, Op::Div, Op::Sqrt, Op::Fma}) {
    for (auto [E, M] : {std::pair{5, 10}, {3, 7}, {8, 23}}) {
      const Format f = make_format(E, M, true, Round::RNE);
      Checker chk("planted double rounding");
      auto dut = planted([](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
        const Format w = make_format(g.exp_bits + 1, g.frac_bits, true, g.round);
        // re-encode the operands in the wider format (exact), compute, convert back
        auto widen = [&](uint64_t x) { return mpfr_from_double(w, mpfr_to_double(g, x)).bits; };
        const Result r = mpfr_apply(w, o, widen(a), widen(b), widen(c));
        Result back = mpfr_from_double(g, mpfr_to_double(w, r.bits));
        if (bits_are_nan(w, r.bits)) back.bits = g.qnan();
        back.flags |= r.flags & (kInvalid | kDivZero);
        return back;
      });
      run_random(chk, f, op, 300000, 6, oracle_op, dut);
      expect_caught(chk, f, op);
    }
  }
}

TEST(Planted, WrongSignOfExactZeroIsCaughtBySpecials) {
  const Format f = make_format(5, 10, true, Round::RDN);
  Checker chk("planted zero sign");
  auto dut = planted([](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
    Result r = mpfr_apply(g, o, a, b, c);
    if (r.bits == g.neg_zero()) r.bits = 0;  // x - x = +0 even under RDN
    return r;
  });
  run_specials(chk, f, Op::Sub, oracle_op, dut);
  expect_caught(chk, f, Op::Sub);
}

TEST(Planted, SinglePairErrorIsCaughtByExhaustive) {
  const Format f = make_format(4, 3, false, Round::RTZ);
  Checker chk("planted single pair");
  auto dut = planted([](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
    Result r = mpfr_apply(g, o, a, b, c);
    if (a == 0x9d && b == 0x37) r.bits ^= 0x80;
    return r;
  });
  run_exhaustive(chk, f, Op::Div, oracle_op, dut);
  expect_caught(chk, f, Op::Div);
  EXPECT_EQ(chk.errors(), 1u);
  EXPECT_EQ(chk.checks(), 256u * 256u);
  EXPECT_NE(chk.report().find("0x9d"), std::string::npos);
}

TEST(Planted, NativeCheckerCatchesWrongBitsAndNanness) {
  if (!native_supported(false)) GTEST_SKIP();
  const Format f = make_format(8, 23);
  auto native = [](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
    return native_spec_op(g, o, a, b, c);
  };
  {
    Checker chk("planted native lsb", NanMatch::AnyNan);
    auto dut = planted([](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
      Result r = mpfr_apply(g, o, a, b, c);
      if (!bits_are_nan(g, r.bits) && (a & 7) == 3) r.bits ^= 1;  // only on some operands
      return r;
    });
    run_uniform(chk, f, Op::Add, 10000, 7, native, dut);
    expect_caught(chk, f, Op::Add);
  }
  {
    // NaN-as-NaN must not accept a non-NaN: a DUT returning +inf instead of NaN.
    Checker chk("planted native nan", NanMatch::AnyNan);
    auto dut = planted([](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
      Result r = mpfr_apply(g, o, a, b, c);
      if (bits_are_nan(g, r.bits)) r.bits = g.inf();
      return r;
    });
    run_specials(chk, f, Op::Mul, native, dut);
    expect_caught(chk, f, Op::Mul);
  }
  {
    // ... and a model that is right passes.
    Checker chk("native vs oracle", NanMatch::AnyNan);
    run_uniform(chk, f, Op::Fma, 10000, 7, native, oracle_op);
    EXPECT_TRUE(chk.ok()) << chk.report();
  }
}

TEST(Planted, CanonicalNanIsRequiredAgainstTheOracle) {
  // Against MPFR the NaN bits must be the canonical NaN: a propagated payload is an error.
  const Format f = make_format(5, 10);
  Checker chk("planted nan payload");
  auto dut = planted([](const Format& g, Op o, uint64_t a, uint64_t b, uint64_t c) {
    Result r = mpfr_apply(g, o, a, b, c);
    if (bits_are_nan(g, a) && bits_are_nan(g, r.bits)) r.bits = a | (1ull << (g.frac_bits - 1));
    return r;
  });
  run_specials(chk, f, Op::Add, oracle_op, dut);
  expect_caught(chk, f, Op::Add);
}

}  // namespace
}  // namespace ru::num::testing
