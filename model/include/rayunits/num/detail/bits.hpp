// rayunits num: the bit patterns of native float and double (IEEE binary32 / binary64), one
// definition for the format model's fast paths, fp.hpp's fp_bits / fp_from_bits and the soft
// model's from_double. (C++17: no std::bit_cast.) The MPFR oracle keeps its own on purpose: it
// shares no code with the model it checks.
#pragma once

#include <cstdint>
#include <cstring>

namespace ru::num::detail {

inline uint64_t double_bits(double x) {
  uint64_t u;
  std::memcpy(&u, &x, 8);
  return u;
}
inline double double_from_bits(uint64_t u) {
  double x;
  std::memcpy(&x, &u, 8);
  return x;
}
inline uint32_t float_bits(float x) {
  uint32_t u;
  std::memcpy(&u, &x, 4);
  return u;
}
inline float float_from_bits(uint32_t u) {
  float x;
  std::memcpy(&x, &u, 4);
  return x;
}

}  // namespace ru::num::detail
