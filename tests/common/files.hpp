// Small file helpers of the tests: a whole file as a string, line counts.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace ru::test {

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

inline int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

}  // namespace ru::test
