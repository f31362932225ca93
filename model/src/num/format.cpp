// Format names, validation, option parsing. See docs/FORMAT.md.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>

#include "rayunits/num/format.hpp"

namespace ru::num {
namespace detail {
Result from_decimal(const Format& f, bool neg, const std::string& digits, long exp10);
}

static const char* kAccepted =
    "accepted: eXmY[-ftz] with X exponent bits in [2,11], Y fraction bits in [1,52], 1+X+Y <= 64 "
    "(e.g. e5m10, e7m16, e8m23, e7m16-ftz)";

void Format::validate() const {
  if (exp_bits < kMinExp || exp_bits > kMaxExp || frac_bits < kMinFrac || frac_bits > kMaxFrac ||
      1 + exp_bits + frac_bits > kMaxWidth) {
    throw FormatError("invalid format e" + std::to_string(exp_bits) + "m" + std::to_string(frac_bits) +
                      "; " + kAccepted);
  }
}

static bool parse_uint(std::string_view s, size_t& pos, int& out) {
  size_t start = pos;
  if (pos + 1 < s.size() && s[pos] == '0' && s[pos + 1] >= '0' && s[pos + 1] <= '9') return false;  // no leading zeros
  long v = 0;
  while (pos < s.size() && s[pos] >= '0' && s[pos] <= '9') {
    v = v * 10 + (s[pos] - '0');
    if (v > 100000) return false;
    ++pos;
  }
  out = static_cast<int>(v);
  return pos > start;
}

Format Format::parse(std::string_view name) {
  Format f;
  size_t pos = 0;
  bool ok = !name.empty() && name[0] == 'e';  // canonical spelling only: parse(name()) round-trips
  int e = 0, m = 0;
  if (ok) {
    pos = 1;
    ok = parse_uint(name, pos, e) && pos < name.size() && name[pos] == 'm';
  }
  if (ok) {
    ++pos;
    ok = parse_uint(name, pos, m);
  }
  if (ok && pos < name.size()) {
    ok = name.substr(pos) == "-ftz";
    f.subnormals = false;
  }
  if (!ok) throw FormatError("bad format name '" + std::string(name) + "'; " + kAccepted);
  f.exp_bits = e;
  f.frac_bits = m;
  f.validate();
  return f;
}

std::string Format::name() const {
  return "e" + std::to_string(exp_bits) + "m" + std::to_string(frac_bits) + (subnormals ? "" : "-ftz");
}

const char* round_name(Round r) {
  switch (r) {
    case Round::RNE: return "rne";
    case Round::RTZ: return "rtz";
    case Round::RDN: return "rdn";
    case Round::RUP: return "rup";
  }
  return "?";
}

Round parse_round(std::string_view n) {
  if (n == "rne") return Round::RNE;
  if (n == "rtz") return Round::RTZ;
  if (n == "rdn") return Round::RDN;
  if (n == "rup") return Round::RUP;
  throw FormatError("unknown rounding mode '" + std::string(n) + "'; accepted: rne, rtz, rdn, rup");
}

std::string flags_letters(uint8_t fl) {
  std::string s;
  if (fl & kInvalid) s += 'i';
  if (fl & kDivZero) s += 'z';
  if (fl & kOverflow) s += 'o';
  if (fl & kUnderflow) s += 'u';
  if (fl & kInexact) s += 'x';
  return s.empty() ? "-" : s;
}

static const char* kOpNames[] = {"add", "sub", "mul", "div", "sqrt", "fma", "min", "max", "lt", "le", "eq"};

Op parse_op(std::string_view n) {
  for (int i = 0; i < 11; ++i)
    if (n == kOpNames[i]) return static_cast<Op>(i);
  throw FormatError("unknown operation '" + std::string(n) +
                    "'; accepted: add sub mul div sqrt fma min max lt le eq");
}
const char* op_name(Op op) { return kOpNames[static_cast<int>(op)]; }
int op_arity(Op op) {
  switch (op) {
    case Op::Sqrt: return 1;
    case Op::Fma: return 3;
    default: return 2;
  }
}

Result apply(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c) {
  switch (op) {
    case Op::Add: return add(f, a, b);
    case Op::Sub: return sub(f, a, b);
    case Op::Mul: return mul(f, a, b);
    case Op::Div: return div(f, a, b);
    case Op::Sqrt: return sqrt(f, a);
    case Op::Fma: return fma(f, a, b, c);
    case Op::Min: return min(f, a, b);
    case Op::Max: return max(f, a, b);
    case Op::Lt: return lt(f, a, b);
    case Op::Le: return le(f, a, b);
    case Op::Eq: return eq(f, a, b);
  }
  return {};
}

uint64_t parse_operand(const Format& f, std::string_view text) {
  std::string t(text);
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X') && t.find_first_of(".pP") == std::string::npos) {
    errno = 0;
    char* end = nullptr;
    unsigned long long v = std::strtoull(t.c_str() + 2, &end, 16);
    if (errno || *end || end == t.c_str() + 2)
      throw FormatError("bad bit pattern '" + t + "'; expected 0x followed by hex digits");
    if (v & ~f.mask())
      throw FormatError("bit pattern '" + t + "' does not fit " + f.name() + " (" +
                        std::to_string(f.width()) + " bits)");
    return v;
  }
  // Plain decimals ([-+]digits[.digits][e[-+]digits]) are rounded once from their exact value.
  {
    size_t i = 0;
    bool neg = false;
    if (i < t.size() && (t[i] == '-' || t[i] == '+')) neg = t[i++] == '-';
    std::string digits;
    long frac_digits = 0;
    bool dot = false, any = false;
    for (; i < t.size(); ++i) {
      if (t[i] >= '0' && t[i] <= '9') {
        digits += t[i];
        any = true;
        if (dot) ++frac_digits;
      } else if (t[i] == '.' && !dot) {
        dot = true;
      } else {
        break;
      }
    }
    long exp10 = 0;
    bool ok = any;
    if (ok && i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
      ++i;
      bool eneg = false;
      if (i < t.size() && (t[i] == '-' || t[i] == '+')) eneg = t[i++] == '-';
      const size_t start = i;
      for (; i < t.size() && t[i] >= '0' && t[i] <= '9'; ++i)
        if (exp10 < 100000000) exp10 = exp10 * 10 + (t[i] - '0');
      ok = i > start;
      if (eneg) exp10 = -exp10;
    }
    if (ok && i == t.size()) return detail::from_decimal(f, neg, digits, exp10 - frac_digits).bits;
  }
  // inf, nan and hexadecimal floating-point literals go through strtod (exact for hex literals
  // of up to 53 significant bits).
  errno = 0;
  char* end = nullptr;
  double d = std::strtod(t.c_str(), &end);
  if (t.empty() || *end ||
      (t.find_first_of("xX") == std::string::npos && t.find_first_of("iInN") == std::string::npos))
    throw FormatError("bad number '" + t + "'; expected a decimal number (e.g. 1.5, -2e-3, inf, nan) or 0x bits");
  return from_double(f, d).bits;
}

}  // namespace ru::num
