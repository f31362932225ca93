// rayunits tb: the generic test plan of a registered unit (used for every unit whose testbench
// has no plan of its own; registered as the fallback plan "*", see register_all_tests()).
// Everything comes from the unit registry: the records and port bindings (RegistryAdapter),
// the golden model, the random vectors (UnitSpec::random_inputs). For each configuration
// <unit>_<cfg> (Long_<unit>_<cfg> for long configurations):
//   random      random vectors of the registry generator (20,000; long configurations 10^6)
//   reset       random vectors with a reset every ~40 cycles (dropped, replayed)
//   inject_*    (configurations tagged "selftest") the harness's planted errors
// and, for fast configurations, Long_<unit>_<cfg>.random with 10^6 vectors (label long).
#include <gtest/gtest.h>

#include "rayunits/tb/registry_adapter.hpp"
#include "rayunits/tb/testing.hpp"

namespace ru::tb {
namespace {

constexpr uint64_t kFastRandom = 20000;
constexpr uint64_t kLongRandom = 1000000;

struct Ctx {
  const ConfigDesc* cfg = nullptr;
  const synth::UnitSpec* u = nullptr;
  synth::UnitConfig uc;
  std::string suite;

  ScoreboardTest make(const std::string& test) const {
    ScoreboardTest t;
    t.cfg = cfg;
    t.name = suite + "." + test;
    const synth::UnitSpec* us = u;
    const synth::UnitConfig c = uc;
    t.adapter = [us, c] { return std::make_unique<RegistryAdapter>(*us, c); };
    t.opt = make_options(*cfg, t.name);
    return t;
  }
  uint64_t seed(const std::string& test) const { return mix_seed(global_options().seed, suite + "." + test); }
  std::function<std::unique_ptr<VectorSource>()> random(const std::string& test, uint64_t n) const {
    const synth::UnitSpec* us = u;
    const synth::UnitConfig c = uc;
    const uint64_t s = seed(test);
    return [us, c, s, n] { return registry_random_source(*us, c, s, n); };
  }
};

void add_random(Ctx c, const std::string& suite, const std::string& test, uint64_t n, uint32_t reset_every) {
  c.suite = suite;
  register_test(suite, test, [c, test, n, reset_every] {
    ScoreboardTest t = c.make(test);
    t.source = c.random(test, n);
    t.opt.reset_every = reset_every;
    expect_clean(t.name, run_scoreboard(t), n);
  });
}

}  // namespace

void registry_plan(const ConfigDesc& cfg) {
  Ctx c;
  c.cfg = &cfg;
  c.u = &synth::find_unit(cfg.unit);
  c.uc = unit_config(cfg);
  const bool is_long = cfg.has_tag("long");
  c.suite = (is_long ? "Long_" : "") + cfg.full_name();
  add_random(c, c.suite, "random", vector_count(cfg, is_long ? kLongRandom : kFastRandom), 3000);
  add_random(c, c.suite, "reset", vector_count(cfg, is_long ? kLongRandom / 10 : kFastRandom / 4), 40);
  if (!is_long) add_random(c, "Long_" + cfg.full_name(), "random", vector_count(cfg, kLongRandom), 3000);
  if (cfg.has_tag("selftest")) {
    SelftestPlan p;
    p.suite = c.suite;
    p.stages = c.uc.stages;
    p.make = [c](const std::string& test) { return c.make(test); };
    p.seed = [c](const std::string& test) { return c.seed(test); };
    p.random = [c](const std::string& test, uint64_t n) { return c.random(test, n); };
    for (const synth::Field& f : synth::fields_for(*c.u, c.uc, synth::PortDir::Out)) p.out_bits.push_back(f.bits);
    add_harness_selftests(p);
  }
}

namespace {
PlanRegistrar r_any("*", registry_plan);
}  // namespace

}  // namespace ru::tb
