// Bit-accurate model of rtl/ru_texture.sv; see rayunits/noise/texture.hpp and docs/NOISE.md
// ("The procedural texture unit").
#include "rayunits/noise/texture.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ru::noise {

namespace {
std::int64_t wrap_signed(std::int64_t v, int bits) {
  const std::uint64_t m = (std::uint64_t{1} << bits) - 1, u = static_cast<std::uint64_t>(v) & m;
  return (u >> (bits - 1)) ? static_cast<std::int64_t>(u) - static_cast<std::int64_t>(m) - 1 : static_cast<std::int64_t>(u);
}
void need(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("texture: " + what);
}
}  // namespace

const char* texture_mode_name(TextureMode m) {
  switch (m) {
    case TextureMode::kFbm: return "fbm";
    case TextureMode::kTurbulence: return "turbulence";
    case TextureMode::kGranite: return "granite";
    case TextureMode::kMarble: return "marble";
    case TextureMode::kWood: return "wood";
  }
  return "?";
}

void TextureConfig::validate() const {
  noise.validate();
  need(octaves >= 1 && octaves <= 8, "octaves must be 1..8, got " + std::to_string(octaves));
  need(lac_shift >= 1 && lac_shift <= 2, "lacunarity shift must be 1..2, got " + std::to_string(lac_shift));
  need(gain_shift >= 1 && gain_shift <= 2, "gain shift must be 1..2, got " + std::to_string(gain_shift));
  need(out_frac >= 4 && out_frac <= 20, "output fraction bits must be 4..20, got " + std::to_string(out_frac));
  need(in_w() <= 31, "input words of " + std::to_string(in_w()) +
                         " bits (int + frac + lacunarity x (octaves - 1)) exceed 31");
  need(sum_frac() <= 30, "sum of " + std::to_string(sum_frac()) +
                             " fraction bits (noise out_w + gain x (octaves - 1)) exceeds 30");
}

std::string TextureConfig::describe() const {
  return noise.describe() + " octaves=" + std::to_string(octaves) + " lac=2^" + std::to_string(lac_shift) +
         " gain=2^-" + std::to_string(gain_shift) + " outF=" + std::to_string(out_frac);
}

int texture_groups(int n, int units) { return (n + units - 1) / units; }

FixedTexture::FixedTexture(TextureConfig c, const TableSet& t) : c_(c), noise_((c.validate(), c.noise), t) {}

double FixedTexture::to_real(std::int64_t value) const { return std::ldexp(static_cast<double>(value), -c_.out_frac); }

std::int64_t FixedTexture::quantize(double u) const {
  return wrap_signed(static_cast<std::int64_t>(std::floor(std::ldexp(u, c_.in_frac()))), c_.in_w());
}

// Restoring square root, one result bit per step from the top (the RTL's recurrence).
std::int64_t FixedTexture::sqrt_floor(std::int64_t v) const {
  std::uint64_t rem = static_cast<std::uint64_t>(v), root = 0;
  for (int i = 31; i >= 0; --i) {
    const std::uint64_t trial = (root << (i + 1)) + (std::uint64_t{1} << (2 * i));  // (2 root + 2^i) 2^i
    if (trial <= rem) {
      rem -= trial;
      root |= std::uint64_t{1} << i;
    }
  }
  return static_cast<std::int64_t>(root);
}

std::int64_t FixedTexture::eval(TextureMode m, int n, std::int64_t x, std::int64_t y, std::int64_t z,
                                TextureTrace* tr) const {
  const TextureConfig& C = c_;
  const int E = C.extra_bits(), nw = C.noise.in_w(), SF = C.sum_frac();
  n = std::clamp(n, 1, C.octaves);
  const std::int64_t X = wrap_signed(x, C.in_w()), Y = wrap_signed(y, C.in_w()), Z = wrap_signed(z, C.in_w());
  const bool absolute = m == TextureMode::kTurbulence || m == TextureMode::kGranite || m == TextureMode::kMarble;
  // (1) octaves: inputs by shifting (exact), noise values, sum with gain 2^-G o (exact).
  std::int64_t sum = 0;
  for (int o = 0; o < n; ++o) {
    const int sh = E - C.lac_shift * o;
    const std::int64_t in[3] = {wrap_signed(X >> sh, nw), wrap_signed(Y >> sh, nw), wrap_signed(Z >> sh, nw)};
    const std::int64_t v = noise_.eval(in[0], in[1], in[2]);
    sum += (absolute ? std::llabs(v) : v) * (std::int64_t{1} << (C.gain_shift * (C.octaves - 1 - o)));
    if (tr) {
      for (int a = 0; a < 3; ++a) tr->in[o][a] = in[a];
      tr->v[o] = v;
    }
  }
  if (tr) {
    tr->n = n;
    tr->sum = sum;
    tr->root = 0;
  }
  // (2) transfer function, exact; (3) floor to OutF fraction bits.
  int frac = SF;        // fraction bits of r
  unsigned __int128 r;  // the result (>= 0) before the final floor, or the signed sum below
  switch (m) {
    default:  // codes 5..7: as fbm (the RTL's default branch)
    case TextureMode::kFbm:
    case TextureMode::kTurbulence: {
      const int sh = SF - C.out_frac;
      return sh >= 0 ? (sum >> sh) : sum * (std::int64_t{1} << -sh);  // floor
    }
    case TextureMode::kGranite: {  // min(1, 1.5 T), SF + 1 fraction bits
      frac = SF + 1;
      const std::int64_t t15 = 3 * sum, one = std::int64_t{1} << frac;
      r = static_cast<unsigned __int128>(std::min(t15, one));
      break;
    }
    case TextureMode::kMarble: {  // |2 frac(u_x + 1.5 T) - 1|, MF = max(B + E, SF + 1) fraction bits
      frac = std::max(C.in_frac(), SF + 1);
      const std::int64_t s = X * (std::int64_t{1} << (frac - C.in_frac())) + 3 * sum * (std::int64_t{1} << (frac - SF - 1));
      const std::int64_t fr = s & ((std::int64_t{1} << frac) - 1);
      r = static_cast<unsigned __int128>(std::llabs(2 * fr - (std::int64_t{1} << frac)));
      break;
    }
    case TextureMode::kWood: {  // frac(4 root + S)^2, WF = max(B + E - 2, SF) fraction bits, squared
      const std::int64_t root = sqrt_floor(X * X + Y * Y);  // floor(sqrt(u_x^2 + u_y^2) 2^(B+E))
      if (tr) tr->root = root;
      const int wf = std::max(C.in_frac() - 2, SF);
      const std::int64_t g = root * (std::int64_t{1} << (wf - (C.in_frac() - 2))) + sum * (std::int64_t{1} << (wf - SF));
      const std::uint64_t fr = static_cast<std::uint64_t>(g) & ((std::uint64_t{1} << wf) - 1);
      r = static_cast<unsigned __int128>(fr) * fr;
      frac = 2 * wf;
      break;
    }
  }
  const int sh = frac - C.out_frac;
  return static_cast<std::int64_t>(sh >= 0 ? (r >> sh) : (r << -sh));
}

}  // namespace ru::noise
