// The single generator of every noise table (see rayunits/noise/tables.hpp and docs/NOISE.md).
#include <algorithm>
#include <cinttypes>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "rayunits/noise/tables.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::noise {

namespace {

using util::splitmix64;

// Uniform in [0, 1) with 53 random bits.
double uniform01(std::uint64_t& s) { return util::unit_double(splitmix64(s)); }

// Uniform integer in [0, n) without modulo bias (rejection).
std::uint64_t bounded(std::uint64_t& s, std::uint64_t n) {
  struct Stream {  // the caller's splitmix64 state as a generator
    std::uint64_t& s;
    std::uint64_t next() { return splitmix64(s); }
  } g{s};
  return util::bounded_modulo(g, n);
}

std::array<std::uint8_t, 256> permutation(std::uint64_t& s) {
  std::array<std::uint8_t, 256> p{};
  for (int i = 0; i < 256; ++i) p[i] = static_cast<std::uint8_t>(i);
  for (int i = 255; i > 0; --i) std::swap(p[i], p[bounded(s, static_cast<std::uint64_t>(i) + 1)]);
  return p;
}

Vec3 normalized(Vec3 v) { return (1.0 / std::sqrt(dot(v, v))) * v; }

// Coulomb force on every vector (F_i = sum_j (G_i - G_j) / |G_i - G_j|^3, §4.4), with the
// radial component removed so the step stays (to first order) on the sphere.
std::vector<Vec3> tangential_forces(const std::vector<Vec3>& g) {
  const std::size_t n = g.size();
  std::vector<Vec3> f(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      Vec3 d = g[i] - g[j];
      double r2 = dot(d, d);
      double inv3 = 1.0 / (r2 * std::sqrt(r2));
      Vec3 fij = inv3 * d;
      f[i] = f[i] + fij;
      f[j] = f[j] - fij;
    }
  }
  for (std::size_t i = 0; i < n; ++i) f[i] = f[i] - dot(f[i], g[i]) * g[i];
  return f;
}

}  // namespace

double coulomb_energy(const std::vector<Vec3>& g) {
  double e = 0;
  for (std::size_t i = 0; i < g.size(); ++i)
    for (std::size_t j = i + 1; j < g.size(); ++j) {
      Vec3 d = g[i] - g[j];
      e += 1.0 / std::sqrt(dot(d, d));
    }
  return e;
}

double min_chord_distance(const std::vector<Vec3>& g) {
  double m = INFINITY;
  for (std::size_t i = 0; i < g.size(); ++i)
    for (std::size_t j = i + 1; j < g.size(); ++j) {
      Vec3 d = g[i] - g[j];
      m = std::min(m, std::sqrt(dot(d, d)));
    }
  return m;
}

std::vector<Vec3> relaxed_gradients(std::uint64_t& s, int n, int steps, RelaxStats* stats) {
  if (n < 2) throw std::invalid_argument("relaxed_gradients: need at least 2 vectors");
  std::vector<Vec3> g;
  g.reserve(n);
  // §4.4: Perlin's original construction -- components uniform in [-1, 1], rejected unless
  // the vector lies inside the unit ball, then normalized.
  while (static_cast<int>(g.size()) < n) {
    Vec3 v{2 * uniform01(s) - 1, 2 * uniform01(s) - 1, 2 * uniform01(s) - 1};
    double r2 = dot(v, v);
    if (r2 > 1.0 || r2 < 1e-6) continue;
    g.push_back(normalized(v));
  }
  RelaxStats st;
  st.points = n;
  st.steps = steps;
  st.energy_initial = coulomb_energy(g);
  st.min_dist_initial = min_chord_distance(g);
  // Time steps: every vector moves along its tangential force, the largest move being a
  // fraction alpha of the mean spacing sqrt(4 pi / n); alpha decays linearly from 0.1 to 0.001
  // so the particles settle instead of oscillating. Then back onto the sphere.
  const double spacing = std::sqrt(4 * M_PI / n);
  for (int k = 0; k < steps; ++k) {
    std::vector<Vec3> f = tangential_forces(g);
    double fmax = 0;
    for (const Vec3& v : f) fmax = std::max(fmax, std::sqrt(dot(v, v)));
    if (fmax == 0) break;
    double alpha = 0.1 * (1.0 - static_cast<double>(k) / steps) + 0.001;
    double eta = alpha * spacing / fmax;
    for (int i = 0; i < n; ++i) g[i] = normalized(g[i] + eta * f[i]);
  }
  st.energy_final = coulomb_energy(g);
  st.min_dist_final = min_chord_distance(g);
  {
    std::vector<Vec3> f = tangential_forces(g);
    double fmax = 0, total = 0;
    for (int i = 0; i < n; ++i) {
      fmax = std::max(fmax, std::sqrt(dot(f[i], f[i])));
      // magnitude of the full (untangential) force sum for scale: n-1 unit-ish pairs
    }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (i != j) {
          Vec3 d = g[i] - g[j];
          total += 1.0 / dot(d, d);
        }
    st.max_tangential_force = fmax / (total / n);
  }
  if (stats) *stats = st;
  return g;
}

