// rayunits tb: options, test-plan registry and the GoogleTest glue (see testing.hpp).
#include "rayunits/tb/testing.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <random>
#include <sstream>

namespace ru::tb {

bool ConfigDesc::has_tag(const std::string& t) const {
  for (const auto& x : tags)
    if (x == t) return true;
  return false;
}

std::string ConfigDesc::tag_value(const std::string& key, const std::string& def) const {
  for (const auto& x : tags)
    if (x.size() > key.size() && x.compare(0, key.size(), key) == 0 && x[key.size()] == '=')
      return x.substr(key.size() + 1);
  return def;
}

std::vector<ConfigDesc>& registered_configs() {
  static std::vector<ConfigDesc> v;
  return v;
}

std::vector<std::pair<std::string, TestPlan>>& registered_plans() {
  static std::vector<std::pair<std::string, TestPlan>> v;
  return v;
}

GlobalOptions& global_options() {
  static GlobalOptions g;
  return g;
}

namespace {

bool parse_u64(const std::string& s, uint64_t& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 0);
  if (errno || *end || s[0] == '-') return false;
  out = v;
  return true;
}

bool set_option(const std::string& key, const std::string& val, bool has_val) {
  GlobalOptions& g = global_options();
  auto need = [&](const char* what) {
    if (!has_val || val.empty()) {
      std::cerr << "error: --" << key << " needs a value (" << what << ")\n";
      return false;
    }
    return true;
  };
  uint64_t u = 0;
  if (key == "seed") {
    if (!need("an integer or 'random'")) return false;
    if (val == "random") {
      g.seed = std::random_device{}() ^ static_cast<uint64_t>(
                                          std::chrono::steady_clock::now().time_since_epoch().count());
      g.seed &= 0xffffffffffffull;
      return true;
    }
    if (!parse_u64(val, u)) {
      std::cerr << "error: --seed=" << val << ": expected a non-negative integer or 'random'\n";
      return false;
    }
    g.seed = u;
  } else if (key == "vectors") {
    if (!need("a count") ) return false;
    if (!parse_u64(val, u)) {
      std::cerr << "error: --vectors=" << val << ": expected a non-negative integer\n";
      return false;
    }
    g.vectors = static_cast<int64_t>(u);
  } else if (key == "max-errors") {
    if (!need("a count")) return false;
    if (!parse_u64(val, u) || u < 1 || u > 1000000) {
      std::cerr << "error: --max-errors=" << val << ": expected an integer >= 1\n";
      return false;
    }
    g.max_errors = static_cast<int>(u);
  } else if (key == "trace" && !has_val) {
    g.trace_always = true;
  } else if (key == "no-trace-on-fail" && !has_val) {
    g.trace_on_fail = false;
  } else if (key == "trace-dir") {
    if (!need("a directory")) return false;
    g.trace_dir = val;
  } else if (key == "vector-file") {
    if (!need("a file")) return false;
    g.vector_files.push_back(val);
  } else if (key == "progress" && !has_val) {
    g.progress = true;
  } else {
    std::cerr << "error: unknown option --" << key << (has_val ? "=" + val : "")
              << " (accepted: --seed=N|random --vectors=N --max-errors=N --trace "
                 "--no-trace-on-fail --trace-dir=DIR --vector-file=FILE --progress, gtest options)\n";
    return false;
  }
  return true;
}

}  // namespace

bool parse_options(int& argc, char** argv) {
  GlobalOptions& g = global_options();
  if (argc > 0) g.argv0 = argv[0];
  struct Env {
    const char* var;
    const char* key;
  };
  for (const Env& e : {Env{"RU_SEED", "seed"}, Env{"RU_VECTORS", "vectors"},
                       Env{"RU_TRACE_DIR", "trace-dir"}, Env{"RU_VECTOR_FILE", "vector-file"}}) {
    const char* v = std::getenv(e.var);
    if (v && *v && !set_option(e.key, v, true)) {
      std::cerr << "       (from the environment variable " << e.var << ")\n";
      return false;
    }
  }
  int out = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--gtest", 0) == 0 || a.rfind("--", 0) != 0) {
      if (a.rfind("--", 0) != 0 && a.rfind("-", 0) != 0) {
        std::cerr << "error: unexpected argument '" << a << "'\n";
        return false;
      }
      argv[out++] = argv[i];
      continue;
    }
    const size_t eq = a.find('=');
    const std::string key = a.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
    const bool has_val = eq != std::string::npos;
    const std::string val = has_val ? a.substr(eq + 1) : std::string();
    if (!set_option(key, val, has_val)) return false;
  }
  argc = out;
  argv[argc] = nullptr;
  return true;
}

