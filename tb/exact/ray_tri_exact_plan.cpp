// tb/exact: the test plan of the unit ray_tri_exact (ru_ray_tri_exact, the exactly-once
// ray-triangle unit of issue 14) on the shared scoreboard. The unit has a handshake (in_ready_o)
// and a variable latency, so the scoreboard checks its results in input order against the golden
// model (units::ray_tri_exact<Soft> with ExactFilter::PermanentFormat: hit, why, t, beta, gamma,
// slow, every bit) and, in every cycle, in_ready_o and out_valid_o against ExactTiming below: a
// replay of the unit's timing rules (rtl/ru_ray_tri_exact.sv's header) that takes each test's
// side-path requests from the model (ExactPathInfo: which edges, the interval) and their
// latencies from rtl/ru_exact_path.sv's formula (exact_requests.hpp, GMP). The variable latency is
// therefore checked exactly, not bounded.
//
// Per configuration (UnitSpec tests / long_tests): the generic plan (tb/src/registry_plan.cpp:
// random vectors of the registry generator -- alternately synthetic-scene tests and
// units::ExactTriGen's grids, vertices and extremes -- with random traffic and resets, and the
// harness's planted errors with the selftest tag) plus stimulus_reaches_both_paths; configurations
// with the RTL's own plants (Plant=1: a shrunk edge bound, wrong results; Plant=2: no early stop,
// other timing) instead run planted_rtl_error_caught, which must report errors of that kind.
#include <gtest/gtest.h>

#include <algorithm>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "exact_requests.hpp"
#include "rayunits/num/fp.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/tb/registry_adapter.hpp"
#include "rayunits/tb/testing.hpp"

namespace ru::tb {
namespace {

using namespace ru::tb_exact;

struct ExactCfg {
  Format f;
  int stages = 0, digit = 16, slack = 1;
};

ExactCfg exact_cfg(const synth::UnitSpec& u, const synth::UnitConfig& uc) {
  ExactCfg c;
  c.f = uc.fmt;
  c.stages = uc.stages;
  c.digit = static_cast<int>(synth::param_value(u, uc, "DigitW"));
  c.slack = static_cast<int>(synth::param_value(u, uc, "Slack"));
  return c;
}

// The side-path requests of one test, in the order the unit issues them: their latencies.
std::vector<int> side_path_plan(const ExactCfg& c, const Req& r) {
  ru::num::SoftScope scope(c.f);
  using ru::num::Soft;
  using ru::units::Vec3;
  auto S = [&](int i) { return Soft::from_bits(r.bits[i]); };
  auto V = [&](int i) { return Vec3<Soft>{S(i), S(i + 1), S(i + 2)}; };
  ru::units::ExactTriOptions o;
  o.filter = ru::units::ExactFilter::PermanentFormat;
  const auto res = ru::units::ray_tri_exact(V(0), V(3), V(6), V(9), V(12), S(15), S(16), o);
  std::vector<int> plan;
  auto add = [&](int op) {
    Req q = r;
    q.op = op;
    plan.push_back(latency(c.f, c.digit, false, q, expect(c.f, q)));
  };
  for (int k = 0; k < 3; ++k)
    if (res.path.edge_mask & (1u << k)) add(k);
  if (res.path.slow_interval) add(3);
  return plan;
}

// The longest side-path time of one test: the longest requests by exact_requests.hpp's latency()
// (three edges with every tie term looked at and all zero, the interval with V != 0), one cycle
// between requests.
int worst_test_cycles(const ExactCfg& c) {
  Req r;
  Expect e{0};
  e.ties = 3;
  e.all_zero = true;
  const int edge = latency(c.f, c.digit, false, r, e);
  r.op = 3;
  const int interval = latency(c.f, c.digit, false, r, Expect{1});
  return 3 * (edge + 1) + interval + 1;
}
// A bound on any test's latency: every test ahead of it in the buffer (Cap) taking the longest.
int max_latency(const ExactCfg& c) { return 2 * c.stages + (c.stages + 2 + c.slack) * (worst_test_cycles(c) + 1); }

// The timing rules of rtl/ru_ray_tri_exact.sv, cycle by cycle (see its header):
//  * a test accepted in cycle c reaches the end of the pipeline in cycle c + Stages;
//  * there, if it is the oldest inside and decided, it leaves in that cycle; else it is stored;
//  * a stored oldest test, in each cycle with no side-path request outstanding: leaves if decided,
//    else issues its next request, whose result comes latency + 1 cycles later and is looked at
//    in the cycle after;
//  * in_ready_o = tests inside < Cap = Stages + 1 + Slack; one test leaves per cycle at most.
class ExactTiming final : public HandshakeTiming {
 public:
  // latency: Stages (a planted error of the reference shifts it)
  ExactTiming(const ExactCfg& c, int latency) : c_(c), latency_(latency), cap_(c.stages + 1 + c.slack) {}
  bool ready() const override { return inside_ < cap_; }
  bool step(uint64_t cycle, const Record* acc) override {
    if (acc) {
      Req r;
      for (int k = 0; k < 17; ++k) r.bits[k] = static_cast<uint32_t>(acc->v[k]);
      items_.push_back({cycle, side_path_plan(c_, r)});
    }
    Item* arriving = nullptr;
    for (Item& it : items_)
      if (!it.arrived && it.accepted + static_cast<uint64_t>(latency_) == cycle) arriving = &it;
    const bool xp_valid = pending_ && cycle == pend_cycle_;
    bool out = false;
    if (!items_.empty()) {
      Item& head = items_.front();
      const bool stored = head.arrived, arr = arriving == &head && !stored;
      const bool done = head.ops_done == head.plan.size();
      if ((stored || arr) && done && !pending_) {
        out = true;
        if (arriving == &head) arriving = nullptr;
      } else if (stored && !done && !pending_) {
        pending_ = true;
        pend_cycle_ = cycle + 1 + static_cast<uint64_t>(head.plan[head.ops_done]);
      }
      if (xp_valid) {
        pending_ = false;
        ++head.ops_done;
      }
    }
    if (arriving) arriving->arrived = true;
    if (out) items_.pop_front();
    inside_ += (acc ? 1 : 0) - (out ? 1 : 0);
    return out;
  }
  void reset() override {
    items_.clear();
    inside_ = 0;
    pending_ = false;
  }

