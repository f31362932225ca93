// rayunits util: the content hash of results and caches (FNV-1a 64; not cryptographic: it names
// results, it does not defend against forged inputs).
#pragma once

#include <cstdint>
#include <string_view>
#include <string>

namespace ru::util {

// FNV-1a 64 of `bytes`, continuing from `h` (the offset basis by default).
std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = 1469598103934665603ull);
// The same as 16 lower-case hex digits.
std::string fnv1a64_hex(std::string_view bytes);
std::string hex64(std::uint64_t h);

}  // namespace ru::util
