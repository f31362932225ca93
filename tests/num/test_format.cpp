// Format names (parse/print/validate and the error messages), option parsing, conversions
// (from/to double, from/to int64 in every rounding mode), classify, min/max/compare semantics
// (-0/+0, NaN, sNaN, FTZ flushing), abs/neg, apply() dispatch, dot3 and parse_operand.
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "harness.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::num::testing {
namespace {

constexpr uint8_t X = kInexact, U = kUnderflow, I = kInvalid;

// ---- names ----------------------------------------------------------------------------------

TEST(FormatName, EveryValidFormatRoundTrips) {
  int count = 0;
  for (int E = 2; E <= 11; ++E) {
    for (int M = 1; M <= 52 && 1 + E + M <= 64; ++M) {
      for (bool sub : {true, false}) {
        const std::string name = "e" + std::to_string(E) + "m" + std::to_string(M) + (sub ? "" : "-ftz");
        Format f;
        ASSERT_NO_THROW(f = Format::parse(name)) << name;
        EXPECT_EQ(f.exp_bits, E) << name;
        EXPECT_EQ(f.frac_bits, M) << name;
        EXPECT_EQ(f.subnormals, sub) << name;
        EXPECT_EQ(f.round, Round::RNE) << name;
        EXPECT_EQ(f.name(), name);
        EXPECT_EQ(fmt_name(f), name);
        EXPECT_NO_THROW(f.validate());
        ++count;
      }
    }
  }
  EXPECT_EQ(count, 2 * 10 * 52);  // E in [2,11] x M in [1,52] all fit in 64 bits
}

TEST(FormatName, DerivedParameters) {
  const Format h = Format::parse("e5m10");
  EXPECT_EQ(h.width(), 16);
  EXPECT_EQ(h.bias(), 15);
  EXPECT_EQ(h.emin(), -14);
  EXPECT_EQ(h.emax(), 15);
  EXPECT_EQ(h.inf(), 0x7c00u);
  EXPECT_EQ(h.inf(true), 0xfc00u);
  EXPECT_EQ(h.qnan(), 0x7e00u);
  EXPECT_EQ(h.max_finite(), 0x7bffu);
  EXPECT_EQ(h.min_normal(), 0x0400u);
  EXPECT_EQ(h.min_subnormal(true), 0x8001u);
  EXPECT_EQ(h.one(), 0x3c00u);
  EXPECT_EQ(h.mask(), 0xffffu);
  const Format d = Format::parse("e11m52");
  EXPECT_EQ(d.width(), 64);
  EXPECT_EQ(d.mask(), ~0ull);
  EXPECT_EQ(d.one(), 0x3ff0000000000000ull);
  EXPECT_EQ(d.qnan(), 0x7ff8000000000000ull);
  const Format t = Format::parse("e2m1");
  EXPECT_EQ(t.bias(), 1);
  EXPECT_EQ(t.one(), 0x2u);
  EXPECT_EQ(t.qnan(), 0x7u);
  EXPECT_EQ(t.max_finite(), 0x5u);
}

void expect_format_error(const std::string& name) {
  try {
    Format::parse(name);
    ADD_FAILURE() << "'" << name << "' was accepted";
  } catch (const FormatError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
    // The message names the accepted ranges.
    for (const char* s : {"2", "11", "52", "64"}) EXPECT_NE(msg.find(s), std::string::npos) << msg;
    EXPECT_NE(msg.find("ftz"), std::string::npos) << msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "'" << name << "' threw something other than FormatError: " << e.what();
  }
}

TEST(FormatName, BadNamesAreRejectedWithTheAcceptedRanges) {
  for (const char* bad : {"",
                          "e",
                          "e8",
                          "e8m",
                          "m23",
                          "8m23",
                          "x8m23",
                          "e1m10",
                          "e0m5",
                          "e12m10",
                          "e8m0",
                          "e8m53",
                          "e11m53",
                          "e10m54",
                          "e8m23-",
                          "e8m23-ft",
                          "e8m23ftz",
                          "e8m23-ftzz",
                          "e8m23 ",
                          " e8m23",
                          "e-3m4",
                          "e3m-4",
                          "e8.5m23",
                          "e99999999999999999999m1",
                          "e8m23-ftz-ftz",
                          "e8m23-rne",
                          "fp32",
                          "e8x23"}) {
    expect_format_error(bad);
  }
}

TEST(FormatName, ValidateRejectsOutOfRangeParameters) {
  for (auto [E, M] : {std::pair{1, 10}, {12, 10}, {5, 0}, {5, 53}, {11, 53}, {0, 0}, {-1, 5}, {8, -3}}) {
    Format f = make_format(E, M);
    EXPECT_THROW(f.validate(), FormatError) << E << " " << M;
    try {
      f.validate();
    } catch (const FormatError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("11"), std::string::npos) << msg;
      EXPECT_NE(msg.find("52"), std::string::npos) << msg;
    }
  }
  EXPECT_NO_THROW(make_format(11, 52).validate());
  EXPECT_NO_THROW(make_format(2, 1).validate());
  EXPECT_NO_THROW(make_format(2, 52).validate());
}