 private:
  struct Item {
    uint64_t accepted;
    std::vector<int> plan;
    bool arrived = false;
    size_t ops_done = 0;
  };
  ExactCfg c_;
  int latency_, cap_;
  std::deque<Item> items_;
  int inside_ = 0;
  bool pending_ = false;
  uint64_t pend_cycle_ = 0;
};

void exact_plan(const ConfigDesc& cfg) {
  const synth::UnitSpec& u = synth::find_unit(cfg.unit);
  const synth::UnitConfig uc = unit_config(cfg);
  const ExactCfg c = exact_cfg(u, uc);
  const long long plant = synth::param_value(u, uc, "Plant");
  RegistryPlanHooks h;
  h.timing = true;
  h.fast_random = 4000;  // a quarter of them reach the side path (hundreds of cycles each)
  h.long_random = 20000;
  // resets about every three longest side-path tests: most results survive to be checked
  h.reset_every = static_cast<uint32_t>(3 * worst_test_cycles(c));
  const int bound = max_latency(c);
  h.options = [c, bound](RunOptions& o) {
    o.max_latency = bound;
    o.timing = [c](const RunOptions& ro) {
      return std::make_unique<ExactTiming>(c, ro.stages + ro.inject.latency_delta);
    };
  };
  const std::string suite = (cfg.has_tag("long") ? "Long_" : "") + cfg.full_name();
  if (plant != 0) {
    // The RTL's planted errors must be reported: wrong results (1) or wrong cycles (2).
    const ConfigDesc* cp = &cfg;
    register_test(suite, "planted_rtl_error_caught", [cp, h, plant] {
      ScoreboardTest t = registry_test(*cp, "planted_rtl_error_caught", 2000, h);
      std::cerr << "(planted RTL error, Plant=" << plant << ": the MISMATCH reports below are expected)\n";
      const RunStats st = run_scoreboard(t);
      ASSERT_FALSE(st.errors.empty()) << "Plant=" << plant << " went unnoticed";
      if (plant == 1)
        EXPECT_TRUE(std::any_of(st.errors.begin(), st.errors.end(), [](const Mismatch& m) { return m.kind == Mismatch::Data; }))
            << "a shrunk edge bound certifies wrong signs: wrong results expected";
      else
        EXPECT_NE(st.errors[0].kind, Mismatch::Data) << "no early stop changes the timing first, not the results";
    });
    return;
  }
  registry_plan(cfg, h);
  // The stimulus exercises both paths: at least 10 % of the tests take the side path, at least
  // 40 % are decided by the fast path (none at M <= 3: there the bound 2^K7 P never lies below
  // |V|), at least 5 % hit (from the model, whose slow bit the RTL's slow_o equals test by test).
  register_test(suite, "stimulus_reaches_both_paths", [&u, uc] {
    const uint64_t n = 4000;
    const auto gen = u.random_inputs(uc, mix_seed(global_options().seed, "paths"));
    const auto model = u.golden(uc);
    uint64_t in[17], out[6];
    uint64_t slow = 0, hits = 0;
    for (uint64_t i = 0; i < n; ++i) {
      gen(in);
      model(in, out);
      hits += out[0];
      slow += out[5];
    }
    std::printf("%s: %llu of %llu tests take the side path, %llu hit\n", u.name.c_str(),
                static_cast<unsigned long long>(slow), static_cast<unsigned long long>(n),
                static_cast<unsigned long long>(hits));
    EXPECT_GE(slow, n / 10);
    if (uc.fmt.frac_bits > 3) {
      EXPECT_GE(n - slow, 4 * n / 10);
    }
    EXPECT_GE(hits, n / 20);
  });
}

PlanRegistrar r_exact("ray_tri_exact", exact_plan);

}  // namespace
}  // namespace ru::tb
