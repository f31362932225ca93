// rayunits util: the process launcher (see rayunits/util/process.hpp).
#include "rayunits/util/process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

#include "rayunits/util/interrupt.hpp"

namespace ru::util {
namespace fs = std::filesystem;

namespace {
double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}
// Reads what is available on fd into s; false at EOF or error (fd closed).
bool drain(int& fd, std::string* s) {
  char buf[8192];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n > 0) {
      if (s) s->append(buf, static_cast<size_t>(n));
      if (static_cast<size_t>(n) < sizeof buf) return true;
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return true;
    close_fd(fd);
    return false;
  }
}
}  // namespace

std::string self_exe() {
  char buf[4096];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return std::string();
  const std::string p(buf, static_cast<std::size_t>(n));
  // The binary was replaced while this process runs (a rebuild during a long sweep or report):
  // the path names the new program, "/proc/self/exe" still this one (a forked child execs it).
  const std::string deleted = " (deleted)";
  if (p.size() > deleted.size() && p.compare(p.size() - deleted.size(), deleted.size(), deleted) == 0)
    return "/proc/self/exe";
  return p;
}

std::string find_program(const std::string& name) {
  if (name.empty()) return {};
  auto ok = [](const std::string& p) {
    struct stat st {};
    return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
  };
  if (name.find('/') != std::string::npos)
    return ok(name) ? fs::absolute(name).lexically_normal().string() : std::string();
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  size_t b = 0;
  while (b <= dirs.size()) {
    size_t e = dirs.find(':', b);
    if (e == std::string::npos) e = dirs.size();
    std::string d = dirs.substr(b, e - b);
    if (d.empty()) d = ".";
    std::string p = d + "/" + name;
    if (ok(p)) return fs::absolute(p).lexically_normal().string();
    b = e + 1;
  }
  return {};
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string shell_join(const std::vector<std::string>& argv) {
  std::string s;
  for (const auto& a : argv) {
    const bool plain = !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                         "0123456789_-+=./:,@%") == std::string::npos;
    s += (s.empty() ? "" : " ") + (plain ? a : shell_quote(a));
  }
  return s;
}

Child::Child(const std::vector<std::string>& argv, const ProcessOptions& opt) : opt_(opt) {
  t0_ = now_s();
  if (argv.empty()) throw ProcessError("run_process: empty command");
  const std::string exe = find_program(argv[0]);
  if (exe.empty()) {
    pre_.error = "cannot execute '" + argv[0] + "': not found or not executable";
    pre_.exit_code = 127;
    return;
  }
  // Everything the child needs is prepared before fork(): the child only calls
  // async-signal-safe functions (the parent may be multi-threaded).
  std::vector<char*> args;
  args.push_back(const_cast<char*>(exe.c_str()));
  for (size_t i = 1; i < argv.size(); ++i) args.push_back(const_cast<char*>(argv[i].c_str()));
  args.push_back(nullptr);

  int child_fd[3] = {-1, -1, -1};  // what the child gets as 0, 1, 2 (-1: inherit)
  int parent_fd[3] = {-1, -1, -1};
  auto cleanup = [&] {
    for (int& f : child_fd) close_fd(f);
    for (int& f : parent_fd) close_fd(f);
  };
  auto setup = [&](int k, const Redirect& r) {
    if (r.kind == Redirect::Inherit) return;
    if (r.kind == Redirect::Null || r.kind == Redirect::File) {
      const std::string p = r.kind == Redirect::Null ? "/dev/null" : r.path;
      const int flags = k == 0 ? O_RDONLY : O_WRONLY | O_CREAT | (r.append ? O_APPEND : O_TRUNC);
      child_fd[k] = ::open(p.c_str(), flags | O_CLOEXEC, 0644);
      if (child_fd[k] < 0) {
        const std::string why = std::strerror(errno);
        cleanup();
        throw ProcessError(std::string(k == 0 ? "cannot read '" : "cannot write '") + p + "': " + why);
      }
      return;
    }
    int p[2];
    if (::pipe2(p, O_CLOEXEC) != 0) {
      cleanup();
      throw ProcessError(std::string("pipe failed: ") + std::strerror(errno));
    }
    child_fd[k] = k == 0 ? p[0] : p[1];
    parent_fd[k] = k == 0 ? p[1] : p[0];
  };
  setup(0, opt.in);
  setup(1, opt.out);
  if (!opt.err_to_out) setup(2, opt.err);
  int report[2];  // the child writes errno here if exec fails (closed by a successful exec)
  if (::pipe2(report, O_CLOEXEC) != 0) {
    cleanup();
    throw ProcessError(std::string("pipe failed: ") + std::strerror(errno));
  }
  const char* cwd = opt.cwd.empty() ? nullptr : opt.cwd.c_str();
  const bool group = opt.new_group, merge = opt.err_to_out;
  const int death_signal = opt.parent_death_signal;
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const std::string why = std::strerror(errno);
    cleanup();
    ::close(report[0]);
    ::close(report[1]);
    throw ProcessError("fork failed: " + why);
  }
  if (pid == 0) {
    if (group) ::setpgid(0, 0);
    if (death_signal > 0) {
      ::prctl(PR_SET_PDEATHSIG, death_signal);
      if (::getppid() != parent) ::_exit(127);  // the parent died before prctl
    }
    int e = 0;
    if (cwd && ::chdir(cwd) != 0) e = errno;
    for (int k = 0; k < 3 && !e; ++k)
      if (child_fd[k] >= 0 && ::dup2(child_fd[k], k) < 0) e = errno;
    if (!e && merge && ::dup2(1, 2) < 0) e = errno;
    if (!e) {
      ::execv(args[0], args.data());
      e = errno;
    }
    ssize_t ignored = ::write(report[1], &e, sizeof e);
    (void)ignored;
    ::_exit(127);
  }
  if (group) ::setpgid(pid, pid);  // also in the parent: no window before the child's call
  pid_ = pid;
  ::close(report[1]);
  for (int& f : child_fd) close_fd(f);
  in_ = parent_fd[0];
  out_ = parent_fd[1];
  err_ = parent_fd[2];
  int e = 0;
  ssize_t n;
  while ((n = ::read(report[0], &e, sizeof e)) < 0 && errno == EINTR) {
  }
  ::close(report[0]);
  if (n == static_cast<ssize_t>(sizeof e)) {  // exec failed: reap the child now
    int st = 0;
    while (::waitpid(pid_, &st, 0) < 0 && errno == EINTR) {
    }
    reaped_ = true;
    pid_ = -1;
    pre_.error = (cwd && e == ENOENT ? "cannot run '" + exe + "' in '" + opt.cwd + "': "
                                     : "cannot execute '" + exe + "': ") +
                 std::strerror(e);
    pre_.exit_code = 127;
    close_fd(in_);
    close_fd(out_);
    close_fd(err_);
  }
}

