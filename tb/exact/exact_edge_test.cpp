// tb/exact: ru_exact_edge (the exact side path of the exactly-once ray-triangle unit, issue 14)
// against the golden model's exact edge sign, units::exact_detail::exact_edge_sign (GMP
// rationals), cycle by cycle: the sign of every result, and its latency against the formula of
// rtl/ru_exact_edge.sv's header (with the number of tie terms needed, counted here with GMP
// independently of the model). The configurations are tb_exact_edge_top.sv's instances.
//
// Vectors per configuration: random bit patterns (finite, every exponent), small-integer grids
// (exact zero volumes and zero tie terms), rays through the edge's end points with d along,
// against or across the edge (sign 0 and each tie term deciding), and extremes (largest finite,
// smallest subnormal mixed). Planted errors in the RTL (Plant 1: no tie terms, Plant 2: one
// product's sign) must be reported by the same checker.
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "Vtb_exact_edge_top.h"
#include "rayunits/num/format.hpp"
#include "rayunits/units/ray_tri_exact.hpp"
#include "rayunits/units/vec.hpp"
#include "verilated.h"

namespace {

using ru::num::Format;
using ru::units::Vec3d;

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
// tb_exact_edge_top.sv's instances, in order
const Config kConfigs[] = {{"e5m10", fmt(5, 10), 16, 0}, {"e8m23", fmt(8, 23), 32, 0}, {"e3m2", fmt(3, 2), 4, 0},
                           {"e6m12", fmt(6, 12), 8, 0},  {"e4m3-ftz", fmt(4, 3, false), 8, 0},
                           {"e5m10 plant 1", fmt(5, 10), 16, 1}, {"e5m10 plant 2", fmt(5, 10), 16, 2}};
constexpr int kNumConfigs = sizeof(kConfigs) / sizeof(kConfigs[0]);

// One edge test: 15 operand bit patterns (a, d, m, q1, q2; x, y, z each).
struct Vec {
  uint32_t bits[15];
};

// The value of a bit pattern as the unit reads it (flush-to-zero: a subnormal reads as zero).
double value(const Format& f, uint32_t b) {
  if (!f.subnormals && ((b >> f.frac_bits) & f.exp_field_max()) == 0) return 0.0;
  return ru::num::to_double(f, b);
}
Vec3d vec3(const Format& f, const uint32_t* b) { return {value(f, b[0]), value(f, b[1]), value(f, b[2])}; }

struct Expect {
  int sign;
  int ties;  // tie terms evaluated (0: S != 0)
  bool all_zero;
};
Expect expect(const Format& f, const Vec& v) {
  const Vec3d a = vec3(f, v.bits), d = vec3(f, v.bits + 3), m = vec3(f, v.bits + 6), q1 = vec3(f, v.bits + 9),
              q2 = vec3(f, v.bits + 12);
  Expect e{ru::units::exact_detail::exact_edge_sign(a, d, m, q1, q2, false), 0, false};
  // how many terms the unit must look at (tb-side GMP, for the latency)
  auto q = [](double x) { return mpq_class(x); };
  const mpq_class sx = q(a.x) - q(m.x), sy = q(a.y) - q(m.y), sz = q(a.z) - q(m.z);
  const mpq_class ex = q(q1.x) - q(q2.x), ey = q(q1.y) - q(q2.y), ez = q(q1.z) - q(q2.z);
  const mpq_class S = (sy * q(d.z) - sz * q(d.y)) * ex + (sz * q(d.x) - sx * q(d.z)) * ey +
                      (sx * q(d.y) - sy * q(d.x)) * ez;
  if (sgn(S) != 0) return e;
  const mpq_class g[3] = {q(d.y) * ez - q(d.z) * ey, q(d.z) * ex - q(d.x) * ez, q(d.x) * ey - q(d.y) * ex};
  for (int i = 0; i < 3; ++i) {
    e.ties = i + 1;
    if (sgn(g[i]) != 0) return e;
  }
  e.all_zero = true;
  return e;
}

// Latency from the accepting clock edge to the edge after which out_valid_o is high
// (rtl/ru_exact_edge.sv: 9 conversion cycles, per multiplication ND + 2, ...).
int latency(const Config& c, const Expect& e) {
  const int L = (1 << c.f.exp_bits) + c.f.frac_bits - 2, nd = (L + 3 + c.digit - 1) / c.digit;
  int n = 9 + 3 * (1 + 3 * (nd + 2)) + 1;
  if (c.plant == 1) return n + (e.ties ? 1 : 0);  // no tie terms: straight to the end
  n += e.ties * (1 + 2 * (nd + 2) + 1);
  return n + (e.all_zero ? 1 : 0);
}

uint32_t enc(const Format& f, double x) {
  const auto r = ru::num::from_double(f, x);
  return static_cast<uint32_t>(r.bits);
}

class Gen {
 public:
  Gen(const Format& f, uint64_t seed) : f_(f), rng_(seed) {}
  uint32_t random_finite() {
    const uint64_t e = rng_() % f_.exp_field_max();  // 0 .. max-1: finite
    const uint64_t m = rng_() & f_.frac_mask();
    return static_cast<uint32_t>(((rng_() & 1) ? f_.sign_bit() : 0) | (e << f_.frac_bits) | m);
  }
  uint32_t extreme() {
    switch (rng_() % 4) {
      case 0: return static_cast<uint32_t>(f_.max_finite(rng_() & 1));
      case 1: return static_cast<uint32_t>((rng_() & 1 ? f_.sign_bit() : 0) | 1);  // smallest subnormal
      case 2: return static_cast<uint32_t>(f_.min_normal(rng_() & 1));
      default: return random_finite();
    }
  }
  // small integers times a power of two that the format represents exactly
  uint32_t grid(int scale) {
    const int k = static_cast<int>(rng_() % 7) - 3;
    return enc(f_, std::ldexp(k, scale));
  }
  Vec random() {
    Vec v;
    for (auto& b : v.bits) b = random_finite();
    lexmin_m(v);
    return v;
  }
  Vec extremes() {
    Vec v;
    for (auto& b : v.bits) b = extreme();
    lexmin_m(v);
    return v;
  }
  Vec grids() {
    Vec v;
    const int scale = static_cast<int>(rng_() % 3) - 1;
    for (auto& b : v.bits) b = grid(scale);
    lexmin_m(v);
    return v;
  }
  // a at an end point of the edge, d along / against / across the edge (S = 0 exactly)
  Vec through_vertex() {
    Vec v = grids();
    const bool at_q1 = rng_() & 1;
    for (int c = 0; c < 3; ++c) v.bits[c] = v.bits[(at_q1 ? 9 : 12) + c];
    const int kind = static_cast<int>(rng_() % 3);
    for (int c = 0; c < 3 && kind < 2; ++c) {  // d = +-e (every tie term zero)
      const double e = value(f_, v.bits[9 + c]) - value(f_, v.bits[12 + c]);
      v.bits[3 + c] = enc(f_, kind == 0 ? e : -e);
    }
    return v;
  }

