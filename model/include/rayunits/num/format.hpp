// rayunits: runtime-parameterized IEEE-754-style binary floating-point format.
//
// A value is a raw bit pattern held in the low 1+E+M bits of a uint64_t:
//   [sign | E-bit biased exponent | M-bit stored fraction], bias = 2^(E-1)-1.
// Semantics (the contract the RTL units implement bit for bit) are documented in
// docs/FORMAT.md; the short version:
//   * rounding RNE (default), RTZ, RDN, RUP; tininess is detected AFTER rounding;
//   * every NaN result is the canonical quiet NaN: sign 0, exponent all ones,
//     fraction MSB set, all other fraction bits 0;
//   * flush-to-zero formats (-ftz): subnormal inputs read as zero of the same sign
//     (no flag); a result whose value rounded with unbounded exponent is below the
//     smallest normal becomes zero of the same sign and raises underflow+inexact.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ru::num {

enum class Round : uint8_t { RNE = 0, RTZ = 1, RDN = 2, RUP = 3 };

// Flag bits, same order as the RTL's flags_o = {invalid, divzero, overflow, underflow, inexact}.
enum FlagBit : uint8_t {
  kInexact = 1u << 0,
  kUnderflow = 1u << 1,
  kOverflow = 1u << 2,
  kDivZero = 1u << 3,
  kInvalid = 1u << 4,
};

// Thrown for invalid format names/parameters and bad option values. what() is one line.
class FormatError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct Format {
  int exp_bits = 8;         // E in [2, 11]
  int frac_bits = 23;       // M in [1, 52]
  bool subnormals = true;   // false: flush-to-zero ("-ftz")
  Round round = Round::RNE;

  static constexpr int kMinExp = 2, kMaxExp = 11, kMinFrac = 1, kMaxFrac = 52, kMaxWidth = 64;

  // Parses "eXmY" or "eXmY-ftz" (rounding stays RNE). Throws FormatError.
  static Format parse(std::string_view name);
  // Throws FormatError if the parameters are out of range.
  void validate() const;
  // "e7m16" or "e7m16-ftz" (the rounding mode is not part of the name).
  std::string name() const;

  int width() const { return 1 + exp_bits + frac_bits; }
  int bias() const { return (1 << (exp_bits - 1)) - 1; }
  int emax() const { return bias(); }      // largest unbiased exponent of a finite value
  int emin() const { return 1 - bias(); }  // unbiased exponent of the smallest normal
  uint64_t mask() const { return width() == 64 ? ~0ull : ((1ull << width()) - 1); }
  uint64_t frac_mask() const { return (1ull << frac_bits) - 1; }
  uint64_t exp_field_max() const { return (1ull << exp_bits) - 1; }
  uint64_t sign_bit() const { return 1ull << (exp_bits + frac_bits); }

  // Distinguished bit patterns.
  uint64_t pos_zero() const { return 0; }
  uint64_t neg_zero() const { return sign_bit(); }
  uint64_t inf(bool neg = false) const { return (neg ? sign_bit() : 0) | (exp_field_max() << frac_bits); }
  uint64_t qnan() const { return inf() | (1ull << (frac_bits - 1)); }  // canonical NaN
  uint64_t max_finite(bool neg = false) const { return inf(neg) - 1; }
  uint64_t min_normal(bool neg = false) const { return (neg ? sign_bit() : 0) | (1ull << frac_bits); }
  uint64_t min_subnormal(bool neg = false) const { return (neg ? sign_bit() : 0) | 1; }
  uint64_t one() const { return static_cast<uint64_t>(bias()) << frac_bits; }

  bool operator==(const Format& o) const {
    return exp_bits == o.exp_bits && frac_bits == o.frac_bits && subnormals == o.subnormals &&
           round == o.round;
  }
  bool operator!=(const Format& o) const { return !(*this == o); }
};

const char* round_name(Round r);          // "rne", "rtz", "rdn", "rup"
Round parse_round(std::string_view name);  // throws FormatError
std::string flags_letters(uint8_t flags);  // "izoux" subset in that order, "-" when none

struct Result {
  uint64_t bits = 0;
  uint8_t flags = 0;
};

