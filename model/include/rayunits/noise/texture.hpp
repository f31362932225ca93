// rayunits noise: bit-accurate fixed-point model of the procedural texture unit rtl/ru_texture.sv
// (issue 15 §2; Kensler sec. 6.2: "a higher level procedural texturing hardware unit that manages
// one or more noise units to efficiently compute the results of these summations").
//
// One request: a point (three input words), a mode and an octave count n. The unit evaluates
// n octaves of the noise unit (FixedNoise, either datapath) at lacunarity 2^LacShift, sums them
// exactly with gain 2^-GainShift (turbulence: |noise|), and applies one of the renderer's
// material transfer functions (render/tracer.hpp, material_color):
//   fbm        S = sum_o 2^(-G o) v_o                      (v_o = the o-th octave's noise value)
//   turbulence T = sum_o 2^(-G o) |v_o|
//   granite    min(1, 1.5 T)                                (the renderer's default material)
//   marble     |2 frac(u_x + 1.5 T) - 1|                    (= triangle wave of (q_x + 3T) / 2)
//   wood       frac(4 sqrt(u_x^2 + u_y^2) + S)^2            (= frac(2 (sqrt(q_x^2+q_y^2) + S/2))^2)
// with u = q / 2 the half-resolution coordinate the noise unit takes and v_o = value_o / 2^OutW
// (the renderer's noise_at value, noise::FixedNoise::to_real times 2).
//
// Words. Inputs: three two's-complement words of in_w() = IntBits + FracBits + E bits, E =
// LacShift (Octaves - 1): u = word / 2^(FracBits + E). Octave o's noise input is the word shifted
// right by E - LacShift o, low IntBits + FracBits bits (so the octave inputs are exactly the
// noise unit's quantize(2^(L o) u): floor commutes with the shift). Output: a signed word of
// out_w() = OutF + 2 bits, value / 2^OutF (fbm in (-1, 1), the others in [0, 1]).
//
// Every step is exact except two floors, both in the RTL too: the square root (floor of
// sqrt(X^2 + Y^2), the words as integers) and the final scaling to OutF fraction bits.
#pragma once

#include <cstdint>
#include <string>

#include "rayunits/noise/fixed.hpp"

namespace ru::noise {

enum class TextureMode : int { kFbm = 0, kTurbulence = 1, kGranite = 2, kMarble = 3, kWood = 4 };
constexpr int kTextureModes = 5;
const char* texture_mode_name(TextureMode m);  // "fbm", "turbulence", "granite", "marble", "wood"

struct TextureConfig {
  FixedConfig noise = default_config(NoiseDatapath::kTrunc);  // the noise units inside
  int octaves = 8;     // most octaves per request (Octaves), 1..8
  int lac_shift = 1;   // lacunarity 2^lac_shift, 1..2
  int gain_shift = 1;  // gain 2^-gain_shift, 1..2
  int out_frac = 12;   // OutF: fraction bits of the output, 4..20

  int extra_bits() const { return lac_shift * (octaves - 1); }          // E
  int in_w() const { return noise.in_w() + extra_bits(); }                // input word width
  int in_frac() const { return noise.frac_bits + extra_bits(); }          // B + E
  int sum_frac() const { return noise.out_w + gain_shift * (octaves - 1); }  // SF of the sums
  int sum_w() const { return sum_frac() + 2; }                            // signed, |S| < 2
  int out_w() const { return out_frac + 2; }
  void validate() const;  // std::invalid_argument, one line naming the field
  std::string describe() const;
};

struct TextureTrace {
  int n;                     // octaves evaluated (the request's, clamped to 1..octaves)
  std::int64_t in[8][3];     // noise input words per octave
  std::int64_t v[8];         // noise output words per octave
  std::int64_t sum;          // the exact sum, sum_frac() fraction bits
  std::int64_t root;         // floor(sqrt(X^2 + Y^2)) (wood)
};

class FixedTexture {
 public:
  explicit FixedTexture(TextureConfig c = {}, const TableSet& t = builtin_tables());
  const TextureConfig& config() const { return c_; }
  const FixedNoise& noise() const { return noise_; }

  // x, y, z: input words (low in_w() bits used, two's complement); n: octaves (clamped to
  // 1..octaves). Returns the output word (value / 2^out_frac).
  std::int64_t eval(TextureMode m, int n, std::int64_t x, std::int64_t y, std::int64_t z,
                    TextureTrace* tr = nullptr) const;
  double to_real(std::int64_t value) const;       // value / 2^out_frac
  std::int64_t quantize(double u) const;          // floor(u 2^(B+E)), wrapped to in_w() bits
  std::int64_t sqrt_floor(std::int64_t v) const;  // floor(sqrt(v)), v >= 0 (the RTL's recurrence)

 private:
  TextureConfig c_;
  FixedNoise noise_;
};

// The octave count per request that the unit issues, and the issue interval in cycles of a unit
// with `units` noise instances: ceil(n / units) (one group of `units` octaves per cycle).
int texture_groups(int n, int units);

}  // namespace ru::noise
