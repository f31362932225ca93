// rayunits: integer option values of `synth`, `gen` and `synth-sweep` (whose options are parsed
// with CLI11 in model/cli/synth_options.hpp) and of the sweep's --stages list (sweep.cpp).
#pragma once

#include <cerrno>
#include <cstdlib>
#include <string>

#include "rayunits/synth/units.hpp"

namespace ru::synth {

// `v` as an integer in lo..hi; otherwise SynthError "OPT expects an integer in LO..HI, got 'V'".
inline int parse_int(const std::string& opt, const std::string& v, int lo, int hi) {
  errno = 0;
  char* end = nullptr;
  const long x = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end || errno || x < lo || x > hi)
    throw SynthError(opt + " expects an integer in " + std::to_string(lo) + ".." + std::to_string(hi) +
                     ", got '" + v + "'");
  return static_cast<int>(x);
}

}  // namespace ru::synth