 private:
  void lexmin_m(Vec& v) {  // m = the lexicographically smaller end point (as the unit chooses), mostly
    const Vec3d q1 = vec3(f_, v.bits + 9), q2 = vec3(f_, v.bits + 12);
    const bool first = rng_() % 8 == 0 ? (rng_() & 1) : ru::units::lex_first_is_min(q1, q2);
    for (int c = 0; c < 3; ++c) v.bits[6 + c] = v.bits[(first ? 9 : 12) + c];
  }
  Format f_;
  std::mt19937_64 rng_;
};

// The Verilated top and one instance's ports.
struct Dut {
  std::unique_ptr<VerilatedContext> ctx = std::make_unique<VerilatedContext>();
  std::unique_ptr<Vtb_exact_edge_top> top = std::make_unique<Vtb_exact_edge_top>(ctx.get());
  struct Ports {
    CData* in_valid;
    CData* in_ready;
    VlWide<15>* ops;
    CData* out_valid;
    CData* sign;
  };
  Ports port(int i) {
    Vtb_exact_edge_top& t = *top;
    const Ports p[kNumConfigs] = {
        {&t.in_valid_0, &t.in_ready_0, &t.ops_0, &t.out_valid_0, &t.sign_0},
        {&t.in_valid_1, &t.in_ready_1, &t.ops_1, &t.out_valid_1, &t.sign_1},
        {&t.in_valid_2, &t.in_ready_2, &t.ops_2, &t.out_valid_2, &t.sign_2},
        {&t.in_valid_3, &t.in_ready_3, &t.ops_3, &t.out_valid_3, &t.sign_3},
        {&t.in_valid_4, &t.in_ready_4, &t.ops_4, &t.out_valid_4, &t.sign_4},
        {&t.in_valid_5, &t.in_ready_5, &t.ops_5, &t.out_valid_5, &t.sign_5},
        {&t.in_valid_6, &t.in_ready_6, &t.ops_6, &t.out_valid_6, &t.sign_6}};
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

int decode_sign(CData s) { return s == 1 ? 1 : s == 3 ? -1 : s == 0 ? 0 : 99; }

struct Tally {
  long vectors = 0, sign_errors = 0, latency_errors = 0, zeros = 0, ties = 0;
  std::string first;
};

// Drives vectors through instance i, back to back (the next one offered while the unit is busy:
// in_valid_i stays high and must be taken exactly when in_ready_o is).
Tally run(Dut& dut, int i, const std::vector<Vec>& vecs) {
  const Config& c = kConfigs[i];
  Dut::Ports p = dut.port(i);
  Tally t;
  size_t next = 0;
  int busy_for = -1, want = 0;
  Expect cur{};
  const Vec* cur_vec = nullptr;
  for (long cycle = 0; next < vecs.size() || busy_for >= 0; ++cycle) {
    if (cycle > 1000000000) break;
    const bool offer = next < vecs.size();
    if (offer)
      for (int k = 0; k < 15; ++k) (*p.ops)[k] = vecs[next].bits[k];
    *p.in_valid = offer;
    dut.top->clk_i = 0;
    dut.top->eval();
    const bool taken = offer && *p.in_ready;
    dut.top->clk_i = 1;
    dut.top->eval();
    if (busy_for >= 0) ++busy_for;
    if (*p.out_valid) {
      const int got = decode_sign(*p.sign);
      if (!cur_vec) {
        ++t.sign_errors;
        if (t.first.empty()) t.first = "out_valid_o without a test in flight";
      } else {
        ++t.vectors;
        t.zeros += cur.sign == 0;
        t.ties += cur.ties > 0;
        const bool bad_sign = got != cur.sign, bad_lat = busy_for != want;
        t.sign_errors += bad_sign;
        t.latency_errors += bad_lat;
        if ((bad_sign || bad_lat) && t.first.empty()) {
          t.first = std::string(c.name) + ": sign " + std::to_string(got) + " (model " + std::to_string(cur.sign) +
                    "), latency " + std::to_string(busy_for) + " (expected " + std::to_string(want) + "), operands";
          for (uint32_t b : cur_vec->bits) t.first += " " + std::to_string(b);
        }
      }
      cur_vec = nullptr;
      busy_for = -1;
    } else if (busy_for > want + 10) {
      ++t.latency_errors;
      if (t.first.empty()) t.first = std::string(c.name) + ": no result after " + std::to_string(busy_for) + " cycles";
      cur_vec = nullptr;
      busy_for = -1;
    }
    if (taken) {
      if (cur_vec) {
        ++t.sign_errors;
        if (t.first.empty()) t.first = "in_ready_o high while a test is in flight";
      }
      cur_vec = &vecs[next];
      cur = expect(c.f, vecs[next]);
      want = latency(c, cur);
      busy_for = 0;
      ++next;
    }
  }
  *p.in_valid = 0;
  return t;
}

std::vector<Vec> vectors(const Format& f, uint64_t seed, int n) {
  Gen g(f, seed);
  std::vector<Vec> v;
  for (int i = 0; i < n; ++i) {
    switch (i % 4) {
      case 0: v.push_back(g.random()); break;
      case 1: v.push_back(g.grids()); break;
      case 2: v.push_back(g.through_vertex()); break;
      default: v.push_back(g.extremes()); break;
    }
  }
  return v;
}

class ExactEdgeRtl : public ::testing::TestWithParam<int> {};

TEST_P(ExactEdgeRtl, SignAndLatencyEqualTheModel) {
  const Config& c = kConfigs[GetParam()];
  Dut dut;
  dut.reset();
  const Tally t = run(dut, GetParam(), vectors(c.f, 1234 + GetParam(), 10000));
  std::printf("%s: %ld tests, %ld with S = 0 (tie terms used), %ld sign 0\n", c.name, t.vectors, t.ties, t.zeros);
  EXPECT_EQ(t.vectors, 10000);
  EXPECT_GT(t.ties, 1000);  // the generator reaches the tie terms
  EXPECT_GT(t.zeros, 250);  // and the all-zero case
  EXPECT_EQ(t.sign_errors, 0) << t.first;
  EXPECT_EQ(t.latency_errors, 0) << t.first;
}
INSTANTIATE_TEST_SUITE_P(Configs, ExactEdgeRtl, ::testing::Values(0, 1, 2, 3, 4),
                         [](const auto& info) {
                           std::string n = kConfigs[info.param].name;
                           for (char& ch : n) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                           return n;
                         });

// The checker reports planted RTL errors: no tie terms (zeros of S not broken by the ray), and
// one product of the cross product with the wrong sign.
TEST(ExactEdgeRtlPlanted, PlantedErrorsAreReported) {
  for (int i : {5, 6}) {
    Dut dut;
    dut.reset();
    const Tally t = run(dut, i, vectors(kConfigs[i].f, 99, 400));
    std::printf("%s: %ld sign errors, %ld latency errors of %ld\n", kConfigs[i].name, t.sign_errors,
                t.latency_errors, t.vectors);
    EXPECT_GT(t.sign_errors, 20) << kConfigs[i].name;
  }
}

// A reset while a test is in flight drops it: no result comes out, and the unit takes the next.
TEST(ExactEdgeRtl, ResetDropsTheTestInFlight) {
  Dut dut;
  dut.reset();
  Dut::Ports p = dut.port(0);
  const std::vector<Vec> v = vectors(kConfigs[0].f, 7, 2);
  for (int k = 0; k < 15; ++k) (*p.ops)[k] = v[0].bits[k];
  *p.in_valid = 1;
  dut.tick();
  *p.in_valid = 0;
  for (int k = 0; k < 5; ++k) dut.tick();
  EXPECT_FALSE(*p.in_ready);
  dut.reset();
  EXPECT_TRUE(*p.in_ready);
  for (int k = 0; k < 200; ++k) {
    dut.tick();
    EXPECT_FALSE(*p.out_valid);
  }
  const Tally t = run(dut, 0, {v[1]});
  EXPECT_EQ(t.vectors, 1);
  EXPECT_EQ(t.sign_errors + t.latency_errors, 0) << t.first;
}

}  // namespace