void register_test(const std::string& suite, const std::string& name, std::function<void()> body) {
  struct Fixture : public ::testing::Test {
    explicit Fixture(std::function<void()> b) : body_(std::move(b)) {}
    void TestBody() override { body_(); }
    std::function<void()> body_;
  };
  ::testing::RegisterTest(suite.c_str(), name.c_str(), nullptr, nullptr, __FILE__, __LINE__,
                          [body]() -> ::testing::Test* { return new Fixture(body); });
}

bool register_all_tests() {
  bool ok = true;
  for (const ConfigDesc& c : registered_configs()) {
    bool found = false;
    for (auto& [unit, plan] : registered_plans()) {
      if (unit == c.unit) {
        plan(c);
        found = true;
      }
    }
    // A unit without a plan of its own gets the generic registry plan (tb/src/registry_plan.cpp).
    for (auto& [unit, plan] : registered_plans()) {
      if (!found && unit == "*") {
        plan(c);
        found = true;
      }
    }
    if (!found) {
      std::cerr << "error: no test plan for unit '" << c.unit << "' (configuration " << c.name << ")\n";
      ok = false;
    }
  }
  return ok;
}

uint64_t vector_count(const ConfigDesc& cfg, uint64_t def) {
  const GlobalOptions& g = global_options();
  if (g.vectors >= 0) return static_cast<uint64_t>(g.vectors);
  const std::string n = cfg.tag_value("n", "");
  if (!n.empty()) return std::strtoull(n.c_str(), nullptr, 10);
  return def;
}

RunOptions make_options(const ConfigDesc& cfg, const std::string& test_name) {
  const GlobalOptions& g = global_options();
  RunOptions o;
  o.test = test_name;
  o.seed = g.seed;
  o.stages = static_cast<int>(cfg.param("Stages", 0));
  o.max_errors = g.max_errors;
  o.progress = g.progress;
  o.rerun_hint = g.argv0 + " --gtest_filter='" + test_name + "' --seed=" + std::to_string(g.seed);
  if (g.vectors >= 0) o.rerun_hint += " --vectors=" + std::to_string(g.vectors);
  for (const auto& f : g.vector_files) o.rerun_hint += " --vector-file=" + f;
  return o;
}

static std::string trace_file_name(const std::string& test, uint64_t seed) {
  std::string n;
  for (char c : test) n += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '.';
  const std::string dir = global_options().trace_dir;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  return dir + "/" + n + "_seed" + std::to_string(seed) + ".fst";
}

RunStats run_scoreboard(const ScoreboardTest& t, std::string* trace_file) {
  const GlobalOptions& g = global_options();
  RunOptions o = t.opt;
  DutOptions d;
  d.seed = o.seed;
  d.trace = g.trace_always;
  if (g.trace_always) {
    o.trace_path = trace_file_name(t.name, o.seed);
    if (trace_file) *trace_file = o.trace_path;
  }
  RunStats st;
  {
    auto dut = t.cfg->make(d);
    auto ad = t.adapter();
    auto src = t.source();
    st = run(*dut, *ad, *src, o);
  }
  if (!st.ok() && !g.trace_always && g.trace_on_fail) {
    // Same seed, same stream, same X randomization: the run is reproduced exactly; trace a
    // window of up to 2000 cycles before the first error until just after the last one.
    RunOptions r = o;
    r.trace_path = trace_file_name(t.name, o.seed);
    const uint64_t first = st.errors.front().cycle, last = st.errors.back().cycle;
    r.trace_from = first > 2000 ? first - 2000 : 0;
    r.stop_after_cycle = last + 8;
    r.quiet = true;
    d.trace = true;
    auto dut = t.cfg->make(d);
    auto ad = t.adapter();
    auto src = t.source();
    RunStats rs = run(*dut, *ad, *src, r);
    const bool same = rs.errors.size() == st.errors.size() && rs.errors.front().cycle == first;
    std::cerr << "[" << t.name << "] FST trace of cycles " << r.trace_from << ".." << last
              << " (time = 10 x cycle): " << r.trace_path
              << (same ? "" : "  (warning: the traced re-run did not reproduce the same errors)")
              << "\n";
    if (trace_file) *trace_file = r.trace_path;
  }
  return st;
}

std::string run_summary(const RunStats& st) {
  std::ostringstream os;
  os << st.checked << " results checked in " << st.cycles << " cycles (" << st.issued << " issued, "
     << st.resets << " reset cycles, " << st.dropped << " dropped by reset and re-issued), "
     << st.seconds << " s";
  return os.str();
}

void expect_clean(const std::string& name, const RunStats& st, uint64_t expect_checked) {
  std::cerr << "[" << name << "] seed=" << global_options().seed << ": " << run_summary(st) << "\n";
  EXPECT_TRUE(st.ok()) << st.errors.size() << " mismatch(es)" << (st.aborted ? " (stopped early)" : "")
                       << "; first:\n"
                       << (st.errors.empty() ? "" : st.errors.front().report);
  if (!st.aborted) {
    EXPECT_EQ(st.checked, expect_checked) << "every vector must be checked exactly once";
  }
}

