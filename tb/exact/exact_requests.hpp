// tb/exact: the request generator and the exact side path's reference (results with GMP via the
// golden model, latencies by the formula of rtl/ru_exact_path.sv's header), shared by the tests of
// ru_exact_path (exact_path_test.cpp) and of ru_ray_tri_exact (ray_tri_exact_plan.cpp).
#pragma once

#include <gmpxx.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <limits>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/units/ray_tri_exact.hpp"
#include "rayunits/units/ray_tri_exact_gen.hpp"
#include "rayunits/units/vec.hpp"

namespace ru::tb_exact {

using ru::num::Format;
using ru::units::Vec3d;

// One request: op (0..2 edge k, 3 interval) and 17 operand bit patterns; the generator is the
// unit registry's (units::ExactTriGen).
using Req = ru::units::ExactTriRecord;
using Gen = ru::units::ExactTriGen;

inline double value(const Format& f, uint32_t b) { return ru::units::exact_gen_value(f, b); }
inline Vec3d vec3(const Format& f, const uint32_t* b) { return ru::units::exact_gen_vec3(f, b); }
inline uint32_t enc(const Format& f, double x) { return static_cast<uint32_t>(ru::num::from_double(f, x).bits); }

struct Expect {
  int res;        // edge: -1, 0, +1; interval: 1 inside, 0 not
  int ties = 0;   // edge: tie terms looked at (0: S != 0)
  bool all_zero = false;
  bool v_zero = false;  // interval: V = 0
};

inline mpq_class q(double x) { return mpq_class(x); }

inline Expect expect(const Format& f, const Req& r) {
  const Vec3d a = vec3(f, r.bits), d = vec3(f, r.bits + 3);
  const Vec3d p[3] = {vec3(f, r.bits + 6), vec3(f, r.bits + 9), vec3(f, r.bits + 12)};
  Expect e;
  if (r.op == 3) {
    const double tmin = value(f, r.bits[15]), tmax = value(f, r.bits[16]);
    e.res = ru::units::exact_detail::exact_interval(a, d, p[0], p[1], p[2], tmin, tmax) ? 1 : 0;
    // V = ((p2 - p0) x (p1 - p2)) . d (tb-side GMP, for the latency)
    const mpq_class e1[3] = {q(p[2].x) - q(p[0].x), q(p[2].y) - q(p[0].y), q(p[2].z) - q(p[0].z)};
    const mpq_class e0[3] = {q(p[1].x) - q(p[2].x), q(p[1].y) - q(p[2].y), q(p[1].z) - q(p[2].z)};
    const mpq_class V = (e1[1] * e0[2] - e1[2] * e0[1]) * q(d.x) + (e1[2] * e0[0] - e1[0] * e0[2]) * q(d.y) +
                        (e1[0] * e0[1] - e1[1] * e0[0]) * q(d.z);
    e.v_zero = sgn(V) == 0;
    return e;
  }
  const Vec3d& q1 = p[(r.op + 1) % 3];
  const Vec3d& q2 = p[(r.op + 2) % 3];
  const Vec3d& m = ru::units::lex_first_is_min(q1, q2) ? q1 : q2;
  e.res = ru::units::exact_detail::exact_edge_sign(a, d, m, q1, q2, false);
  const mpq_class sx = q(a.x) - q(m.x), sy = q(a.y) - q(m.y), sz = q(a.z) - q(m.z);
  const mpq_class ex = q(q1.x) - q(q2.x), ey = q(q1.y) - q(q2.y), ez = q(q1.z) - q(q2.z);
  const mpq_class S =
      (sy * q(d.z) - sz * q(d.y)) * ex + (sz * q(d.x) - sx * q(d.z)) * ey + (sx * q(d.y) - sy * q(d.x)) * ez;
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
// (rtl/ru_exact_path.sv's header).
// no_ties: ru_exact_path's Plant 1 (no tie terms: straight to the end).
inline int latency(const Format& f, int digit, bool no_ties, const Req& r, const Expect& e) {
  const int L = (1 << f.exp_bits) + f.frac_bits - 2, nd = (L + 3 + digit - 1) / digit;
  if (r.op == 3) return e.v_zero ? 18 * nd + 69 : 20 * nd + 77;
  const int n = 9 * nd + 41;
  if (no_ties) return n + (e.ties ? 1 : 0);
  return n + e.ties * (2 * nd + 6) + (e.all_zero ? 1 : 0);
}

inline std::vector<Req> requests(const Format& f, uint64_t seed, int n) {
  Gen g(f, seed);
  std::vector<Req> v;
  for (int i = 0; i < n; ++i) v.push_back(g.next(i));
  return v;
}

// The instances of a Verilated top, in order: "" when every expected instance line is in the
// file (dir/file) after the one before, else what is missing. The tests' configuration lists
// restate the tops' parameters; this keeps the two in step.
inline std::string missing_instances(const std::string& path, const std::vector<std::string>& lines) {
  std::ifstream in(path);
  if (!in) return path + " not found";
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string s = ss.str();
  size_t pos = 0;
  for (const std::string& l : lines) {
    const size_t at = s.find(l, pos);
    if (at == std::string::npos) return "not found in order: " + l;
    pos = at;
  }
  return "";
}

}  // namespace ru::tb_exact