TEST(FormatName, RoundingModesOpsAndFlags) {
  for (Round r : kRounds) {
    EXPECT_STREQ(round_name(r), rnd_name(r));
    EXPECT_EQ(parse_round(rnd_name(r)), r);
  }
  for (const char* bad : {"", "RNE", "nearest", "rn", "rne "}) {
    try {
      parse_round(bad);
      ADD_FAILURE() << "accepted rounding '" << bad << "'";
    } catch (const FormatError& e) {
      const std::string msg = e.what();
      for (const char* s : {"rne", "rtz", "rdn", "rup"}) EXPECT_NE(msg.find(s), std::string::npos) << msg;
    }
  }
  for (Op op : kAllOps) {
    EXPECT_STREQ(op_name(op), op_str(op));
    EXPECT_EQ(parse_op(op_str(op)), op);
    EXPECT_EQ(op_arity(op), arity(op)) << op_str(op);
  }
  for (const char* bad : {"", "ADD", "fms", "unordered", "abs", "add "}) {
    try {
      parse_op(bad);
      ADD_FAILURE() << "accepted op '" << bad << "'";
    } catch (const FormatError& e) {
      const std::string msg = e.what();
      for (const char* s : {"add", "sqrt", "fma", "eq"}) EXPECT_NE(msg.find(s), std::string::npos) << msg;
    }
  }
  for (unsigned fl = 0; fl < 32; ++fl)
    EXPECT_EQ(flags_letters(static_cast<uint8_t>(fl)), flag_str(static_cast<uint8_t>(fl)));
  EXPECT_EQ(flags_letters(0), "-");
  EXPECT_EQ(flags_letters(kInvalid | kInexact), "ix");
}

// ---- conversions ---------------------------------------------------------------------------

uint64_t mix(uint64_t& s) { return ru::util::splitmix64(s); }

double bits_double(uint64_t u) {
  double d;
  std::memcpy(&d, &u, 8);
  return d;
}

bool same_double(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  uint64_t x, y;
  std::memcpy(&x, &a, 8);
  std::memcpy(&y, &b, 8);
  return x == y;
}

// Doubles that stress a format's rounding: random bit patterns, values over and around the
// format's range, format values +- tiny offsets and exact midpoints, specials.
std::vector<double> doubles_for(const Format& f, uint64_t seed, int count) {
  std::vector<double> out = {0.0,
                             -0.0,
                             HUGE_VAL,
                             -HUGE_VAL,
                             std::nan(""),
                             -std::nan(""),
                             bits_double(0x7ff0000000000001ull),
                             bits_double(0xfff4000000000000ull),
                             0x1p-1074,
                             -0x1p-1074,
                             0x1p-1022,
                             DBL_MAX,
                             -DBL_MAX,
                             1.0,
                             -1.0,
                             0.5,
                             3.0};
  OperandGen gen(f, seed);
  uint64_t s = seed;
  for (int i = 0; i < count; ++i) {
    switch (i % 5) {
      case 0:
        out.push_back(bits_double(mix(s)));
        break;
      case 1: {  // random value over the format's exponent range +- a few binades
        const int lo = f.emin() - f.frac_bits - 4, hi = f.emax() + 3;
        const int e = lo + static_cast<int>(mix(s) % static_cast<uint64_t>(hi - lo + 1));
        const double m = 1.0 + static_cast<double>(mix(s) >> 12) * 0x1p-52;
        out.push_back(((mix(s) & 1) ? -1 : 1) * std::ldexp(m, std::max(e, -1074)));
        break;
      }
      default: {  // a format value moved by 1/2 ulp (a tie), or by +-2^-k ulp
        const uint64_t x = gen.next();
        const double v = mpfr_to_double(make_format(f.exp_bits, f.frac_bits, true), x);
        if (!std::isfinite(v)) {
          out.push_back(v);
          break;
        }
        const int ue = v == 0 ? f.emin() : std::max(std::ilogb(v), f.emin());
        const double ulp = std::ldexp(1.0, ue - f.frac_bits);
        const int k = 1 + static_cast<int>(mix(s) % 4);  // 1: exactly half, else off the tie
        const double off = std::ldexp(ulp, -k) * ((mix(s) & 1) ? 1 : -1);
        const double w = v + off;  // exact when M+k+1 <= 53 (else close enough)
        out.push_back(w);
        break;
      }
    }
  }
  return out;
}

