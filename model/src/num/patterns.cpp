// Test-vector generators (see patterns.hpp). Integer arithmetic only, own PRNG: the output
// depends on (E, M, seed) alone and is the same on every host.
#include "rayunits/num/patterns.hpp"

#include <algorithm>
#include <unordered_set>

namespace ru::num {

namespace {

using u128 = unsigned __int128;

int bitlen128(u128 x) {
  int n = 0;
  while (x >> 64) {
    x >>= 64;
    n += 64;
  }
  uint64_t lo = static_cast<uint64_t>(x);
  return lo ? n + 64 - __builtin_clzll(lo) : n;
}

}  // namespace

std::vector<uint64_t> special_values(const Format& f) {
  const int E = f.exp_bits, M = f.frac_bits;
  const uint64_t sign = 1ull << (E + M);
  const uint64_t fmask = (1ull << M) - 1;
  const uint64_t emax_field = (1ull << E) - 1;  // all ones: INF/NaN
  const uint64_t max_bexp = emax_field - 1;     // largest biased exponent of a finite value
  const uint64_t bias = (1ull << (E - 1)) - 1;
  const uint64_t msb = 1ull << (M - 1);
  auto pack = [&](uint64_t bexp, uint64_t frac) { return (bexp << M) | (frac & fmask); };

  std::vector<uint64_t> mags;  // positive patterns; each is emitted with both signs
  // Zero and the subnormals: min, 2*min, max, max-1, MSB only, MSB|1.
  mags.push_back(0);
  for (uint64_t fr : {uint64_t{1}, uint64_t{2}, fmask, fmask - 1, msb, msb | 1}) {
    if (fr != 0 && fr <= fmask) mags.push_back(pack(0, fr));
  }
  // Normals: the smallest, the largest, and significands 0 / 1 / MSB / all-ones / all-ones-1 at
  // the exponent edges and around 1.0 (exponent fields 1, 2, bias-1, bias, bias+1, max-1, max).
  std::vector<uint64_t> exps = {1, 2, bias - 1, bias, bias + 1, max_bexp - 1, max_bexp};
  if (max_bexp > 8) exps.push_back((bias + 1 + max_bexp) / 2), exps.push_back((1 + bias) / 2);
  for (uint64_t e : exps) {
    if (e < 1 || e > max_bexp) continue;
    for (uint64_t fr : {uint64_t{0}, uint64_t{1}, fmask, fmask - 1, msb, msb | 1, fmask >> 1}) {
      if (fr <= fmask) mags.push_back(pack(e, fr));
    }
  }
  // 1.5, 3.0 (if finite), infinity, NaNs.
  if (bias + 1 <= max_bexp) mags.push_back(pack(bias + 1, msb));
  mags.push_back(pack(emax_field, 0));      // INF
  mags.push_back(pack(emax_field, msb));    // canonical quiet NaN
  mags.push_back(pack(emax_field, fmask));  // quiet NaN, full payload
  if (M >= 2) {
    mags.push_back(pack(emax_field, 1));           // signaling NaN, smallest payload
    mags.push_back(pack(emax_field, fmask >> 1));  // signaling NaN, largest payload
  }

  std::vector<uint64_t> out;
  std::unordered_set<uint64_t> seen;
  auto add = [&](uint64_t x) {
    if (seen.insert(x).second) out.push_back(x);
  };
  for (uint64_t m : mags) {
    add(m);
    add(m | sign);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

OperandGen::OperandGen(const Format& f, uint64_t seed)
    : E_(f.exp_bits),
      M_(f.frac_bits),
      bias_((int64_t{1} << (f.exp_bits - 1)) - 1),
      emin_(1 - bias_),
      emax_(bias_),
      max_bexp_((int64_t{1} << f.exp_bits) - 2),
      frac_mask_((1ull << f.frac_bits) - 1),
      sign_bit_(1ull << (f.exp_bits + f.frac_bits)),
      specials_(special_values(f)),
      // Mix the format into the seed so different formats get unrelated streams.
      rng_(seed ^ (static_cast<uint64_t>(f.exp_bits) << 56) ^ (static_cast<uint64_t>(f.frac_bits) << 48)) {}

uint64_t OperandGen::rnd() { return rng_.next(); }

// Lemire's multiply-shift with rejection: exact and host independent.
uint64_t OperandGen::below(uint64_t n) { return util::bounded_lemire(rng_, n); }

bool OperandGen::chance(unsigned percent) { return below(100) < percent; }

uint64_t OperandGen::pack(bool neg, uint64_t bexp, uint64_t frac) const {
  return (neg ? sign_bit_ : 0) | (bexp << M_) | (frac & frac_mask_);
}

uint64_t OperandGen::structured_frac() {
  const uint64_t all = frac_mask_;
  if (chance(30)) return rnd() & all;
  switch (below(12)) {
    case 0:
      return 0;
    case 1:
      return 1;
    case 2:
      return all;
    case 3:
      return all - 1;
    case 4:
      return 1ull << (M_ - 1);
    case 5:
      return (1ull << (M_ - 1)) | 1;
    case 6: {  // a run of ones [i, j)
      uint64_t i = below(M_ + 1), j = below(M_ + 1);
      if (i > j) std::swap(i, j);
      return ((j >= 64 ? ~0ull : (1ull << j) - 1) & ~((1ull << i) - 1)) & all;
    }
    case 7: {  // all ones with a run of zeros [i, j)
      uint64_t i = below(M_ + 1), j = below(M_ + 1);
      if (i > j) std::swap(i, j);
      return all & ~((j >= 64 ? ~0ull : (1ull << j) - 1) & ~((1ull << i) - 1));
    }
    case 8: {  // a few random bits set
      uint64_t v = 0;
      for (uint64_t k = 1 + below(3); k > 0; --k) v |= 1ull << below(M_);
      return v;
    }
    case 9: {  // all ones with a few bits cleared
      uint64_t v = all;
      for (uint64_t k = 1 + below(3); k > 0; --k) v &= ~(1ull << below(M_));
      return v;
    }
    case 10:
      return below(16) & all;
    default:
      return all - (below(16) & all);
  }
}

int64_t OperandGen::normal_bexp() {
  if (chance(50)) return 1 + static_cast<int64_t>(below(max_bexp_));
  const int64_t edges[] = {
      1, 2, 3, bias_ - 2, bias_ - 1, bias_, bias_ + 1, bias_ + 2, max_bexp_ - 2, max_bexp_ - 1, max_bexp_};
  return std::clamp<int64_t>(edges[below(std::size(edges))], 1, max_bexp_);
}

uint64_t OperandGen::random_finite() {
  const bool neg = chance(50);
  if (chance(15)) return pack(neg, 0, structured_frac());  // subnormal (or zero)
  return pack(neg, normal_bexp(), structured_frac());
}

uint64_t OperandGen::random_normal_exp(int64_t u) {
  // A value with unbiased exponent u and a structured significand; below the normal range it
  // is truncated into a subnormal (or zero), above it clamps to the largest finite value.
  const bool neg = chance(50);
  if (u > emax_) return pack(neg, max_bexp_, frac_mask_);
  if (u >= emin_) return pack(neg, u + bias_, structured_frac());
  bool ok = false;
  uint64_t v = from_sig(neg, (1ull << M_) | structured_frac(), u - M_, ok);
  return ok ? v : pack(neg, 0, 0);
}

uint64_t OperandGen::from_sig(bool neg, u128 sig, int64_t exp2, bool& ok) const {
  ok = false;
  if (sig == 0) return 0;
  const int n = bitlen128(sig);
  if (n > M_ + 1) {
    sig >>= (n - (M_ + 1));
    exp2 += n - (M_ + 1);
  } else {
    sig <<= (M_ + 1 - n);
    exp2 -= (M_ + 1 - n);
  }
  const int64_t lead = exp2 + M_;
  if (lead > emax_) return 0;
  if (lead >= emin_) {
    ok = true;
    return pack(neg, static_cast<uint64_t>(lead + bias_), static_cast<uint64_t>(sig));
  }
  const int64_t sh = (emin_ - M_) - exp2;  // > 0
  if (sh > M_) return 0;
  const uint64_t s = static_cast<uint64_t>(sig >> sh);
  if (s == 0) return 0;
  ok = true;
  return pack(neg, 0, s);
}

uint64_t OperandGen::step(uint64_t x, int64_t ulps) const {
  const uint64_t s = x & sign_bit_;
  const int64_t mag = static_cast<int64_t>(x & ~sign_bit_);
  const int64_t maxmag = static_cast<int64_t>(pack(false, max_bexp_, frac_mask_));
  return s | static_cast<uint64_t>(std::clamp<int64_t>(mag + ulps, 0, maxmag));
}

void OperandGen::unpack(uint64_t x, uint64_t& sig, int64_t& exp2) const {
  const int64_t bexp = static_cast<int64_t>((x >> M_) & ((1ull << E_) - 1));
  const uint64_t frac = x & frac_mask_;
  if (bexp == 0) {
    sig = frac;
    exp2 = emin_ - M_;
  } else {
    sig = frac | (1ull << M_);
    exp2 = bexp - bias_ - M_;
  }
}

uint64_t OperandGen::sig_with_bits(int bits) {
  if (bits <= 0) return 0;
  const uint64_t top = 1ull << (bits - 1);
  return top | (rnd() & (top - 1));
}

uint64_t OperandGen::odd_with_bits(int bits) { return sig_with_bits(bits) | 1; }

// ---------------------------------------------------------------------------------------------

uint64_t OperandGen::next() {
  const uint64_t k = below(100);
  if (k < 20) return specials_[below(specials_.size())];
  if (k < 40) return rnd() & (sign_bit_ | (sign_bit_ - 1));
  if (k < 80) return random_finite();
  if (k < 88)
    return pack(chance(50), std::clamp<int64_t>(bias_ - 1 + below(3), 1, max_bexp_), structured_frac());
  return sqrt_case();
}

uint64_t OperandGen::sqrt_case() {
  const bool neg = chance(10);
  // Target unbiased exponent of the value, over the whole range including subnormals.
  const int64_t lo = emin_ - M_, hi = emax_;
  const int64_t L = lo + static_cast<int64_t>(below(static_cast<uint64_t>(hi - lo + 1)));
  bool ok = false;
  uint64_t v = 0;
  if (chance(40)) {  // exact square of a short significand
    const int k = 1 + static_cast<int>(below((M_ + 2) / 2));
    const u128 r = sig_with_bits(k);
    const u128 sq = r * r;
    int64_t e = (L - (bitlen128(sq) - 1)) / 2;  // value = sq * 2^(2e)
    v = from_sig(neg, sq, 2 * e, ok);
  } else {  // square of a midpoint of the (M+1)-bit grid: sqrt lands next to a tie
    const u128 r = odd_with_bits(M_ + 2);
    const u128 sq = r * r;  // <= 2M+4 <= 108 bits
    int64_t e = (L - (bitlen128(sq) - 1)) / 2;
    v = from_sig(neg, sq, 2 * e, ok);
    if (ok && chance(50)) v = step(v, chance(50) ? 1 : -1);
  }
  return ok ? v : random_finite();
}

void OperandGen::pair(uint64_t& a, uint64_t& b) {
  const uint64_t k = below(100);
  if (k < 16) {
    a = next();
    b = next();
  } else if (k < 22) {
    a = specials_[below(specials_.size())];
    b = random_finite();
    if (chance(50)) std::swap(a, b);
  } else if (k < 40) {
    pair_expdiff(a, b);
  } else if (k < 50) {
    pair_add_tie(a, b);
  } else if (k < 61) {
    pair_cancel(a, b);
  } else if (k < 70) {
    pair_threshold(a, b, false);
  } else if (k < 75) {
    pair_threshold(a, b, true);
  } else if (k < 81) {
    pair_near_pow2(a, b);
  } else if (k < 89) {
    pair_mul_tie(a, b);
  } else if (k < 96) {
    pair_div_near_tie(a, b);
  } else {
    pair_div_exact(a, b);
  }
}

void OperandGen::pair_near_pow2(uint64_t& a, uint64_t& b) {
  // ma * mb just below (or above) 2^(2M+1): the product sits next to the power of two 2^(T+1),
  // where T is the smallest normal's binade minus one (rounds up into the normal range?), the
  // largest binade (rounds up to overflow?) or random.
  int64_t T;
  const uint64_t r = below(10);
  if (r < 4)
    T = emin_ - 1;
  else if (r < 7)
    T = emax_;
  else
    T = emin_ + static_cast<int64_t>(below(static_cast<uint64_t>(emax_ - emin_ + 1)));
  const int64_t lo = std::max(emin_, T - emax_), hi = std::min(emax_, T - emin_);
  if (lo > hi) {
    pair_threshold(a, b, false);
    return;
  }
  const uint64_t top = uint64_t{1} << M_;
  const u128 ma = top | structured_frac();
  const u128 p = u128{1} << (2 * M_ + 1);
  u128 mb = chance(70) ? p / ma : (p + ma - 1) / ma;  // below / above the power of two
  if (mb >= (u128{2} << M_)) mb = (u128{2} << M_) - 1;
  if (mb < top) mb = top;
  const int64_t ua = lo + static_cast<int64_t>(below(static_cast<uint64_t>(hi - lo + 1)));
  const bool neg = chance(50);
  a = pack(neg, static_cast<uint64_t>(ua + bias_), static_cast<uint64_t>(ma));
  b = pack(chance(50) ? neg : !neg, static_cast<uint64_t>(T - ua + bias_), static_cast<uint64_t>(mb));
  if (chance(25)) a = step(a, chance(50) ? 1 : -1);
  if (chance(50)) std::swap(a, b);
}

void OperandGen::pair_expdiff(uint64_t& a, uint64_t& b) {
  const int64_t ds[] = {0,
                        1,
                        M_,
                        M_ + 1,
                        M_ + 2,
                        M_ + 3 + static_cast<int64_t>(below(M_ + 8)),
                        2 * M_ + 3 + static_cast<int64_t>(below(64))};
  const int64_t d = ds[below(std::size(ds))];
  const int64_t ea = normal_bexp();
  a = pack(chance(50), ea, structured_frac());
  int64_t eb = chance(50) ? ea - d : ea + d;
  if (eb > max_bexp_) eb = ea - d;
  if (eb >= 1) {
    b = pack(chance(50), std::min(eb, max_bexp_), structured_frac());
  } else {
    b = random_normal_exp(eb - bias_);  // below the normal range: subnormal or zero
  }
  if (chance(50)) std::swap(a, b);
}

void OperandGen::pair_add_tie(uint64_t& a, uint64_t& b) {
  // b is (close to) half an ulp of a, or a quarter / three quarters of it.
  const int64_t ea = normal_bexp();
  a = pack(chance(50), ea, structured_frac());
  const int64_t ulp_exp = ea - bias_ - M_;  // a's ulp is 2^ulp_exp
  const int k = static_cast<int>(below(M_ + 1));
  u128 sig = u128{1} << k;
  int64_t exp2 = ulp_exp - 1 - k;  // sig*2^exp2 = half ulp
  switch (below(6)) {
    case 0:
      break;
    case 1:
      sig += 1;
      break;
    case 2:
      sig -= (k > 0 ? 1 : 0);
      break;
    case 3:
      sig = 3;
      exp2 = ulp_exp - 2;
      break;  // three quarters of an ulp
    case 4:
      sig = 1;
      exp2 = ulp_exp - 2;
      break;  // a quarter of an ulp
    default:
      sig = (u128{1} << (k + 1)) + 3;
      exp2 = ulp_exp - 2 - k;
      break;  // just above half
  }
  bool ok = false;
  b = from_sig(chance(50), sig, exp2, ok);
  if (!ok) b = random_finite();
  if (chance(50)) std::swap(a, b);
}

void OperandGen::pair_cancel(uint64_t& a, uint64_t& b) {
  a = random_finite();
  b = chance(50) ? a ^ sign_bit_ : a;  // b = -a (for add) or b = a (for sub)
  switch (below(5)) {
    case 0:
      break;
    case 1:
      b = step(b, chance(50) ? 1 : -1);
      break;
    case 2:
      b = step(b, chance(50) ? 2 : -2);
      break;
    case 3:
      b = step(b, static_cast<int64_t>(below(64)) - 32);
      break;
    default:  // same exponent, random significand
      b = (b & ~frac_mask_) | structured_frac();
      break;
  }
  if (chance(50)) std::swap(a, b);
}

void OperandGen::pair_threshold(uint64_t& a, uint64_t& b, bool quotient) {
  // Unbiased exponent T of the exact product / quotient at the overflow or underflow threshold.
  const int64_t targets[] = {emax_,      emax_ + 1,      emax_ - 1,      emin_,         emin_ - 1,
                             emin_ - M_, emin_ - M_ - 1, emin_ - M_ - 2, emin_ - M_ / 2};
  const int64_t T = targets[below(std::size(targets))];
  // a and b normal: ua in [emin, emax], ub = T - ua (product) or ua - T (quotient) in range too.
  int64_t lo, hi;
  if (!quotient) {
    lo = std::max(emin_, T - emax_);
    hi = std::min(emax_, T - emin_);
  } else {
    lo = std::max(emin_, emin_ + T);
    hi = std::min(emax_, emax_ + T);
  }
  int64_t ua, ub;
  if (lo <= hi && chance(85)) {
    ua = lo + static_cast<int64_t>(below(static_cast<uint64_t>(hi - lo + 1)));
  } else {  // allow a subnormal operand
    ua = emin_ - static_cast<int64_t>(below(M_ + 1)) + (quotient ? 0 : T - emin_);
    ua = std::clamp<int64_t>(ua, emin_ - M_, emax_);
  }
  ub = quotient ? ua - T : T - ua;
  a = random_normal_exp(ua);
  b = random_normal_exp(ub);
  if (!quotient && chance(50)) std::swap(a, b);
}

void OperandGen::pair_mul_tie(uint64_t& a, uint64_t& b) {
  // Odd x (kx bits) * odd y (ky bits): a product of exactly M+2 bits is an exact tie.
  int target;
  switch (below(4)) {
    case 0:
    case 1:
      target = M_ + 2;
      break;
    case 2:
      target = M_ + 3;
      break;
    default:
      target = 2 + static_cast<int>(below(M_ + 1));
      break;
  }
  const int kx = 1 + static_cast<int>(below(std::min(M_ + 1, target)));
  const int ky = std::clamp(target - kx + static_cast<int>(below(2)), 1, M_ + 1);
  const u128 x = odd_with_bits(kx), y = odd_with_bits(ky);
  // Unbiased exponent of the product: normal range, subnormal range, or near overflow.
  int64_t T;
  const uint64_t r = below(10);
  if (r < 5)
    T = emin_ + static_cast<int64_t>(below(static_cast<uint64_t>(emax_ - emin_ + 1)));
  else if (r < 8)
    T = emin_ - 1 - static_cast<int64_t>(below(M_ + 1));
  else
    T = emax_ - static_cast<int64_t>(below(2));
  const int64_t lo = std::max(emin_ - M_, T - emax_), hi = std::min(emax_, T - (emin_ - M_));
  if (lo > hi) {
    a = next();
    b = next();
    return;
  }
  const int64_t ua = lo + static_cast<int64_t>(below(static_cast<uint64_t>(hi - lo + 1)));
  const int64_t ub = T - ua;
  bool oka = false, okb = false;
  a = from_sig(chance(50), x, ua - (kx - 1), oka);
  b = from_sig(chance(50), y, ub - (ky - 1), okb);
  if (!oka || !okb) {
    a = next();
    b = next();
    return;
  }
  if (chance(25)) a = step(a, chance(50) ? 1 : -1);
  if (chance(50)) std::swap(a, b);
}

void OperandGen::pair_div_near_tie(uint64_t& a, uint64_t& b) {
  // a = b * q' (truncated), q' an odd midpoint of the quotient grid: a/b lies next to a tie.
  const int qbits = chance(70) ? M_ + 2 : 2 + static_cast<int>(below(M_ + 1));
  const u128 q = odd_with_bits(qbits);
  const u128 mb = (u128{1} << M_) | structured_frac();
  int64_t T;  // unbiased exponent of the quotient
  const uint64_t r = below(10);
  if (r < 5)
    T = emin_ + static_cast<int64_t>(below(static_cast<uint64_t>(emax_ - emin_ + 1)));
  else if (r < 8)
    T = emin_ - 1 - static_cast<int64_t>(below(M_ + 1));
  else
    T = emax_;
  const int64_t lo = std::max(emin_, emin_ - M_ + T), hi = std::min(emax_, emax_ + T);
  if (lo > hi) {
    pair_threshold(a, b, true);
    return;
  }
  const int64_t ua = lo + static_cast<int64_t>(below(static_cast<uint64_t>(hi - lo + 1)));
  const int64_t ub = ua - T;
  bool oka = false, okb = false;
  b = from_sig(chance(50), mb, ub - M_, okb);
  // a = mb*q * 2^(ub - M + T - (qbits-1)): value b*q'*2^(T-qbits+1).
  a = from_sig(chance(50), mb * q, ub - M_ + T - (qbits - 1), oka);
  if (!oka || !okb) {
    pair_threshold(a, b, true);
    return;
  }
  if (chance(50)) a = step(a, static_cast<int64_t>(below(3)) - 1);
}

void OperandGen::pair_div_exact(uint64_t& a, uint64_t& b) {
  const int kb = 1 + static_cast<int>(below(M_ + 1));
  const int kq = 1 + static_cast<int>(below(static_cast<uint64_t>(M_ + 2 - kb)));
  const u128 mb = sig_with_bits(kb), q = sig_with_bits(kq);
  const int64_t ub = emin_ + static_cast<int64_t>(below(static_cast<uint64_t>(emax_ - emin_ + 1)));
  const int64_t T = emin_ - M_ + static_cast<int64_t>(below(static_cast<uint64_t>(emax_ - emin_ + M_ + 1)));
  bool oka = false, okb = false;
  b = from_sig(chance(50), mb, ub - (kb - 1), okb);
  a = from_sig(chance(50), mb * q, ub - (kb - 1) + T - (kq - 1), oka);
  if (!oka || !okb) pair_threshold(a, b, true);
}

// ---------------------------------------------------------------------------------------------

void OperandGen::triple(uint64_t& a, uint64_t& b, uint64_t& c) {
  const uint64_t k = below(100);
  auto small_c = [&]() -> uint64_t {
    switch (below(4)) {
      case 0:
        return chance(50) ? pack(false, 0, 0) : pack(true, 0, 0);
      case 1:
        return pack(chance(50), 0, 1 + below(2));  // tiny: mostly only changes the sticky
      case 2:
        return random_normal_exp(emin_ + static_cast<int64_t>(below(3)));
      default:
        return next();
    }
  };
  if (k < 18) {
    a = next();
    b = next();
    c = next();
  } else if (k < 27) {
    pair(a, b);
    c = next();
  } else if (k < 50) {
    triple_cancel(a, b, c);
  } else if (k < 65) {
    triple_expdiff(a, b, c);
  } else if (k < 77) {
    pair_threshold(a, b, false);
    c = small_c();
  } else if (k < 88) {
    pair_near_pow2(a, b);
    c = small_c();
  } else {
    pair_mul_tie(a, b);
    c = small_c();
  }
}

void OperandGen::dot3(uint64_t a[3], uint64_t b[3]) {
  const uint64_t k = below(100);
  for (int i = 0; i < 3; ++i) pair(a[i], b[i]);
  // products with unbiased exponents T - delta_i (operands split at random), delta_0 = 0
  auto at_exponents = [&](const int64_t d1, const int64_t d2) {
    const int64_t T = emin_ + static_cast<int64_t>(below(static_cast<uint64_t>(2 * (emax_ - emin_) + 1)));
    const int64_t d[3] = {0, d1, d2};
    for (int i = 0; i < 3; ++i) {
      const int64_t t = T - d[i];
      const int64_t lo = std::max(emin_ - M_, t - emax_), hi = std::min(emax_, t - emin_ + M_);
      const int64_t ua = lo > hi ? t / 2 : lo + static_cast<int64_t>(below(static_cast<uint64_t>(hi - lo + 1)));
      a[i] = random_normal_exp(ua);
      b[i] = random_normal_exp(t - ua);
    }
  };
  auto delta = [&]() -> int64_t {
    switch (below(4)) {
      case 0: return static_cast<int64_t>(below(4));
      case 1: return 2 * M_ + 2 + static_cast<int64_t>(below(7));
      case 2: return 4 * M_ + 3 + static_cast<int64_t>(below(7));
      default: return static_cast<int64_t>(below(static_cast<uint64_t>(6 * M_ + 12)));
    }
  };
  if (k < 20) {
    return;  // independent pairs
  } else if (k < 35) {  // p1 = -p0 exactly; p2 anything
    if (chance(50)) at_exponents(0, delta());
    a[1] = a[0];
    b[1] = b[0] ^ sign_bit_;
    if (chance(30)) {  // same product, operand exponents traded: a1 = 2 a0, b1 = -b0 / 2
      const uint64_t ea = (a[0] >> M_) & ((1ull << E_) - 1), eb = (b[0] >> M_) & ((1ull << E_) - 1);
      if (ea >= 1 && ea + 1 <= static_cast<uint64_t>(max_bexp_) && eb >= 2) {
        a[1] = a[0] + (1ull << M_);
        b[1] = (b[0] - (1ull << M_)) ^ sign_bit_;
      }
    }
  } else if (k < 45) {  // p1 = -(a0*b0) as one operand (the product exact in the format)
    uint64_t sa, sb;
    int64_t ea, eb;
    a[0] = random_normal_exp(normal_bexp() - bias_);
    b[0] = pack(chance(50), static_cast<uint64_t>(bias_ + static_cast<int64_t>(below(3)) - 1),
                (sig_with_bits(1 + static_cast<int>(below(2))) << (M_ > 1 ? M_ - 1 : 0)) & frac_mask_);
    unpack(a[0], sa, ea);
    unpack(b[0], sb, eb);
    bool ok = false;
    const uint64_t p = from_sig(((a[0] ^ b[0]) & sign_bit_) == 0, static_cast<u128>(sa) * sb, ea + eb, ok);
    if (ok) {
      a[1] = p;
      b[1] = pack(false, static_cast<uint64_t>(bias_), 0);  // 1.0
      if (chance(30)) a[1] = step(a[1], chance(50) ? 1 : -1);
    }
  } else if (k < 60) {  // p2 = -p1 (or one ulp off) far below or near p0
    at_exponents(delta(), 0);
    a[2] = a[1];
    b[2] = b[1] ^ sign_bit_;
    if (chance(30)) b[2] = step(b[2], chance(50) ? 1 : -1);
    if (chance(30)) std::swap(a[0], a[2]), std::swap(b[0], b[2]);
  } else if (k < 72) {  // p1 ~ -p0, one ulp apart
    a[1] = a[0];
    b[1] = step(b[0] ^ sign_bit_, chance(50) ? 1 : -1);
    if (chance(50)) at_exponents(0, delta()), a[1] = a[0], b[1] = step(b[0] ^ sign_bit_, 1);
  } else if (k < 95) {
    at_exponents(delta(), delta());
  } else {
    for (int i = 0; i < 3; ++i)
      if (chance(40)) (chance(50) ? a[i] : b[i]) = specials_[below(specials_.size())];
  }
  if (chance(50)) {  // permute the products
    const int i = static_cast<int>(below(3)), j = static_cast<int>(below(3));
    std::swap(a[i], a[j]);
    std::swap(b[i], b[j]);
  }
}
void OperandGen::triple_cancel(uint64_t& a, uint64_t& b, uint64_t& c) {
  // c ~ -(a*b): the exact product truncated to M+1 bits, moved by a few ulps.
  for (int attempt = 0; attempt < 4; ++attempt) {
    const int64_t T =
        emin_ - M_ / 2 + static_cast<int64_t>(below(static_cast<uint64_t>(emax_ - emin_ + M_ / 2 + 1)));
    const int64_t lo = std::max(emin_, T - emax_), hi = std::min(emax_, T - emin_);
    if (lo > hi) continue;
    const int64_t ua = lo + static_cast<int64_t>(below(static_cast<uint64_t>(hi - lo + 1)));
    a = random_normal_exp(ua);
    b = random_normal_exp(T - ua);
    uint64_t sa, sb;
    int64_t ea, eb;
    unpack(a, sa, ea);
    unpack(b, sb, eb);
    const bool pneg = ((a ^ b) & sign_bit_) != 0;
    bool ok = false;
    c = from_sig(chance(85) ? !pneg : pneg, static_cast<u128>(sa) * sb, ea + eb, ok);
    if (!ok || sa == 0 || sb == 0) continue;
    switch (below(5)) {
      case 0:
      case 1:
        break;
      case 2:
        c = step(c, chance(50) ? 1 : -1);
        break;
      case 3:
        c = step(c, static_cast<int64_t>(below(9)) - 4);
        break;
      default:
        c = (c & ~frac_mask_) | structured_frac();
        break;
    }
    if (chance(50)) std::swap(a, b);
    return;
  }
  a = next();
  b = next();
  c = next();
}

void OperandGen::triple_expdiff(uint64_t& a, uint64_t& b, uint64_t& c) {
  // c's exponent differs from the product's by 0, 1, M, M+1, M+2, 2M+1..2M+3 or more.
  const int64_t T = emin_ + static_cast<int64_t>(below(static_cast<uint64_t>(emax_ - emin_ + 1)));
  const int64_t lo = std::max(emin_, T - emax_), hi = std::min(emax_, T - emin_);
  if (lo > hi) {
    triple_cancel(a, b, c);
    return;
  }
  const int64_t ua = lo + static_cast<int64_t>(below(static_cast<uint64_t>(hi - lo + 1)));
  a = random_normal_exp(ua);
  b = random_normal_exp(T - ua);
  const int64_t ds[] = {0,
                        1,
                        M_,
                        M_ + 1,
                        M_ + 2,
                        2 * M_ + 1,
                        2 * M_ + 2,
                        2 * M_ + 3,
                        M_ + 3 + static_cast<int64_t>(below(M_ + 8)),
                        2 * M_ + 4 + static_cast<int64_t>(below(64))};
  const int64_t d = ds[below(std::size(ds))];
  const int64_t uc = chance(50) ? T - d : T + d;
  c = random_normal_exp(uc);
}

}  // namespace ru::num
