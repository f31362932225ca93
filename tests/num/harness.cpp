// Shared test harness (see harness.hpp).
#include "harness.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "rayunits/util/rng.hpp"

#if !defined(__x86_64__)
#include <cfenv>
#endif

namespace ru::num::testing {

std::string fmt_name(const Format& f) {
  return "e" + std::to_string(f.exp_bits) + "m" + std::to_string(f.frac_bits) + (f.subnormals ? "" : "-ftz");
}

const char* rnd_name(Round r) {
  switch (r) {
    case Round::RNE:
      return "rne";
    case Round::RTZ:
      return "rtz";
    case Round::RDN:
      return "rdn";
    case Round::RUP:
      return "rup";
  }
  return "?";
}

const char* op_str(Op op) {
  static const char* n[] = {"add", "sub", "mul", "div", "sqrt", "fma", "min", "max", "lt", "le", "eq"};
  const unsigned i = static_cast<unsigned>(op);
  return i < 11 ? n[i] : "?";
}

int arity(Op op) {
  if (op == Op::Sqrt) return 1;
  if (op == Op::Fma) return 3;
  return 2;
}

std::string flag_str(uint8_t fl) {
  std::string s;
  if (fl & kInvalid) s += 'i';
  if (fl & kDivZero) s += 'z';
  if (fl & kOverflow) s += 'o';
  if (fl & kUnderflow) s += 'u';
  if (fl & kInexact) s += 'x';
  return s.empty() ? "-" : s;
}

bool bits_are_nan(const Format& f, uint64_t x) {
  const uint64_t ones = (1ull << f.exp_bits) - 1;
  return ((x >> f.frac_bits) & ones) == ones && (x & ((1ull << f.frac_bits) - 1)) != 0;
}

std::string describe(const Format& f, uint64_t x) {
  const int E = f.exp_bits, M = f.frac_bits;
  const int digits = (1 + E + M + 3) / 4;
  char hex[32];
  std::snprintf(hex, sizeof hex, "0x%0*llx", digits, static_cast<unsigned long long>(x));
  if (1 + E + M < 64 && (x >> (1 + E + M)) != 0) return std::string(hex) + " = (does not fit the format)";
  const bool neg = (x >> (E + M)) & 1;
  const uint64_t ones = (1ull << E) - 1;
  const uint64_t e = (x >> M) & ones, fr = x & ((1ull << M) - 1);
  const int bias = (1 << (E - 1)) - 1;
  std::string out(hex);
  if (e == ones) {
    if (fr == 0) return out + (neg ? " = -inf" : " = +inf");
    return out + ((fr >> (M - 1)) & 1 ? " = qNaN" : " = sNaN") + (neg ? " (sign set)" : "");
  }
  double v = e == 0 ? std::ldexp(static_cast<double>(fr), 1 - bias - M)
                    : std::ldexp(static_cast<double>(fr | (1ull << M)), static_cast<int>(e) - bias - M);
  if (neg) v = -v;
  char buf[96];
  std::snprintf(buf, sizeof buf, " = %.17g (%a)%s", v, v, e == 0 && fr != 0 ? " subnormal" : "");
  return out + buf;
}

Format make_format(int E, int M, bool subnormals, Round r) {
  Format f;
  f.exp_bits = E;
  f.frac_bits = M;
  f.subnormals = subnormals;
  f.round = r;
  return f;
}

Result model_op(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) {
  switch (op) {
    case Op::Add:
      return ru::num::add(f, a, b);
    case Op::Sub:
      return ru::num::sub(f, a, b);
    case Op::Mul:
      return ru::num::mul(f, a, b);
    case Op::Div:
      return ru::num::div(f, a, b);
    case Op::Sqrt:
      return ru::num::sqrt(f, a);
    case Op::Fma:
      return ru::num::fma(f, a, b, c);
    case Op::Min:
      return ru::num::min(f, a, b);
    case Op::Max:
      return ru::num::max(f, a, b);
    case Op::Lt:
      return ru::num::lt(f, a, b);
    case Op::Le:
      return ru::num::le(f, a, b);
    case Op::Eq:
      return ru::num::eq(f, a, b);
  }
  return {};
}

Result oracle_op(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) {
  return mpfr_apply(f, op, a, b, c);
}

// ---- Checker -------------------------------------------------------------------------------

Checker::Checker(std::string what, NanMatch nan, int max_errors)
    : what_(std::move(what)), nan_(nan), max_errors_(max_errors) {}

bool Checker::check(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c, const Result& exp,
                    const Result& act) {
  ++checks_;
  const bool is_cmp = op == Op::Lt || op == Op::Le || op == Op::Eq;
  bool same_bits = exp.bits == act.bits;
  if (!same_bits && nan_ == NanMatch::AnyNan && !is_cmp)
    same_bits = bits_are_nan(f, exp.bits) && bits_are_nan(f, act.bits);
  if (same_bits && exp.flags == act.flags) return true;
  ++errors_;
  if (messages_.size() < static_cast<size_t>(max_errors_)) {
    std::ostringstream m;
    m << what_ << " MISMATCH: " << fmt_name(f) << " " << rnd_name(f.round) << " " << op_str(op) << "\n";
    const char* names[] = {"a", "b", "c"};
    const uint64_t ops[] = {a, b, c};
    for (int i = 0; i < arity(op); ++i) m << "    " << names[i] << "        " << describe(f, ops[i]) << "\n";
    auto res = [&](const Result& r) {
      return (is_cmp ? std::to_string(r.bits) : describe(f, r.bits)) + "  flags " + flag_str(r.flags);
    };
    m << "    expected " << res(exp) << "\n";
    m << "    actual   " << res(act) << (same_bits ? "   (results match, flags differ)" : "") << "\n";
    messages_.push_back(m.str());
  }
  return false;
}

void Checker::fail(const std::string& message) {
  ++errors_;
  if (messages_.size() < static_cast<size_t>(max_errors_))
    messages_.push_back(what_ + " MISMATCH: " + message + "\n");
}

std::string Checker::report() const {
  std::ostringstream m;
  for (const auto& s : messages_) m << s;
  m << what_ << ": " << errors_ << " mismatch(es) in " << checks_ << " checks";
  if (done()) m << " (stopped after " << max_errors_ << " errors)";
  m << "\n";
  return m.str();
}

// ---- drivers -------------------------------------------------------------------------------

void run_random(Checker& chk, const Format& f, Op op, uint64_t count, uint64_t seed, const OpFn& ref,
                const OpFn& dut) {
  OperandGen gen(f, seed);
  const int n = arity(op);
  for (uint64_t i = 0; i < count && !chk.done(); ++i) {
    uint64_t a = 0, b = 0, c = 0;
    if (n == 1)
      a = gen.next();
    else if (n == 2)
      gen.pair(a, b);
    else
      gen.triple(a, b, c);
    chk.check(f, op, a, b, c, ref(f, op, a, b, c), dut(f, op, a, b, c));
  }
}

void run_uniform(Checker& chk, const Format& f, Op op, uint64_t count, uint64_t seed, const OpFn& ref,
                 const OpFn& dut) {
  uint64_t x = seed * 0x2545F4914F6CDD1Dull + 1;
  auto next = [&] { return ru::util::splitmix64(x) & f.mask(); };
  const int n = arity(op);
  for (uint64_t i = 0; i < count && !chk.done(); ++i) {
    const uint64_t a = next(), b = n >= 2 ? next() : 0, c = n >= 3 ? next() : 0;
    chk.check(f, op, a, b, c, ref(f, op, a, b, c), dut(f, op, a, b, c));
  }
}

void run_specials(Checker& chk, const Format& f, Op op, const OpFn& ref, const OpFn& dut) {
  const std::vector<uint64_t> sv = special_values(f);
  const int n = arity(op);
  if (n == 1) {
    for (uint64_t a : sv) chk.check(f, op, a, 0, 0, ref(f, op, a, 0, 0), dut(f, op, a, 0, 0));
    return;
  }
  if (n == 2) {
    for (uint64_t a : sv)
      for (uint64_t b : sv) {
        if (chk.done()) return;
        chk.check(f, op, a, b, 0, ref(f, op, a, b, 0), dut(f, op, a, b, 0));
      }
    return;
  }
  // fma: specials x specials x {every 5th special}, and a*b = 1*specials + c specials.
  for (size_t k = 0; k < sv.size(); k += 5) {
    const uint64_t c = sv[k];
    for (uint64_t a : sv)
      for (uint64_t b : sv) {
        if (chk.done()) return;
        chk.check(f, op, a, b, c, ref(f, op, a, b, c), dut(f, op, a, b, c));
      }
  }
  for (uint64_t b : sv)
    for (uint64_t c : sv) {
      if (chk.done()) return;
      const uint64_t a = f.one();
      chk.check(f, op, a, b, c, ref(f, op, a, b, c), dut(f, op, a, b, c));
    }
}

void run_exhaustive(Checker& chk, const Format& f, Op op, const OpFn& ref, const OpFn& dut) {
  const uint64_t N = 1ull << (1 + f.exp_bits + f.frac_bits);
  const int n = arity(op);
  for (uint64_t a = 0; a < N; ++a) {
    if (n == 1) {
      chk.check(f, op, a, 0, 0, ref(f, op, a, 0, 0), dut(f, op, a, 0, 0));
      continue;
    }
    for (uint64_t b = 0; b < N; ++b) {
      if (n == 2) {
        chk.check(f, op, a, b, 0, ref(f, op, a, b, 0), dut(f, op, a, b, 0));
      } else {
        for (uint64_t c = 0; c < N; ++c) chk.check(f, op, a, b, c, ref(f, op, a, b, c), dut(f, op, a, b, c));
      }
      if (chk.done()) return;
    }
  }
}

// ---- grids ---------------------------------------------------------------------------------

std::vector<std::pair<int, int>> grid_formats() {
  std::vector<std::pair<int, int>> out;
  for (int E : {3, 4, 5, 6, 7, 8, 11})
    for (int M : {1, 2, 3, 7, 10, 16, 23, 30, 52})
      if (1 + E + M <= 64) out.emplace_back(E, M);
  return out;
}

std::vector<std::pair<int, int>> small_formats(int min_width, int max_width) {
  std::vector<std::pair<int, int>> out;
  for (int w = min_width; w <= max_width; ++w)
    for (int E = 2; E <= 11; ++E) {
      const int M = w - 1 - E;
      if (M >= 1 && M <= 52) out.emplace_back(E, M);
    }
  return out;
}

std::vector<std::pair<int, int>> edge_formats() {
  return {{2, 1},   {2, 10}, {2, 23}, {2, 52}, {9, 52}, {10, 52},
          {10, 10}, {5, 2},  {6, 9},  {8, 7},  {9, 22}, {11, 40}};
}

std::string em_param_name(const ::testing::TestParamInfo<std::pair<int, int>>& info) {
  return "e" + std::to_string(info.param.first) + "m" + std::to_string(info.param.second);
}

uint64_t scaled(uint64_t count) {
  static const double scale = [] {
    const char* s = std::getenv("RU_NUM_SCALE");
    const double v = s ? std::atof(s) : 1.0;
    return v > 0 ? v : 1.0;
  }();
  const double n = static_cast<double>(count) * scale;
  return n < 1 ? 1 : static_cast<uint64_t>(n);
}

// ---- native hardware -----------------------------------------------------------------------

#if defined(__x86_64__)

namespace {

// MXCSR: flags IE(0) DE(1) ZE(2) OE(3) UE(4) PE(5), DAZ(6), masks (7..12), RC (13..14), FTZ(15).
uint32_t mxcsr_control(Round r, bool ftz) {
  uint32_t rc = 0;
  switch (r) {
    case Round::RNE:
      rc = 0;
      break;
    case Round::RDN:
      rc = 1;
      break;
    case Round::RUP:
      rc = 2;
      break;
    case Round::RTZ:
      rc = 3;
      break;
  }
  return 0x1F80u | (rc << 13) | (ftz ? 0x8040u : 0u);
}

uint8_t mxcsr_flags(uint32_t st) {
  uint8_t fl = 0;
  if (st & 0x01) fl |= kInvalid;
  if (st & 0x04) fl |= kDivZero;
  if (st & 0x08) fl |= kOverflow;
  if (st & 0x10) fl |= kUnderflow;
  if (st & 0x20) fl |= kInexact;
  return fl;
}

bool have_fma() {
  static const bool v = __builtin_cpu_supports("fma");
  return v;
}

// One asm block: load the control word, execute, store the status, restore the caller's MXCSR.
#define RU_NATIVE2(INSN, T, X, Y)                                                                         \
  asm volatile("stmxcsr %[sv]\n\tldmxcsr %[ctl]\n\t" INSN " %[y], %[x]\n\tstmxcsr %[st]\n\tldmxcsr %[sv]" \
               : [x] "+x"(X), [st] "=m"(st), [sv] "=m"(saved)                                             \
               : [y] "x"(Y), [ctl] "m"(ctl))

template <class T>
Result native_t(Op op, uint64_t ab, uint64_t bb, uint64_t cb, Round r, bool ftz) {
  T x, y, z;
  std::memcpy(&x, &ab, sizeof(T));  // little endian: low bytes
  std::memcpy(&y, &bb, sizeof(T));
  std::memcpy(&z, &cb, sizeof(T));
  const uint32_t ctl = mxcsr_control(r, ftz);
  uint32_t st = 0, saved = 0;
  constexpr bool f32 = sizeof(T) == 4;
  switch (op) {
    case Op::Add:
      if (f32)
        RU_NATIVE2("addss", T, x, y);
      else
        RU_NATIVE2("addsd", T, x, y);
      break;
    case Op::Sub:
      if (f32)
        RU_NATIVE2("subss", T, x, y);
      else
        RU_NATIVE2("subsd", T, x, y);
      break;
    case Op::Mul:
      if (f32)
        RU_NATIVE2("mulss", T, x, y);
      else
        RU_NATIVE2("mulsd", T, x, y);
      break;
    case Op::Div:
      if (f32)
        RU_NATIVE2("divss", T, x, y);
      else
        RU_NATIVE2("divsd", T, x, y);
      break;
    case Op::Sqrt: {
      T src = x;
      if (f32)
        RU_NATIVE2("sqrtss", T, x, src);
      else
        RU_NATIVE2("sqrtsd", T, x, src);
      break;
    }
    case Op::Fma:
      if (!have_fma()) {
        std::fprintf(stderr, "native fma: this CPU has no FMA instructions\n");
        std::abort();
      }
      // z = x*y + z
      if (f32) {
        asm volatile(
            "stmxcsr %[sv]\n\tldmxcsr %[ctl]\n\tvfmadd231ss %[y], %[x], %[z]\n\tstmxcsr %[st]\n\tldmxcsr "
            "%[sv]"
            : [z] "+x"(z), [st] "=m"(st), [sv] "=m"(saved)
            : [x] "x"(x), [y] "x"(y), [ctl] "m"(ctl));
      } else {
        asm volatile(
            "stmxcsr %[sv]\n\tldmxcsr %[ctl]\n\tvfmadd231sd %[y], %[x], %[z]\n\tstmxcsr %[st]\n\tldmxcsr "
            "%[sv]"
            : [z] "+x"(z), [st] "=m"(st), [sv] "=m"(saved)
            : [x] "x"(x), [y] "x"(y), [ctl] "m"(ctl));
      }
      x = z;
      break;
    default:
      std::fprintf(stderr, "native_op: unsupported op\n");
      std::abort();
  }
  uint64_t out = 0;
  std::memcpy(&out, &x, sizeof(T));
  return {out, mxcsr_flags(st)};
}

#undef RU_NATIVE2

}  // namespace

bool native_supported(bool /*ftz*/) { return have_fma(); }

Result native_op(int width, Op op, uint64_t a, uint64_t b, uint64_t c, Round r, bool ftz) {
  return width == 32 ? native_t<float>(op, a, b, c, r, ftz) : native_t<double>(op, a, b, c, r, ftz);
}

#else  // portable fallback: <cfenv>, volatile operands; no FTZ/DAZ control

namespace {
template <class T>
Result native_t(Op op, uint64_t ab, uint64_t bb, uint64_t cb, Round r) {
  volatile T x, y, z;
  T tx, ty, tz;
  std::memcpy(&tx, &ab, sizeof(T));
  std::memcpy(&ty, &bb, sizeof(T));
  std::memcpy(&tz, &cb, sizeof(T));
  x = tx;
  y = ty;
  z = tz;
  const int old = std::fegetround();
  std::fesetround(r == Round::RNE   ? FE_TONEAREST
                  : r == Round::RTZ ? FE_TOWARDZERO
                  : r == Round::RDN ? FE_DOWNWARD
                                    : FE_UPWARD);
  std::feclearexcept(FE_ALL_EXCEPT);
  volatile T res;
  switch (op) {
    case Op::Add:
      res = x + y;
      break;
    case Op::Sub:
      res = x - y;
      break;
    case Op::Mul:
      res = x * y;
      break;
    case Op::Div:
      res = x / y;
      break;
    case Op::Sqrt:
      res = std::sqrt(static_cast<T>(x));
      break;
    default:
      res = std::fma(static_cast<T>(x), static_cast<T>(y), static_cast<T>(z));
      break;
  }
  const int ex = std::fetestexcept(FE_ALL_EXCEPT);
  std::fesetround(old);
  uint8_t fl = 0;
  if (ex & FE_INVALID) fl |= kInvalid;
  if (ex & FE_DIVBYZERO) fl |= kDivZero;
  if (ex & FE_OVERFLOW) fl |= kOverflow;
  if (ex & FE_UNDERFLOW) fl |= kUnderflow;
  if (ex & FE_INEXACT) fl |= kInexact;
  T out = res;
  uint64_t bits = 0;
  std::memcpy(&bits, &out, sizeof(T));
  return {bits, fl};
}
}  // namespace

bool native_supported(bool ftz) { return !ftz; }

Result native_op(int width, Op op, uint64_t a, uint64_t b, uint64_t c, Round r, bool /*ftz*/) {
  return width == 32 ? native_t<float>(op, a, b, c, r) : native_t<double>(op, a, b, c, r);
}

#endif

Result native_spec_op(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) {
  Result r = native_op(f.width(), op, a, b, c, f.round, !f.subnormals);
  if (op == Op::Fma) {
    const int M = f.frac_bits;
    const uint64_t ones = (1ull << f.exp_bits) - 1, fm = (1ull << M) - 1;
    auto ex = [&](uint64_t x) { return (x >> M) & ones; };
    auto is_zero = [&](uint64_t x) { return ex(x) == 0 && ((x & fm) == 0 || !f.subnormals); };
    auto is_inf = [&](uint64_t x) { return ex(x) == ones && (x & fm) == 0; };
    const bool c_qnan = ex(c) == ones && ((c >> (M - 1)) & 1);
    if (c_qnan && ((is_zero(a) && is_inf(b)) || (is_inf(a) && is_zero(b)))) r.flags |= kInvalid;
  }
  return r;
}

}  // namespace ru::num::testing
