// Format-to-format conversion (num::convert) and integer conversion to a given width
// (num::to_int(f, a, r, int_w)) against the MPFR oracle (issue 16 §1, the golden model of the
// conversion unit).
//
// Oracle for convert: the operand's exact value from MPFR (mpfr_to_double is exact for every
// format up to e11m52; an FTZ source reads subnormals as zero) rounded once into the target by
// MPFR (mpfr_from_double); NaN-ness and the signaling bit are decoded here. Oracle for the
// width: mpfr_to_int and the saturation rule written out here.
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "harness.hpp"
#include "rayunits/num/mpfr_ref.hpp"
#include "rayunits/num/patterns.hpp"

namespace ru::num::testing {
namespace {

using ConvFn = std::function<Result(const Format& to, const Format& from, uint64_t a)>;

Result oracle_convert(const Format& to, const Format& from, uint64_t a) {
  const uint64_t e = (a >> from.frac_bits) & from.exp_field_max(), fr = a & from.frac_mask();
  if (e == from.exp_field_max() && fr != 0) {
    const bool quiet = from.frac_bits == 1 || ((fr >> (from.frac_bits - 1)) & 1) != 0;
    Result r = mpfr_from_double(to, std::nan(""));
    r.flags = quiet ? 0 : kInvalid;
    return r;
  }
  return mpfr_from_double(to, mpfr_to_double(from, a));
}

std::vector<Format> variants(int E, int M) {
  std::vector<Format> v;
  for (bool sub : {true, false})
    for (Round r : {Round::RNE, Round::RTZ, Round::RDN, Round::RUP}) v.push_back(make_format(E, M, sub, r));
  return v;
}

// Compares `fn` with the oracle on xs for every target variant (subnormals/FTZ, four roundings).
void compare(Checker& chk, const Format& from, int toE, int toM, const std::vector<uint64_t>& xs, const ConvFn& fn) {
  for (const Format& to : variants(toE, toM)) {
    for (uint64_t a : xs) {
      a &= from.mask();
      const Result exp = oracle_convert(to, from, a), act = fn(to, from, a);
      chk.count();
      if (exp.bits != act.bits || exp.flags != act.flags) {
        chk.fail(fmt_name(from) + " -> " + fmt_name(to) + " " + rnd_name(to.round) + " convert(" +
                 describe(from, a) + "): expected " + describe(to, exp.bits) + " flags " + flag_str(exp.flags) +
                 ", actual " + describe(to, act.bits) + " flags " + flag_str(act.flags));
        if (chk.done()) return;
      }
    }
  }
}

std::vector<uint64_t> all_patterns(const Format& f) {
  std::vector<uint64_t> v;
  for (uint64_t a = 0; a <= f.mask(); ++a) v.push_back(a);
  return v;
}

std::vector<uint64_t> random_and_special(const Format& f, int n, uint64_t seed) {
  std::vector<uint64_t> v = special_values(f);
  OperandGen g(f, seed);
  for (int i = 0; i < n; ++i) v.push_back(g.next());
  return v;
}

const ConvFn kModel = [](const Format& to, const Format& from, uint64_t a) { return convert(to, from, a); };

// Every pattern of every format of at most 8 bits into every other one and into e5m10 / e8m23,
// every target rounding mode, subnormals and FTZ on both sides.
TEST(Convert, ExhaustiveSmallFormatsMatchMpfr) {
  const std::vector<std::pair<int, int>> small = {{2, 1}, {2, 3}, {3, 2}, {4, 3}, {5, 2}, {3, 4}, {2, 5}};
  std::vector<std::pair<int, int>> targets = small;
  targets.push_back({5, 10});
  targets.push_back({8, 23});
  Checker chk("convert vs MPFR, exhaustive small formats");
  for (const auto& [E, M] : small)
    for (bool sub : {true, false}) {
      const Format from = make_format(E, M, sub);
      const std::vector<uint64_t> xs = all_patterns(from);
      for (const auto& [tE, tM] : targets) compare(chk, from, tE, tM, xs, kModel);
    }
  EXPECT_GT(chk.checks(), 100000u);
  EXPECT_TRUE(chk.ok()) << chk.report();
}

// The pairs the issue names and the ones the renderer and TRaX storage would use, random and
// TestFloat-style special operands.
TEST(Convert, WideFormatPairsMatchMpfr) {
  const std::vector<std::pair<std::pair<int, int>, std::pair<int, int>>> pairs = {
      {{8, 23}, {7, 16}}, {{7, 16}, {8, 23}}, {{5, 10}, {8, 23}},  {{8, 23}, {5, 10}},
      {{11, 52}, {8, 23}}, {{8, 23}, {11, 52}}, {{11, 52}, {5, 10}}, {{6, 12}, {5, 10}}};
  Checker chk("convert vs MPFR, wide pairs");
  uint64_t seed = 1;
  for (const auto& [src, dst] : pairs)
    for (bool sub : {true, false}) {
      const Format from = make_format(src.first, src.second, sub);
      compare(chk, from, dst.first, dst.second, random_and_special(from, static_cast<int>(scaled(4000)), seed++),
              kModel);
    }
  EXPECT_TRUE(chk.ok()) << chk.report();
}

// Widening is exact, and narrowing the widened value gives the operand back.
TEST(Convert, WideningIsExactAndRoundTrips) {
  for (const auto& [n, w] : std::vector<std::pair<Format, Format>>{
           {make_format(5, 10), make_format(8, 23)}, {make_format(7, 16), make_format(8, 23)},
           {make_format(8, 23), make_format(11, 52)}, {make_format(3, 2), make_format(5, 10)}}) {
    for (uint64_t a : random_and_special(n, 5000, 7)) {
      a &= n.mask();
      const Result up = convert(w, n, a);
      if (bits_are_nan(n, a)) {
        EXPECT_TRUE(bits_are_nan(w, up.bits));
        continue;
      }
      EXPECT_EQ(up.flags, 0) << fmt_name(n) << " -> " << fmt_name(w) << " " << describe(n, a);
      const Result back = convert(n, w, up.bits);
      EXPECT_EQ(back.bits, a) << describe(n, a);
      EXPECT_EQ(back.flags, 0) << describe(n, a);
    }
  }
}

// The checker catches a converter that truncates (rounds toward zero whatever the mode) and one
// that forgets the signaling-NaN flag.
TEST(Convert, PlantedErrorsAreCaught) {
  const Format from = make_format(8, 23);
  const std::vector<uint64_t> xs = random_and_special(from, 2000, 3);
  const ConvFn truncating = [](const Format& to, const Format& f, uint64_t a) {
    Format t = to;
    t.round = Round::RTZ;
    return convert(t, f, a);
  };
  const ConvFn quiet_snan = [](const Format& to, const Format& f, uint64_t a) {
    Result r = convert(to, f, a);
    r.flags &= static_cast<uint8_t>(~kInvalid);
    return r;
  };
  for (const ConvFn& bad : {truncating, quiet_snan}) {
    Checker chk("planted");
    compare(chk, from, 5, 10, xs, bad);
    EXPECT_FALSE(chk.ok());
  }
}

// to_int with a width: the oracle's 64-bit result saturated to the width here.
IntResult oracle_to_int_w(const Format& f, uint64_t a, Round r, int w) {
  const IntResult x = mpfr_to_int(f, a, r);
  if (w == 64) return x;
  const int64_t hi = (int64_t{1} << (w - 1)) - 1, lo = -(int64_t{1} << (w - 1));
  if ((x.flags & kInvalid) != 0) return {x.value < 0 ? lo : hi, kInvalid};
  if (x.value > hi) return {hi, kInvalid};
  if (x.value < lo) return {lo, kInvalid};
  return x;
}

TEST(Convert, ToIntOfAWidthMatchesMpfr) {
  Checker chk("to_int(w) vs MPFR");
  for (const auto& [E, M] : std::vector<std::pair<int, int>>{{5, 10}, {8, 23}, {11, 52}, {7, 16}, {4, 3}})
    for (bool sub : {true, false}) {
      const Format f = make_format(E, M, sub);
      std::vector<uint64_t> xs = random_and_special(f, static_cast<int>(scaled(3000)), 11);
      for (int w : {8, 16, 32, 64}) {
        const double edge = std::ldexp(1.0, w - 1);  // +-2^(w-1) and its neighbours, halfway points
        for (double v : {edge, -edge, edge - 1, -edge - 1, edge - 0.5, -edge - 0.5, edge + 0.5})
          for (Round r : {Round::RNE, Round::RUP}) {
            Format g = f;
            g.round = r;
            const uint64_t x = from_double(g, v).bits;
            for (int d = -2; d <= 2; ++d) xs.push_back((x & f.sign_bit()) | ((x & ~f.sign_bit()) + d));
          }
        for (uint64_t a : xs) {
          a &= f.mask();
          for (Round r : {Round::RNE, Round::RTZ, Round::RDN, Round::RUP}) {
            const IntResult exp = oracle_to_int_w(f, a, r, w), act = to_int(f, a, r, w);
            chk.count();
            if (exp.value != act.value || exp.flags != act.flags)
              chk.fail(fmt_name(f) + " to_int(" + describe(f, a) + ", " + rnd_name(r) + ", " + std::to_string(w) +
                       "): expected " + std::to_string(exp.value) + " flags " + flag_str(exp.flags) + ", actual " +
                       std::to_string(act.value) + " flags " + flag_str(act.flags));
          }
          if (chk.done()) break;
        }
      }
    }
  EXPECT_TRUE(chk.ok()) << chk.report();
  const Format d = make_format(11, 52);
  EXPECT_EQ(to_int(d, from_double(d, 2147483648.0).bits, Round::RNE, 32).value, INT32_MAX);
  EXPECT_EQ(to_int(d, from_double(d, 2147483648.0).bits, Round::RNE, 32).flags, kInvalid);
  EXPECT_EQ(to_int(d, from_double(d, -2147483648.0).bits, Round::RNE, 32).flags, 0);
  EXPECT_EQ(to_int(d, from_double(d, 2147483647.5).bits, Round::RTZ, 32).value, INT32_MAX);
  EXPECT_EQ(to_int(d, from_double(d, 2147483647.5).bits, Round::RTZ, 32).flags, kInexact);
  EXPECT_EQ(to_int(d, from_double(d, 2147483647.5).bits, Round::RNE, 32).flags, kInvalid);
  EXPECT_EQ(to_int(d, d.qnan(), Round::RNE, 32).value, INT32_MAX);
  EXPECT_THROW(to_int(d, 0, Round::RNE, 0), std::invalid_argument);
}

}  // namespace
}  // namespace ru::num::testing
