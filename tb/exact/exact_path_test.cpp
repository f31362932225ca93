// tb/exact: ru_exact_path (the exact side path of the exactly-once ray-triangle unit, issue 14)
// cycle by cycle against the golden model's exact path (GMP rationals):
//   op 0..2  the perturbed sign of edge k      units::exact_detail::exact_edge_sign
//   op 3     the exact interval test           units::exact_detail::exact_interval
// Every result bit, and every latency against the formula of rtl/ru_exact_path.sv's header (the
// number of tie terms it needs and whether V = 0, counted here with GMP independently of the
// model). The configurations are tb_exact_path_top.sv's instances.
//
// Requests per configuration: random finite bit patterns (every exponent), small-integer grids
// (exact zero volumes, zero tie terms, V = 0), rays through a vertex with d along, against or
// across an edge, extremes (largest finite, smallest subnormal mixed), and intervals whose bound
// is exactly the hit's t (strictness), infinite and NaN bounds. Planted errors in the RTL
// (Plant 1: no tie terms, 2: one product's sign, 3: an inclusive lower bound) must be reported.
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "Vtb_exact_path_top.h"
#include "rayunits/num/format.hpp"
#include "rayunits/units/ray_tri_exact.hpp"
#include "rayunits/units/vec.hpp"
#include "verilated.h"

#include "exact_requests.hpp"

