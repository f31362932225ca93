// rayunits tb: the test plan of the floating-point units (fp_add, fp_mul, fp_div, fp_sqrt,
// fp_fma, fp_cmp, fp_dot3, fp_dot3_fused). For each configuration <unit>_<cfg> (suite; Long_<unit>_<cfg> for long configs):
//   special          every op x every pair of special values (TestFloat-style patterns; fp_sqrt:
//                    every special value; fp_fma: every triple, the op cycling)
//   random           weighted random operands (default 20,000; long configs 10^6; --vectors=N)
//   reset            random operands with a reset every ~40 cycles (stale results, replay)
//   exhaustive       every op x every operand pair, fp_sqrt every operand, fp_fma every op x
//                    every triple, the dot products every sextuple (4-bit formats; tagged "exhaustive")
//   file_<name>      tb/vectors/<unit>.*.txt whose format matches, and every --vector-file
//   inject_*         planted errors the harness must report (configurations tagged "selftest")
// and, for fast configurations, Long_<unit>_<cfg>.random with 10^6 vectors (label long).
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <sstream>

#include "rayunits/tb/fp.hpp"
#include "rayunits/tb/testing.hpp"
#include "rayunits/tb/vector_file.hpp"

namespace ru::tb {
namespace {

using ru::num::Format;

constexpr uint64_t kFastRandom = 20000;
constexpr uint64_t kLongRandom = 1000000;

struct Ctx {
  const ConfigDesc* cfg;
  const FpUnitSpec* spec;
  Format f;
  int stages;
  std::string suite;

