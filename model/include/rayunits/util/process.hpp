// rayunits util: the project's one process launcher (argv vector, no shell).
//
// run_process(argv, opt) runs a program and waits for it: argv[0] is looked up on PATH unless
// it contains a '/', stdin/stdout/stderr are inherited, /dev/null, captured into strings or
// written to files, an optional timeout kills the child, and SIGINT/SIGTERM (util/interrupt.hpp)
// stops it. The child runs in its own process group (unless new_group is false) and the whole
// group is signalled, so the tools a tool starts (yosys -> abc) stop too: SIGKILL on timeout,
// SIGTERM on interrupt (SIGKILL if it is still there 5 s later).
//
// Child is the same launcher for a co-process the caller talks to through pipes (the RTL
// co-simulation): Redirect::capture() on stdin/stdout gives the caller in_fd()/out_fd(), and
// wait() collects the rest of the output and the exit status.
#pragma once

#include <sys/types.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace ru::util {

// A process could not be set up (fork/pipe failed, a redirect file cannot be opened).
struct ProcessError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Resolves a program name (searched on PATH) or path to an absolute executable path;
// "" when it cannot be found / is not executable.
std::string find_program(const std::string& name_or_path);

// The running executable's absolute path (/proc/self/exe); "" when it cannot be read. When the
// file was replaced after this process started (rebuilt during a long sweep or report), the path
// would name the new program: then "/proc/self/exe" itself, which a forked child can still exec,
// so the jobs of one run all run one program.
std::string self_exe();

// POSIX shell quoting ('...' with ' written as '\''), for commands shown to people (and
// tests that build a shell command line). The launcher itself never uses a shell.
std::string shell_quote(const std::string& s);
std::string shell_join(const std::vector<std::string>& argv);  // quoted where needed

struct Redirect {
  enum Kind { Inherit, Null, Capture, File };
  Kind kind = Inherit;
  std::string path;     // File
  bool append = false;  // File: append instead of truncate
  static Redirect inherit() { return {}; }
  static Redirect null() { return {Null, "", false}; }
  static Redirect capture() { return {Capture, "", false}; }
  static Redirect file(std::string p, bool append = false) { return {File, std::move(p), append}; }
};

struct ProcessOptions {
  std::string cwd;                      // "" = the current directory
  double timeout_s = 0;                 // > 0: SIGKILL the group after that many seconds
  Redirect in = Redirect::null();       // stdin (Capture: a pipe, Child::in_fd())
  Redirect out = Redirect::inherit();   // stdout
  Redirect err = Redirect::inherit();   // stderr
  bool err_to_out = false;              // 2>&1 (err is ignored)
  bool stop_on_interrupt = true;        // util::interrupted() stops the child
  bool new_group = true;                // own process group (signalled as a whole)
  // > 0: the child gets this signal when the thread that started it dies (PR_SET_PDEATHSIG),
  // e.g. SIGTERM so that the jobs of a SIGKILLed sweep runner stop too. run_process() blocks
  // that thread until the child ends; with a Child, the starting thread must outlive it.
  int parent_death_signal = 0;
};

struct ProcessResult {
  bool started = false;   // false: not found / could not execute (error says why; exit_code 127)
  std::string error;
  int exit_code = -1;     // the exit status; -1 if killed by a signal or timed out
  int term_signal = 0;    // the signal that ended it, if any
  bool timed_out = false;
  bool interrupted = false;  // stopped because of util::interrupted()
  double seconds = 0;
  std::string out, err;   // captured output (Redirect::capture())
  // exit status, 128 + signal when killed (as a shell reports it)
  int status() const { return term_signal ? 128 + term_signal : exit_code; }
};

ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& opt = {});

// std::system without the shell: stdin/stdout/stderr inherited, the caller's process group
// (Ctrl-C reaches both). Returns the exit status (128 + signal; 127 if it could not start).
int run_foreground(const std::vector<std::string>& argv);

// A started child process. Not copyable; the destructor closes the pipes and, if the child is
// still running, sends SIGTERM (to its group) and reaps it.
class Child {
 public:
  // Throws ProcessError when the process cannot be set up; a program that cannot be executed
  // gives started() == false (and wait() reports it).
  Child(const std::vector<std::string>& argv, const ProcessOptions& opt);
  ~Child();
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }
  int in_fd() const { return in_; }    // stdin pipe (Redirect::capture() on in), else -1
  int out_fd() const { return out_; }  // stdout pipe (capture), else -1
  void close_in();                     // EOF for the child
  // Waits for the child (timeout and interrupt as in the options, counted from the start),
  // reading what is left on the captured pipes into the result.
  ProcessResult wait();
  void signal_group(int sig);

 private:
  ProcessOptions opt_;
  ProcessResult pre_;  // start failure
  pid_t pid_ = -1;
  int in_ = -1, out_ = -1, err_ = -1;
  double t0_ = 0;
  bool reaped_ = false;
};

}  // namespace ru::util