class Conversions : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(Conversions, FromDoubleMatchesMpfr) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      Checker chk("from_double vs MPFR");
      for (double d : doubles_for(f, 11 * E + M, static_cast<int>(scaled(3000)))) {
        const Result exp = mpfr_from_double(f, d), act = from_double(f, d);
        chk.count();
        if (exp.bits != act.bits || exp.flags != act.flags) {
          char buf[400];
          std::snprintf(
              buf, sizeof buf, "%s %s from_double(%a = %.17g): expected %s flags %s, actual %s flags %s",
              fmt_name(f).c_str(), rnd_name(r), d, d, describe(f, exp.bits).c_str(),
              flag_str(exp.flags).c_str(), describe(f, act.bits).c_str(), flag_str(act.flags).c_str());
          chk.fail(buf);
          if (chk.done()) break;
        }
      }
      EXPECT_TRUE(chk.ok()) << chk.report();
    }
  }
}

TEST_P(Conversions, ToDoubleIsExactAndRoundTrips) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    const Format f = make_format(E, M, sub);
    OperandGen gen(f, 5);
    Checker chk("to_double");
    std::vector<uint64_t> xs = special_values(f);
    for (int i = 0; i < static_cast<int>(scaled(5000)); ++i) xs.push_back(gen.next());
    for (uint64_t x : xs) {
      chk.count();
      const double d = to_double(f, x);
      const double want = mpfr_to_double(f, x);
      if (!same_double(d, want)) {
        char buf[300];
        std::snprintf(buf, sizeof buf, "%s to_double(%s) = %a, expected %a", fmt_name(f).c_str(),
                      describe(f, x).c_str(), d, want);
        chk.fail(buf);
        continue;
      }
      if (std::isnan(d)) continue;
      // Round trip: exact, no flags (a flushed subnormal comes back as the signed zero).
      for (Round r : kRounds) {
        Format g = f;
        g.round = r;
        const Result back = from_double(g, d);
        const bool sub_in = ((x >> M) & ((1ull << E) - 1)) == 0;
        const uint64_t want_bits = (!sub && sub_in) ? (x & f.sign_bit()) : x;
        if (back.bits != want_bits || back.flags != 0) {
          chk.fail(fmt_name(g) + " " + rnd_name(r) + " from_double(to_double(" + describe(f, x) +
                   ")) = " + describe(f, back.bits) + " flags " + flag_str(back.flags));
        }
      }
      if (chk.done()) break;
    }
    EXPECT_TRUE(chk.ok()) << chk.report();
  }
}

std::vector<int64_t> ints_for(const Format& f, uint64_t seed, int count) {
  std::vector<int64_t> out = {0, 1, -1, 2, 3, 7, INT64_MAX, INT64_MIN, INT64_MIN + 1, INT64_MAX - 1};
  uint64_t s = seed;
  for (int i = 0; i < count; ++i) {
    const uint64_t u = mix(s);
    switch (i % 4) {
      case 0:
        out.push_back(static_cast<int64_t>(u));
        break;
      case 1:
        out.push_back(static_cast<int64_t>(u) >> (u % 63));
        break;   // every magnitude
      case 2: {  // around 2^k: (2^k +- small) including ties at M+1 bits
        const int k = static_cast<int>(u % 63);
        const int64_t base = int64_t{1} << k;
        const int64_t d = static_cast<int64_t>(mix(s) % 5) - 2;
        const int64_t tie = k > f.frac_bits ? (int64_t{1} << (k - f.frac_bits - 1)) : 0;
        out.push_back((u & 64 ? -1 : 1) * (base + tie + d));
        break;
      }
      default: {  // odd with M+2 bits (a tie at M+1 bits) shifted left
        const int bits = std::min(f.frac_bits + 2, 62);
        const uint64_t v = (mix(s) & ((1ull << (bits - 1)) - 1)) | (1ull << (bits - 1)) | 1;
        const int room = 62 - bits;
        const int j = room > 0 ? static_cast<int>(mix(s) % static_cast<uint64_t>(room + 1)) : 0;
        const int64_t x = static_cast<int64_t>(v << j);
        out.push_back(u & 1 ? -x : x);
        break;
      }
    }
  }
  return out;
}

TEST_P(Conversions, FromIntMatchesMpfr) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      Checker chk("from_int vs MPFR");
      for (int64_t v : ints_for(f, 3 * E + M, static_cast<int>(scaled(3000)))) {
        const Result exp = mpfr_from_int(f, v), act = from_int(f, v);
        chk.count();
        if (exp.bits != act.bits || exp.flags != act.flags) {
          chk.fail(fmt_name(f) + " " + rnd_name(r) + " from_int(" + std::to_string(v) + "): expected " +
                   describe(f, exp.bits) + " flags " + flag_str(exp.flags) + ", actual " +
                   describe(f, act.bits) + " flags " + flag_str(act.flags));
          if (chk.done()) break;
        }
      }
      EXPECT_TRUE(chk.ok()) << chk.report();
    }
  }
}