void add_harness_selftests(const SelftestPlan& p) {
  const std::string note = "(planted error: the MISMATCH report below is expected)\n";
  register_test(p.suite, "inject_bitflip", [p, note] {
    ScoreboardTest t = p.make("inject_bitflip");
    t.source = p.random("inject_bitflip", 2000);
    expect_clean(t.name + " control", run_scoreboard(t), 2000);
    Rng rng(p.seed("inject_bitflip"));
    t.opt.inject.flip_item = 700;
    t.opt.inject.flip_field = static_cast<int>(rng.below(p.out_bits.size()));
    t.opt.inject.flip_bit = static_cast<int>(rng.below(static_cast<uint64_t>(p.out_bits[t.opt.inject.flip_field])));
    std::cerr << note;
    std::string trace;
    const RunStats st = run_scoreboard(t, &trace);
    ASSERT_EQ(st.errors.size(), 1u) << "exactly the planted error must be reported";
    const Mismatch& m = st.errors[0];
    EXPECT_EQ(m.kind, Mismatch::Data);
    EXPECT_EQ(m.item, 700);
    EXPECT_EQ(m.field_mask, 1u << t.opt.inject.flip_field);
    EXPECT_NE(m.report.find("seed="), std::string::npos);
    EXPECT_NE(m.report.find("<-- differs"), std::string::npos);
    if (global_options().trace_on_fail) {
      std::error_code ec;
      EXPECT_GT(std::filesystem::file_size(trace, ec), 0u) << "no FST written: " << trace;
    }
  });
  for (int delta : {+1, -1}) {
    if (delta < 0 && p.stages == 0) continue;
    // A handshake unit's results may come later than Stages: one expected a cycle early is
    // caught only by a timing reference.
    if (delta < 0 && p.handshake && !p.timing) continue;
    const std::string name = delta > 0 ? "inject_latency_late" : "inject_latency_early";
    register_test(p.suite, name, [p, note, delta, name] {
      ScoreboardTest t = p.make(name);
      t.source = p.random(name, 500);
      expect_clean(t.name + " control", run_scoreboard(t), 500);
      t.opt.inject.latency_delta = delta;
      std::cerr << note;
      const RunStats st = run_scoreboard(t);
      ASSERT_FALSE(st.errors.empty()) << "a one-cycle latency error went unnoticed";
      // Late expectation: the DUT's first result arrives one cycle before it is expected.
      // Early expectation: the first expected result finds out_valid_o = 0.
      EXPECT_EQ(st.errors[0].kind, delta > 0 ? Mismatch::UnexpectedValid : Mismatch::MissingValid);
      EXPECT_TRUE(st.aborted) << "the harness must stop after --max-errors mismatches";
      EXPECT_EQ(st.errors.size(), static_cast<size_t>(global_options().max_errors));
    });
  }
  if (p.stages > 0) {
    register_test(p.suite, "inject_stale", [p, note] {
      ScoreboardTest t = p.make("inject_stale");
      t.source = p.random("inject_stale", 400);
      t.opt.traffic = Traffic::BackToBack;  // the pipeline is full when reset comes
      t.opt.reset_every = 0;
      t.opt.reset_at = {200};
      const RunStats ctl = run_scoreboard(t);
      expect_clean(t.name + " control", ctl, 400);
      // a unit with a handshake may hold fewer inputs than Stages (ru_texture: one per
      // ceil(n / Units) cycles): at least one must be in flight
      EXPECT_GE(ctl.dropped, p.handshake ? uint64_t{1} : static_cast<uint64_t>(p.stages - 1))
          << "reset did not hit a full pipeline";
      // Planted: the harness drops its expectations at the reset but rst_ni stays high, i.e. a
      // DUT whose reset does not clear its pipeline. Its in-flight results are stale.
      t.opt.inject.skip_reset = true;
      std::cerr << note;
      const RunStats st = run_scoreboard(t);
      ASSERT_FALSE(st.errors.empty()) << "stale results after reset went unnoticed";
      if (p.handshake) {
        // the stale state shows as a result or as in_ready_o, in the first cycle that differs
        EXPECT_TRUE(st.errors[0].kind == Mismatch::UnexpectedValid || st.errors[0].kind == Mismatch::Ready);
        EXPECT_GE(st.errors[0].cycle, 201u);
      } else {
        EXPECT_EQ(st.errors[0].kind, Mismatch::UnexpectedValid);
        EXPECT_EQ(st.errors[0].cycle, 201u);
      }
      EXPECT_NE(st.errors[0].report.find("last reset in cycle 200"), std::string::npos);
    });
  }
}

}  // namespace ru::tb
