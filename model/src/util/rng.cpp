// rayunits util: generators (see rayunits/util/rng.hpp).
#include "rayunits/util/rng.hpp"

namespace ru::util {

std::uint64_t mix_seed(std::uint64_t seed, const std::string& salt) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the salt, then mixed with the seed
  for (unsigned char c : salt) h = (h ^ c) * 1099511628211ull;
  std::uint64_t x = seed ^ h;
  return splitmix64(x);
}

}  // namespace ru::util