TEST_P(Conversions, ToIntMatchesMpfr) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    const Format f = make_format(E, M, sub);
    OperandGen gen(f, 9);
    std::vector<uint64_t> xs = special_values(f);
    for (int i = 0; i < static_cast<int>(scaled(3000)); ++i) xs.push_back(gen.next());
    // Values around +-2^63 and halfway points (k + 1/2) when representable.
    for (int64_t v : {int64_t{1} << 62, INT64_MIN, int64_t{5}, int64_t{-5}, int64_t{1} << 53})
      for (Round r : kRounds) {
        Format g = f;
        g.round = r;
        const uint64_t x = from_int(g, v).bits;
        for (int d = -2; d <= 2; ++d) xs.push_back((x & f.sign_bit()) | ((x & ~f.sign_bit()) + d));
      }
    for (int k = 0; k < 64; ++k) {
      const double h = std::ldexp(1.0, k) + 0.5;  // k + 1/2 for small k
      xs.push_back(from_double(f, h).bits);
      xs.push_back(from_double(f, -h).bits);
    }
    Checker chk("to_int vs MPFR");
    for (uint64_t x : xs) {
      x &= f.mask();
      for (Round r : kRounds) {
        const IntResult exp = mpfr_to_int(f, x, r), act = to_int(f, x, r);
        chk.count();
        if (exp.value != act.value || exp.flags != act.flags) {
          chk.fail(fmt_name(f) + " to_int(" + describe(f, x) + ", " + rnd_name(r) + "): expected " +
                   std::to_string(exp.value) + " flags " + flag_str(exp.flags) + ", actual " +
                   std::to_string(act.value) + " flags " + flag_str(act.flags));
        }
      }
      if (chk.done()) break;
    }
    EXPECT_TRUE(chk.ok()) << chk.report();
  }
}

INSTANTIATE_TEST_SUITE_P(Grid, Conversions, ::testing::ValuesIn(grid_formats()), em_param_name);

TEST(ConversionsHand, KnownValues) {
  const Format h = Format::parse("e5m10");
  EXPECT_EQ(from_double(h, 1.0).bits, 0x3c00u);
  EXPECT_EQ(from_double(h, -2.0).bits, 0xc000u);
  EXPECT_EQ(from_double(h, 65504.0).bits, 0x7bffu);
  EXPECT_EQ(from_double(h, 65520.0).bits, 0x7c00u);
  EXPECT_EQ(from_double(h, 65520.0).flags, kOverflow | X);
  EXPECT_EQ(from_double(h, 0x1p-24).bits, 0x0001u);
  EXPECT_EQ(from_double(h, 0x1p-24).flags, 0);
  EXPECT_EQ(from_double(h, 0x1p-25).bits, 0x0000u);  // tie -> even (0)
  EXPECT_EQ(from_double(h, 0x1p-25).flags, U | X);
  EXPECT_EQ(from_double(h, (1.5 - 0x1p-20) * 0x1p-24).bits, 0x0001u);  // no double rounding
  EXPECT_EQ(from_double(h, -0.0).bits, 0x8000u);
  EXPECT_EQ(from_double(h, std::nan("")).bits, 0x7e00u);
  EXPECT_EQ(from_double(h, std::nan("")).flags, 0);
  EXPECT_EQ(from_double(h, bits_double(0x7ff0000000000001ull)).flags, I);  // signaling double
  EXPECT_EQ(from_double(h, bits_double(0x7ff0000000000001ull)).bits, 0x7e00u);
  Format hz = Format::parse("e5m10-ftz");
  EXPECT_EQ(from_double(hz, 0x1p-24).bits, 0x0000u);  // tiny -> flushed
  EXPECT_EQ(from_double(hz, 0x1p-24).flags, U | X);
  EXPECT_EQ(from_double(hz, -0x1p-15).bits, 0x8000u);
  EXPECT_EQ(to_double(hz, 0x0001), 0.0);
  EXPECT_TRUE(std::signbit(to_double(hz, 0x8001)));
  EXPECT_EQ(to_double(h, 0x0001), 0x1p-24);
  EXPECT_EQ(to_double(h, 0xfbff), -65504.0);
  EXPECT_TRUE(std::isnan(to_double(h, 0x7d00)));
  EXPECT_EQ(to_double(h, 0xfc00), -HUGE_VAL);
  EXPECT_EQ(from_int(h, 2049).bits, 0x6800u);
  EXPECT_EQ(from_int(h, -65536).bits, 0xfc00u);
  Format hr = h;
  hr.round = Round::RTZ;
  EXPECT_EQ(from_int(hr, -65536).bits, 0xfbffu);
  EXPECT_EQ(to_int(h, 0x4100, Round::RNE).value, 2);  // 2.5
  EXPECT_EQ(to_int(h, 0x4100, Round::RUP).value, 3);
  EXPECT_EQ(to_int(h, 0xc100, Round::RDN).value, -3);
  EXPECT_EQ(to_int(h, 0xc100, Round::RTZ).value, -2);
  EXPECT_EQ(to_int(h, 0xc100, Round::RTZ).flags, X);
  EXPECT_EQ(to_int(h, 0x7c00, Round::RNE).value, INT64_MAX);
  EXPECT_EQ(to_int(h, 0xfc00, Round::RNE).value, INT64_MIN);
  EXPECT_EQ(to_int(h, 0xfc00, Round::RNE).flags, I);
  EXPECT_EQ(to_int(h, 0xfe00, Round::RNE).value, INT64_MAX);  // NaN
  EXPECT_EQ(to_int(h, 0xfe00, Round::RNE).flags, I);
  EXPECT_EQ(to_int(hz, 0x03ff, Round::RUP).value, 0);  // flushed subnormal
  EXPECT_EQ(to_int(hz, 0x03ff, Round::RUP).flags, 0);
  EXPECT_EQ(to_int(h, 0x03ff, Round::RUP).value, 1);
  EXPECT_EQ(to_int(h, 0x03ff, Round::RUP).flags, X);
  const Format d = Format::parse("e11m52");
  EXPECT_EQ(to_int(d, 0xc3e0000000000000ull, Round::RNE).value, INT64_MIN);  // -2^63 fits
  EXPECT_EQ(to_int(d, 0xc3e0000000000000ull, Round::RNE).flags, 0);
  EXPECT_EQ(to_int(d, 0x43e0000000000000ull, Round::RNE).flags, I);  // 2^63 does not
  EXPECT_EQ(to_int(d, 0x43dfffffffffffffull, Round::RNE).value, 0x7ffffffffffffc00ll);
}

