// The inline add/sub fast paths (detail/fast_paths.hpp: a 64-bit path for M <= 29, the general
// fast path up to M = 44) against the general integer-significand code (detail::add_general,
// itself verified against MPFR and native hardware): every valid format E x M, all four
// rounding modes, with and without subnormals, on pairs biased towards close exponents (the
// alignment, cancellation and sticky-bit cases). Bits and flags must agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>

#include "rayunits/num/format.hpp"
#include "rayunits/units/synthetic.hpp"  // Rng (splitmix64)

namespace ru::num {
namespace {

using ru::units::Rng;

// b: uniformly random, or with an exponent within 2 or M+7 of a's, or a's fraction with the
// last three bits changed (massive cancellation).
uint64_t partner(const Format& f, uint64_t a, Rng& s) {
  const int kind = static_cast<int>(s.next() % 4);
  if (kind == 0) return s.next() & f.mask();
  const int64_t ea = static_cast<int64_t>((a >> f.frac_bits) & f.exp_field_max());
  const int64_t span = kind == 1 ? 3 : f.frac_bits + 8;
  int64_t eb = ea + static_cast<int64_t>(s.next() % static_cast<uint64_t>(span)) * ((s.next() & 1) ? 1 : -1);
  eb = std::max<int64_t>(0, std::min<int64_t>(eb, static_cast<int64_t>(f.exp_field_max())));
  const uint64_t frac = kind == 3 ? ((a & f.frac_mask()) ^ (s.next() & 7)) : (s.next() & f.frac_mask());
  return ((s.next() & 1) ? f.sign_bit() : 0) | (static_cast<uint64_t>(eb) << f.frac_bits) | frac;
}

struct Counts {
  uint64_t pairs = 0, fast = 0, differ = 0;
  std::string first;
};

// add/sub (with their fast paths) in format f against add_general/sub_general in format g.
Counts compare(const Format& f, const Format& g, uint64_t n, uint64_t seed) {
  Counts c;
  Rng s(seed);
  for (uint64_t i = 0; i < n; ++i) {
    const uint64_t a = s.next() & f.mask(), b = partner(f, a, s);
    const Result x = add(f, a, b), y = detail::add_general(g, a, b);
    const Result u = sub(f, a, b), v = detail::sub_general(g, a, b);
    Result t;
    c.fast += detail::dispatch_fast<detail::AddFastOp>(f, a, b, t);
    ++c.pairs;
    if (x.bits != y.bits || x.flags != y.flags || u.bits != v.bits || u.flags != v.flags) {
      if (c.differ++ == 0)
        c.first = f.name() + " round " + std::to_string(static_cast<int>(f.round)) + " a=" + std::to_string(a) +
                  " b=" + std::to_string(b);
    }
  }
  return c;
}

TEST(FastPaths, AddSubEqualGeneralCodeInEveryFormat) {
  uint64_t pairs = 0, fast = 0;
  for (int e = Format::kMinExp; e <= Format::kMaxExp; ++e)
    for (int m = Format::kMinFrac; m <= Format::kMaxFrac; ++m) {
      if (1 + e + m > 64) continue;
      for (int r = 0; r < 4; ++r)
        for (bool sub : {true, false}) {
          Format f;
          f.exp_bits = e;
          f.frac_bits = m;
          f.subnormals = sub;
          f.round = static_cast<Round>(r);
          const Counts c = compare(f, f, 300, (static_cast<uint64_t>(e) << 40) ^ (static_cast<uint64_t>(m) << 8) ^
                                                  (static_cast<uint64_t>(r) << 1) ^ (sub ? 1 : 0));
          ASSERT_EQ(c.differ, 0u) << "first difference: " << c.first;
          pairs += c.pairs;
          fast += c.fast;
        }
    }
  // The fast paths were exercised, not skipped.
  EXPECT_GT(fast, pairs / 2) << fast << " of " << pairs << " pairs took a fast path";
}

TEST(FastPaths, ComparisonCatchesAPlantedRoundingDifference) {
  Format f = Format::parse("e8m23"), g = f;
  g.round = Round::RTZ;
  EXPECT_GT(compare(f, g, 2000, 5).differ, 0u);
  Format h = Format::parse("e5m10"), k = h;
  k.subnormals = false;
  EXPECT_GT(compare(h, k, 20000, 6).differ, 0u);
}

}  // namespace
}  // namespace ru::num
