// Soft (runtime-format value type) and the generic helpers of num/fp.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "rayunits/num/fp.hpp"
#include "rayunits/num/patterns.hpp"
#include "rayunits/units/synthetic.hpp"

using namespace ru::num;

namespace {

Format F(const char* name) { return Format::parse(name); }

// Every Soft operator is exactly one call of the format model.
TEST(UnitsSoft, OperatorsAreTheFormatOps) {
  for (const char* name : {"e5m10", "e7m16", "e4m3-ftz", "e8m23"}) {
    const Format f = F(name);
    SoftScope scope(f);
    OperandGen gen(f, 7);
    for (int i = 0; i < 3000; ++i) {
      uint64_t a, b;
      gen.pair(a, b);
      const Soft x = Soft::from_bits(a), y = Soft::from_bits(b);
      ASSERT_EQ((x + y).bits, add(f, a, b).bits) << name;
      ASSERT_EQ((x - y).bits, sub(f, a, b).bits) << name;
      ASSERT_EQ((x * y).bits, mul(f, a, b).bits) << name;
      ASSERT_EQ((x / y).bits, div(f, a, b).bits) << name;
      ASSERT_EQ((-x).bits, neg(f, a)) << name;
      ASSERT_EQ(x < y, lt(f, a, b).bits == 1) << name;
      ASSERT_EQ(x <= y, le(f, a, b).bits == 1) << name;
      ASSERT_EQ(x > y, lt(f, b, a).bits == 1) << name;
      ASSERT_EQ(x == y, eq(f, a, b).bits == 1) << name;
      ASSERT_EQ(fp_min(x, y).bits, min(f, a, b).bits) << name;
      ASSERT_EQ(fp_max(x, y).bits, max(f, a, b).bits) << name;
      ASSERT_EQ(fp_abs(x).bits, abs(f, a)) << name;
      // ... and each records the model's flags once in the thread's statistics.
      auto flags_of = [&](auto op) {
        reset_soft_stats();
        op();
        const SoftStats st = soft_stats();
        EXPECT_EQ(st.ops, 1u) << name;
        return st.flags;
      };
      ASSERT_EQ(flags_of([&] { (void)(x < y); }), lt(f, a, b).flags) << name;
      ASSERT_EQ(flags_of([&] { (void)(x <= y); }), le(f, a, b).flags) << name;
      ASSERT_EQ(flags_of([&] { (void)fp_min(x, y); }), min(f, a, b).flags) << name;
      ASSERT_EQ(flags_of([&] { (void)fp_max(x, y); }), max(f, a, b).flags) << name;
      for (Round r : {Round::RDN, Round::RUP, Round::RTZ}) {
        Format fr = f;
        fr.round = r;
        ASSERT_EQ(fp_sub_round(x, y, r).bits, sub(fr, a, b).bits) << name;
        ASSERT_EQ(fp_mul_round(x, y, r).bits, mul(fr, a, b).bits) << name;
      }
    }
  }
}

TEST(UnitsSoft, FlagCountsAndScope) {
  const Format f = F("e5m10");
  {
    SoftScope scope(f);
    const Soft big = Soft::from_double(60000.0);
    reset_soft_stats();
    Soft x = big * big;  // overflow + inexact
    EXPECT_EQ(x.bits, f.inf());
    Soft z = Soft::from_double(0.0);
    Soft n = z / z;  // invalid
    (void)n;
    Soft y = Soft::from_double(1.0) / z;  // divide by zero
    (void)y;
    const SoftStats& s = soft_stats();
    EXPECT_EQ(s.overflow, 1u);
    EXPECT_EQ(s.invalid, 1u);
    EXPECT_EQ(s.divzero, 1u);
    EXPECT_EQ(s.ops, 5u);  // mul, from_double(0), div, from_double(1), div
    EXPECT_TRUE(s.flags & kOverflow);
    EXPECT_EQ(soft_format(), f);
  }
  // The scope restored the default format.
  EXPECT_EQ(soft_format(), (Format{8, 23, true, Round::RNE}));
  EXPECT_THROW(SoftScope bad(Format{1, 3, true, Round::RNE}), FormatError);
}

// min/max of float/double follow the format's minNum/maxNum exactly (-0 < +0, NaN ignored).
TEST(UnitsSoft, NativeMinMaxMatchFormat) {
  const Format f32 = F("e8m23"), f64 = F("e11m52");
  for (uint64_t a : special_values(f32))
    for (uint64_t b : special_values(f32)) {
      const float x = fp_from_bits<float>(a), y = fp_from_bits<float>(b);
      const auto mn = min(f32, a, b), mx = max(f32, a, b);
      ASSERT_EQ(fp_bits(fp_min(x, y)), is_nan(f32, mn.bits) ? f32.qnan() : mn.bits);
      ASSERT_EQ(fp_bits(fp_max(x, y)), is_nan(f32, mx.bits) ? f32.qnan() : mx.bits);
    }
  for (uint64_t a : special_values(f64))
    for (uint64_t b : special_values(f64)) {
      const double x = fp_from_bits<double>(a), y = fp_from_bits<double>(b);
      const auto mn = min(f64, a, b), mx = max(f64, a, b);
      ASSERT_EQ(fp_bits(fp_min(x, y)), is_nan(f64, mn.bits) ? f64.qnan() : mn.bits);
      ASSERT_EQ(fp_bits(fp_max(x, y)), is_nan(f64, mx.bits) ? f64.qnan() : mx.bits);
    }
}

// The expression shape of cross/dot in float equals e8m23 bit for bit: no FP contraction.
// a*b - c*d with the products rounded separately differs from fma(a, b, -c*d) for most
// random inputs; the planted fused variant must be caught by the same comparison.
float two_products(float a, float b, float c, float d) { return a * b - c * d; }
float two_products_fused(float a, float b, float c, float d) { return std::fma(a, b, -(c * d)); }

TEST(UnitsSoft, FloatMatchesE8m23NoContraction) {
  SoftScope scope(F("e8m23"));
  ru::units::Rng rng(3);
  int native_mismatch = 0, fused_mismatch = 0;
  for (int i = 0; i < 20000; ++i) {
    float v[4];
    for (float& x : v) x = static_cast<float>(rng.uniform(-2, 2));
    const Soft s = Soft::from_double(v[0]) * Soft::from_double(v[1]) -
                   Soft::from_double(v[2]) * Soft::from_double(v[3]);
    native_mismatch += fp_bits(two_products(v[0], v[1], v[2], v[3])) != s.bits;
    fused_mismatch += fp_bits(two_products_fused(v[0], v[1], v[2], v[3])) != s.bits;
  }
  EXPECT_EQ(native_mismatch, 0);
  EXPECT_GT(fused_mismatch, 1000) << "the checker must see a fused multiply-add";
}

}  // namespace