// ---- classify ------------------------------------------------------------------------------

TEST(Classify, EveryPatternOfSmallFormatsAndRandomOfLarge) {
  for (auto [E, M] : {std::pair{2, 1}, {3, 4}, {5, 2}, {5, 10}, {8, 23}, {11, 52}, {4, 3}}) {
    for (bool sub : {true, false}) {
      const Format f = make_format(E, M, sub);
      std::vector<uint64_t> xs = special_values(f);
      OperandGen gen(f, 1);
      for (int i = 0; i < 2000; ++i) xs.push_back(gen.next());
      if (f.width() <= 8)
        for (uint64_t x = 0; x < (1ull << f.width()); ++x) xs.push_back(x);
      for (uint64_t x : xs) {
        const bool neg = (x >> (E + M)) & 1;
        const uint64_t e = (x >> M) & ((1ull << E) - 1), fr = x & ((1ull << M) - 1);
        Class want;
        if (e == (1ull << E) - 1)
          want =
              fr == 0 ? (neg ? Class::NegInf : Class::PosInf) : ((fr >> (M - 1)) ? Class::QNaN : Class::SNaN);
        else if (e == 0)
          want = fr == 0 ? (neg ? Class::NegZero : Class::PosZero)
                         : (neg ? Class::NegSubnormal : Class::PosSubnormal);
        else
          want = neg ? Class::NegNormal : Class::PosNormal;
        EXPECT_EQ(classify(f, x), want) << fmt_name(f) << " " << describe(f, x);
        EXPECT_EQ(is_nan(f, x), want == Class::QNaN || want == Class::SNaN) << describe(f, x);
      }
    }
  }
  std::set<std::string> names;
  for (int c = 0; c <= static_cast<int>(Class::QNaN); ++c) names.insert(class_name(static_cast<Class>(c)));
  EXPECT_EQ(names.size(), 10u);
  // M = 1: every NaN is quiet.
  EXPECT_EQ(classify(make_format(4, 1), 0x1f), Class::QNaN);
}

// ---- min / max / compare --------------------------------------------------------------------