// Arithmetic: every op uses f.round and f.subnormals. Operands must fit in f.width() bits.
// add, sub, mul, div, sqrt and fma are inline (fast paths in rayunits/num/detail/fast_paths.hpp
// and detail/double_paths.hpp, general path in softfloat.cpp; bit for bit the same).
inline Result add(const Format& f, uint64_t a, uint64_t b);
inline Result sub(const Format& f, uint64_t a, uint64_t b);
inline Result mul(const Format& f, uint64_t a, uint64_t b);
inline Result div(const Format& f, uint64_t a, uint64_t b);
inline Result sqrt(const Format& f, uint64_t a);
inline Result fma(const Format& f, uint64_t a, uint64_t b, uint64_t c);  // a*b+c, one rounding
// 3-term dot product as the RTL builds it (two rounding levels, not fused):
//   p_i = round(a_i*b_i);  y = round(round(p0 + p1) + p2); flags are the OR of all five ops.
Result dot3(const Format& f, const uint64_t a[3], const uint64_t b[3]);
// Fused 3-term dot product: round(a0*b0 + a1*b1 + a2*b2), the exact sum rounded once; flags of
// that one rounding (docs/FORMAT.md gives the special cases). What rtl/ru_fp_dot3_fused.sv builds.
Result dot3_fused(const Format& f, const uint64_t a[3], const uint64_t b[3]);

// min/max: IEEE 754-2008 minNum/maxNum: a NaN operand is ignored (both NaN: canonical NaN),
// -0 < +0, invalid only for a signaling NaN operand. FTZ formats flush subnormal operands first.
// min, max, lt and le are inline (two non-NaN operands decided in detail/fast_paths.hpp, the
// NaN cases in softfloat.cpp).
inline Result min(const Format& f, uint64_t a, uint64_t b);
inline Result max(const Format& f, uint64_t a, uint64_t b);
// Comparisons return bits 1 or 0. lt/le are signaling (invalid on any NaN operand);
// eq and unordered are quiet (invalid only on a signaling NaN).
inline Result lt(const Format& f, uint64_t a, uint64_t b);
inline Result le(const Format& f, uint64_t a, uint64_t b);
Result eq(const Format& f, uint64_t a, uint64_t b);
Result unordered(const Format& f, uint64_t a, uint64_t b);
uint64_t abs(const Format& f, uint64_t a);  // clears the sign bit, no flags, no flushing
uint64_t neg(const Format& f, uint64_t a);  // flips the sign bit, no flags, no flushing

// Conversions. from_double rounds correctly (flags as for an arithmetic result; a double NaN
// gives the canonical NaN, invalid if it was signaling). to_double is exact (every format value
// is a double); FTZ formats read subnormals as zero.
Result from_double(const Format& f, double x);
double to_double(const Format& f, uint64_t a);
Result from_int(const Format& f, int64_t x);
struct IntResult {
  int64_t value = 0;
  uint8_t flags = 0;
};
// Rounds with mode r. NaN -> INT64_MAX, out of range -> saturated; both raise invalid only.
IntResult to_int(const Format& f, uint64_t a, Round r);
// The same for an int_w-bit two's complement integer (1 <= int_w <= 64): the value is rounded
// first, then a result outside [-2^(int_w-1), 2^(int_w-1) - 1] saturates with invalid only
// (NaN -> the largest value), as IEEE 754 convertToInteger with saturation (RISC-V fcvt.w).
IntResult to_int(const Format& f, uint64_t a, Round r, int int_w);
// Format-to-format conversion: a (a value of `from`; an FTZ `from` reads subnormals as zero)
// rounded once into `to` (to.round, to.subnormals): overflow, underflow and inexact as for an
// arithmetic result; NaN -> the canonical NaN of `to` (invalid if a was signaling); +-INF and
// +-0 keep their sign. Exact when `to` holds every value of `from`.
Result convert(const Format& to, const Format& from, uint64_t a);

enum class Class : uint8_t {
  NegInf, NegNormal, NegSubnormal, NegZero, PosZero, PosSubnormal, PosNormal, PosInf, SNaN, QNaN
};
Class classify(const Format& f, uint64_t a);  // raw classification (no flushing)
const char* class_name(Class c);
inline bool is_nan(const Format& f, uint64_t a) {
  return ((a >> f.frac_bits) & f.exp_field_max()) == f.exp_field_max() && (a & f.frac_mask()) != 0;
}

// Operation names used by the CLI (--batch), the harness and the reports.
enum class Op : uint8_t { Add, Sub, Mul, Div, Sqrt, Fma, Min, Max, Lt, Le, Eq };
Op parse_op(std::string_view name);  // throws FormatError naming the accepted ops
const char* op_name(Op op);
int op_arity(Op op);  // 1, 2 or 3
Result apply(const Format& f, Op op, uint64_t a, uint64_t b = 0, uint64_t c = 0);

// Parses a decimal number (rounded into f) or a raw bit pattern "0x..." (must fit the width).
// Throws FormatError with a one-line message on bad input.
uint64_t parse_operand(const Format& f, std::string_view text);

}  // namespace ru::num

#include "rayunits/num/detail/fast_paths.hpp"
