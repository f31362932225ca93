// tb/exact: ru_ray_tri_exact (the exactly-once ray-triangle unit, issue 14) cycle by cycle
// against its golden model, units::ray_tri_exact<Soft> with ExactFilter::PermanentFormat (hit,
// why, t, beta, gamma bit for bit, and which tests took the side path), and against a replay of
// the unit's timing rules (rtl/ru_ray_tri_exact.sv's header) in every cycle: in_ready_o and
// out_valid_o, so every result's cycle. The replay takes the side-path requests of each test from
// the model (ExactPathInfo: which edges, the interval) and their latencies from
// rtl/ru_exact_path.sv's formula (exact_requests.hpp, GMP). The variable latency is therefore
// checked exactly, not bounded.
//
// Stimulus per configuration: render-like tests (a triangle in [-1,1]^3, a ray aimed near it;
// mostly decided on the fast path, back to back) and exact_requests.hpp's adversarial requests
// (random bit patterns, small-integer grids with exact zeros, rays through vertices and along
// edges, extremes, bounds exactly at t, infinite and NaN bounds; many need the side path), with
// random gaps in in_valid_i. All configurations run at once in one Verilated model. Planted
// errors (Plant 1: a shrunk edge bound, wrong results; 2: no early stop, wrong timing) must be
// reported.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <deque>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#ifdef RU_TB_EXACT_LONG
#include "Vtb_ray_tri_exact_long_top.h"
#else
#include "Vtb_ray_tri_exact_top.h"

#endif
#include "exact_requests.hpp"
#include "rayunits/num/fp.hpp"
#include "rayunits/units/ray_tri_exact.hpp"
#include "verilated.h"