TEST(Compare, SignedZerosNaNsAndFlushing) {
  const Format h = make_format(5, 10);
  const Format z = make_format(5, 10, false);
  const uint64_t pz = 0x0000, nz = 0x8000, one = 0x3c00, qn = 0x7e00, qn2 = 0xfe55, sn = 0x7d00, inf = 0x7c00;
  auto R = [](uint64_t b, uint8_t f) { return Result{b, f}; };
  auto expect = [&](const Format& f, Op op, uint64_t a, uint64_t b, Result want) {
    const Result got = model_op(f, op, a, b, 0);
    EXPECT_TRUE(got.bits == want.bits && got.flags == want.flags)
        << fmt_name(f) << " " << op_str(op) << "(" << describe(f, a) << ", " << describe(f, b)
        << ") = " << describe(f, got.bits) << " " << flag_str(got.flags) << ", expected "
        << describe(f, want.bits) << " " << flag_str(want.flags);
    const Result ref = mpfr_apply(f, op, a, b);
    EXPECT_TRUE(ref.bits == want.bits && ref.flags == want.flags) << "oracle disagrees with the test";
  };
  expect(h, Op::Min, pz, nz, R(nz, 0));
  expect(h, Op::Min, nz, pz, R(nz, 0));
  expect(h, Op::Max, pz, nz, R(pz, 0));
  expect(h, Op::Max, nz, pz, R(pz, 0));
  expect(h, Op::Min, qn, one, R(one, 0));
  expect(h, Op::Min, one, qn2, R(one, 0));
  expect(h, Op::Max, qn2, inf, R(inf, 0));
  expect(h, Op::Min, sn, one, R(one, I));  // minNum with a signaling NaN: the number, invalid
  expect(h, Op::Max, one, sn, R(one, I));
  expect(h, Op::Min, qn2, qn2, R(qn, 0));  // both NaN: canonical
  expect(h, Op::Max, sn, qn2, R(qn, I));
  expect(h, Op::Lt, qn, one, R(0, I));
  expect(h, Op::Le, one, qn, R(0, I));
  expect(h, Op::Eq, qn, qn, R(0, 0));
  expect(h, Op::Eq, sn, one, R(0, I));
  expect(h, Op::Eq, pz, nz, R(1, 0));
  expect(h, Op::Lt, nz, pz, R(0, 0));
  expect(h, Op::Le, nz, pz, R(1, 0));
  expect(h, Op::Lt, 0xfc00, 0xfbff, R(1, 0));
  expect(h, Op::Le, inf, inf, R(1, 0));
  // Subnormals: ordered normally with subnormals, read as zeros when flushed.
  expect(h, Op::Lt, 0x0001, 0x0002, R(1, 0));
  expect(z, Op::Lt, 0x0001, 0x0002, R(0, 0));
  expect(z, Op::Eq, 0x0001, 0x8002, R(1, 0));
  expect(z, Op::Min, 0x8001, 0x0000, R(0x8000, 0));  // flushed bits of the chosen operand
  expect(z, Op::Max, 0x0005, 0x8000, R(0x0000, 0));
  expect(h, Op::Max, 0x0005, 0x8000, R(0x0005, 0));
  expect(z, Op::Min, 0x0003, qn, R(0x0000, 0));
  expect(z, Op::Min, 0x0003, 0x3c00, R(0x0000, 0));
  // unordered: quiet (invalid only for sNaN)
  EXPECT_EQ(unordered(h, qn, one).bits, 1u);
  EXPECT_EQ(unordered(h, qn, one).flags, 0);
  EXPECT_EQ(unordered(h, one, sn).bits, 1u);
  EXPECT_EQ(unordered(h, one, sn).flags, I);
  EXPECT_EQ(unordered(h, one, inf).bits, 0u);
  EXPECT_EQ(unordered(h, one, inf).flags, 0);
}

TEST(Compare, UnorderedAgainstPlainLogic) {
  for (auto [E, M] : grid_formats()) {
    for (bool sub : {true, false}) {
      const Format f = make_format(E, M, sub);
      OperandGen gen(f, 3);
      for (int i = 0; i < 500; ++i) {
        uint64_t a, b;
        gen.pair(a, b);
        const bool na = bits_are_nan(f, a), nb = bits_are_nan(f, b);
        auto snan = [&](uint64_t x) { return bits_are_nan(f, x) && M >= 2 && !((x >> (M - 1)) & 1); };
        const Result r = unordered(f, a, b);
        EXPECT_EQ(r.bits, (na || nb) ? 1u : 0u) << describe(f, a) << " " << describe(f, b);
        EXPECT_EQ(r.flags, (snan(a) || snan(b)) ? I : 0) << describe(f, a) << " " << describe(f, b);
      }
    }
  }
}

TEST(BitOps, AbsNegAreBitOperations) {
  for (auto [E, M] : {std::pair{5, 10}, {2, 1}, {11, 52}, {8, 23}}) {
    for (bool sub : {true, false}) {
      const Format f = make_format(E, M, sub);
      OperandGen gen(f, 4);
      for (int i = 0; i < 1000; ++i) {
        const uint64_t x = gen.next();
        EXPECT_EQ(ru::num::abs(f, x), x & ~f.sign_bit());
        EXPECT_EQ(ru::num::neg(f, x), x ^ f.sign_bit());
      }
      EXPECT_EQ(ru::num::abs(f, f.sign_bit() | 1), 1u);  // no flushing
      EXPECT_EQ(ru::num::neg(f, f.qnan()), f.qnan() | f.sign_bit());
    }
  }
}

// ---- apply(), dot3, parse_operand ----------------------------------------------------------

TEST(Dispatch, ApplyEqualsTheEntryPoints) {
  for (auto [E, M] : {std::pair{5, 10}, {3, 2}, {8, 23}, {11, 52}}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, r != Round::RTZ, r);
      OperandGen gen(f, 8);
      for (Op op : kAllOps) {
        for (int i = 0; i < 500; ++i) {
          uint64_t a, b, c;
          gen.triple(a, b, c);
          const Result x = apply(f, op, a, b, c), y = model_op(f, op, a, b, c);
          EXPECT_TRUE(x.bits == y.bits && x.flags == y.flags) << op_str(op);
        }
      }
    }
  }
}