TableSet generate_tables(std::uint64_t seed) {
  TableSet t;
  t.seed = seed;
  std::uint64_t s = seed;
  t.perm_x = permutation(s);
  t.perm_y = permutation(s);
  t.perm_z = permutation(s);
  t.grad256 = relaxed_gradients(s, 256, 600, &t.relax256);
  t.grad64 = relaxed_gradients(s, 64, 1500, &t.relax64);
  for (int i = 0; i < 64; ++i) {
    const double c[3] = {t.grad64[i].x, t.grad64[i].y, t.grad64[i].z};
    for (int a = 0; a < 3; ++a) t.grad64_q16[i][a] = static_cast<std::int32_t>(std::llround(c[a] * 65536.0));
  }
  return t;
}

namespace {

void appendf(std::string& s, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
void appendf(std::string& s, const char* fmt, ...) {
  char buf[256];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  s += buf;
}

std::string perm_cpp(const char* name, const std::array<std::uint8_t, 256>& p) {
  std::string s;
  appendf(s, "inline constexpr std::uint8_t %s[256] = {", name);
  for (int i = 0; i < 256; ++i) appendf(s, "%s%d%s", i % 16 == 0 ? "\n    " : " ", p[i], i < 255 ? "," : "");
  s += "};\n";
  return s;
}

std::string grad_cpp(const char* name, const std::vector<Vec3>& g) {
  std::string s;
  appendf(s, "inline constexpr double %s[%zu][3] = {\n", name, g.size());
  for (const Vec3& v : g) appendf(s, "    {%a, %a, %a},\n", v.x, v.y, v.z);
  s += "};\n";
  return s;
}

}  // namespace

std::string render_cpp_header(const TableSet& t) {
  std::string s;
  s += "// GENERATED by `rayunits noise tables --write` (model/src/noise/tables_gen.cpp). Do not edit:\n"
       "// tests/noise regenerates this file and fails if it differs. Seed and method: docs/NOISE.md.\n"
       "#pragma once\n#include <cstdint>\n\nnamespace ru::noise::gen {\n\n";
  appendf(s, "inline constexpr std::uint64_t kSeed = 0x%016" PRIx64 "ull;\n\n", t.seed);
  s += "// Per-axis permutations of 0..255 (xor hash, dissertation sec. 4.5).\n";
  s += perm_cpp("kPermX", t.perm_x);
  s += perm_cpp("kPermY", t.perm_y);
  s += perm_cpp("kPermZ", t.perm_z);
  s += "\n// Relaxed unit gradients (sec. 4.4), exact doubles.\n";
  s += grad_cpp("kGrad256", t.grad256);
  s += grad_cpp("kGrad64", t.grad64);
  s += "\n// kGrad64 rounded to signed Q1.16 (llround(g * 65536)): the hardware's stored table.\n";
  s += "inline constexpr std::int32_t kGrad64Q16[64][3] = {\n";
  for (const auto& q : t.grad64_q16) appendf(s, "    {%d, %d, %d},\n", q[0], q[1], q[2]);
  s += "};\n\n}  // namespace ru::noise::gen\n";
  return s;
}

std::string render_svh(const TableSet& t) {
  std::string s;
  s += "// GENERATED by `rayunits noise tables --write` (model/src/noise/tables_gen.cpp). Do not edit:\n"
       "// tests/noise regenerates this file and fails if it differs. Included inside module ru_noise.\n";
  appendf(s, "// Seed 0x%016" PRIx64 ". Tables as `case` statements (dissertation sec. 4.10).\n", t.seed);
  s += "//\n// Hash tables (sec. 4.13): entry i = {P[(i + 1) mod 256] mod 64, P[i] mod 64}, i.e. the\n"
       "// 6-bit hash of cell i (low half) and of cell i + 1 (high half).\n";
  const std::array<std::uint8_t, 256>* perms[3] = {&t.perm_x, &t.perm_y, &t.perm_z};
  const char axis[3] = {'x', 'y', 'z'};
  for (int a = 0; a < 3; ++a) {
    const auto& p = *perms[a];
    appendf(s, "function automatic logic [11:0] ru_noise_hash_%c(input logic [7:0] idx);\n", axis[a]);
    s += "  case (idx)\n";
    for (int i = 0; i < 256; ++i)
      appendf(s, "    8'd%d: ru_noise_hash_%c = {6'd%d, 6'd%d};\n", i, axis[a], p[(i + 1) % 256] % 64, p[i] % 64);
    s += "  endcase\nendfunction\n\n";
  }
  s += "// Gradient table: 64 relaxed unit vectors, stored as signed Q1.16 and narrowed to\n"
       "// GradW bits by ru_noise_gq() (a constant function of the module's FracBits).\n"
       "// Result {z, y, x}, x in the low GradW bits.\n";
  s += "function automatic logic [3*GradW-1:0] ru_noise_grad(input logic [5:0] idx);\n";
  s += "  case (idx)\n";
  auto lit = [](std::int32_t v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s18'sd%d", v < 0 ? "-" : "", v < 0 ? -v : v);
    return std::string(buf);
  };
  for (int i = 0; i < 64; ++i) {
    const auto& q = t.grad64_q16[i];
    appendf(s, "    6'd%d: ru_noise_grad = {ru_noise_gq(%s), ru_noise_gq(%s), ru_noise_gq(%s)};\n", i, lit(q[2]).c_str(),
            lit(q[1]).c_str(), lit(q[0]).c_str());
  }
  s += "  endcase\nendfunction\n";
  return s;
}

}  // namespace ru::noise
