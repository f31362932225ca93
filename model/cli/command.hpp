// Subcommand registry of the `rayunits` command. Each subcommand lives in its own
// cmd_<name>.cpp and registers itself with RU_COMMAND; main.cpp dispatches.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace ru::cli {

struct Command {
  const char* name;  // "fp", or two words: "bench fp", "study tri"
  const char* summary;            // one line for `rayunits --help`
  int (*run)(int argc, char** argv);  // argv[0] is the last word of the command name
};

// Errors that main() prints as one line "rayunits: error: ..." with exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

bool register_command(const Command& c);
const std::vector<Command>& commands();

}  // namespace ru::cli

#define RU_CLI_CAT2(a, b) a##b
#define RU_CLI_CAT(a, b) RU_CLI_CAT2(a, b)
#define RU_COMMAND(NAME, SUMMARY, FN)                                                 \
  static const bool RU_CLI_CAT(ru_cmd_registered_, __LINE__) =                      \
      ::ru::cli::register_command(::ru::cli::Command{NAME, SUMMARY, FN})
