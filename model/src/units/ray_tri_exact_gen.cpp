// rayunits units: the exactly-once unit's operand generator (ray_tri_exact_gen.hpp).
#include "rayunits/units/ray_tri_exact_gen.hpp"

#include <gmpxx.h>

#include <cmath>
#include <limits>

namespace ru::units {

using num::Format;

double exact_gen_value(const Format& f, uint32_t b) {
  if (!f.subnormals && ((b >> f.frac_bits) & f.exp_field_max()) == 0) return 0.0;
  return num::to_double(f, b);
}
Vec3d exact_gen_vec3(const Format& f, const uint32_t* b) {
  return {exact_gen_value(f, b[0]), exact_gen_value(f, b[1]), exact_gen_value(f, b[2])};
}

ExactTriGen::ExactTriGen(const Format& f, uint64_t seed) : f_(f), rng_(seed) {}

uint32_t ExactTriGen::enc(double x) const { return static_cast<uint32_t>(num::from_double(f_, x).bits); }

ExactTriRecord ExactTriGen::next(int i) {
  ExactTriRecord r;
  const int kind = i % 5;
  r.op = static_cast<int>(below(4));
  for (int k = 0; k < 15; ++k) r.bits[k] = kind == 0 ? random_finite() : kind == 4 ? extreme() : grid(scale_);
  if (kind == 1 || kind == 2) scale_ = static_cast<int>(below(3)) - 1;
  if (kind == 2) through_vertex(r);
  if (kind == 3) {  // d = +-e or in the triangle's plane (V = 0), from a grid
    const int k = static_cast<int>(below(3));
    for (int c = 0; c < 3; ++c) {
      const double e = exact_gen_value(f_, r.bits[6 + 3 * ((k + 1) % 3) + c]) -
                       exact_gen_value(f_, r.bits[6 + 3 * ((k + 2) % 3) + c]);
      r.bits[3 + c] = enc(below(2) ? e : -e);
    }
  }
  bounds(r);
  return r;
}

uint32_t ExactTriGen::random_finite() {
  const uint64_t e = below(f_.exp_field_max());  // 0 .. max-1: finite
  return static_cast<uint32_t>((below(2) ? f_.sign_bit() : 0) | (e << f_.frac_bits) | (rng_.next() & f_.frac_mask()));
}

uint32_t ExactTriGen::extreme() {
  switch (below(4)) {
    case 0: return static_cast<uint32_t>(f_.max_finite(below(2) != 0));
    case 1: return static_cast<uint32_t>((below(2) ? f_.sign_bit() : 0) | 1);  // smallest subnormal
    case 2: return static_cast<uint32_t>(f_.min_normal(below(2) != 0));
    default: return random_finite();
  }
}

uint32_t ExactTriGen::grid(int scale) { return enc(std::ldexp(static_cast<int>(below(7)) - 3, scale)); }

// a at a vertex, d along / against / across the record's edge
void ExactTriGen::through_vertex(ExactTriRecord& r) {
  const int v = static_cast<int>(below(3));
  for (int c = 0; c < 3; ++c) r.bits[c] = r.bits[6 + 3 * v + c];
  const int k = r.op % 3, kind = static_cast<int>(below(3));
  for (int c = 0; c < 3 && kind < 2; ++c) {
    const double e = exact_gen_value(f_, r.bits[6 + 3 * ((k + 1) % 3) + c]) -
                     exact_gen_value(f_, r.bits[6 + 3 * ((k + 2) % 3) + c]);
    r.bits[3 + c] = enc(kind == 0 ? e : -e);
  }
}

// t_min, t_max: random, special, or exactly the hit's t (when the format has it)
void ExactTriGen::bounds(ExactTriRecord& r) {
  const double inf = std::numeric_limits<double>::infinity();
  auto pick = [&](bool lower) -> uint32_t {
    switch (below(8)) {
      case 0: return enc(lower ? -inf : inf);
      case 1: return enc(lower ? inf : -inf);
      case 2: return below(4) == 0 ? static_cast<uint32_t>(f_.qnan()) : enc(0.0);
      case 3:
      case 4: {
        const double t = exact_t(r);
        if (std::isfinite(t)) return enc(t);
        return random_finite();
      }
      default: return random_finite();
    }
  };
  r.bits[15] = pick(true);
  r.bits[16] = pick(false);
}

// Va / V rounded to the format when V != 0 (exact when representable)
double ExactTriGen::exact_t(const ExactTriRecord& r) const {
  const Vec3d a = exact_gen_vec3(f_, r.bits), d = exact_gen_vec3(f_, r.bits + 3);
  const Vec3d p0 = exact_gen_vec3(f_, r.bits + 6), p1 = exact_gen_vec3(f_, r.bits + 9),
              p2 = exact_gen_vec3(f_, r.bits + 12);
  auto q = [](double x) { return mpq_class(x); };
  const mpq_class e1[3] = {q(p2.x) - q(p0.x), q(p2.y) - q(p0.y), q(p2.z) - q(p0.z)};
  const mpq_class e0[3] = {q(p1.x) - q(p2.x), q(p1.y) - q(p2.y), q(p1.z) - q(p2.z)};
  const mpq_class n[3] = {e1[1] * e0[2] - e1[2] * e0[1], e1[2] * e0[0] - e1[0] * e0[2], e1[0] * e0[1] - e1[1] * e0[0]};
  const mpq_class V = n[0] * q(d.x) + n[1] * q(d.y) + n[2] * q(d.z);
  if (sgn(V) == 0) return std::numeric_limits<double>::quiet_NaN();
  const mpq_class Va = n[0] * (q(p2.x) - q(a.x)) + n[1] * (q(p2.y) - q(a.y)) + n[2] * (q(p2.z) - q(a.z));
  const mpq_class t = Va / V;
  return exact_gen_value(f_, enc(t.get_d()));
}

}  // namespace ru::units
