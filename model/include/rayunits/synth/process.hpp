// rayunits: running external tools (yosys, nextpnr) and temp directories for the synth flow.
#pragma once

#include <string>
#include <vector>

namespace ru::synth {

// Thin names over rayunits/util/process.hpp and util/interrupt.hpp kept for the synthesis flow.

// util::find_program: a program name (searched on PATH) or path to an absolute executable
// path; returns "" when it cannot be found / is not executable.
std::string find_program(const std::string& name_or_path);

struct ProcResult {
  int exit_code = -1;  // -1: killed by a signal or timed out
  bool timed_out = false;
  double seconds = 0;
};

// Runs argv (util::run_process; argv[0] a path from find_program or a name on PATH) in `cwd`,
// stdout and stderr appended to `log_path`. timeout_s > 0 kills the child's process group
// (SIGKILL) after that many seconds; exit_code 127 if it cannot be executed. Throws
// SynthError("interrupted") after an interrupt (see below). Thread-safe.
ProcResult run_process(const std::vector<std::string>& argv, const std::string& cwd,
                       const std::string& log_path, int timeout_s = 0);

// util::install_interrupt_handler / util::interrupted: SIGINT/SIGTERM set a flag instead of
// killing the process: run_process() then stops its child and throws SynthError("interrupted"),
// so temp directories are removed on the way out and sweeps stop taking new points. The CLI
// commands install it.
void install_interrupt_handler();
bool interrupted();

// A fresh directory (mkdtemp) removed with its contents on destruction unless keep() was called.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix, const std::string& parent = "");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  void keep() { keep_ = true; }

 private:
  std::string path_;
  bool keep_ = false;
};

// Writes `text` to `path` atomically (temp file in the same directory, then rename).
void write_file_atomic(const std::string& path, const std::string& text);
std::string read_file(const std::string& path);  // throws SynthError if unreadable

}  // namespace ru::synth
