// rayunits noise: the lookup tables of Kensler's gradient noise (dissertation ch. 4) and their
// generator. ONE generator (generate_tables) produces every table that the float references,
// the fixed-point model and the RTL use; render_cpp_header() and render_svh() turn its output
// into the two checked-in generated files
//   model/include/rayunits/noise/noise_tables_data.hpp   (C++ arrays)
//   rtl/ru_noise_tables.svh                              (Verilog `case` functions)
// and tests/noise regenerates both and compares them byte for byte, so they cannot drift.
// Regenerate with scripts/gen_noise_tables.sh (= `rayunits noise tables --write`).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ru::noise {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};
inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// The generator's seed (any 64-bit value; this one is the default and the checked-in tables').
constexpr std::uint64_t kTableSeed = 0x4b656e736c657209ull;  // "Kensler" + 0x09 (2009)

// Statistics of one Coulomb relaxation run (§4.4).
struct RelaxStats {
  int points = 0;
  int steps = 0;
  double energy_initial = 0;   // sum over pairs i<j of 1/|G_i - G_j|
  double energy_final = 0;
  double min_dist_initial = 0;  // smallest chord distance between two vectors
  double min_dist_final = 0;
  double max_tangential_force = 0;  // at the end, relative to the mean force magnitude
};

struct TableSet {
  std::uint64_t seed = kTableSeed;
  // Per-axis permutations of 0..255 (§4.5 xor hash: h = Px[i] ^ Py[j] ^ Pz[k]).
  std::array<std::uint8_t, 256> perm_x{}, perm_y{}, perm_z{};
  // Relaxed unit gradient vectors (§4.4), 256- and 64-entry tables (independent runs).
  std::vector<Vec3> grad256, grad64;
  // The 64-entry table in the hardware's stored form: round(g * 2^16), half away from zero
  // (signed Q1.16, |value| <= 65536). The fixed-point model and the RTL derive every
  // narrower gradient width from these integers (see docs/NOISE.md, "Gradient table").
  std::array<std::array<std::int32_t, 3>, 64> grad64_q16{};
  RelaxStats relax256, relax64;
};

// Runs the generator (deterministic: splitmix64 stream, IEEE double arithmetic only).
TableSet generate_tables(std::uint64_t seed = kTableSeed);

// Coulomb relaxation of n random unit vectors on the sphere (exposed for the tests).
std::vector<Vec3> relaxed_gradients(std::uint64_t& rng_state, int n, int steps, RelaxStats* stats);
double coulomb_energy(const std::vector<Vec3>& g);
double min_chord_distance(const std::vector<Vec3>& g);

// The generator's PRNG is a splitmix64 stream (ru::util::splitmix64, rayunits/util/rng.hpp).

std::string render_cpp_header(const TableSet& t);
std::string render_svh(const TableSet& t);

// Paths of the generated files relative to the repository root.
constexpr const char* kGeneratedHeaderPath = "model/include/rayunits/noise/noise_tables_data.hpp";
constexpr const char* kGeneratedSvhPath = "rtl/ru_noise_tables.svh";

// The checked-in tables (from noise_tables_data.hpp), as a TableSet (relax stats empty).
const TableSet& builtin_tables();

// Ken Perlin's published permutation for improved noise (2002 reference implementation).
extern const std::array<std::uint8_t, 256> kPerlinPermutation;

}  // namespace ru::noise
