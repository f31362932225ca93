// Subprocesses and temp directories for the synthesis flow (the launcher and the interrupt
// flag are util/process.hpp and util/interrupt.hpp; these are the flow's names for them).
#include "rayunits/synth/process.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rayunits/synth/units.hpp"
#include "rayunits/util/interrupt.hpp"
#include "rayunits/util/process.hpp"

namespace ru::synth {
namespace fs = std::filesystem;

std::string find_program(const std::string& name) { return util::find_program(name); }

ProcResult run_process(const std::vector<std::string>& argv, const std::string& cwd,
                       const std::string& log_path, int timeout_s) {
  util::ProcessOptions o;
  o.cwd = cwd;
  o.out = util::Redirect::file(log_path, /*append=*/true);
  o.err_to_out = true;
  o.timeout_s = timeout_s > 0 ? timeout_s : 0;
  util::ProcessResult p;
  try {
    p = util::run_process(argv, o);
  } catch (const util::ProcessError& e) {
    throw SynthError(e.what());
  }
  if (util::interrupted()) throw SynthError("interrupted");
  ProcResult r;
  r.exit_code = p.started ? p.exit_code : 127;
  r.timed_out = p.timed_out;
  r.seconds = p.seconds;
  return r;
}

void install_interrupt_handler() { util::install_interrupt_handler(); }
bool interrupted() { return util::interrupted(); }

TempDir::TempDir(const std::string& prefix, const std::string& parent) {
  std::string base = parent;
  if (base.empty()) {
    const char* t = std::getenv("TMPDIR");
    base = (t && *t) ? t : "/tmp";
  }
  std::string tmpl = base + "/" + prefix + "XXXXXX";
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (!::mkdtemp(buf.data()))
    throw SynthError("cannot create a temp directory in '" + base + "': " + std::strerror(errno));
  path_ = buf.data();
}

TempDir::~TempDir() {
  if (keep_ || path_.empty()) return;
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void write_file_atomic(const std::string& path, const std::string& text) {
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::string tmpl = (dir / ("." + p.filename().string() + ".tmpXXXXXX")).string();
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  int fd = ::mkstemp(buf.data());
  if (fd < 0) throw SynthError("cannot write '" + path + "': " + std::strerror(errno));
  size_t done = 0;
  while (done < text.size()) {
    ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      int e = errno;
      ::close(fd);
      ::unlink(buf.data());
      throw SynthError("cannot write '" + path + "': " + std::strerror(e));
    }
    done += static_cast<size_t>(n);
  }
  ::fchmod(fd, 0644);
  if (::close(fd) != 0 || ::rename(buf.data(), path.c_str()) != 0) {
    int e = errno;
    ::unlink(buf.data());
    throw SynthError("cannot write '" + path + "': " + std::strerror(e));
  }
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SynthError("cannot read '" + path + "'");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace ru::synth
