// rayunits util: the project's pseudo-random generators (one definition each).
//
// Every stream in the project is one of these, so a seed means the same numbers on every host
// and compiler (integer arithmetic only; the double conversions are exact). Published numbers
// and checked-in tables (noise tables, report workloads, procedural scenes, test vectors)
// depend on the exact streams: tests/util/test_rng.cpp pins the first outputs of each use.
//
//   splitmix64(state)       Steele/Lea/Flood's SplitMix64 step: state += golden gamma, mixed
//                           output. Used as a stream of its own (noise tables, procedural
//                           scenes, report workloads, benchmarks) and to seed xoshiro.
//   SplitMix64              the same as an object (next(), uniform()).
//   Xoshiro256ss            Blackman/Vigna's xoshiro256**, seeded with four splitmix64 outputs
//                           of the seed (test vectors: num::OperandGen, units::Rng, tb::Rng).
//   bounded_*(g, n)         the three ways the areas map a stream to [0, n); they draw
//                           different numbers of outputs, so each stream keeps its own.
#pragma once

#include <cstdint>
#include <limits>
#include <string>

namespace ru::util {

inline constexpr std::uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ull;

// One SplitMix64 step: advances `state` and returns its mixed value.
constexpr std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += kGoldenGamma);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// 53 random bits as a double in [0, 1) (the top bits of x; exact).
constexpr double unit_double(std::uint64_t x) { return static_cast<double>(x >> 11) * 0x1.0p-53; }

class SplitMix64 {
 public:
  using result_type = std::uint64_t;
  explicit constexpr SplitMix64(std::uint64_t seed) : s_(seed) {}
  constexpr std::uint64_t next() { return splitmix64(s_); }
  constexpr std::uint64_t operator()() { return next(); }
  double uniform() { return unit_double(next()); }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  static constexpr std::uint64_t min() { return 0; }
  static constexpr std::uint64_t max() { return std::numeric_limits<std::uint64_t>::max(); }
  constexpr std::uint64_t state() const { return s_; }

 private:
  std::uint64_t s_;
};

class Xoshiro256ss {
 public:
  using result_type = std::uint64_t;
  // The four state words are splitmix64 outputs of `seed`.
  explicit constexpr Xoshiro256ss(std::uint64_t seed) : s_{} {
    for (auto& s : s_) s = splitmix64(seed);
  }
  constexpr std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  constexpr std::uint64_t operator()() { return next(); }
  double uniform() { return unit_double(next()); }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  static constexpr std::uint64_t min() { return 0; }
  static constexpr std::uint64_t max() { return std::numeric_limits<std::uint64_t>::max(); }

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
};

// Uniform integers in [0, n), n > 0, from a generator g (g.next()).
// Lemire's multiply-shift with rejection: unbiased (num::OperandGen, tb::Rng).
template <class G>
std::uint64_t bounded_lemire(G& g, std::uint64_t n) {
  unsigned __int128 m = static_cast<unsigned __int128>(g.next()) * n;
  std::uint64_t lo = static_cast<std::uint64_t>(m);
  if (lo < n) {
    const std::uint64_t thresh = -n % n;
    while (lo < thresh) {
      m = static_cast<unsigned __int128>(g.next()) * n;
      lo = static_cast<std::uint64_t>(m);
    }
  }
  return static_cast<std::uint64_t>(m >> 64);
}
// Modulo with rejection of the top partial range: unbiased (units::Rng, the noise tables).
template <class G>
std::uint64_t bounded_modulo(G& g, std::uint64_t n) {
  const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;  // accept x < limit
  std::uint64_t x;
  do x = g.next();
  while (x >= limit);
  return x % n;
}
// Multiply-shift without rejection: one output per call, bias < n / 2^64 (report workloads).
template <class G>
std::uint64_t bounded_mulshift(G& g, std::uint64_t n) {
  return static_cast<std::uint64_t>((static_cast<unsigned __int128>(g.next()) * n) >> 64);
}

// An independent stream seed for (seed, salt): FNV-1a over the salt, xored into the seed,
// one splitmix64 step (the RTL testbenches' per-stream seeds).
std::uint64_t mix_seed(std::uint64_t seed, const std::string& salt);

}  // namespace ru::util
