// Bit-accurate model of rtl/ru_noise.sv; see rayunits/noise/fixed.hpp and docs/NOISE.md.
#include "rayunits/noise/fixed.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace ru::noise {

void FixedConfig::validate() const {
  if (frac_bits < 4 || frac_bits > 16)
    throw std::invalid_argument("noise: fraction bits must be 4..16, got " + std::to_string(frac_bits));
  if (datapath == NoiseDatapath::kTrunc && (frac_bits < 5 || frac_bits > 12))
    throw std::invalid_argument("noise: the truncated datapath needs 5..12 fraction bits (its kernel weight is a "
                                "2^B-entry table), got " + std::to_string(frac_bits));
  if (int_bits < 1 || int_bits > 24)
    throw std::invalid_argument("noise: input integer bits must be 1..24, got " + std::to_string(int_bits));
  if (out_w < 2 || out_w > 2 * frac_bits + 6)
    throw std::invalid_argument("noise: output width must be 2.." + std::to_string(2 * frac_bits + 6) +
                                " for " + std::to_string(frac_bits) + " fraction bits, got " +
                                std::to_string(out_w));
}

std::string FixedConfig::describe() const {
  return "B=" + std::to_string(frac_bits) + " int=" + std::to_string(int_bits) + " out=" + std::to_string(out_w) +
         (datapath == NoiseDatapath::kTrunc ? " trunc" : "");
}

int narrow_gradient(std::int32_t q16, int frac_bits) {
  if (frac_bits >= 16) return q16;
  int sh = 16 - frac_bits;
  return (q16 + (1 << (sh - 1))) >> sh;  // arithmetic shift = floor
}

int narrow_gradient_clamped(std::int32_t q16, int grad_frac_bits) {
  const int m = (1 << grad_frac_bits) - 1;
  return std::clamp(narrow_gradient(q16, grad_frac_bits), -m, m);
}

namespace {

// Constant correction of a truncated array (docs/NOISE.md, "The truncated datapath"): half of
// the result's last place (round to nearest) plus the expected value E of the dropped
// partial-product bits rounded to column K (the lowest kept one); e4 = 4 E (an integer: each
// dropped bit is 1 with probability 1/4, or 1/2 on a squarer's diagonal).
std::int64_t correction(int r, int k, std::int64_t e4) {
  std::int64_t c = std::int64_t{1} << (r - 1);
  if (k > 0) c += (std::int64_t{1} << k) * ((e4 + (std::int64_t{1} << (k + 1))) >> (k + 2));
  return c;
}

[[noreturn]] void range_fail_table(const FixedConfig& c) {
  std::fprintf(stderr, "noise fixed model: the kernel weight table's last entry is not 0 (%s)\n", c.describe().c_str());
  std::abort();
}

}  // namespace

