// rayunits noise: bit-accurate fixed-point model of the hardware noise unit rtl/ru_noise.sv
// (Kensler sec. 4.9-4.13, Fig. 4.13). The RTL computes exactly these bits; every truncation
// point is listed in docs/NOISE.md ("Fixed-point datapath") and repeated at the code below.
//
// Input: three two's-complement words of in_w() = int_bits + frac_bits bits, read as
// u = word / 2^frac_bits in units of the half-resolution lattice (one unit = one cell = two
// units of the full-resolution lattice). Output: a signed out_w-bit word `value` with
// value / 2^(out_w + 1) ~= N(u) = NoiseRef(tables, 64).half_cell(u), saturated to out_w bits.
// Equivalently value / 2^(out_w - 1) is a fraction in [-1, 1) equal to 4 N(u) = 2 half(2u).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rayunits/noise/tables.hpp"

namespace ru::noise {

// Which datapath (docs/NOISE.md): kFull is rtl/ru_noise.sv (every product exact, then floored:
// Kensler's datapath, the baseline every figure is compared with); kTrunc is rtl/ru_noise_trunc.sv
// (the smaller unit of issue 15: one squarer per axis, the kernel weight w = t^4 (4t - 3) from a
// 2^B-entry table of the correctly rounded value (so B <= 12), gradients with B-3 fraction bits,
// dot products from truncated arrays with a constant correction, the eight contributions summed
// exactly).
enum class NoiseDatapath { kFull, kTrunc };

struct FixedConfig {
  int frac_bits = 8;  // B: fraction bits of the inputs and of every internal quantity, 4..16 (kTrunc 5..12)
  int int_bits = 8;   // integer bits of each input incl. sign, 1..24 (cells wrap modulo 256)
  int out_w = 10;     // width of the output word, 2..2*frac_bits+6
  NoiseDatapath datapath = NoiseDatapath::kFull;

  int in_w() const { return int_bits + frac_bits; }
  // Throws std::invalid_argument with a one-line message naming the bad field.
  void validate() const;
  std::string describe() const;  // "B=8 int=8 out=10" (+ " trunc" for the truncated datapath)
};

// The default widths (FracBits 8, IntBits 8, OutW 10) with the given datapath.
inline FixedConfig default_config(NoiseDatapath d) {
  FixedConfig c;
  c.datapath = d;
  return c;
}

// Intermediate values of one evaluation (for tests, the RTL testbench's diagnostics, docs).
struct FixedTrace {
  int cell[3];                 // 8-bit cell index per axis
  int frac[3];                 // B-bit fraction per axis
  int hash[3][2];              // 6-bit hash of cell and cell + 1 per axis
  int sq[3][2];                // truncated squares per axis and corner bit
  int d[8], t[8], t2[8], t4[8], t5[8], w[8];  // per corner c = cx + 2 cy + 4 cz (kTrunc: t = the
                                              // weight table's index min(d, 2^B - 1), t2 t4 t5 = 0)
  int h[8];                    // gradient index per corner
  std::array<int, 3> g[8];     // gradient (B fraction bits) per corner
  std::int64_t dot[8];         // floor(offset . g / 2^B)
  std::int64_t contrib[8];     // w * dot (2B fraction bits, exact)
  std::int64_t sum;            // sum of contrib (2B fraction bits, exact)
  std::int64_t value;          // the output word
  bool saturated;
};

class FixedNoise {
 public:
  explicit FixedNoise(FixedConfig c = {}, const TableSet& t = builtin_tables());

  const FixedConfig& config() const { return c_; }
  // x, y, z: input words; only the low in_w bits are used (read as two's complement).
  std::int64_t eval(std::int64_t x, std::int64_t y, std::int64_t z, FixedTrace* trace = nullptr) const;
  // N(u) represented by an output word: value / 2^(out_w + 1).
  double to_real(std::int64_t value) const;
  // The input word for coordinate u: floor(u * 2^B), wrapped to in_w bits (sign-extended).
  std::int64_t quantize(double u) const;
  // The real coordinate an input word stands for (after wrapping to in_w bits).
  double input_real(std::int64_t word) const;

  // The hardware tables for this configuration.
  int hash_entry(int axis, int cell) const { return hash_[axis][cell & 255]; }  // {next, cur}
  const std::array<int, 3>& grad(int idx) const { return grad_[idx & 63]; }       // B frac bits

