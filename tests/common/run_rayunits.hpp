// One way for tests to run the `rayunits` command: an argv vector (no shell) through the
// project's process launcher, stdout and stderr captured, a timeout so a hang fails the test.
#pragma once

#include <string>
#include <vector>

#include "rayunits/util/process.hpp"

namespace ru::test {

struct CmdRun {
  int code;  // exit status (128 + signal when killed)
  std::string out, err;
};

// `<build>/model/cli/rayunits ARGS...` (RU_BINARY_DIR comes from tests/CMakeLists.txt).
inline CmdRun run_rayunits(const std::vector<std::string>& args, double timeout_s = 600, const std::string& cwd = "") {
  std::vector<std::string> argv = {std::string(RU_BINARY_DIR) + "/model/cli/rayunits"};
  argv.insert(argv.end(), args.begin(), args.end());
  ru::util::ProcessOptions o;
  o.cwd = cwd;
  o.out = ru::util::Redirect::capture();
  o.err = ru::util::Redirect::capture();
  o.timeout_s = timeout_s;
  const auto r = ru::util::run_process(argv, o);
  return {r.status(), r.out, r.err};
}

}  // namespace ru::test
