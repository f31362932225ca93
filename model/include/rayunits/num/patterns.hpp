// Test-vector generators for the number formats (used by tests/num and the RTL testbenches).
//
// special_values(): the TestFloat scheme ported to any (E, M): signed zeros, the smallest and
// largest subnormal / normal, infinities, quiet and signaling NaNs, 1.0 and its neighbours, and
// significands 0 / 1 / MSB / all-ones / all-ones-1 at the exponent edges and around 1.0.
//
// OperandGen: a deterministic weighted mix of special values, uniformly random bit patterns,
// random finite values with structured significands, and operand pairs/triples built to hit
// the hard cases of each operation: exponent differences 0, 1, M, M+1, M+2, > M+3, exact and
// near rounding ties (add, mul, div, sqrt, fma), cancellation (b ~ -a, c ~ -a*b), and
// products/quotients at the overflow and underflow thresholds.
//
// Determinism: the sequence depends only on the format's (E, M) and the seed (xoshiro256**
// of util/rng.hpp seeded by splitmix64, integer arithmetic only), so it is identical on every host and
// compiler. The rounding mode and the subnormal setting do not change the sequence.
#pragma once

#include <cstdint>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::num {

// Distinct special bit patterns of f, in a fixed order. Every pattern fits f.width() bits.
std::vector<uint64_t> special_values(const Format& f);

class OperandGen {
 public:
  OperandGen(const Format& f, uint64_t seed);
  // One operand (for unary ops and as a building block).
  uint64_t next();
  // Two operands for add/sub/mul/div/min/max/compare.
  void pair(uint64_t& a, uint64_t& b);
  // Three operands for fma (a*b+c).
  void triple(uint64_t& a, uint64_t& b, uint64_t& c);
  // One sqrt operand over the whole exponent range (subnormals included), 10 % negative: an
  // exact square of a short significand, or the square of an (M+2)-bit odd number (a rounding
  // midpoint: the root lands next to a tie), half of those moved by one ulp.
  uint64_t sqrt_case();
  // Two 3-vectors for the dot products (dot3, dot3_fused): independent pairs; a product pair
  // cancelling exactly (p1 = -p0, also with the operands' exponents traded so the products'
  // significands differ by a factor 2) beside a third product of any size; the two smaller
  // products cancelling each other (exactly or nearly) below a large one; near cancellation
  // (one ulp apart); products whose exponents differ by 0..3, around 2M+5 and around 4M+6
  // (the alignment limits of rtl/ru_fp_dot3_fused.sv); special values mixed in.
  void dot3(uint64_t a[3], uint64_t b[3]);

 private:
  uint64_t rnd();                 // xoshiro256** (util/rng.hpp)
  uint64_t below(uint64_t n);     // uniform in [0, n), n > 0
  bool chance(unsigned percent);  // true with probability percent/100
  uint64_t pack(bool neg, uint64_t bexp, uint64_t frac) const;
  uint64_t structured_frac();  // TestFloat-like significand shapes
  uint64_t random_finite();
  uint64_t random_normal_exp(int64_t bexp);  // normal (or clamped) value with biased exponent
  int64_t normal_bexp();                     // biased exponent of a random normal, edge-weighted
  // Value sig * 2^exp2 truncated to M+1 bits; ok=false if it is not a finite nonzero value
  // of the format (overflow / below the smallest subnormal).
  uint64_t from_sig(bool neg, unsigned __int128 sig, int64_t exp2, bool& ok) const;
  uint64_t step(uint64_t x, int64_t ulps) const;  // move by whole bit-pattern steps, same sign
  // Decompose a finite nonzero value into integer significand and exponent (x = sig*2^exp2).
  void unpack(uint64_t x, uint64_t& sig, int64_t& exp2) const;
  uint64_t odd_with_bits(int bits);  // random odd integer with exactly `bits` bits
  uint64_t sig_with_bits(int bits);  // random integer with exactly `bits` bits

  void pair_expdiff(uint64_t& a, uint64_t& b);
  void pair_add_tie(uint64_t& a, uint64_t& b);
  void pair_cancel(uint64_t& a, uint64_t& b);
  void pair_threshold(uint64_t& a, uint64_t& b, bool quotient);
  void pair_mul_tie(uint64_t& a, uint64_t& b);
  void pair_near_pow2(uint64_t& a, uint64_t& b);
  void pair_div_near_tie(uint64_t& a, uint64_t& b);
  void pair_div_exact(uint64_t& a, uint64_t& b);
  void triple_cancel(uint64_t& a, uint64_t& b, uint64_t& c);
  void triple_expdiff(uint64_t& a, uint64_t& b, uint64_t& c);

  int E_, M_;
  int64_t bias_, emin_, emax_, max_bexp_;  // max_bexp_: largest biased exponent of a finite value
  uint64_t frac_mask_, sign_bit_;
  std::vector<uint64_t> specials_;
  util::Xoshiro256ss rng_;
};

}  // namespace ru::num