Child::~Child() {
  close_fd(in_);
  close_fd(out_);
  close_fd(err_);
  if (pid_ > 0 && !reaped_) {
    signal_group(SIGTERM);
    int st = 0;
    while (::waitpid(pid_, &st, 0) < 0 && errno == EINTR) {
    }
  }
}

void Child::close_in() { close_fd(in_); }

void Child::signal_group(int sig) {
  if (pid_ <= 0 || reaped_) return;
  if (opt_.new_group && ::kill(-pid_, sig) == 0) return;
  ::kill(pid_, sig);
}

ProcessResult Child::wait() {
  if (pid_ <= 0) {
    ProcessResult r = pre_;
    r.seconds = now_s() - t0_;
    return r;
  }
  ProcessResult r;
  r.started = true;
  close_in();
  for (int fd : {out_, err_})
    if (fd >= 0) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
  int status = 0;
  bool exited = reaped_;
  double term_sent = 0;
  bool killed = false;
  double quiet_since = 0;  // after the exit: stop draining if the pipes stay silent (grandchildren)
  while (!exited || out_ >= 0 || err_ >= 0) {
    if (!exited) {
      const pid_t w = ::waitpid(pid_, &status, WNOHANG);
      if (w == pid_ || (w < 0 && errno != EINTR)) {
        exited = true;
        reaped_ = true;
        quiet_since = now_s();
      }
    }
    if (!exited) {
      const double t = now_s();
      if (!killed && opt_.timeout_s > 0 && t - t0_ > opt_.timeout_s) {
        signal_group(SIGKILL);
        killed = true;
        r.timed_out = true;
      } else if (!killed && !term_sent && opt_.stop_on_interrupt && interrupted()) {
        signal_group(SIGTERM);
        term_sent = t;
        r.interrupted = true;
      } else if (!killed && term_sent && t - term_sent > 5.0) {
        signal_group(SIGKILL);
        killed = true;
      }
    }
    pollfd fds[2];
    int nf = 0;
    if (out_ >= 0) fds[nf++] = {out_, POLLIN, 0};
    if (err_ >= 0) fds[nf++] = {err_, POLLIN, 0};
    if (nf == 0) {
      if (!exited) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    const int pr = ::poll(fds, static_cast<nfds_t>(nf), 20);
    if (pr > 0) {
      quiet_since = now_s();
      for (int k = 0; k < nf; ++k) {
        if (!(fds[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
        if (fds[k].fd == out_)
          drain(out_, opt_.out.kind == Redirect::Capture ? &r.out : nullptr);
        else
          drain(err_, opt_.err.kind == Redirect::Capture ? &r.err : nullptr);
      }
    } else if (exited && now_s() - quiet_since > 1.0) {
      close_fd(out_);  // a grandchild keeps the pipe open: do not wait for it
      close_fd(err_);
    }
  }
  r.seconds = now_s() - t0_;
  if (WIFEXITED(status) && !r.timed_out) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.term_signal = WTERMSIG(status);
  return r;
}

ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& opt) {
  Child c(argv, opt);
  return c.wait();
}

int run_foreground(const std::vector<std::string>& argv) {
  ProcessOptions o;
  o.in = Redirect::inherit();
  o.new_group = false;
  o.stop_on_interrupt = false;
  try {
    const ProcessResult r = run_process(argv, o);
    return r.started ? r.status() : 127;
  } catch (const ProcessError&) {
    return 127;
  }
}

}  // namespace ru::util
