// Synthetic ray-triangle and ray-box workloads (see units/synthetic.hpp).
#include "rayunits/units/synthetic.hpp"

#include <cmath>

namespace ru::units {

namespace {
Vec3d add(const Vec3d& a, const Vec3d& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3d scale(const Vec3d& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
Vec3d normalize(const Vec3d& v) {
  const double n = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x / n, v.y / n, v.z / n};
}
}  // namespace

// Rejection on the top partial range, then modulo: unbiased.
uint64_t Rng::below(uint64_t n) { return util::bounded_modulo(*this, n); }

Vec3d Rng::unit_vector() {
  for (;;) {
    Vec3d v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
    const double n2 = v.x * v.x + v.y * v.y + v.z * v.z;
    if (n2 > 1e-6 && n2 <= 1.0) return normalize(v);
  }
}

std::vector<TriRecord> synth_tri(const SynthTriOptions& o) {
  Rng rng(o.seed);
  const double lo = 1.0 - std::sqrt(2.0);  // u, v in [lo, 1]: P(inside) = 0.5 / 2 = 1/4
  std::vector<TriRecord> out;
  out.reserve(o.triangles * o.rays_per_packet);
  for (size_t i = 0; i < o.triangles; ++i) {
    const Vec3d c{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    Vec3d p[3];
    for (auto& v : p) v = add(c, {rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)});
    const Vec3d a = scale(rng.unit_vector(), 5.0);
    const double s = o.log2_spread > 0 ? o.scale * std::exp2(rng.uniform(-o.log2_spread, o.log2_spread)) : o.scale;
    for (size_t j = 0; j < o.rays_per_packet; ++j) {
      const double u = rng.uniform(lo, 1.0), v = rng.uniform(lo, 1.0);
      Vec3d target;
      for (int k = 0; k < 3; ++k) target[k] = p[0][k] + u * (p[1][k] - p[0][k]) + v * (p[2][k] - p[0][k]);
      TriRecord r;
      r.a = scale(a, s);
      r.d = normalize({target.x - a.x, target.y - a.y, target.z - a.z});
      r.p0 = scale(p[0], s);
      r.p1 = scale(p[1], s);
      r.p2 = scale(p[2], s);
      r.t_min = 0.0;
      r.t_max = INFINITY;
      out.push_back(r);
    }
  }
  return out;
}

std::vector<BoxRecord> synth_box(const SynthBoxOptions& o) {
  Rng rng(o.seed);
  std::vector<BoxRecord> out;
  out.reserve(o.boxes * o.rays_per_packet);
  for (size_t i = 0; i < o.boxes; ++i) {
    const Vec3d c{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    const Vec3d h{rng.uniform(0.05, 0.5), rng.uniform(0.05, 0.5), rng.uniform(0.05, 0.5)};
    Vec3d lo, hi;
    for (int k = 0; k < 3; ++k) {
      lo[k] = (c[k] - h[k]) * o.scale;
      hi[k] = (c[k] + h[k]) * o.scale;
    }
    const Vec3d packet_origin = scale(rng.unit_vector(), 5.0);
    for (size_t j = 0; j < o.rays_per_packet; ++j) {
      Vec3d a = packet_origin;
      if (rng.uniform() < o.inside_fraction)
        for (int k = 0; k < 3; ++k) a[k] = c[k] + rng.uniform(-h[k], h[k]);
      Vec3d target;
      for (int k = 0; k < 3; ++k) target[k] = c[k] + 1.6 * rng.uniform(-h[k], h[k]);
      Vec3d d = normalize({target.x - a.x, target.y - a.y, target.z - a.z});
      BoxRecord r;
      r.o = scale(a, o.scale);
      if (rng.uniform() < o.axis_parallel_fraction) {
        // One or two direction components exactly zero; keep the others pointing at target.
        const int zeros = 1 + static_cast<int>(rng.below(2));
        const int first = static_cast<int>(rng.below(3));
        for (int z = 0; z < zeros; ++z) {
          const int k = (first + z) % 3;
          d[k] = rng.uniform() < 0.5 ? 0.0 : -0.0;
          // The ray's k coordinate stays put: start it inside the slab range most of the time.
          r.o[k] = (c[k] + 1.4 * rng.uniform(-h[k], h[k])) * o.scale;
          if (rng.uniform() < o.on_plane_fraction) r.o[k] = rng.uniform() < 0.5 ? lo[k] : hi[k];
        }
        if (d.x == 0 && d.y == 0 && d.z == 0) d.x = 1.0;
      }
      for (int k = 0; k < 3; ++k) r.inv[k] = 1.0 / d[k];  // +-INF for +-0
      r.lo = lo;
      r.hi = hi;
      r.t_min = 0.0;
      r.t_max = rng.uniform() < o.finite_tmax_fraction ? rng.uniform(0.5, 8.0) * o.scale : INFINITY;
      out.push_back(r);
    }
  }
  return out;
}

AdversarialBoxGen::AdversarialBoxGen(const ru::num::Format& f, uint64_t seed)
    : f_(f), rng_(seed), maxf_(ru::num::to_double(f, f.max_finite())) {}

double AdversarialBoxGen::q(double x) const { return ru::num::to_double(f_, ru::num::from_double(f_, x).bits); }

BoxRecord AdversarialBoxGen::next() {
  const double scale = std::ldexp(1.0, static_cast<int>(rng_.below(9)) - 4);
  BoxRecord r;
  for (int k = 0; k < 3; ++k) {
    const double c = rng_.uniform(-1, 1) * scale, h = rng_.uniform(0.01, 0.5) * scale;
    r.lo[k] = q(c - h);
    r.hi[k] = q(c + h);
  }
  // Target: a corner (kind 0), an edge point (1: x free) or a face point (2: x, y free).
  Vec3d target;
  const int kind = static_cast<int>(rng_.below(3));
  for (int k = 0; k < 3; ++k) {
    const bool free_coord = (kind == 1 && k == 0) || (kind == 2 && k != 2);
    target[k] = free_coord ? q(rng_.uniform(r.lo[k], r.hi[k])) : (rng_.below(2) ? r.lo[k] : r.hi[k]);
  }
  Vec3d d = rng_.unit_vector();
  if (rng_.below(4) == 0) d[static_cast<int>(rng_.below(3))] = rng_.below(2) ? 0.0 : -0.0;  // grazing
  const double dist = rng_.uniform(0.5, 4) * scale;
  for (int k = 0; k < 3; ++k) {
    r.o[k] = q(target[k] - dist * d[k]);
    double inv = 1.0 / q(d[k]);
    if (std::fabs(inv) > maxf_) inv = std::copysign(INFINITY, inv);
    r.inv[k] = q(inv);
  }
  r.t_min = rng_.below(3) == 0 ? q(rng_.uniform(0, 1) * dist) : 0.0;
  r.t_max = rng_.below(3) == 0 ? q(rng_.uniform(0.5, 2) * dist) : INFINITY;
  return r;
}

std::vector<BoxRecord> adversarial_box(const ru::num::Format& f, uint64_t seed, size_t n) {
  AdversarialBoxGen gen(f, seed);
  std::vector<BoxRecord> out;
  out.reserve(n);
  for (size_t i = 0; i < n; ++i) out.push_back(gen.next());
  return out;
}

}  // namespace ru::units
