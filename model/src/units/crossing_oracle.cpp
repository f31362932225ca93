// Exact crossing oracle of the perturbed ray (units/crossing_oracle.hpp).
#include "rayunits/units/crossing_oracle.hpp"

#include <gmpxx.h>

#include <cmath>

namespace ru::units {
namespace {

struct Q3 {
  mpq_class v[3];
};

Q3 q3(const Vec3d& p) { return {{mpq_class(p.x), mpq_class(p.y), mpq_class(p.z)}}; }

// det of the 3x3 matrix with rows r0, r1, r2 (cofactor expansion along r0).
mpq_class det3(const Q3& r0, const Q3& r1, const Q3& r2) {
  return r0.v[0] * (r1.v[1] * r2.v[2] - r1.v[2] * r2.v[1]) - r0.v[1] * (r1.v[0] * r2.v[2] - r1.v[2] * r2.v[0]) +
         r0.v[2] * (r1.v[0] * r2.v[1] - r1.v[1] * r2.v[0]);
}

Q3 minus(const Q3& x, const Q3& y) {
  Q3 r;
  for (int i = 0; i < 3; ++i) r.v[i] = x.v[i] - y.v[i];
  return r;
}

// Sign of det[pi - a - delta, pj - a - delta, d] at delta = (eps, eps^2, eps^3).
int orient(const Q3& pi, const Q3& pj, const Q3& a, const Q3& d, OraclePlant plant) {
  const Q3 u = minus(pi, a), w = minus(pj, a);
  const mpq_class D0 = det3(u, w, d);
  if (sgn(D0) != 0 || plant == OraclePlant::NoPerturbation) return sgn(D0);
  int order[3] = {0, 1, 2};
  if (plant == OraclePlant::ReversedOrder) order[0] = 2, order[2] = 0;
  for (int k : order) {
    Q3 uk = u, wk = w;
    uk.v[k] -= 1;
    wk.v[k] -= 1;
    const mpq_class g = det3(uk, wk, d) - D0;
    if (sgn(g) != 0) return sgn(g);
  }
  return 0;
}

bool finite(const Vec3d& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

bool oracle_crosses(const Vec3d& a_, const Vec3d& d_, const Vec3d& p0_, const Vec3d& p1_, const Vec3d& p2_,
                    double t_min, double t_max, OraclePlant plant) {
  if (!finite(a_) || !finite(d_) || !finite(p0_) || !finite(p1_) || !finite(p2_)) return false;
  if (std::isnan(t_min) || std::isnan(t_max)) return false;
  const Q3 a = q3(a_), d = q3(d_), p[3] = {q3(p0_), q3(p1_), q3(p2_)};
  const int o0 = orient(p[0], p[1], a, d, plant), o1 = orient(p[1], p[2], a, d, plant),
            o2 = orient(p[2], p[0], a, d, plant);
  if (plant == OraclePlant::NoPerturbation) {
    if ((o0 < 0 || o1 < 0 || o2 < 0) && (o0 > 0 || o1 > 0 || o2 > 0)) return false;
  } else if (o0 == 0 || o0 != o1 || o1 != o2) {
    return false;
  }
  // n = (p1 - p0) x (p2 - p0); t = n.(p0 - a) / n.d
  const Q3 e1 = minus(p[1], p[0]), e2 = minus(p[2], p[0]);
  const mpq_class nx = e1.v[1] * e2.v[2] - e1.v[2] * e2.v[1], ny = e1.v[2] * e2.v[0] - e1.v[0] * e2.v[2],
                  nz = e1.v[0] * e2.v[1] - e1.v[1] * e2.v[0];
  const mpq_class nd = nx * d.v[0] + ny * d.v[1] + nz * d.v[2];
  if (sgn(nd) == 0) return false;
  const Q3 w = minus(p[0], a);
  const mpq_class t = (nx * w.v[0] + ny * w.v[1] + nz * w.v[2]) / nd;
  if (!std::isinf(t_min) && !(t > mpq_class(t_min))) return false;
  if (std::isinf(t_min) && t_min > 0) return false;
  if (!std::isinf(t_max) && !(t < mpq_class(t_max))) return false;
  if (std::isinf(t_max) && t_max < 0) return false;
  return true;
}

int oracle_crossings(const Vec3d& a, const Vec3d& d, const std::vector<Vec3d>& verts,
                     const std::vector<std::array<int, 3>>& tris, const std::vector<int>& which, double t_min,
                     double t_max, OraclePlant plant) {
  int n = 0;
  for (int t : which) n += oracle_crosses(a, d, verts[tris[t][0]], verts[tris[t][1]], verts[tris[t][2]], t_min, t_max, plant);
  return n;
}

}  // namespace ru::units