// One loop for both dot products: `dut` against `oracle` (MPFR) on f, operands from OperandGen
// (pair per product for dot3; dot3 for the fused one: cancellation and alignment cases). The
// planted tests below run it on wrong implementations.
using Dot3Fn = Result (*)(const Format&, const uint64_t*, const uint64_t*);
Checker run_dot3(const Format& f, uint64_t n, uint64_t seed, bool fused, Dot3Fn oracle, Dot3Fn dut) {
  OperandGen gen(f, seed);
  const std::string name = fused ? "dot3_fused" : "dot3";
  Checker chk(name + " vs MPFR");
  for (uint64_t i = 0; i < n && !chk.done(); ++i) {
    uint64_t a[3], b[3];
    if (fused)
      gen.dot3(a, b);
    else
      for (int k = 0; k < 3; ++k) gen.pair(a[k], b[k]);
    const Result want = oracle(f, a, b), got = dut(f, a, b);
    chk.count();
    if (want.bits != got.bits || want.flags != got.flags) {
      std::string m = fmt_name(f) + " " + rnd_name(f.round) + " " + name + "(";
      for (int k = 0; k < 3; ++k) m += describe(f, a[k]) + " * " + describe(f, b[k]) + (k < 2 ? ", " : ")");
      chk.fail(m + ": expected " + describe(f, want.bits) + " " + flag_str(want.flags) + ", actual " +
               describe(f, got.bits) + " " + flag_str(got.flags));
    }
  }
  return chk;
}
Checker run_dot3_fused(const Format& f, uint64_t n, uint64_t seed, Dot3Fn dut) {
  return run_dot3(f, n, seed, true, mpfr_dot3_fused, dut);
}

// dot3: the composition of three products and two sums, against MPFR's composition.
class Dot3 : public ::testing::TestWithParam<std::pair<int, int>> {};
TEST_P(Dot3, MatchesRoundedComposition) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Checker chk = run_dot3(make_format(E, M, sub, r), scaled(2000), 21, false, mpfr_dot3, dot3);
      EXPECT_TRUE(chk.ok()) << chk.report();
    }
  }
}
INSTANTIATE_TEST_SUITE_P(Grid, Dot3, ::testing::ValuesIn(grid_formats()), em_param_name);

// dot3_fused (the model: exact GMP sum, one round_pack) against MPFR (exact products, mpfr_sum).
class Dot3Fused : public ::testing::TestWithParam<std::pair<int, int>> {};
TEST_P(Dot3Fused, MatchesMpfrSum) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Checker chk = run_dot3_fused(make_format(E, M, sub, r), scaled(3000), 23, dot3_fused);
      EXPECT_TRUE(chk.ok()) << chk.report();
    }
  }
}
INSTANTIATE_TEST_SUITE_P(Grid, Dot3Fused, ::testing::ValuesIn(grid_formats()), em_param_name);

// The loop above catches planted errors: the unfused composition (two extra roundings), and the
// exact sum with the smallest product dropped whenever the other two cancel exactly (the case a
// windowed adder gets wrong if it jams the third product).
Result drop_third_after_cancel(const Format& f, const uint64_t* a, const uint64_t* b) {
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) {
      const Result pi = mpfr_apply(f, Op::Mul, a[i], b[i]), pj = mpfr_apply(f, Op::Mul, a[j], b[j]);
      const Result s = mpfr_apply(f, Op::Add, pi.bits, pj.bits);
      if (pi.flags == 0 && pj.flags == 0 && s.flags == 0 && (s.bits & ~f.sign_bit()) == 0 &&
          (pi.bits & ~f.sign_bit()) != 0)
        return {f.round == Round::RDN ? f.sign_bit() : 0, 0};
    }
  return mpfr_dot3_fused(f, a, b);
}
TEST(Dot3FusedPlanted, UnfusedAndDroppedTermAreCaught) {
  for (const char* name : {"e5m10", "e8m23", "e3m2"}) {
    const Format f = Format::parse(name);
    EXPECT_GT(run_dot3_fused(f, 20000, 5, dot3).errors(), 0u) << name << ": unfused composition not caught";
    EXPECT_GT(run_dot3_fused(f, 20000, 5, drop_third_after_cancel).errors(), 0u)
        << name << ": dropped third product not caught";
  }
}

