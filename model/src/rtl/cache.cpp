// rayunits rtl: a unit configuration under the scoreboard, its Verilator build cached by content
// (rayunits/rtl/cache.hpp).
#include "rayunits/rtl/cache.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "rayunits/synth/process.hpp"
#include "rayunits/util/hash.hpp"
#include "rayunits/util/process.hpp"

namespace ru::rtl {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::string source_dir_of(const CacheOptions& r) {
  if (!r.source_dir.empty()) return fs::absolute(r.source_dir).lexically_normal().string();
#ifdef RU_SOURCE_DIR
  return RU_SOURCE_DIR;
#else
  throw RtlError("no source directory (build from the repository or give --source-dir)");
#endif
}

void say(const CacheOptions& r, const std::string& line) {
  if (r.progress) r.progress(line);
}

// First line of `prog args` (stdout, else stderr), cached per process.
std::string tool_version(const std::vector<std::string>& argv, const std::string& package) {
  static std::mutex m;
  static std::map<std::string, std::string> cache;
  std::lock_guard<std::mutex> l(m);
  const std::string id = argv[0];
  auto it = cache.find(id);
  if (it != cache.end()) return it->second;
  const std::string exe = util::find_program(argv[0]);
  if (exe.empty()) throw RtlError("missing tool '" + argv[0] + "' (Debian package " + package + ")");
  std::vector<std::string> a = argv;
  a[0] = exe;
  util::ProcessOptions o;
  o.out = util::Redirect::capture();
  o.err_to_out = true;
  o.timeout_s = 60;
  const util::ProcessResult p = util::run_process(a, o);
  std::string v = p.out.substr(0, p.out.find('\n'));
  if (!p.started || p.exit_code != 0 || v.empty())
    throw RtlError("cannot run '" + exe + "' to read its version (Debian package " + package + ")");
  return cache[id] = v;
}

// Content hash of everything a test executable is built from besides the unit's RTL: the harness
// (tb/), the golden models and their library (model/), the build description (CMakeLists.txt).
std::string harness_hash(const std::string& src) {
  std::vector<std::string> files;
  for (const char* top : {"tb", "model/include", "model/src", "model/data/registry.json", "model/CMakeLists.txt",
                          "CMakeLists.txt"}) {
    const fs::path p = fs::path(src) / top;
    if (fs::is_regular_file(p)) {
      files.push_back(top);
    } else if (fs::is_directory(p)) {
      for (const auto& e : fs::recursive_directory_iterator(p))
        if (e.is_regular_file()) files.push_back(fs::relative(e.path(), src).string());
    }
  }
  if (files.empty()) throw RtlError("'" + src + "' is not a rayunits source directory (no tb/ or model/)");
  std::sort(files.begin(), files.end());
  std::uint64_t h = util::fnv1a64("");
  for (const std::string& f : files) {
    h = util::fnv1a64(f, h);
    h = util::fnv1a64(std::string(1, '\0'), h);
    h = util::fnv1a64(synth::read_file((fs::path(src) / f).string()), h);
  }
  return util::hex64(h);
}

// An exclusive flock on `path` for the object's lifetime (blocking; a line while it waits).
class FileLock {
 public:
  FileLock(const std::string& path, const CacheOptions& r) {
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw RtlError("cannot open the lock file '" + path + "'");
    if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) return;
    say(r, "rtl: waiting for another build in " + fs::path(path).parent_path().string());
    while (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      if (synth::interrupted()) {
        ::close(fd_);
        throw RtlError("interrupted");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  ~FileLock() { ::close(fd_); }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_ = -1;
};

// The last non-empty line of a log that names an error, else its last non-empty line.
std::string log_error_line(const std::string& path) {
  std::ifstream f(path);
  std::string line, last, err;
  while (std::getline(f, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    last = line;
    if (line.find("rror") != std::string::npos && err.empty()) err = line;
  }
  std::string s = err.empty() ? last : err;
  if (s.size() > 300) s = s.substr(0, 300) + "...";
  return s;
}

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One line of a gtest failure message: the scoreboard's "MISMATCH at cycle ..." line and the
// first output that differs, else the first line after gtest's "file:line".
std::string failure_line(const std::string& m) {
  std::istringstream in(m);
  std::string line, mismatch, differs, first;
  for (int n = 0; std::getline(in, line); ++n) {
    const size_t b = line.find_first_not_of(' ');
    if (b == std::string::npos) continue;
    line = line.substr(b);
    if (n == 1 && first.empty()) first = line;
    if (mismatch.empty() && line.find("MISMATCH") != std::string::npos) mismatch = line;
    if (differs.empty() && line.find("<-- differs") != std::string::npos) differs = line;
  }
  if (!mismatch.empty()) return mismatch + (differs.empty() ? "" : "; " + differs);
  return first.empty() ? m.substr(0, m.find('\n')) : first;
}

}  // namespace

std::string default_cache_dir() {
  if (const char* c = std::getenv("RU_RTL_CACHE"); c && *c) return c;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/rayunits/rtl";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/rayunits/rtl";
  return "/tmp/rayunits-rtl-cache";
}

std::string tb_config(const synth::UnitSpec& u, const synth::UnitConfig& c) {
  std::string s;
  if (u.uses_format) s = c.fmt.name() + ":";
  s += "s" + std::to_string(c.stages);
  if (u.uses_format && c.fmt.round != num::Round::RNE) s += std::string(":") + num::round_name(c.fmt.round);
  for (const auto& [k, v] : c.params) s += ":" + k + "=" + std::to_string(v);
  return s;
}

// The parts every key has: the harness and model sources and the tools.
void common_parts(const CacheOptions& o, json& parts) {
  parts["tb_hash"] = harness_hash(source_dir_of(o));
  parts["verilator"] = tool_version({"verilator", "--version"}, "verilator");
  parts["compiler"] = tool_version({"c++", "--version"}, "g++");
}

std::string rtl_hash_of(const CacheOptions& o, const synth::UnitSpec& u) {
  try {
    return synth::sources_hash(synth::resolve_sources(u, o.rtl_dir.empty() ? synth::default_rtl_dir() : o.rtl_dir));
  } catch (const std::exception& e) {
    throw RtlError(e.what());
  }
}

Key build_key(const Request& r) {
  if (!r.unit) throw RtlError("no unit");
  Key k;
  k.parts["rtl_hash"] = rtl_hash_of(r, *r.unit);
  k.parts["unit"] = r.unit->name;
  k.parts["config"] = tb_config(*r.unit, r.cfg);
  if (!r.unit->design_file.empty()) {  // a run-time design: its graph too (the RTL hash covers its module)
    try {
      k.parts["design"] = util::fnv1a64_hex(synth::read_file(r.unit->design_file));
    } catch (const std::exception& e) {
      throw RtlError(e.what());
    }
  }
  common_parts(r, k.parts);
  k.hash = util::fnv1a64_hex(k.parts.dump());
  return k;
}

namespace {

// The cached executable of key k, or its build: `spec` declares the target in the cache's build
// tree (RU_TB_JOB_CONFIGS for a test executable, RU_TB_COSIM_JOB for a companion; target name
// "tbjob_<key>").
// extra_registry: the registry JSON of a unit given at run time (RU_TB_EXTRA_REGISTRY), or empty.
Build ensure_product(const CacheOptions& r, const Key& k, const std::string& what, bool cosim, const std::string& spec,
                     const std::string& extra_registry = "") {
  const fs::path cache = fs::absolute(r.cache_dir.empty() ? default_cache_dir() : r.cache_dir);
  const fs::path bin = cache / "bin" / k.hash;
  Build b;
  b.key = k.hash;
  b.exe = (bin / "tb").string();
  if (fs::exists(b.exe)) {
    b.hit = true;
    say(r, "rtl: " + what + ": cache hit " + k.hash);
    return b;
  }
  const std::string src = source_dir_of(r);
  for (const auto& [tool, pkg] : std::vector<std::pair<std::string, std::string>>{{"cmake", "cmake"}, {"ninja", "ninja-build"}})
    if (util::find_program(tool).empty()) throw RtlError("missing tool '" + tool + "' (Debian package " + pkg + ")");
  std::error_code ec;
  const fs::path tree = cache / "trees" / util::fnv1a64_hex(src);
  fs::create_directories(tree, ec);
  fs::create_directories(cache / "logs", ec);
  if (ec) throw RtlError("cannot create the cache directory '" + cache.string() + "': " + ec.message());
  FileLock lock((tree / ".lock").string(), r);
  if (fs::exists(b.exe)) {  // built by another process while this one waited
    b.hit = true;
    say(r, "rtl: " + what + ": cache hit " + k.hash + " (built by another process meanwhile)");
    return b;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::string target = "tbjob_" + k.hash;
  const std::string log = (cache / "logs" / (k.hash + ".build.log")).string();
  fs::remove(log, ec);
  const std::string rtl = fs::absolute(r.rtl_dir.empty() ? synth::default_rtl_dir() : r.rtl_dir).string();
  say(r, "rtl: " + what + ": cache miss " + k.hash + ", building (log " + log + ")");
  const fs::path build = tree / "build";
  std::string extra;
  if (!extra_registry.empty()) {
    extra = (cache / "logs" / (k.hash + ".registry.json")).string();
    synth::write_file_atomic(extra, extra_registry);
  }
  const char* jobs_env = std::getenv("RU_JOBS");
  const std::string jobs = jobs_env && *jobs_env ? jobs_env : std::to_string(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::vector<std::string>> steps = {
      {"cmake", "-S", src, "-B", build.string(), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release", "-DRU_TB=ON",
       "-DRU_TB_JOBS_ONLY=ON", "-DRU_TB_RTL_DIR=" + rtl, "-DRU_TB_EXTRA_REGISTRY=" + extra,
       "-DRU_TB_JOB_CONFIGS=" + (cosim ? std::string() : target + "=" + spec),
       "-DRU_TB_COSIM_JOB=" + (cosim ? target + "=" + spec : std::string())},
      {"cmake", "--build", build.string(), "--target", target, "-j", jobs},
  };
  for (const auto& argv : steps) {
    say(r, "rtl:   " + argv[0] + " " + argv[1] + " ...");
    util::ProcessOptions o;
    o.out = util::Redirect::file(log, true);
    o.err_to_out = true;
    std::vector<std::string> a = argv;
    a[0] = util::find_program(a[0]);
    const util::ProcessResult p = util::run_process(a, o);
    if (p.interrupted) throw RtlError("interrupted");
    if (!p.started || p.status() != 0)
      throw RtlError("building " + what + " failed (log " + log + "): " + log_error_line(log));
  }
  const fs::path built = build / "tb" / target;
  if (!fs::exists(built)) throw RtlError("building " + what + ": no executable " + built.string() + " (log " + log + ")");
  fs::create_directories(bin, ec);
  const fs::path tmp = bin / "tb.tmp";
  fs::copy_file(built, tmp, fs::copy_options::overwrite_existing, ec);
  if (ec) throw RtlError("cannot copy " + built.string() + " into the cache: " + ec.message());
  b.seconds = since(t0);
  json m = k.parts;
  m["key"] = k.hash;
  m["rtl_dir"] = rtl;
  m["source_dir"] = src;
  m["build_s"] = b.seconds;
  synth::write_file_atomic((bin / "manifest.json").string(), m.dump(2) + "\n");
  fs::rename(tmp, b.exe, ec);
  if (ec) throw RtlError("cannot install " + b.exe + ": " + ec.message());
  // The model's objects are not needed again (the tree keeps the shared libraries only).
  fs::remove_all(build / "tb" / "CMakeFiles" / (target + ".dir"), ec);
  fs::remove(built, ec);
  say(r, "rtl: " + what + ": built in " + std::to_string(static_cast<int>(b.seconds + 0.5)) + " s");
  return b;
}

}  // namespace

Build ensure_built(const Request& r) {
  const Key k = build_key(r);
  const std::string cfg = k.parts["config"].get<std::string>();
  return ensure_product(r, k, r.unit->name + " " + cfg, false, r.unit->name + ":" + cfg,
                        r.unit->design_file.empty() ? "" : synth::registry_json({*r.unit}));
}

Build ensure_cosim(const CosimRequest& r) {
  if (r.units.empty()) throw RtlError("a co-simulation companion needs at least one unit");
  Key k;
  k.parts["kind"] = "cosim";
  std::string spec, what;
  for (const auto& [u, c] : r.units) {
    const std::string cfg = tb_config(*u, c);
    k.parts["units"].push_back({{"unit", u->name}, {"config", cfg}, {"rtl_hash", rtl_hash_of(r, *u)}});
    spec += (spec.empty() ? "" : "|") + u->name + ":" + cfg;
    what += (what.empty() ? "" : ", ") + u->name + " " + cfg;
  }
  common_parts(r, k.parts);
  k.hash = util::fnv1a64_hex(k.parts.dump());
  return ensure_product(r, k, "co-simulation of " + what, true, spec);
}

json to_json(const Row& r) {
  json j = {{"unit", r.unit},
            {"stages", r.stages},
            {"params", r.params},
            {"config", r.config},
            {"key", r.key},
            {"rtl_hash", r.rtl_hash},
            {"vectors", r.vectors},
            {"seed", r.seed},
            {"status", r.status},
            {"tests", r.tests},
            {"failed", r.failed},
            {"failed_tests", r.failed_tests},
            {"first_failure", r.first_failure},
            {"cache_hit", r.cache_hit},
            {"build_s", r.build_s},
            {"run_s", r.run_s},
            {"verilator", r.verilator}};
  if (!r.format.empty()) {
    j["format"] = r.format;
    j["round"] = r.round;
    j["ftz"] = r.ftz;
  }
  return j;
}

Row run(const Request& r) {
  const Key k = build_key(r);
  const Build b = ensure_built(r);
  Row row;
  row.unit = r.unit->name;
  if (r.unit->uses_format) {
    num::Format f = r.cfg.fmt;
    f.subnormals = true;
    row.format = f.name();
    row.round = num::round_name(r.cfg.fmt.round);
    row.ftz = !r.cfg.fmt.subnormals;
  }
  row.stages = r.cfg.stages;
  for (const auto& [n, v] : r.cfg.params) row.params[n] = v;
  row.config = k.parts["config"].get<std::string>();
  row.key = b.key;
  row.rtl_hash = k.parts["rtl_hash"].get<std::string>();
  row.vectors = r.vectors;
  row.seed = r.seed;
  row.cache_hit = b.hit;
  row.build_s = b.seconds;
  row.verilator = k.parts["verilator"].get<std::string>();
  if (r.build_only) {
    row.status = "built";
    return row;
  }
  synth::TempDir tmp("ru-rtl-");
  const std::string report = tmp.path() + "/gtest.json";
  util::ProcessOptions o;
  o.cwd = tmp.path();
  o.timeout_s = r.timeout_s;
  const util::ProcessResult p =
      util::run_process({b.exe, "--vectors=" + std::to_string(r.vectors), "--seed=" + std::to_string(r.seed),
                         "--no-trace-on-fail", "--gtest_output=json:" + report,
                         std::string("--gtest_filter=") + (r.long_tests ? "*" : "-Long_*")},
                        o);
  row.run_s = p.seconds;
  if (p.interrupted) throw RtlError("interrupted");
  if (p.timed_out) {
    row.status = "timeout";
    row.first_failure = "timed out after " + std::to_string(static_cast<long>(r.timeout_s)) + " s";
    return row;
  }
  json g;
  try {
    g = json::parse(synth::read_file(report));
  } catch (const std::exception&) {
    throw RtlError(r.unit->name + " " + row.config + ": the test executable ended with status " +
                   std::to_string(p.status()) + " without a report (" + b.exe + ")");
  }
  row.tests = g.value("tests", 0);
  for (const json& suite : g.value("testsuites", json::array()))
    for (const json& t : suite.value("testsuite", json::array())) {
      if (!t.contains("failures")) continue;
      ++row.failed;
      if (row.failed_tests.size() < 20)
        row.failed_tests.push_back(suite.value("name", "") + "." + t.value("name", ""));
      if (row.first_failure.empty() && !t["failures"].empty()) {
        row.first_failure = failure_line(t["failures"][0].value("failure", ""));
      }
    }
  row.status = row.failed == 0 && p.exit_code == 0 && row.tests > 0 ? "pass" : "fail";
  if (row.status == "fail" && row.failed == 0)
    row.first_failure = row.tests == 0 ? "no tests ran" : "exit status " + std::to_string(p.status());
  return row;
}

}  // namespace ru::rtl