namespace {

using namespace ru::tb_exact;
using ru::num::Soft;
using ru::units::Vec3;

struct Config {
  const char* name;
  Format f;
  int stages, digit, slack, plant;
  double min_fast;
};
Format fmt(int e, int m, bool sub, ru::num::Round r = ru::num::Round::RNE) {
  Format f;
  f.exp_bits = e;
  f.frac_bits = m;
  f.subnormals = sub;
  f.round = r;
  return f;
}
// The Verilated top's instances, in order (TbTopListsTheseConfigurations checks it). min_fast:
// the share of tests the fast path must decide in this stimulus (at M <= 3 the bound 2^K7 P is
// never below |V|: every test takes the side path).
#ifdef RU_TB_EXACT_LONG
#define RU_SUITE(name) LongExactTriRtl##name
using Top = Vtb_ray_tri_exact_long_top;
constexpr const char* kTopFile = "tb_ray_tri_exact_long_top.sv";
const Config kConfigs[] = {
    {"e5m10 Stages 0", fmt(5, 10, true), 0, 16, 1, 0, 0.5},
    {"e8m23 Stages 6 Slack 2", fmt(8, 23, true), 6, 32, 2, 0, 0.5},
    {"e4m3-ftz Stages 3 Slack 0", fmt(4, 3, false), 3, 8, 0, 0, 0.0},
    {"e6m12 RTZ Stages 2", fmt(6, 12, true, ru::num::Round::RTZ), 2, 8, 1, 0, 0.5},
    {"e5m10 Stages 2 plant 1", fmt(5, 10, true), 2, 16, 1, 1, 0.0},
    {"e5m10 Stages 2 plant 2", fmt(5, 10, true), 2, 16, 1, 2, 0.0},
};
#define RU_PORT_LIST RU_PORTS(0), RU_PORTS(1), RU_PORTS(2), RU_PORTS(3), RU_PORTS(4), RU_PORTS(5)
#else
#define RU_SUITE(name) ExactTriRtl##name
using Top = Vtb_ray_tri_exact_top;
constexpr const char* kTopFile = "tb_ray_tri_exact_top.sv";
const Config kConfigs[] = {{"e5m10 Stages 2", fmt(5, 10, true), 2, 16, 1, 0, 0.5}};
#define RU_PORT_LIST RU_PORTS(0)
#endif
constexpr int kNumConfigs = sizeof(kConfigs) / sizeof(kConfigs[0]);

// What the unit must output for one test, and the side-path requests (op, latency) it makes.
struct Expected {
  bool hit = false;
  int why = 0;
  uint32_t t = 0, beta = 0, gamma = 0;
  bool slow = false;
  std::vector<std::pair<int, int>> plan;
};

Expected model(const Config& c, const Req& r) {
  ru::num::SoftScope scope(c.f);
  auto S = [&](int i) { return Soft::from_bits(r.bits[i]); };
  auto V = [&](int i) { return Vec3<Soft>{S(i), S(i + 1), S(i + 2)}; };
  ru::units::ExactTriOptions o;
  o.filter = ru::units::ExactFilter::PermanentFormat;
  const auto res = ru::units::ray_tri_exact(V(0), V(3), V(6), V(9), V(12), S(15), S(16), o);
  Expected e;
  e.hit = res.hit;
  e.why = static_cast<int>(res.why);
  e.t = static_cast<uint32_t>(res.t.bits);
  e.beta = static_cast<uint32_t>(res.beta.bits);
  e.gamma = static_cast<uint32_t>(res.gamma.bits);
  e.slow = res.path.slow();
  auto add = [&](int op) {
    Req q = r;
    q.op = op;
    e.plan.emplace_back(op, latency(c.f, c.digit, false, q, expect(c.f, q)));
  };
  for (int k = 0; k < 3; ++k)
    if (res.path.edge_mask & (1u << k)) add(k);
  if (res.path.slow_interval) add(3);
  return e;
}

// A render-like test: triangle in [-1,1]^3, origin in [-4,4]^3, the ray aimed at a point near the
// triangle, t in (0, 8).
Req render_like(const Format& f, std::mt19937_64& g) {
  std::uniform_real_distribution<double> u(-1, 1);
  Req r{};
  double p[9];
  for (double& x : p) x = u(g);
  double a[3], d[3];
  for (int c = 0; c < 3; ++c) {
    a[c] = 4 * u(g);
    const double target = (p[c] + p[3 + c] + p[6 + c]) / 3 + 0.6 * u(g);
    d[c] = target - a[c];
  }
  for (int c = 0; c < 3; ++c) {
    r.bits[c] = enc(f, a[c]);
    r.bits[3 + c] = enc(f, d[c]);
  }
  for (int i = 0; i < 9; ++i) r.bits[6 + i] = enc(f, p[i]);
  r.bits[15] = enc(f, 0.0);
  r.bits[16] = enc(f, 8.0);
  return r;
}

std::vector<Req> stimulus(const Format& f, uint64_t seed, int n) {
  Gen gen(f, seed);
  std::mt19937_64 g(seed + 1);
  std::vector<Req> v;
  for (int i = 0; i < n; ++i) v.push_back(i % 3 == 0 ? gen.next(i / 3) : render_like(f, g));
  return v;
}

// The timing rules of rtl/ru_ray_tri_exact.sv, cycle by cycle.
class Replay {
 public:
  // skew: cycles added to every side-path latency (a planted timing error of the reference)
  Replay(int stages, int slack, int skew = 0) : stages_(stages), cap_(stages + 1 + slack), skew_(skew) {}
  struct Step {
    bool in_ready = false, accepted = false, out = false;
    long out_index = -1;
  };
  // One cycle: drv_valid is in_valid_i; plans[i] is test i's side-path requests, fast[i] whether
  // its fast path decides it.
  Step step(long cycle, bool drv_valid, long next_index, const std::vector<Expected>& exp) {
    Step s;
    s.in_ready = inside_ < cap_;
    s.accepted = drv_valid && s.in_ready;
    if (s.accepted) items_.push_back({next_index, cycle});
    Item* arriving = nullptr;
    for (Item& it : items_)
      if (!it.arrived && it.accepted + stages_ == cycle) arriving = &it;
    const bool xp_valid = pending_ && cycle == pend_cycle_;
    if (!items_.empty()) {
      Item& head = items_.front();
      const Expected& e = exp[static_cast<size_t>(head.index)];
      const bool stored = head.arrived, arr = arriving == &head && !stored;
      const bool done = !e.slow || head.ops_done == e.plan.size();
      if ((stored || arr) && done && !pending_) {
        s.out = true;
        s.out_index = head.index;
        if (arriving == &head) arriving = nullptr;
      } else if (stored && !done && !pending_) {
        pending_ = true;
        pend_cycle_ = cycle + 1 + e.plan[head.ops_done].second + skew_;  // L: latency() (exact_requests.hpp)
      }
      if (xp_valid) {
        pending_ = false;
        ++head.ops_done;
      }
    }
    if (arriving) arriving->arrived = true;
    if (s.out) items_.pop_front();
    inside_ += (s.accepted ? 1 : 0) - (s.out ? 1 : 0);
    return s;
  }
  void reset() {
    items_.clear();
    inside_ = 0;
    pending_ = false;
  }

