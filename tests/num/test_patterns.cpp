// The test-vector generators: special_values() holds what the TestFloat scheme asks for in
// every format; OperandGen is deterministic (pinned by golden hashes, so the sequence is the
// same on every host) and really produces the hard cases it promises (measured with the oracle).
#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "harness.hpp"

namespace ru::num::testing {
namespace {

TEST(SpecialValues, EveryFormatHasTheTestFloatSet) {
  for (int E = 2; E <= 11; ++E) {
    for (int M = 1; M <= 52; ++M) {
      const Format f = make_format(E, M);
      const std::vector<uint64_t> sv = special_values(f);
      const std::set<uint64_t> s(sv.begin(), sv.end());
      ASSERT_EQ(s.size(), sv.size()) << fmt_name(f) << ": duplicates";
      for (uint64_t x : sv) ASSERT_EQ(x & ~f.mask(), 0u) << fmt_name(f) << ": does not fit";
      const uint64_t sign = f.sign_bit(), fm = f.frac_mask();
      std::vector<uint64_t> must = {
          0,        f.min_subnormal(), fm,          f.min_normal(), f.max_finite(),      f.inf(),
          f.qnan(), f.one(),           f.one() + 1, f.one() - 1,    f.min_normal() | fm, f.min_normal() + 1};
      if (M >= 2) must.push_back(f.inf() | 1);  // signaling NaN
      if (M >= 2) must.push_back(fm - 1);       // subnormal all-ones - 1
      if (M >= 2) must.push_back(f.max_finite() - 1);
      for (uint64_t m : must) {
        EXPECT_TRUE(s.count(m)) << fmt_name(f) << " lacks " << describe(f, m);
        EXPECT_TRUE(s.count(m | sign)) << fmt_name(f) << " lacks " << describe(f, m | sign);
      }
      // Significands 0 / 1 / all-ones / all-ones-1 at the smallest and largest exponent and at 1.0.
      for (uint64_t e : {uint64_t{1}, f.exp_field_max() - 1, static_cast<uint64_t>(f.bias())})
        for (uint64_t fr : {uint64_t{0}, uint64_t{1}, fm, fm - 1})
          EXPECT_TRUE(s.count((e << M) | fr)) << fmt_name(f);
      // A signaling NaN exists only for M >= 2.
      size_t snans = 0;
      for (uint64_t x : sv) snans += classify(f, x) == Class::SNaN;
      if (M == 1)
        EXPECT_EQ(snans, 0u);
      else
        EXPECT_GE(snans, 2u);
      if (E + M <= 4) {
        EXPECT_EQ(sv.size(), size_t{1} << f.width()) << "tiny formats: every value";
      }
    }
  }
}

uint64_t fnv(uint64_t h, uint64_t x) {
  for (int i = 0; i < 8; ++i) h = (h ^ ((x >> (8 * i)) & 0xff)) * 0x100000001b3ull;
  return h;
}

uint64_t sequence_hash(const Format& f, uint64_t seed, int n) {
  OperandGen g(f, seed);
  uint64_t h = 0xcbf29ce484222325ull;
  for (int i = 0; i < n; ++i) {
    uint64_t a, b, c;
    h = fnv(h, g.next());
    g.pair(a, b);
    h = fnv(fnv(h, a), b);
    g.triple(a, b, c);
    h = fnv(fnv(fnv(h, a), b), c);
  }
  return h;
}

TEST(OperandGen, DeterministicAndHostIndependent) {
  const Format h = make_format(5, 10);
  EXPECT_EQ(sequence_hash(h, 42, 1000), sequence_hash(h, 42, 1000));
  EXPECT_NE(sequence_hash(h, 42, 1000), sequence_hash(h, 43, 1000));
  // Rounding mode and subnormal setting do not change the sequence.
  EXPECT_EQ(sequence_hash(h, 42, 1000), sequence_hash(make_format(5, 10, false, Round::RUP), 42, 1000));
  // Golden values: the sequence must be identical on every host and compiler. If you change
  // the generator on purpose, print the new values and update them here.
  EXPECT_EQ(sequence_hash(h, 42, 1000), 0xb155a3f255eb25efull) << std::hex << sequence_hash(h, 42, 1000);
  EXPECT_EQ(sequence_hash(make_format(11, 52), 7, 1000), 0xb5d4be21687a560full)
      << std::hex << sequence_hash(make_format(11, 52), 7, 1000);
  EXPECT_EQ(sequence_hash(make_format(2, 1), 1, 1000), 0xa19051dfbab55eedull)
      << std::hex << sequence_hash(make_format(2, 1), 1, 1000);
}

TEST(OperandGen, OutputsFitEveryFormat) {
  for (int E = 2; E <= 11; ++E) {
    for (int M = 1; M <= 52; ++M) {
      const Format f = make_format(E, M);
      OperandGen g(f, static_cast<uint64_t>(E * 100 + M));
      for (int i = 0; i < 300; ++i) {
        uint64_t a, b, c;
        ASSERT_EQ(g.next() & ~f.mask(), 0u) << fmt_name(f);
        g.pair(a, b);
        ASSERT_EQ((a | b) & ~f.mask(), 0u) << fmt_name(f);
        g.triple(a, b, c);
        ASSERT_EQ((a | b | c) & ~f.mask(), 0u) << fmt_name(f);
      }
    }
  }
}

// Is op(a, b, c) exactly halfway between two neighbours of f? (exact at M+2 bits, inexact in
// f without underflow/overflow; finite operands)
bool is_tie(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) {
  const double x = mpfr_to_double(f, a), y = mpfr_to_double(f, b), z = mpfr_to_double(f, c);
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return false;
  const Result rf = mpfr_apply(f, op, a, b, c);
  if (!(rf.flags & kInexact) || (rf.flags & (kUnderflow | kOverflow))) return false;
  mpfr_t X, Y, Z, R;
  mpfr_inits2(f.frac_bits + 2, X, Y, Z, R, static_cast<mpfr_ptr>(nullptr));
  mpfr_set_d(X, x, MPFR_RNDN);
  mpfr_set_d(Y, y, MPFR_RNDN);
  mpfr_set_d(Z, z, MPFR_RNDN);
  int t = 1;
  switch (op) {
    case Op::Add:
      t = mpfr_add(R, X, Y, MPFR_RNDN);
      break;
    case Op::Mul:
      t = mpfr_mul(R, X, Y, MPFR_RNDN);
      break;
    case Op::Div:
      t = mpfr_div(R, X, Y, MPFR_RNDN);
      break;
    case Op::Sqrt:
      t = mpfr_sqrt(R, X, MPFR_RNDN);
      break;
    case Op::Fma:
      t = mpfr_fma(R, X, Y, Z, MPFR_RNDN);
      break;
    default:
      break;
  }
  mpfr_clears(X, Y, Z, R, static_cast<mpfr_ptr>(nullptr));
  return t == 0;
}

struct Coverage {
  int n = 0, special = 0, subnormal = 0, overflow = 0, underflow = 0, tie = 0, exact = 0, cancel = 0;
  int up_to_min_normal = 0;  // tiny before rounding, the smallest normal after
  std::set<int64_t> expdiffs;
};

TEST(OperandGen, ProducesTheHardCases) {
  for (auto [E, M] : {std::pair{5, 10}, {8, 23}, {4, 3}, {11, 52}, {3, 7}}) {
    const Format f = make_format(E, M);
    const std::vector<uint64_t> sv = special_values(f);
    const std::set<uint64_t> specials(sv.begin(), sv.end());
    OperandGen g(f, 99);
    auto exp_of = [&](uint64_t x) { return static_cast<int64_t>((x >> M) & f.exp_field_max()); };
    auto finite_nonzero = [&](uint64_t x) {
      return exp_of(x) != static_cast<int64_t>(f.exp_field_max()) && (x & ~f.sign_bit()) != 0;
    };
    Format z = f;
    z.round = Round::RTZ;
    for (Op op : {Op::Add, Op::Mul, Op::Div, Op::Fma, Op::Sqrt}) {
      Coverage cv;
      const int N = 20000;
      for (int i = 0; i < N; ++i) {
        uint64_t a = 0, b = 0, c = 0;
        if (op == Op::Sqrt)
          a = g.next();
        else if (op == Op::Fma)
          g.triple(a, b, c);
        else
          g.pair(a, b);
        ++cv.n;
        cv.special += specials.count(a) > 0;
        cv.subnormal += exp_of(a) == 0 && (a & f.frac_mask()) != 0;
        const Result r = mpfr_apply(f, op, a, b, c);
        cv.overflow += (r.flags & kOverflow) != 0;
        cv.underflow += (r.flags & kUnderflow) != 0;
        cv.exact += r.flags == 0 && finite_nonzero(r.bits);
        if (i % 4 == 0) cv.tie += is_tie(f, op, a, b, c);
        if ((r.bits & ~f.sign_bit()) == f.min_normal() && (r.flags & kInexact) &&
            (mpfr_apply(z, op, a, b, c).bits & ~f.sign_bit()) < f.min_normal())
          ++cv.up_to_min_normal;
        if (op == Op::Add && finite_nonzero(a) && finite_nonzero(b)) {
          cv.expdiffs.insert(std::abs(exp_of(a) - exp_of(b)));
          // cancellation: |a + b| < |a| * 2^-(M/2)
          const double va = mpfr_to_double(f, a), vr = mpfr_to_double(f, r.bits);
          if (std::isfinite(vr) && std::fabs(vr) < std::fabs(va) * std::ldexp(1.0, -(M / 2 + 1))) ++cv.cancel;
        }
        if (op == Op::Fma && finite_nonzero(c) && finite_nonzero(a) && finite_nonzero(b)) {
          const double vc = mpfr_to_double(f, c), vr = mpfr_to_double(f, r.bits);
          if (std::isfinite(vr) && std::fabs(vr) < std::fabs(vc) * std::ldexp(1.0, -(M / 2 + 1))) ++cv.cancel;
        }
      }
      const std::string where = fmt_name(f) + " " + op_str(op);
      auto pct = [&](int k) { return 100.0 * k / cv.n; };
      EXPECT_GT(pct(cv.special), 3) << where;
      EXPECT_GT(pct(cv.subnormal), 1) << where;
      if (op == Op::Mul || op == Op::Fma) {
        EXPECT_GT(pct(cv.overflow), 1) << where;
        EXPECT_GT(pct(cv.underflow), 1) << where;
        EXPECT_GT(cv.up_to_min_normal, 2) << where << ": no results rounding up to the smallest normal";
      }
      if (op == Op::Div) {
        EXPECT_GT(pct(cv.overflow), 0.5) << where;
        EXPECT_GT(pct(cv.underflow), 0.5) << where;
      }
      if (op == Op::Add || op == Op::Mul || op == Op::Fma) {
        EXPECT_GT(4 * pct(cv.tie), 1) << where << ": exact ties";
      }
      if (op != Op::Add) {
        EXPECT_GT(pct(cv.exact), 1) << where << ": exact results";
      }
      if (op == Op::Add || op == Op::Fma) {
        EXPECT_GT(pct(cv.cancel), 2) << where << ": cancellation";
      }
      if (op == Op::Add) {
        const int64_t widest = static_cast<int64_t>(f.exp_field_max()) - 2;  // between normals
        for (int64_t d : {int64_t{0}, int64_t{1}, int64_t{M}, int64_t{M + 1}, int64_t{M + 2}})
          if (d <= widest) {
            EXPECT_TRUE(cv.expdiffs.count(d)) << where << ": exponent difference " << d;
          }
        if (M + 4 <= widest) {
          EXPECT_TRUE(std::any_of(cv.expdiffs.begin(), cv.expdiffs.end(), [&](int64_t d) {
            return d > M + 3;
          })) << where;
        }
      }
    }
  }
}

}  // namespace
}  // namespace ru::num::testing
