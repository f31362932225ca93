// Small helpers shared by the cmd_*.cpp subcommands (CLI11 parsing, number printing).
#pragma once
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "command.hpp"

namespace ru::cli {

// Median of timing samples (benchmarks report medians, see README).
inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// "a,b,,c" -> {a, b, c}
inline std::vector<std::string> split_list(const std::string& v) {
  std::vector<std::string> out;
  size_t b = 0;
  while (b <= v.size()) {
    size_t e = v.find(',', b);
    if (e == std::string::npos) e = v.size();
    if (e > b) out.push_back(v.substr(b, e - b));
    b = e + 1;
  }
  return out;
}

// Parses argv with CLI11. Returns true if the command should run; false if help was printed
// (the caller returns 0). A parse error becomes a UsageError: main() prints it as one line.
inline bool parse_args(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    return false;
  } catch (const CLI::CallForAllHelp&) {
    std::fputs(app.help("", CLI::AppFormatMode::All).c_str(), stdout);
    return false;
  } catch (const CLI::ParseError& e) {
    std::string msg = e.what();
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
    for (char& c : msg)
      if (c == '\n') c = ' ';
    throw UsageError(msg + " (see --help)");
  }
  return true;
}

// The command line as typed (argv[0] is the last word of the command name, see command.hpp),
// with arguments quoted when they contain shell-special characters.
inline std::string command_line(const char* prefix, int argc, char** argv) {
  std::string s = prefix;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    bool plain = !a.empty() && a.find_first_not_of(
                                   "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                   "-_=.,/:+@%") == std::string::npos;
    if (plain) {
      s += " " + a;
    } else {
      std::string q = "'";
      for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
      s += " " + q + "'";
    }
  }
  return s;
}

// Decimal text of a double. Every format value is exactly a double; when its exact decimal
// expansion has at most 40 significant digits it is printed exactly (e.g. 4.875,
// 0.0999755859375), otherwise as %.17g (which still identifies the double uniquely) and
// *exact is set to false. glibc's printf prints exact decimal expansions at any precision.
inline std::string decimal(double v, bool* exact = nullptr) {
  if (exact) *exact = true;
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v < 0 ? "-inf" : "inf";
  char buf[900];
  std::snprintf(buf, sizeof buf, "%.800e", v);  // >= 767, the most digits a double needs
  const char* e = std::strchr(buf, 'e');
  int last = static_cast<int>(e - buf) - 1;
  while (buf[last] == '0') --last;
  int digits = 0;
  for (int i = 0; i <= last; ++i) digits += buf[i] >= '0' && buf[i] <= '9';
  if (digits <= 40) {
    std::snprintf(buf, sizeof buf, "%.*g", digits < 1 ? 1 : digits, v);
    return buf;
  }
  if (exact) *exact = false;
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

inline std::string hexfloat(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", v);
  return buf;
}

}  // namespace ru::cli