// Every operand sextuple of the 4-bit formats (16^6 = 1.7e7 each), every rounding mode, with and
// without subnormals (long).
class LongDot3FusedExhaustive : public ::testing::TestWithParam<std::pair<int, int>> {};
TEST_P(LongDot3FusedExhaustive, EverySextuple) {
  const auto [E, M] = GetParam();
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      Checker chk("dot3_fused vs MPFR (exhaustive)");
      const uint64_t n = 1ull << f.width(), total = n * n * n * n * n * n;
      for (uint64_t v = 0; v < total && !chk.done(); ++v) {
        uint64_t a[3], b[3], w = v;
        for (int k = 0; k < 3; ++k) a[k] = w % n, w /= n;
        for (int k = 0; k < 3; ++k) b[k] = w % n, w /= n;
        const Result want = mpfr_dot3_fused(f, a, b), got = dot3_fused(f, a, b);
        chk.count();
        if (want.bits != got.bits || want.flags != got.flags)
          chk.fail(fmt_name(f) + " " + rnd_name(r) + " dot3_fused sextuple " + std::to_string(v) + ": expected " +
                   describe(f, want.bits) + " " + flag_str(want.flags) + ", actual " + describe(f, got.bits) + " " +
                   flag_str(got.flags));
      }
      EXPECT_TRUE(chk.ok()) << chk.report();
    }
  }
}
INSTANTIATE_TEST_SUITE_P(LongSmall, LongDot3FusedExhaustive, ::testing::Values(std::pair{2, 1}), em_param_name);

TEST(ParseOperand, HexDecimalAndErrors) {
  const Format h = Format::parse("e5m10");
  EXPECT_EQ(parse_operand(h, "0x3c00"), 0x3c00u);
  EXPECT_EQ(parse_operand(h, "0XFFFF"), 0xffffu);
  EXPECT_EQ(parse_operand(h, "1.5"), 0x3e00u);
  EXPECT_EQ(parse_operand(h, "-2"), 0xc000u);
  EXPECT_EQ(parse_operand(h, "1e10"), 0x7c00u);
  EXPECT_EQ(parse_operand(h, "inf"), 0x7c00u);
  EXPECT_EQ(parse_operand(h, "-inf"), 0xfc00u);
  EXPECT_TRUE(bits_are_nan(h, parse_operand(h, "nan")));
  EXPECT_EQ(parse_operand(h, "0x1p-3"), 0x3000u);  // hexadecimal floating-point literal
  EXPECT_EQ(parse_operand(Format::parse("e11m52"), "0xffffffffffffffff"), ~0ull);
  for (const char* bad : {"", "abc", "0x", "0x1g", "0x10000", "1.5.2", "1,5", "--1", "0x-1", "1.5x"}) {
    EXPECT_THROW(parse_operand(h, bad), FormatError) << "'" << bad << "'";
  }
}

// Decimal operands must be rounded once, from the exact decimal value (was a model bug:
// parse_operand went through strtod (double) first, which double-rounds
// decimals that lie within 2^-53 relative of a tie of the format).
TEST(ParseOperand, DecimalIsRoundedOnce) {
  const Format h = Format::parse("e5m10");
  EXPECT_EQ(parse_operand(h, "1.00048828125000000001"), 0x3c01u);  // just above 1 + 2^-11 (a tie)
  EXPECT_EQ(parse_operand(h, "1.00146484374999999999"), 0x3c01u);  // just below 1 + 3*2^-11
  EXPECT_EQ(parse_operand(h, "1.00048828125"), 0x3c00u);           // the tie itself: to even
  // Decimals next to the ties of random formats, every rounding mode, subnormals on and off.
  for (auto [E, M] : grid_formats()) {
    for (bool sub : {true, false}) {
      for (Round r : kRounds) {
        const Format f = make_format(E, M, sub, r);
        OperandGen gen(f, 31);
        Checker chk("parse_operand vs mpfr_strtofr");
        for (int i = 0; i < 200 && !chk.done(); ++i) {
          const uint64_t x = gen.next();
          const double v = mpfr_to_double(make_format(E, M), x);
          if (!std::isfinite(v)) continue;
          // v + half an ulp (of the format) +- 1e-25 relative, as a 40-digit decimal
          const int ue = v == 0 ? f.emin() : std::max(std::ilogb(v), f.emin());
          const double half = std::ldexp(1.0, ue - M - 1);
          char text[128];
          std::snprintf(text, sizeof text, "%.40e", v + half);  // exact when M+2 <= 53
          std::string t(text);
          if (i & 1) t.insert(t.find('e'), "1");  // a 42nd digit pushes the decimal off the tie
          bool ok = false;
          const Result want = mpfr_from_string(f, t.c_str(), &ok);
          ASSERT_TRUE(ok) << t;
          const uint64_t got = parse_operand(f, t);
          chk.count();
          if (got != want.bits) {
            chk.fail(fmt_name(f) + " " + rnd_name(r) + " parse_operand(\"" + t + "\") = " + describe(f, got) +
                     ", expected " + describe(f, want.bits));
          }
        }
        EXPECT_TRUE(chk.ok()) << chk.report();
      }
    }
  }
}

// Only the canonical spelling parses, so parse(name()) and name(parse()) are inverses.
TEST(FormatName, OnlyCanonicalSpellingParses) {
  for (const char* bad : {"E8M23", "e8M23", "e08m23", "e8m023", "e8m23-FTZ", "e8m23 "}) {
    EXPECT_THROW(Format::parse(bad), FormatError) << bad;
  }
  EXPECT_EQ(Format::parse("e10m5").name(), "e10m5");
}

}  // namespace
}  // namespace ru::num::testing