FixedNoise::FixedNoise(FixedConfig c, const TableSet& t) : c_(c) {
  c_.validate();
  const std::array<std::uint8_t, 256>* p[3] = {&t.perm_x, &t.perm_y, &t.perm_z};
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < 256; ++i) hash_[a][i] = ((*p[a])[(i + 1) & 255] % 64) << 6 | ((*p[a])[i] % 64);
  for (int i = 0; i < 64; ++i)
    for (int a = 0; a < 3; ++a)
      grad_[i][a] = trunc() ? narrow_gradient_clamped(t.grad64_q16[i][a], grad_frac_bits())
                            : narrow_gradient(t.grad64_q16[i][a], c_.frac_bits);
  if (trunc()) {
    const int B = c_.frac_bits, gb = grad_frac_bits();
    // (5)-(8) the kernel weight table: w(d) = round(t^4 (4t - 3) 2^B), t = 1 - d 2^-B exactly, for
    // d = 0 .. 2^B - 1 (round half up; B <= 12, so t^4 (4t - 3 2^B) fits 63 bits), saturated at
    // 2^B - 1 (d = 0: w = 1 does not fit B + 1 signed bits). The last entry (t = 2^-B) is 0, so a
    // distance d >= 2^B reads it (the RTL clamps the index to 2^B - 1).
    wtab_.resize(std::size_t{1} << B);
    for (std::int64_t d = 0; d < (std::int64_t{1} << B); ++d) {
      const std::int64_t t = (std::int64_t{1} << B) - d;
      const std::int64_t num = t * t * t * t * (4 * t - 3 * (std::int64_t{1} << B));
      const std::int64_t v = (num + (std::int64_t{1} << (4 * B - 1))) >> (4 * B);
      wtab_[static_cast<std::size_t>(d)] = std::min(v, (std::int64_t{1} << B) - 1);
    }
    if (wtab_.back() != 0) range_fail_table(c_);
    std::int64_t e_dot = 0, dmax_dot = 0;
    const int r_dot = B + gb - dot_frac_bits();
    const int k_dot = r_dot - 2;
    for (int i = 0; i < B; ++i)
      for (int j = 0; j < gb; ++j)
        if (i + j < k_dot) {
          e_dot += 3 * (std::int64_t{1} << (i + j));
          dmax_dot += 3 * (std::int64_t{1} << (i + j));
        }
    corr_dot_ = correction(r_dot, k_dot, e_dot);
    dot_slack_ = std::max(corr_dot_, dmax_dot + (std::int64_t{1} << r_dot) - 1 - corr_dot_);
  }
}

namespace {

[[noreturn]] void range_fail(const char* what, long long v, const FixedConfig& c) {
  std::fprintf(stderr, "noise fixed model: internal range violated: %s = %lld (%s)\n", what, v,
               c.describe().c_str());
  std::abort();
}

// Two's-complement value of the low `bits` bits of v.
std::int64_t sext(std::int64_t v, int bits) {
  std::uint64_t m = (bits >= 64) ? ~0ull : ((1ull << bits) - 1);
  std::uint64_t u = static_cast<std::uint64_t>(v) & m;
  if (bits < 64 && (u >> (bits - 1)) & 1) u |= ~m;
  return static_cast<std::int64_t>(u);
}

bool fits_signed(std::int64_t v, int bits) { return v >= -(1ll << (bits - 1)) && v < (1ll << (bits - 1)); }

}  // namespace

std::int64_t FixedNoise::eval(std::int64_t x, std::int64_t y, std::int64_t z, FixedTrace* tr) const {
  const std::int64_t in[3] = {sext(x, c_.in_w()), sext(y, c_.in_w()), sext(z, c_.in_w())};
  return trunc() ? eval_trunc(in, tr) : eval_full(in, tr);
}

// Steps (1)-(3), the same values in both datapaths (docs/NOISE.md).
FixedNoise::Axes FixedNoise::axes(const std::int64_t in[3], FixedTrace* tr) const {
  const int B = c_.frac_bits;
  const std::int64_t one = 1ll << B;
  Axes x;
  for (int a = 0; a < 3; ++a) {
    // (1) Split: cell = floor(u) mod 256 (arithmetic shift, low 8 bits), frac = low B bits.
    x.cell[a] = static_cast<int>((in[a] >> B) & 255);
    x.frac[a] = static_cast<int>(in[a] & (one - 1));
    // (2) Hash table lookup: one entry gives the hash of the cell and of the next cell.
    const int e = hash_[a][x.cell[a]];
    x.hsh[a][0] = e & 63;
    x.hsh[a][1] = e >> 6;
    // (3) Squares of the per-axis offsets f and 1 - f, truncated to B fraction bits (floor).
    // ru_noise squares both; ru_noise_trunc squares f only and forms sq1 = sq0 + 2^B - 2f, the
    // same value ((1 - f)^2 = f^2 + 1 - 2f; the added term is a multiple of the last place).
    const std::int64_t f = x.frac[a];
    x.sq[a][0] = static_cast<int>((f * f) >> B);
    x.sq[a][1] = static_cast<int>(x.sq[a][0] + one - 2 * f);
  }
  if (tr) {
    for (int a = 0; a < 3; ++a) {
      tr->cell[a] = x.cell[a];
      tr->frac[a] = x.frac[a];
      for (int k = 0; k < 2; ++k) {
        tr->hash[a][k] = x.hsh[a][k];
        tr->sq[a][k] = x.sq[a][k];
      }
    }
  }
  return x;
}

