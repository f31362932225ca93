// rayunits: command dispatcher. See docs/ARCHITECTURE.md for the data flow.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "command.hpp"
#include "rayunits/num/format.hpp"

namespace ru::cli {

static std::vector<Command>& registry() {
  static std::vector<Command> r;
  return r;
}
bool register_command(const Command& c) {
  registry().push_back(c);
  return true;
}
const std::vector<Command>& commands() {
  auto& r = registry();
  std::sort(r.begin(), r.end(), [](const Command& a, const Command& b) { return std::strcmp(a.name, b.name) < 0; });
  return r;
}

static void print_help() {
  std::printf(
      "rayunits - reduced-precision ray tracing hardware units\n\n"
      "usage: rayunits <command> [options]      (rayunits <command> --help for details)\n\n"
      "commands:\n");
  for (const auto& c : commands()) std::printf("  %-10s %s\n", c.name, c.summary);
  std::printf("\nformats are named eXmY (X exponent bits 2..11, Y fraction bits 1..52), "
              "suffix -ftz for flush-to-zero\n");
}

}  // namespace ru::cli

int main(int argc, char** argv) {
  using namespace ru::cli;
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      !std::strcmp(argv[1], "help")) {
    print_help();
    return argc < 2 ? 2 : 0;
  }
  // Two-word commands ("bench fp", "study tri", "noise study") are matched first.
  std::string name = argv[1];
  std::string name2 = argc >= 3 ? name + " " + argv[2] : std::string();
  for (int words : {2, 1}) {
    const std::string& want = words == 2 ? name2 : name;
    if (want.empty()) continue;
    for (const auto& c : commands()) {
      if (want != c.name) continue;
      try {
        return c.run(argc - words, argv + words);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "rayunits %s: error: %s\n", c.name, e.what());
        return 2;
      }
    }
  }
  std::string names;
  for (const auto& c : commands()) names += std::string(names.empty() ? "" : ", ") + c.name;
  std::fprintf(stderr, "rayunits: error: unknown command '%s' (commands: %s)\n", name.c_str(),
               names.c_str());
  return 2;
}