  // Internal ranges the RTL widths rely on (checked on every evaluation; see docs/NOISE.md).
  int w_bits() const { return trunc() ? c_.frac_bits + 1 : c_.frac_bits + 2; }  // signed
  // signed; kTrunc: |dot| < 2 needs dot_frac_bits() + 2 bits from B = 8 on (the table's largest
  // narrowed norm and the truncation's slack: NoiseTrunc.DotRangeByCauchySchwarz), one more below
  int dot_bits() const { return trunc() ? (c_.frac_bits >= 8 ? dot_frac_bits() + 2 : dot_frac_bits() + 3) : c_.frac_bits + 2; }
  int sum_bits() const { return trunc() ? w_bits() + dot_bits() + 2 : 2 * c_.frac_bits + 6; }
  // Fraction bits of the gradients (kFull: B; kTrunc: B - 3) and of the dot product (B in both:
  // kTrunc had B - 2 first, which made the noise 4x coarser near lattice points, docs/NOISE.md).
  int grad_frac_bits() const { return trunc() ? c_.frac_bits - 3 : c_.frac_bits; }
  int dot_frac_bits() const { return c_.frac_bits; }

  // The truncated datapath's arithmetic (kTrunc), public for the tests and docs/NOISE.md:
  //   trunc_weight(d)       the kernel weight w = t^4 (4t - 3), t = 1 - d 2^-B, for the squared
  //                         distance d (B fraction bits, any d >= 0): a 2^B-entry table of the
  //                         exact value rounded to nearest (B + 1 bits signed), saturated at
  //                         1 - 2^-B (d = 0); 0 from d = 2^B - 1 on
  //   trunc_dot(f, g, corner) sum of (f_i - c_i) g_i with B fraction bits: truncated arrays that
  //                         keep the partial-product bits of the columns >= R - 2 (two guard
  //                         columns), add the constant correction and shift right by R = B - 3
  std::int64_t trunc_weight(std::int64_t d) const;
  std::int64_t trunc_dot(const int frac[3], const std::array<int, 3>& g, int corner) const;
  // Correction constant of the dot product (the RTL computes the same by the same formula).
  std::int64_t corr_dot() const { return corr_dot_; }
  // |trunc_dot - exact| * 2^R <= this (R = B - 3; in units of the exact sum): the correction or
  // the dropped bits' largest value minus it, plus the final floor (the range bound uses it).
  std::int64_t trunc_dot_slack() const { return dot_slack_; }

 private:
  bool trunc() const { return c_.datapath == NoiseDatapath::kTrunc; }
  struct Axes {  // steps (1)-(3) per axis
    int cell[3], frac[3], hsh[3][2], sq[3][2];
  };
  struct CornerTrace {
    std::int64_t d, t, t2, t4, t5, w;
    int h;
    const std::array<int, 3>* g;
    std::int64_t dot, contrib;
  };
  Axes axes(const std::int64_t in[3], FixedTrace* trace) const;
  static void trace_corner(FixedTrace* trace, int c, const CornerTrace& k);
  std::int64_t eval_full(const std::int64_t in[3], FixedTrace* trace) const;
  std::int64_t eval_trunc(const std::int64_t in[3], FixedTrace* trace) const;
  std::int64_t finish(std::int64_t sum, int sum_frac_bits, FixedTrace* trace) const;

  FixedConfig c_;
  int hash_[3][256];
  std::array<int, 3> grad_[64];
  std::int64_t corr_dot_ = 0, dot_slack_ = 0;
  std::vector<std::int64_t> wtab_;  // kTrunc: the kernel weight table (trunc_weight)
};

// The kTrunc gradient narrowing: round(q16 / 2^(16 - Gb)) as narrow_gradient, then clamped to
// +-(2^Gb - 1) (the table's largest component, 0.99699, rounds to 1.0 for Gb <= 7).
int narrow_gradient_clamped(std::int32_t q16, int grad_frac_bits);

// The gradient narrowing of docs/NOISE.md: round(q16 / 2^(16 - B)), ties toward +infinity.
int narrow_gradient(std::int32_t q16, int frac_bits);

}  // namespace ru::noise