void FixedNoise::trace_corner(FixedTrace* tr, int c, const CornerTrace& k) {
  if (!tr) return;
  tr->d[c] = static_cast<int>(k.d);
  tr->t[c] = static_cast<int>(k.t);
  tr->t2[c] = static_cast<int>(k.t2);
  tr->t4[c] = static_cast<int>(k.t4);
  tr->t5[c] = static_cast<int>(k.t5);
  tr->w[c] = static_cast<int>(k.w);
  tr->h[c] = k.h;
  tr->g[c] = *k.g;
  tr->dot[c] = k.dot;
  tr->contrib[c] = k.contrib;
}

std::int64_t FixedNoise::eval_full(const std::int64_t in[3], FixedTrace* tr) const {
  const int B = c_.frac_bits;
  const std::int64_t one = 1ll << B;
  const Axes x = axes(in, tr);
  const int* frac = x.frac;
  std::int64_t sum = 0;
  for (int c = 0; c < 8; ++c) {
    const int cb[3] = {c & 1, (c >> 1) & 1, c >> 2};
    // (4) Squared distance (exact sum) and t = 1 - d, zero outside the support (d >= 1).
    std::int64_t d = x.sq[0][cb[0]] + x.sq[1][cb[1]] + x.sq[2][cb[2]];
    std::int64_t t = d < one ? one - d : 0;
    // (5)-(7) Powers of t, each product truncated to B fraction bits (floor).
    std::int64_t t2 = (t * t) >> B;
    std::int64_t t4 = (t2 * t2) >> B;
    std::int64_t t5 = (t4 * t) >> B;
    // (8) Kernel weight 4 t^5 - 3 t^4 (exact).
    std::int64_t w = 4 * t5 - 3 * t4;
    if (!fits_signed(w, w_bits())) range_fail("w", w, c_);
    // (9) Gradient index: xor of the three 6-bit hashes; gradient with B fraction bits.
    int h = x.hsh[0][cb[0]] ^ x.hsh[1][cb[1]] ^ x.hsh[2][cb[2]];
    const std::array<int, 3>& g = grad_[h];
    // (10) Dot product of the offset (f - corner bit, B fraction bits) with the gradient:
    // exact sum of the three products (2B fraction bits), then truncated to B bits (floor).
    std::int64_t p = 0;
    for (int a = 0; a < 3; ++a) p += (frac[a] - (cb[a] ? one : 0)) * static_cast<std::int64_t>(g[a]);
    std::int64_t dt = p >> B;
    if (!fits_signed(dt, dot_bits())) range_fail("dot", dt, c_);
    // (11) Contribution w * dot, exact (2B fraction bits); (12) exact sum of the eight.
    std::int64_t contrib = w * dt;
    sum += contrib;
    trace_corner(tr, c, {d, t, t2, t4, t5, w, h, &g, dt, contrib});
  }
  return finish(sum, 2 * B, tr);
}

std::int64_t FixedNoise::finish(std::int64_t sum, int sum_frac_bits, FixedTrace* tr) const {
  if (!fits_signed(sum, sum_bits())) range_fail("sum", sum, c_);
  // (13) Output scaling: value = floor(sum * 2^(out_w + 1 - F)) (F = sum_frac_bits: 2B for kFull,
  // 2B for kTrunc too), then saturation to out_w bits.
  const int sh = sum_frac_bits - (c_.out_w + 1);
  std::int64_t v = sh >= 0 ? (sum >> sh) : sum * (1ll << -sh);
  const std::int64_t vmax = (1ll << (c_.out_w - 1)) - 1, vmin = -(1ll << (c_.out_w - 1));
  bool sat = v > vmax || v < vmin;
  if (v > vmax) v = vmax;
  if (v < vmin) v = vmin;
  if (tr) {
    tr->sum = sum;
    tr->value = v;
    tr->saturated = sat;
  }
  return v;
}