  ScoreboardTest make(const std::string& test) const {
    ScoreboardTest t;
    t.cfg = cfg;
    t.name = suite + "." + test;
    const FpUnitSpec* s = spec;
    const Format fmt = f;
    const int st = stages;
    t.adapter = [s, fmt, st] { return std::make_unique<FpAdapter>(*s, fmt, st); };
    t.opt = make_options(*cfg, t.name);
    t.opt.format = fp_format_name(f);
    return t;
  }
  uint64_t seed(const std::string& test) const { return mix_seed(global_options().seed, suite + "." + test); }
};

void add_random(const Ctx& c, const std::string& suite, const std::string& test, uint64_t n,
                uint32_t reset_every) {
  Ctx cc = c;
  cc.suite = suite;
  register_test(suite, test, [cc, test, n, reset_every] {
    ScoreboardTest t = cc.make(test);
    const uint64_t seed = cc.seed(test);
    const FpUnitSpec* s = cc.spec;
    const Format f = cc.f;
    t.source = [s, f, seed, n] { return fp_random_source(*s, f, seed, n); };
    t.opt.reset_every = reset_every;
    expect_clean(t.name, run_scoreboard(t), n);
  });
}

// The planted-error tests (tb/include/rayunits/tb/testing.hpp): y_o or flags_o bit flips.
void add_selftests(const Ctx& c) {
  SelftestPlan p;
  p.suite = c.suite;
  p.stages = c.stages;
  p.make = [c](const std::string& test) { return c.make(test); };
  p.seed = [c](const std::string& test) { return c.seed(test); };
  p.random = [c](const std::string& test, uint64_t n) {
    const FpUnitSpec* s = c.spec;
    const Format f = c.f;
    const uint64_t seed = c.seed(test);
    return std::function<std::unique_ptr<VectorSource>()>([s, f, seed, n] { return fp_random_source(*s, f, seed, n); });
  };
  p.out_bits = {c.f.width(), 5};
  add_harness_selftests(p);
}

// Vector files: tb/vectors/<unit>*.txt (format must match, or no format line) and --vector-file.
void add_file_tests(const Ctx& c) {
  std::vector<std::pair<std::string, bool>> files;  // path, explicit
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(RU_TB_VECTOR_DIR, ec)) {
    const std::string fn = e.path().filename().string();
    // <unit>.<anything>.txt (a '.' after the name: fp_dot3.x.txt is not a file of fp_dot3_fused)
    if (e.path().extension() == ".txt" && fn.rfind(c.cfg->unit + ".", 0) == 0)
      files.emplace_back(e.path().string(), false);
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : global_options().vector_files) files.emplace_back(f, true);
  for (const auto& [path, explicit_file] : files) {
    std::string test = "file_" + std::filesystem::path(path).stem().string();
    for (char& ch : test)
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_') ch = '_';
    if (!explicit_file) {
      const VectorFile h = read_vector_file_header(path);
      if (!h.format.empty() && h.format != c.f.name()) continue;
      if (!h.round.empty() && h.round != ru::num::round_name(c.f.round)) continue;
    }
    register_test(c.suite, test, [c, path = path, test] {
      FpAdapter ad(*c.spec, c.f, c.stages);
      VectorFile vf;
      try {
        vf = read_vector_file(path, ad);
      } catch (const std::exception& e) {
        FAIL() << e.what();
      }
      if (!vf.format.empty() && vf.format != c.f.name())
        FAIL() << path << " is for format " << vf.format << ", this configuration is " << c.f.name();
      if (!vf.round.empty() && vf.round != ru::num::round_name(c.f.round))
        FAIL() << path << " is for rounding " << vf.round << ", this configuration uses " << ru::num::round_name(c.f.round);
      // 1. The file's expected outputs (where given) against the golden model.
      int model_errors = 0;
      for (const FileVector& v : vf.vectors) {
        Record exp;
        ad.model(v.in, exp);
        for (size_t i = 0; i < ad.outputs().size(); ++i) {
          const FieldInfo& fi = ad.outputs()[i];
          if ((v.out_mask >> i & 1) && ((exp.v[i] ^ v.out.v[i]) & fi.mask())) {
            if (++model_errors <= 5)
              ADD_FAILURE() << path << ":" << v.line << ": the golden model gives " << fi.name << " = "
                            << hex(exp.v[i], fi.bits) << " (" << ad.decimal(fi, exp.v[i]) << "), the file expects "
                            << hex(v.out.v[i], fi.bits) << " (" << ad.decimal(fi, v.out.v[i]) << ")";
          }
        }
      }
      // 2. The RTL against the golden model on the file's inputs.
      std::vector<Record> recs;
      for (const FileVector& v : vf.vectors) recs.push_back(v.in);
      ScoreboardTest t = c.make(test);
      t.source = [recs] { return std::make_unique<ArraySource>(recs); };
      expect_clean(t.name, run_scoreboard(t), recs.size());
    });
  }
}

void fp_plan(const ConfigDesc& cfg) {
  Ctx c;
  c.cfg = &cfg;
  c.spec = fp_unit_spec(cfg.unit);
  c.f = fp_format(cfg);
  c.stages = static_cast<int>(cfg.param("Stages", 0));
  const bool is_long = cfg.has_tag("long");
  c.suite = (is_long ? "Long_" : "") + cfg.full_name();

  register_test(c.suite, "special", [c] {
    ScoreboardTest t = c.make("special");
    const uint64_t seed = c.seed("special");
    const FpUnitSpec* s = c.spec;
    const Format f = c.f;
    t.source = [s, f, seed] { return fp_special_source(*s, f, seed); };
    const uint64_t n = fp_special_source(*s, f, seed)->total();
    expect_clean(t.name, run_scoreboard(t), n);
  });
  add_random(c, c.suite, "random", vector_count(cfg, is_long ? kLongRandom : kFastRandom), 3000);
  add_random(c, c.suite, "reset", vector_count(cfg, is_long ? kLongRandom / 10 : kFastRandom / 4), 40);
  if (!is_long) add_random(c, "Long_" + cfg.full_name(), "random", vector_count(cfg, kLongRandom), 3000);
  if (cfg.has_tag("exhaustive")) {
    register_test(c.suite, "exhaustive", [c] {
      ScoreboardTest t = c.make("exhaustive");
      const FpUnitSpec* s = c.spec;
      const Format f = c.f;
      t.source = [s, f] { return fp_exhaustive_source(*s, f); };
      t.opt.reset_every = 20000;
      expect_clean(t.name, run_scoreboard(t), fp_exhaustive_count(*s, f));
    });
  }
  if (cfg.has_tag("selftest")) add_selftests(c);
  add_file_tests(c);
}

PlanRegistrar r_add("fp_add", fp_plan);
PlanRegistrar r_mul("fp_mul", fp_plan);
PlanRegistrar r_div("fp_div", fp_plan);
PlanRegistrar r_sqrt("fp_sqrt", fp_plan);
PlanRegistrar r_fma("fp_fma", fp_plan);
PlanRegistrar r_cmp("fp_cmp", fp_plan);
PlanRegistrar r_dot3("fp_dot3", fp_plan);
PlanRegistrar r_dot3f("fp_dot3_fused", fp_plan);

}  // namespace
}  // namespace ru::tb
