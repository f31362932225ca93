// rayunits: integer option values of `synth`, `gen` and `synth-sweep` (whose options are parsed
// with CLI11 in model/cli/synth_options.hpp) and of the sweep's --stages list (sweep.cpp).
#pragma once

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cmath>
#include <string>
#include <vector>

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

// A clock as a frequency or a period with its unit: "400MHz", "1.2GHz", "2.5ns", "2500ps"
// (case-insensitive units), as a period in ps; otherwise SynthError naming what is accepted.
inline double parse_clock_ps(const std::string& opt, const std::string& v) {
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(v.c_str(), &end);
  std::string unit(end ? end : "");
  for (char& c : unit) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  double ps = 0;
  if (unit == "mhz")
    ps = 1e6 / x;
  else if (unit == "ghz")
    ps = 1e3 / x;
  else if (unit == "ns")
    ps = x * 1e3;
  else if (unit == "ps")
    ps = x;
  if (v.empty() || end == v.c_str() || errno || !(x > 0) || !std::isfinite(ps) || ps < 1 || ps > 1e8)
    throw SynthError(opt + " expects a clock with its unit (400MHz, 1.2GHz, 2.5ns, 2500ps; 1 ps .. 100 us), got '" +
                     v + "'");
  return ps;
}

// A comma-separated list of clocks (parse_clock_ps each).
inline std::vector<double> parse_clock_list(const std::string& opt, const std::string& v) {
  std::vector<double> out;
  size_t b = 0;
  while (true) {
    const size_t e = v.find(',', b);
    out.push_back(parse_clock_ps(opt, v.substr(b, e == std::string::npos ? std::string::npos : e - b)));
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return out;
}

}  // namespace ru::synth