namespace {

using namespace ru::tb_exact;

struct Config {
  const char* name;
  Format f;
  int digit;
  int plant;
};
Format fmt(int e, int m, bool sub = true) {
  Format f;
  f.exp_bits = e;
  f.frac_bits = m;
  f.subnormals = sub;
  return f;
}
// tb_exact_path_top.sv's instances, in order
const Config kConfigs[] = {{"e5m10", fmt(5, 10), 16, 0},         {"e8m23", fmt(8, 23), 32, 0},
                           {"e3m2", fmt(3, 2), 4, 0},            {"e6m12", fmt(6, 12), 8, 0},
                           {"e4m3-ftz", fmt(4, 3, false), 8, 0}, {"e5m10 plant 1", fmt(5, 10), 16, 1},
                           {"e5m10 plant 2", fmt(5, 10), 16, 2}, {"e5m10 plant 3", fmt(5, 10), 16, 3}};
constexpr int kNumConfigs = sizeof(kConfigs) / sizeof(kConfigs[0]);

// The Verilated top and one instance's ports.
struct Dut {
  std::unique_ptr<VerilatedContext> ctx = std::make_unique<VerilatedContext>();
  std::unique_ptr<Vtb_exact_path_top> top = std::make_unique<Vtb_exact_path_top>(ctx.get());
  struct Ports {
    CData* in_valid;
    CData* in_ready;
    CData* op;
    VlWide<17>* ops;
    CData* out_valid;
    CData* res;
  };
  Ports port(int i) {
    Vtb_exact_path_top& t = *top;
    const Ports p[kNumConfigs] = {{&t.in_valid_0, &t.in_ready_0, &t.op_0, &t.ops_0, &t.out_valid_0, &t.res_0},
                                  {&t.in_valid_1, &t.in_ready_1, &t.op_1, &t.ops_1, &t.out_valid_1, &t.res_1},
                                  {&t.in_valid_2, &t.in_ready_2, &t.op_2, &t.ops_2, &t.out_valid_2, &t.res_2},
                                  {&t.in_valid_3, &t.in_ready_3, &t.op_3, &t.ops_3, &t.out_valid_3, &t.res_3},
                                  {&t.in_valid_4, &t.in_ready_4, &t.op_4, &t.ops_4, &t.out_valid_4, &t.res_4},
                                  {&t.in_valid_5, &t.in_ready_5, &t.op_5, &t.ops_5, &t.out_valid_5, &t.res_5},
                                  {&t.in_valid_6, &t.in_ready_6, &t.op_6, &t.ops_6, &t.out_valid_6, &t.res_6},
                                  {&t.in_valid_7, &t.in_ready_7, &t.op_7, &t.ops_7, &t.out_valid_7, &t.res_7}};
    return p[i];
  }
  void tick() {
    top->clk_i = 0;
    top->eval();
    top->clk_i = 1;
    top->eval();
  }
  void reset() {
    top->rst_ni = 0;
    tick();
    top->rst_ni = 1;
    tick();
  }
};

int decode(int op, CData s) {
  if (op == 3) return s == 1 ? 1 : s == 0 ? 0 : 99;
  return s == 1 ? 1 : s == 3 ? -1 : s == 0 ? 0 : 99;
}

struct Tally {
  long results = 0, errors = 0, latency_errors = 0;
  long edge_ties = 0, edge_zero = 0, inside = 0, v_zero = 0;
  std::string first;
};

// Drives the requests through instance i back to back: the next one is offered while the unit is
// busy (in_valid_i stays high) and must be taken exactly when in_ready_o is.
Tally run(Dut& dut, int i, const std::vector<Req>& reqs) {
  const Config& c = kConfigs[i];
  Dut::Ports p = dut.port(i);
  Tally t;
  size_t next = 0;
  int busy_for = -1, want = 0;
  Expect cur{};
  const Req* cur_req = nullptr;
  auto fail = [&](const std::string& what) {
    if (!t.first.empty()) return;
    t.first = std::string(c.name) + ": " + what;
    if (cur_req) {
      t.first += "; op " + std::to_string(cur_req->op) + ", operands";
      for (uint32_t b : cur_req->bits) t.first += " " + std::to_string(b);
    }
  };
  while (next < reqs.size() || busy_for >= 0) {
    const bool offer = next < reqs.size();
    if (offer) {
      for (int k = 0; k < 17; ++k) (*p.ops)[k] = reqs[next].bits[k];
      *p.op = static_cast<CData>(reqs[next].op);
    }
    *p.in_valid = offer;
    dut.top->clk_i = 0;
    dut.top->eval();
    const bool taken = offer && *p.in_ready;
    dut.top->clk_i = 1;
    dut.top->eval();
    if (busy_for >= 0) ++busy_for;
    if (*p.out_valid) {
      if (!cur_req) {
        ++t.errors;
        fail("out_valid_o without a request in flight");
      } else {
        ++t.results;
        const int got = decode(cur_req->op, *p.res);
        if (cur_req->op == 3) {
          t.inside += cur.res;
          t.v_zero += cur.v_zero;
        } else {
          t.edge_ties += cur.ties > 0;
          t.edge_zero += cur.res == 0;
        }
        if (got != cur.res) {
          ++t.errors;
          fail("result " + std::to_string(got) + ", model " + std::to_string(cur.res));
        }
        if (busy_for != want) {
          ++t.latency_errors;
          fail("latency " + std::to_string(busy_for) + ", expected " + std::to_string(want));
        }
      }
      cur_req = nullptr;
      busy_for = -1;
    } else if (busy_for > want + 10) {
      ++t.latency_errors;
      fail("no result after " + std::to_string(busy_for) + " cycles");
      cur_req = nullptr;
      busy_for = -1;
    }
    if (taken) {
      if (cur_req) {
        ++t.errors;
        fail("in_ready_o high while a request is in flight");
      }
      cur_req = &reqs[next];
      cur = expect(c.f, reqs[next]);
      want = latency(c.f, c.digit, c.plant == 1, reqs[next], cur);
      busy_for = 0;
      ++next;
    }
  }
  *p.in_valid = 0;
  return t;
}

// kConfigs restates tb_exact_path_top.sv's instances: kept in step by this test.
TEST(ExactPathRtlTop, ListsTheseConfigurations) {
  std::vector<std::string> want;
  for (int i = 0; i < kNumConfigs; ++i) {
    const Config& c = kConfigs[i];
    want.push_back("tb_exact_path_cfg #(.ExpW(" + std::to_string(c.f.exp_bits) + "), .FracW(" +
                   std::to_string(c.f.frac_bits) + "), .Subnormals(" + (c.f.subnormals ? "1" : "0") +
                   "), .DigitW(" + std::to_string(c.digit) + "), .Plant(" + std::to_string(c.plant) + ")) u" +
                   std::to_string(i) + " (");
  }
  EXPECT_EQ(missing_instances(std::string(RU_TB_EXACT_DIR) + "/tb_exact_path_top.sv", want), "");
}

class ExactPathRtl : public ::testing::TestWithParam<int> {};

TEST_P(ExactPathRtl, ResultsAndLatenciesEqualTheModel) {
  const Config& c = kConfigs[GetParam()];
  Dut dut;
  dut.reset();
  const int n = 12000;
  const Tally t = run(dut, GetParam(), requests(c.f, 1234 + GetParam(), n));
  std::printf("%s: %ld requests; edges: %ld with S = 0, %ld sign 0; intervals: %ld inside, %ld with V = 0\n", c.name,
              t.results, t.edge_ties, t.edge_zero, t.inside, t.v_zero);
  EXPECT_EQ(t.results, n);
  EXPECT_GT(t.edge_ties, n / 20);  // the generator reaches the tie terms,
  EXPECT_GT(t.edge_zero, n / 50);  // the all-zero case,
  EXPECT_GT(t.inside, n / 50);     // intervals that hold
  EXPECT_GT(t.v_zero, n / 50);     // and V = 0
  EXPECT_EQ(t.errors, 0) << t.first;
  EXPECT_EQ(t.latency_errors, 0) << t.first;
}
INSTANTIATE_TEST_SUITE_P(Configs, ExactPathRtl, ::testing::Values(0, 1, 2, 3, 4), [](const auto& info) {
  std::string n = kConfigs[info.param].name;
  for (char& ch : n) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return n;
});

// The checker reports planted RTL errors: no tie terms (zeros of S not broken by the ray), one
// product of the cross product with the wrong sign, an inclusive lower bound of the interval.
TEST(ExactPathRtlPlanted, PlantedErrorsAreReported) {
  for (int i : {5, 6, 7}) {
    Dut dut;
    dut.reset();
    const Tally t = run(dut, i, requests(kConfigs[i].f, 99, 2000));
    std::printf("%s: %ld wrong results, %ld wrong latencies of %ld\n", kConfigs[i].name, t.errors, t.latency_errors,
                t.results);
    EXPECT_GT(t.errors, 5) << kConfigs[i].name;
  }
}

// A reset while a request is in flight drops it: no result comes out, and the unit takes the next.
TEST(ExactPathRtl, ResetDropsTheRequestInFlight) {
  Dut dut;
  dut.reset();
  Dut::Ports p = dut.port(0);
  const std::vector<Req> v = requests(kConfigs[0].f, 7, 2);
  for (int k = 0; k < 17; ++k) (*p.ops)[k] = v[0].bits[k];
  *p.op = static_cast<CData>(v[0].op);
  *p.in_valid = 1;
  dut.tick();
  *p.in_valid = 0;
  for (int k = 0; k < 5; ++k) dut.tick();
  EXPECT_FALSE(*p.in_ready);
  dut.reset();
  EXPECT_TRUE(*p.in_ready);
  for (int k = 0; k < 300; ++k) {
    dut.tick();
    EXPECT_FALSE(*p.out_valid);
  }
  const Tally t = run(dut, 0, {v[1]});
  EXPECT_EQ(t.results, 1);
  EXPECT_EQ(t.errors + t.latency_errors, 0) << t.first;
}

}  // namespace