// ---- the truncated datapath (kTrunc, rtl/ru_noise_trunc.sv; docs/NOISE.md) --------------------

std::int64_t FixedNoise::trunc_weight(std::int64_t d) const {
  return wtab_[static_cast<std::size_t>(std::min<std::int64_t>(d, static_cast<std::int64_t>(wtab_.size()) - 1))];
}

std::int64_t FixedNoise::trunc_dot(const int frac[3], const std::array<int, 3>& g, int corner) const {
  // (f_i - c_i) g_i = f_i gl_i - gs_i f_i 2^Gb - c_i g_i 2^B with g_i = -gs_i 2^Gb + gl_i (two's
  // complement, Gb + 1 bits): three truncated unsigned arrays f_i x gl_i (columns >= K) and exact
  // rows; B + Gb fraction bits, then R = B + Gb - B = B - 3 (B fraction bits kept).
  const int B = c_.frac_bits, gb = grad_frac_bits(), r = B + gb - dot_frac_bits(), k = r - 2;
  std::int64_t s = 0;
  for (int a = 0; a < 3; ++a) {
    const std::int64_t f = frac[a], gv = g[a], gl = gv & ((std::int64_t{1} << gb) - 1);
    for (int i = 0; i < B; ++i)
      for (int j = 0; j < gb; ++j)
        if (i + j >= k) s += (((f >> i) & 1) & ((gl >> j) & 1)) << (i + j);
    if (gv < 0) s -= f << gb;
    if ((corner >> a) & 1) s -= gv << B;
  }
  return (s + corr_dot_) >> r;
}

std::int64_t FixedNoise::eval_trunc(const std::int64_t in[3], FixedTrace* tr) const {
  const int B = c_.frac_bits;
  const std::int64_t one = 1ll << B;
  const Axes x = axes(in, tr);
  std::int64_t sum = 0;
  for (int c = 0; c < 8; ++c) {
    const int cb[3] = {c & 1, (c >> 1) & 1, c >> 2};
    // (4) d exact; (5)-(8) the kernel weight from the table (index min(d, 2^B - 1)).
    const std::int64_t d = x.sq[0][cb[0]] + x.sq[1][cb[1]] + x.sq[2][cb[2]];
    const std::int64_t idx = std::min(d, one - 1), w = trunc_weight(d);
    if (!fits_signed(w, w_bits())) range_fail("w", w, c_);
    // (9) gradient (B - 3 fraction bits); (10) dot product with B fraction bits.
    const int h = x.hsh[0][cb[0]] ^ x.hsh[1][cb[1]] ^ x.hsh[2][cb[2]];
    const std::array<int, 3>& g = grad_[h];
    const std::int64_t dt = trunc_dot(x.frac, g, c);
    if (!fits_signed(dt, dot_bits())) range_fail("dot", dt, c_);
    // (11)-(12) w * dot, summed exactly (2B fraction bits).
    const std::int64_t contrib = w * dt;
    sum += contrib;
    trace_corner(tr, c, {d, idx, 0, 0, 0, w, h, &g, dt, contrib});
  }
  return finish(sum, B + dot_frac_bits(), tr);
}

double FixedNoise::to_real(std::int64_t value) const { return std::ldexp(static_cast<double>(value), -(c_.out_w + 1)); }

std::int64_t FixedNoise::quantize(double u) const {
  double s = std::floor(std::ldexp(u, c_.frac_bits));
  return sext(static_cast<std::int64_t>(s), c_.in_w());
}

double FixedNoise::input_real(std::int64_t word) const {
  return std::ldexp(static_cast<double>(sext(word, c_.in_w())), -c_.frac_bits);
}

}  // namespace ru::noise
