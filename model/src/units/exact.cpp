// Exact references with GMP rationals: signed volumes, ray-triangle hit, slab test.
#include "rayunits/units/exact.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ru::units {

mpq_class to_q(double x) {
  if (!std::isfinite(x))
    throw std::domain_error("exact reference: non-finite input " + std::to_string(x));
  return mpq_class(x);  // exact: every finite double is a dyadic rational
}

Vec3q to_q(const Vec3d& v) { return {to_q(v.x), to_q(v.y), to_q(v.z)}; }

mpq_class dot_q(const Vec3q& u, const Vec3q& v) { return u.x * v.x + u.y * v.y + u.z * v.z; }

Vec3q cross_q(const Vec3q& u, const Vec3q& v) {
  return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}

Vec3q sub_q(const Vec3q& u, const Vec3q& v) { return {u.x - v.x, u.y - v.y, u.z - v.z}; }

ExactVolumes exact_volumes(const Vec3d& a_, const Vec3d& d_, const Vec3d& p0_, const Vec3d& p1_,
                           const Vec3d& p2_) {
  const Vec3q a = to_q(a_), d = to_q(d_), p[3] = {to_q(p0_), to_q(p1_), to_q(p2_)};
  ExactVolumes v;
  v.V = dot_q(cross_q(sub_q(p[2], p[0]), sub_q(p[1], p[2])), d);
  v.Va = dot_q(cross_q(sub_q(p[2], p[0]), sub_q(p[2], p[1])), sub_q(a, p[2]));
  mpq_class* vk[3] = {&v.V0, &v.V1, &v.V2};
  for (int k = 0; k < 3; ++k) {
    const Vec3q& q1 = p[(k + 1) % 3];
    const Vec3q& q2 = p[(k + 2) % 3];
    *vk[k] = dot_q(cross_q(sub_q(a, q2), d), sub_q(q1, q2));
  }
  return v;
}

namespace {
// -1: x < bound, 0: equal, +1: x > bound, for a rational x and a double bound (may be +-INF).
int cmp_q_double(const mpq_class& x, double bound) {
  if (std::isinf(bound)) return bound > 0 ? -1 : 1;
  return cmp(x, to_q(bound));
}
}  // namespace

ExactTriHit exact_tri(const Vec3d& a, const Vec3d& d, const Vec3d& p0, const Vec3d& p1,
                      const Vec3d& p2, double t_min, double t_max) {
  ExactTriHit r;
  r.vol = exact_volumes(a, d, p0, p1, p2);
  if (std::isnan(t_min) || std::isnan(t_max)) return r;
  const int s0 = sgn(r.vol.V0), s1 = sgn(r.vol.V1), s2 = sgn(r.vol.V2);
  const bool any_neg = s0 < 0 || s1 < 0 || s2 < 0;
  const bool any_pos = s0 > 0 || s1 > 0 || s2 > 0;
  if (sgn(r.vol.V) == 0) return r;
  r.has_t = true;
  r.t = r.vol.Va / r.vol.V;
  r.beta = r.vol.V1 / r.vol.V;
  r.gamma = r.vol.V2 / r.vol.V;
  if (any_neg && any_pos) return r;
  r.hit = cmp_q_double(r.t, t_min) > 0 && cmp_q_double(r.t, t_max) < 0;
  return r;
}

double XQ::to_double() const {
  switch (kind) {
    case Finite: return q.get_d();
    case PosInf: return INFINITY;
    case NegInf: return -INFINITY;
    default: return NAN;
  }
}

namespace {
XQ xq_of_double(double x) {
  XQ r;
  if (std::isinf(x)) {
    r.kind = x > 0 ? XQ::PosInf : XQ::NegInf;
  } else {
    r.kind = XQ::Finite;
    r.q = to_q(x);
  }
  return r;
}
// Total order on Finite/PosInf/NegInf (None never compared).
int xq_cmp(const XQ& a, const XQ& b) {
  auto rank = [](const XQ& x) { return x.kind == XQ::NegInf ? 0 : x.kind == XQ::Finite ? 1 : 2; };
  int ra = rank(a), rb = rank(b);
  if (ra != rb) return ra < rb ? -1 : 1;
  if (ra != 1) return 0;
  return cmp(a.q, b.q);
}
// (plane - o) * inv exactly, with inv possibly +-INF.
XQ slab_t(const mpq_class& diff, double inv) {
  XQ r;
  if (std::isinf(inv)) {
    const int s = sgn(diff);
    if (s == 0) return r;  // None: ray in the plane, no constraint
    r.kind = (s > 0) == (inv > 0) ? XQ::PosInf : XQ::NegInf;
    return r;
  }
  r.kind = XQ::Finite;
  r.q = diff * to_q(inv);
  return r;
}
// (plane - o) / d exactly; d = +-0: as an infinite reciprocal of d's sign.
XQ slab_t_dir(const mpq_class& diff, double d) {
  if (d == 0) return slab_t(diff, std::copysign(INFINITY, d));
  XQ r;
  r.kind = XQ::Finite;
  r.q = diff / to_q(d);
  return r;
}
// Shared by exact_slab and exact_slab_dir: `t(diff, k)` gives an axis's exact t.
template <class F>
ExactBox slab_test(const Vec3d& o, const Vec3d& dir, const Vec3d& lo, const Vec3d& hi, double t_min, double t_max,
                   F t) {
  ExactBox r;
  if (std::isnan(t_min) || std::isnan(t_max)) return r;
  for (int k = 0; k < 3; ++k)
    if (std::isnan(o[k]) || std::isnan(dir[k]) || std::isnan(lo[k]) || std::isnan(hi[k])) return r;
  r.t_enter = xq_of_double(t_min);
  r.t_exit = xq_of_double(t_max);
  for (int k = 0; k < 3; ++k) {
    const bool neg = std::signbit(dir[k]);
    const mpq_class ok = to_q(o[k]);
    const mpq_class near_plane = to_q(neg ? hi[k] : lo[k]);
    const mpq_class far_plane = to_q(neg ? lo[k] : hi[k]);
    const XQ tn = t(near_plane - ok, dir[k]);
    const XQ tf = t(far_plane - ok, dir[k]);
    if (tn.kind != XQ::None && xq_cmp(tn, r.t_enter) > 0) r.t_enter = tn;
    if (tf.kind != XQ::None && xq_cmp(tf, r.t_exit) < 0) r.t_exit = tf;
  }
  r.hit = xq_cmp(r.t_enter, r.t_exit) <= 0 && r.t_enter.kind != XQ::PosInf &&
          r.t_exit.kind != XQ::NegInf;
  return r;
}
}  // namespace

ExactBox exact_slab(const Vec3d& o, const Vec3d& inv, const Vec3d& lo, const Vec3d& hi,
                    double t_min, double t_max) {
  return slab_test(o, inv, lo, hi, t_min, t_max, slab_t);
}

ExactBox exact_slab_dir(const Vec3d& o, const Vec3d& d, const Vec3d& lo, const Vec3d& hi, double t_min,
                        double t_max) {
  for (int k = 0; k < 3; ++k)
    if (std::isinf(d[k])) throw std::domain_error("exact_slab_dir: infinite direction component");
  return slab_test(o, d, lo, hi, t_min, t_max, slab_t_dir);
}

}  // namespace ru::units
