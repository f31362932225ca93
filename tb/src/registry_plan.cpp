// rayunits tb: the generic test plan of a registered unit (used for every unit whose testbench
// has no plan of its own; registered as the fallback plan "*", see register_all_tests()).
// Everything comes from the unit registry: the records and port bindings (RegistryAdapter),
// the golden model, the random vectors (UnitSpec::random_inputs). For each configuration
// <unit>_<cfg> (Long_<unit>_<cfg> for long configurations):
//   random      random vectors of the registry generator (20,000; long configurations 10^6)
//   reset       random vectors with a reset every ~40 cycles (dropped, replayed)
//   inject_*    (configurations tagged "selftest") the harness's planted errors
// and, for fast configurations, Long_<unit>_<cfg>.random with 10^6 vectors (label long). A unit's
// own plan may call it with hooks (RegistryPlanHooks: options of every run such as a handshake
// unit's timing reference, other vector counts) and add tests of its own.
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
  std::function<void(RunOptions&)> options;

  ScoreboardTest make(const std::string& test) const {
    ScoreboardTest t;
    t.cfg = cfg;
    t.name = suite + "." + test;
    const synth::UnitSpec* us = u;
    const synth::UnitConfig c = uc;
    t.adapter = [us, c] { return std::make_unique<RegistryAdapter>(*us, c); };
    t.opt = make_options(*cfg, t.name);
    if (options) options(t.opt);
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

Ctx make_ctx(const ConfigDesc& cfg, const RegistryPlanHooks& hooks) {
  Ctx c;
  c.cfg = &cfg;
  c.u = &synth::find_unit(cfg.unit);
  c.uc = unit_config(cfg);
  c.suite = (cfg.has_tag("long") ? "Long_" : "") + cfg.full_name();
  c.options = hooks.options;
  return c;
}

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

ScoreboardTest registry_test(const ConfigDesc& cfg, const std::string& test, uint64_t n, const RegistryPlanHooks& hooks) {
  const Ctx c = make_ctx(cfg, hooks);
  ScoreboardTest t = c.make(test);
  t.source = c.random(test, n);
  return t;
}

void registry_plan(const ConfigDesc& cfg, const RegistryPlanHooks& hooks) {
  const Ctx c = make_ctx(cfg, hooks);
  const bool is_long = cfg.has_tag("long");
  const uint64_t fast = hooks.fast_random ? hooks.fast_random : kFastRandom;
  const uint64_t lng = hooks.long_random ? hooks.long_random : kLongRandom;
  add_random(c, c.suite, "random", vector_count(cfg, is_long ? lng : fast), 3000);
  add_random(c, c.suite, "reset", vector_count(cfg, is_long ? lng / 10 : fast / 4),
             hooks.reset_every ? hooks.reset_every : 40);
  if (!is_long) add_random(c, "Long_" + cfg.full_name(), "random", vector_count(cfg, lng), 3000);
  if (cfg.has_tag("selftest")) {
    SelftestPlan p;
    p.suite = c.suite;
    p.stages = c.uc.stages;
    p.make = [c](const std::string& test) { return c.make(test); };
    p.seed = [c](const std::string& test) { return c.seed(test); };
    p.random = [c](const std::string& test, uint64_t n) { return c.random(test, n); };
    for (const synth::Field& f : synth::fields_for(*c.u, c.uc, synth::PortDir::Out)) p.out_bits.push_back(f.bits);
    p.handshake = c.u->handshake;
    p.timing = hooks.timing;
    add_harness_selftests(p);
  }
}

namespace {
PlanRegistrar r_any("*", [](const ConfigDesc& cfg) { registry_plan(cfg); });
}  // namespace

}  // namespace ru::tb