 private:
  struct Item {
    long index, accepted;
    bool arrived = false;
    size_t ops_done = 0;
  };
  int stages_, cap_, skew_;
  std::deque<Item> items_;
  int inside_ = 0;
  bool pending_ = false;
  long pend_cycle_ = 0;
};

struct Dut {
  std::unique_ptr<VerilatedContext> ctx = std::make_unique<VerilatedContext>();
  std::unique_ptr<Top> top = std::make_unique<Top>(ctx.get());
  struct Ports {
    CData* in_valid;
    CData* in_ready;
    VlWide<17>* ops;
    CData* out_valid;
    CData* hit;
    CData* why;
    VlWide<3>* tbg;
    CData* slow;
  };
  Ports port(int i) {
    Top& t = *top;
#define RU_PORTS(n) \
  {&t.in_valid_##n, &t.in_ready_##n, &t.ops_##n, &t.out_valid_##n, &t.hit_##n, &t.why_##n, &t.tbg_##n, &t.slow_##n}
    const Ports p[kNumConfigs] = {RU_PORT_LIST};
#undef RU_PORTS
    return p[i];
  }
};

struct Tally {
  long tests = 0, outputs = 0, slow = 0, hits = 0, result_errors = 0, timing_errors = 0;
  long max_latency = 0;
  std::string first;
  void fail(const std::string& m) {
    if (first.empty()) first = m;
  }
};

// Runs every configuration on its own stimulus at once; reset_at >= 0: reset every lane in that
// cycle (tests in flight are dropped; the lanes then start again from their next test).
// corrupt / skew: planted errors of the reference (every 7th expected hit bit and every 11th
// expected t's last bit flipped; a latency skew of the replay).
std::vector<Tally> run(int n, long reset_at = -1, bool corrupt = false, int skew = 0) {
  const long max_cycles = std::getenv("RU_TB_MAX_CYCLES") ? std::atol(std::getenv("RU_TB_MAX_CYCLES")) : 20'000'000;
  Dut dut;
  struct Lane {
    std::vector<Req> reqs;
    std::vector<Expected> exp;
    Replay replay{0, 0};
    size_t next = 0;
    std::vector<long> accepted_at;
    std::mt19937_64 g;
    long model_out = 0, rtl_out = 0;
  };
  std::vector<Lane> lanes(kNumConfigs);
  for (int i = 0; i < kNumConfigs; ++i) {
    Lane& l = lanes[static_cast<size_t>(i)];
    const Config& c = kConfigs[i];
    l.reqs = stimulus(c.f, 1000 + static_cast<uint64_t>(i), n);
    for (const Req& r : l.reqs) l.exp.push_back(model(c, r));
    for (size_t k = 0; corrupt && k < l.exp.size(); ++k) {
      if (k % 7 == 3) l.exp[k].hit = !l.exp[k].hit;
      if (k % 11 == 5) l.exp[k].t ^= 1;
    }
    l.replay = Replay(c.stages, c.slack, skew);
    l.accepted_at.assign(l.reqs.size(), -1);
    l.g.seed(static_cast<uint64_t>(i) + 7);
  }
  std::vector<Tally> t(kNumConfigs);
  Top& top = *dut.top;
  top.rst_ni = 0;
  top.clk_i = 0;
  top.eval();
  top.clk_i = 1;
  top.eval();
  top.rst_ni = 1;
  for (long cycle = 0;; ++cycle) {
    bool busy = false;
    const bool reset_now = cycle == reset_at;
    top.clk_i = 0;
    std::vector<bool> drv(kNumConfigs);
    for (int i = 0; i < kNumConfigs; ++i) {
      Lane& l = lanes[static_cast<size_t>(i)];
      Dut::Ports p = dut.port(i);
      drv[static_cast<size_t>(i)] = l.next < l.reqs.size() && l.g() % 8 != 0;
      *p.in_valid = drv[static_cast<size_t>(i)];
      const Req& r = l.reqs[std::min(l.next, l.reqs.size() - 1)];
      for (int k = 0; k < 17; ++k) (*p.ops)[k] = r.bits[k];
    }
    top.rst_ni = reset_now ? 0 : 1;
    top.eval();
    for (int i = 0; i < kNumConfigs && !reset_now; ++i) {
      Lane& l = lanes[static_cast<size_t>(i)];
      Tally& ti = t[static_cast<size_t>(i)];
      Dut::Ports p = dut.port(i);
      const Replay::Step s = l.replay.step(cycle, drv[static_cast<size_t>(i)], static_cast<long>(l.next), l.exp);
      const std::string at = std::string(kConfigs[i].name) + " cycle " + std::to_string(cycle) + ": ";
      if (*p.in_ready != s.in_ready) {
        ++ti.timing_errors;
        ti.fail(at + "in_ready_o " + std::to_string(*p.in_ready) + ", expected " + std::to_string(s.in_ready));
      }
      if (s.accepted) {
        l.accepted_at[l.next] = cycle;
        ++l.next;
        ++ti.tests;
      }
      if (std::getenv("RU_TB_VERBOSE") && (*p.out_valid || s.out || s.accepted))
        std::printf("%s acc %d rtl_out %d model_out %d (test %ld: slow %d plan %zu)\n", at.c_str(), int(s.accepted),
                    int(*p.out_valid), int(s.out), s.out_index, s.out_index >= 0 ? int(l.exp[size_t(s.out_index)].slow) : -1,
                    s.out_index >= 0 ? l.exp[size_t(s.out_index)].plan.size() : 0);
      l.model_out += s.out;
      l.rtl_out += *p.out_valid;
      if (*p.out_valid != s.out) {
        ++ti.timing_errors;
        ti.fail(at + "out_valid_o " + std::to_string(*p.out_valid) + ", expected " + std::to_string(s.out) +
                (s.out ? " (test " + std::to_string(s.out_index) + ")" : ""));
      }
      if (*p.out_valid && s.out) {
        const Expected& e = l.exp[static_cast<size_t>(s.out_index)];
        ++ti.outputs;
        ti.slow += e.slow;
        ti.hits += e.hit;
        ti.max_latency = std::max(ti.max_latency, cycle - l.accepted_at[static_cast<size_t>(s.out_index)]);
        const uint32_t got_t = (*p.tbg)[0], got_b = (*p.tbg)[1], got_g = (*p.tbg)[2];
        if (*p.hit != e.hit || *p.why != e.why || got_t != e.t || got_b != e.beta || got_g != e.gamma ||
            *p.slow != e.slow) {
          ++ti.result_errors;
          std::ostringstream m;
          m << at << "test " << s.out_index << ": hit/why/slow " << int(*p.hit) << "/" << int(*p.why) << "/"
            << int(*p.slow) << " t " << std::hex << got_t << " b " << got_b << " g " << got_g << ", expected "
            << std::dec << e.hit << "/" << e.why << "/" << e.slow << " t " << std::hex << e.t << " b " << e.beta
            << " g " << e.gamma;
          ti.fail(m.str());
        }
      }
    }
    if (reset_now)
      for (Lane& l : lanes) l.replay.reset();
    top.clk_i = 1;
    top.eval();
    for (int i = 0; i < kNumConfigs; ++i) {
      const Lane& l = lanes[static_cast<size_t>(i)];
      const Tally& ti = t[static_cast<size_t>(i)];
      // a lane whose output disagrees this much is done (planted errors): no endless desynchronized run
      busy |= (l.next < l.reqs.size() || l.model_out < ti.tests || l.rtl_out < ti.tests) &&
              ti.result_errors + ti.timing_errors < 200;
    }
    if (!busy || cycle > max_cycles) break;
    if (reset_now)  // tests in flight are dropped: the model forgets them
      for (int i = 0; i < kNumConfigs; ++i) {
        t[static_cast<size_t>(i)].tests = t[static_cast<size_t>(i)].outputs;
        lanes[static_cast<size_t>(i)].model_out = lanes[static_cast<size_t>(i)].rtl_out = t[static_cast<size_t>(i)].outputs;
      }
  }
  return t;
}

TEST(RU_SUITE(Top), ListsTheseConfigurations) {
  std::vector<std::string> want;
  for (int i = 0; i < kNumConfigs; ++i) {
    const Config& c = kConfigs[i];
    std::ostringstream w;
    w << "tb_ray_tri_exact_cfg #(.ExpW(" << c.f.exp_bits << "), .FracW(" << c.f.frac_bits << "), .Subnormals("
      << (c.f.subnormals ? 1 : 0) << "), .Round(" << static_cast<int>(c.f.round) << "), .Stages(" << c.stages
      << "), .DigitW(" << c.digit << "), .Slack(" << c.slack << "), .Plant(" << c.plant << ")) u" << i << " (";
    want.push_back(w.str());
  }
  EXPECT_EQ(missing_instances(std::string(RU_TB_EXACT_DIR) + "/" + kTopFile, want), "");
}

TEST(RU_SUITE(), EveryResultAndCycleEqualsTheModel) {
#ifdef RU_TB_EXACT_LONG
  const int def = 5000;
#else
  const int def = 4000;
#endif
  const int n = std::getenv("RU_TB_TESTS") ? std::atoi(std::getenv("RU_TB_TESTS")) : def;
  const std::vector<Tally> t = run(n);
  for (int i = 0; i < kNumConfigs; ++i) {
    const Tally& ti = t[static_cast<size_t>(i)];
    std::printf("%-28s %5ld tests, %4ld took the side path, %4ld hits, max latency %ld cycles: %ld wrong results, %ld "
                "timing errors\n",
                kConfigs[i].name, ti.outputs, ti.slow, ti.hits, ti.max_latency, ti.result_errors, ti.timing_errors);
    if (kConfigs[i].plant == 0) {
      EXPECT_EQ(ti.outputs, n) << kConfigs[i].name;
      EXPECT_EQ(ti.result_errors + ti.timing_errors, 0) << ti.first;
      EXPECT_GE(ti.slow, n / 10) << kConfigs[i].name << ": too few tests reach the side path";
      EXPECT_GE(static_cast<double>(ti.outputs - ti.slow), kConfigs[i].min_fast * n)
          << kConfigs[i].name << ": too few tests decided on the fast path";
      EXPECT_GE(ti.hits, n / 20) << kConfigs[i].name;
    } else {
      std::printf("  planted: %s\n", ti.first.c_str());
      if (kConfigs[i].plant == 1) {
        EXPECT_GT(ti.result_errors, 0) << kConfigs[i].name << ": planted error not caught";
      } else {
        EXPECT_GT(ti.timing_errors, 0) << kConfigs[i].name << ": planted error not caught";
      }
    }
  }
}

// The checkers against planted errors of the reference (the RTL's own plants are in the long
// suite's model): wrong expected results (hit, t) and one cycle more per side-path request.
TEST(RU_SUITE(), PlantedReferenceErrorsAreCaught) {
  const std::vector<Tally> a = run(150, -1, true);
  const std::vector<Tally> b = run(150, -1, false, 1);
  for (int i = 0; i < kNumConfigs; ++i) {
    if (kConfigs[i].plant != 0 || kConfigs[i].min_fast == 0) continue;
    std::printf("%s: corrupted results: %ld wrong results (%s); skew: %ld timing errors\n", kConfigs[i].name,
                a[static_cast<size_t>(i)].result_errors, a[static_cast<size_t>(i)].first.c_str(),
                b[static_cast<size_t>(i)].timing_errors);
    EXPECT_GT(a[static_cast<size_t>(i)].result_errors, 0) << kConfigs[i].name;
    EXPECT_GT(b[static_cast<size_t>(i)].timing_errors, 0) << kConfigs[i].name;
  }
}

// A reset drops every test inside (fast pipeline, buffer, side path) and the unit starts clean.
TEST(RU_SUITE(), ResetDropsTestsInFlight) {
  const std::vector<Tally> t = run(300, 2000);
  for (int i = 0; i < kNumConfigs; ++i) {
    if (kConfigs[i].plant != 0) continue;
    const Tally& ti = t[static_cast<size_t>(i)];
    EXPECT_EQ(ti.result_errors + ti.timing_errors, 0) << ti.first;
    EXPECT_GT(ti.outputs, 0);
  }
}

}  // namespace
