// rayunits formats: table of named number formats with their range and precision.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/num/format.hpp"

namespace ru::cli {
namespace {

struct Named {
  const char* name;
  const char* note;
};

// IEEE-style formats only (exponent all ones = INF/NaN), so the 8-bit ones are NOT the OCP
// FP8 formats of the same name (those reuse the top exponent for finite values).
const Named kNamed[] = {
    {"e2m1", "4-bit; IEEE-style"},
    {"e3m2", "6-bit"},
    {"e2m3", "6-bit"},
    {"e4m3", "8-bit; IEEE-style, not OCP E4M3FN"},
    {"e5m2", "8-bit; IEEE-style like OCP E5M2"},
    {"e3m4", "8-bit"},
    {"e2m5", "8-bit"},
    {"e5m10", "binary16 (half)"},
    {"e8m7", "bfloat16"},
    {"e6m9", "16-bit, wider range than half"},
    {"e8m10", "19-bit, TF32-like"},
    {"e6m12", "19-bit"},
    {"e6m17", "24-bit"},
    {"e7m16", "24-bit; Kensler's proposal (sec. 3.8)"},
    {"e8m15", "24-bit"},
    {"e8m23", "binary32 (float)"},
    {"e7m24", "32-bit"},
    {"e11m52", "binary64 (double)"},
};

std::string pow2_text(double v) {
  int e = 0;
  double m = std::frexp(v, &e);  // v = m * 2^e, m in [0.5, 1)
  if (m != 0.5) return "";
  return "2^" + std::to_string(e - 1);
}

std::string value_text(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  std::string s = buf;
  std::string p = pow2_text(v);
  if (!p.empty()) s += " (" + p + ")";
  return s;
}

int run_formats(int argc, char** argv) {
  CLI::App app{
      "List number formats: width, bias, largest finite value, epsilon (distance from 1 to the "
      "next value, 2^-M), smallest normal and smallest subnormal. Values are rounded to 6 "
      "digits; powers of two are exact.",
      "rayunits formats"};
  std::vector<std::string> names;
  bool ftz = false;
  app.add_option("formats", names, "formats to show (eXmY[-ftz]); default: the named formats");
  app.add_flag("--ftz", ftz, "show the flush-to-zero variants");
  if (!parse_args(app, argc, argv)) return 0;

  std::vector<Named> list;
  if (names.empty()) {
    for (const auto& n : kNamed) list.push_back(n);
  } else {
    for (const auto& n : names) list.push_back({n.c_str(), ""});
  }
  std::vector<ru::num::Format> fmts;
  for (const auto& n : list) {
    ru::num::Format f = ru::num::Format::parse(n.name);  // throws a one-line FormatError
    if (ftz) f.subnormals = false;
    fmts.push_back(f);
  }

  std::printf("%-11s %4s %5s  %-24s %-24s %-26s %-28s %s\n", "format", "bits", "bias", "max finite",
              "epsilon", "min normal", "min subnormal", "note");
  for (size_t i = 0; i < fmts.size(); ++i) {
    const auto& f = fmts[i];
    double maxf = ru::num::to_double(f, f.max_finite());
    double eps = ru::num::to_double(f, f.one() + 1) - 1.0;
    double minn = ru::num::to_double(f, f.min_normal());
    std::string mins = f.subnormals ? value_text(ru::num::to_double(f, f.min_subnormal()))
                                    : std::string("none (flushed)");
    std::printf("%-11s %4d %5d  %-24s %-24s %-26s %-28s %s\n", f.name().c_str(), f.width(), f.bias(),
                value_text(maxf).c_str(), value_text(eps).c_str(), value_text(minn).c_str(),
                mins.c_str(), list[i].note);
  }
  std::printf(
      "\nName eXmY: X exponent bits (2..11), Y stored fraction bits (1..52), width 1+X+Y <= 64;\n"
      "max finite = (2-2^-Y)*2^emax, emax = bias = 2^(X-1)-1; min normal = 2^(1-bias);\n"
      "min subnormal = 2^(1-bias-Y). Suffix -ftz (or --ftz): flush-to-zero, subnormal inputs\n"
      "read as zero and tiny results become zero (see docs/FORMAT.md).\n");
  return 0;
}

}  // namespace

RU_COMMAND("formats", "list number formats with range, epsilon, min normal/subnormal", run_formats);

}  // namespace ru::cli
