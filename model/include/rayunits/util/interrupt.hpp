// rayunits util: SIGINT/SIGTERM handling (one handler, one flag for the whole process).
//
// The handler only sets a flag: long loops poll interrupted() and stop cleanly (temp
// directories removed, partial results kept where a command supports --resume), and
// util::run_process() stops its child's process group when the flag is set.
#pragma once

namespace ru::util {

// Installs the handler for SIGINT and SIGTERM for the rest of the process (CLI commands).
void install_interrupt_handler();
// True once SIGINT or SIGTERM arrived since the handler was installed (or the flag cleared).
bool interrupted();
void clear_interrupted();

// Installs the handler for the guard's lifetime (the flag is cleared first) and restores the
// previous handlers afterwards (a report run inside a longer-lived process).
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  struct Saved;
  Saved* saved_;
};

}  // namespace ru::util
