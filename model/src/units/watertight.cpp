// Watertightness study of the ray-triangle units on closed meshes (units/watertight.hpp).
#include "rayunits/units/watertight.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <type_traits>

#include "rayunits/num/fp.hpp"
#include "rayunits/units/exact.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/util/parallel.hpp"

namespace ru::units {

using ru::num::Format;
using ru::num::Soft;

namespace {

// Is the rational q exactly a value of the format?
bool representable(const Format& f, const mpq_class& q, double& out) {
  const double x = q.get_d();
  if (!std::isfinite(x) || mpq_class(x) != q) return false;  // not even a double
  const ru::num::Result r = ru::num::from_double(f, x);
  if (r.flags) return false;
  if (ru::num::to_double(f, r.bits) != x) return false;  // FTZ: subnormals read as zero
  out = x;
  return true;
}

double round_to(const Format& f, double x) { return ru::num::to_double(f, ru::num::from_double(f, x).bits); }

Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3d crs(const Vec3d& u, const Vec3d& v) {
  return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}
double dt(const Vec3d& u, const Vec3d& v) { return u.x * v.x + u.y * v.y + u.z * v.z; }
Vec3d unit(const Vec3d& v) {
  const double n = std::sqrt(dt(v, v));
  return {v.x / n, v.y / n, v.z / n};
}

struct Ray {
  Vec3d a, d;
  bool vertex = false, near_vertex = false, near_edge = false, inexact = false;
};

// x moved by k ulps of the format (k small; the result rounded into the format).
double move_ulps(const Format& f, double x, int k) {
  int e;
  std::frexp(x, &e);  // |x| in [2^(e-1), 2^e)
  const int ex = x == 0 ? f.emin() : std::max(e - 1, f.emin());
  return round_to(f, x + k * std::ldexp(1.0, ex - f.frac_bits));
}

struct Prepared {
  Format fmt;
  std::vector<Vec3d> v;  // vertices rounded into the format
  const std::vector<std::array<int, 3>>* tris = nullptr;
  std::vector<MeshEdge> edges;
  std::vector<std::vector<int>> vert_faces;
  std::vector<Vec3d> centre;
  std::vector<double> radius;
};

Ray make_ray(const Prepared& P, size_t i, size_t n_plain, uint64_t seed) {
  Rng rng(seed * 0x9e3779b97f4a7c15ull + i);
  Ray ray;
  ray.near_vertex = i >= n_plain;
  ray.vertex = !ray.near_vertex && (i % 2) == 1;
  Vec3d target;
  mpq_class tq[3];
  std::vector<int> faces;
  if (ray.vertex || ray.near_vertex) {
    const int v = static_cast<int>(rng.below(P.v.size()));
    target = P.v[v];
    faces = P.vert_faces[v];
    if (ray.near_vertex) {
      int k[3];
      do {
        for (int x = 0; x < 3; ++x) k[x] = static_cast<int>(rng.below(7)) - 3;
      } while (k[0] == 0 && k[1] == 0 && k[2] == 0);
      for (int x = 0; x < 3; ++x) target[x] = move_ulps(P.fmt, target[x], k[x]);
    }
  } else {
    // Try random edges until one has a representable point p0 + s (p1 - p0), s = k / 2^j.
    bool found = false;
    const MeshEdge* e = nullptr;
    for (int tries = 0; tries < 64 && !found; ++tries) {
      e = &P.edges[rng.below(P.edges.size())];
      const Vec3q p0 = to_q(P.v[e->v0]), p1 = to_q(P.v[e->v1]);
      for (int j = 1; j <= 4 && !found; ++j) {
        const long n = 1L << j;
        const long start = static_cast<long>(rng.below(static_cast<uint64_t>(n / 2)));
        for (long c = 0; c < n / 2 && !found; ++c) {
          const long k = 2 * ((start + c) % (n / 2)) + 1;  // odd numerators: new points only
          mpq_class s(k, n);
          s.canonicalize();
          bool ok = true;
          for (int x = 0; x < 3 && ok; ++x) {
            tq[x] = p0[x] + s * (p1[x] - p0[x]);
            ok = representable(P.fmt, tq[x], target[x]);
          }
          found = ok;
        }
      }
    }
    faces = {e->tri[0], e->tri[1]};
    if (!found) {
      ray.near_edge = true;
      for (int x = 0; x < 3; ++x) target[x] = round_to(P.fmt, (P.v[e->v0][x] + P.v[e->v1][x]) / 2);
    }
  }
  // Inward direction and distance from the incident faces.
  Vec3d n{0, 0, 0};
  double hmin = INFINITY;
  for (int f : faces) {
    const auto& t = (*P.tris)[f];
    const Vec3d nf = crs(sub(P.v[t[1]], P.v[t[0]]), sub(P.v[t[2]], P.v[t[0]]));
    const double len = std::sqrt(dt(nf, nf));
    if (len > 0) n = {n.x + nf.x / len, n.y + nf.y / len, n.z + nf.z / len};
    for (int e = 0; e < 3; ++e) {
      const Vec3d ed = sub(P.v[t[(e + 1) % 3]], P.v[t[e]]);
      const double l = std::sqrt(dt(ed, ed));
      if (l > 0) hmin = std::min(hmin, l);
    }
  }
  const Vec3d inward = unit({-n.x, -n.y, -n.z});
  const double h = 0.3 * hmin;
  const Vec3q target_q = to_q(target);
  for (int attempt = 0; attempt < 24; ++attempt) {
    Vec3d dir;
    do {
      const Vec3d j = rng.unit_vector();
      dir = unit({inward.x + 0.6 * j.x, inward.y + 0.6 * j.y, inward.z + 0.6 * j.z});
    } while (dt(dir, inward) < 0.5);
    Vec3d o;
    for (int x = 0; x < 3; ++x) o[x] = round_to(P.fmt, target[x] + h * dir[x]);
    bool ok = true;
    Vec3d d;
    for (int x = 0; x < 3 && ok; ++x) ok = representable(P.fmt, target_q[x] - to_q(o[x]), d[x]);
    if (ok && (d.x != 0 || d.y != 0 || d.z != 0)) {
      ray.a = o;
      ray.d = d;
      return ray;
    }
  }
  ray.inexact = true;
  for (int x = 0; x < 3; ++x) {
    ray.a[x] = round_to(P.fmt, target[x] + h * inward[x]);
    ray.d[x] = round_to(P.fmt, target[x] - ray.a[x]);
  }
  return ray;
}

std::vector<int> candidates(const Prepared& P, const Ray& r) {
  std::vector<int> out;
  const double tmax = 1.5;
  const double dd = dt(r.d, r.d);
  for (size_t t = 0; t < P.centre.size(); ++t) {
    const Vec3d w = sub(P.centre[t], r.a);
    double s = dd > 0 ? dt(w, r.d) / dd : 0;
    s = std::clamp(s, 0.0, tmax);
    const Vec3d q{r.a.x + s * r.d.x - P.centre[t].x, r.a.y + s * r.d.y - P.centre[t].y,
                  r.a.z + s * r.d.z - P.centre[t].z};
    const double lim = 1.5 * P.radius[t];
    if (dt(q, q) <= lim * lim) out.push_back(static_cast<int>(t));
  }
  return out;
}

template <class T>
int count_hits(const Prepared& P, const Ray& r, const std::vector<int>& cand, const WatertightOptions& opt,
               size_t* slow) {
  const Vec3<T> a = vcast<T>(r.a), d = vcast<T>(r.d);
  const T tmin = ru::num::fp_cast<T>(0.0), tmax = ru::num::fp_cast<T>(1.5);
  int hits = 0;
  for (int t : cand) {
    const auto& tri = (*P.tris)[t];
    const Vec3<T> p0 = vcast<T>(P.v[tri[0]]), p1 = vcast<T>(P.v[tri[1]]), p2 = vcast<T>(P.v[tri[2]]);
    bool hit;
    if constexpr (std::is_same_v<T, Soft>) {
      if (opt.unit) {
        hits += opt.unit(a, d, p0, p1, p2, tmin, tmax);
        continue;
      }
    }
    if (opt.exact) {
      const auto res = ray_tri_exact(a, d, p0, p1, p2, tmin, tmax, opt.exact_opt);
      hit = res.hit;
      *slow += res.path.slow();
    } else {
      hit = opt.robust ? ray_tri_robust(a, d, p0, p1, p2, tmin, tmax, opt.tri).hit
                       : ray_tri_mt(a, d, p0, p1, p2, tmin, tmax, opt.tri).hit;
    }
    hits += hit;
  }
  return hits;
}

}  // namespace

WatertightResult run_watertight(const Mesh& mesh, const WatertightOptions& opt) {
  opt.fmt.validate();
  Prepared P;
  P.fmt = opt.fmt;
  P.tris = &mesh.tris;
  P.edges = closed_mesh_edges(mesh);
  for (const Vec3d& v : mesh.verts) {
    Vec3d r;
    for (int x = 0; x < 3; ++x) {
      r[x] = round_to(opt.fmt, v[x]);
      if (!std::isfinite(r[x]))
        throw ru::num::FormatError("mesh " + mesh.name + ": a vertex overflows " + opt.fmt.name());
    }
    P.v.push_back(r);
  }
  P.vert_faces.resize(P.v.size());
  for (size_t t = 0; t < mesh.tris.size(); ++t) {
    for (int k = 0; k < 3; ++k) P.vert_faces[mesh.tris[t][k]].push_back(static_cast<int>(t));
    const Vec3d& a = P.v[mesh.tris[t][0]];
    const Vec3d& b = P.v[mesh.tris[t][1]];
    const Vec3d& c = P.v[mesh.tris[t][2]];
    const Vec3d cen{(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
    double rad = 0;
    for (const Vec3d* p : {&a, &b, &c}) rad = std::max(rad, std::sqrt(dt(sub(*p, cen), sub(*p, cen))));
    P.centre.push_back(cen);
    P.radius.push_back(rad);
  }

  const Format f32{8, 23, true, ru::num::Round::RNE}, f64{11, 52, true, ru::num::Round::RNE};
  // native paths are bit-identical; a unit given as a function runs in Soft
  const int mode = opt.unit ? 0 : opt.fmt == f32 ? 1 : opt.fmt == f64 ? 2 : 0;

  WatertightResult res;
  res.triangles = mesh.tris.size();
  res.vertices = mesh.verts.size();
  size_t total_cand = 0, done = 0;
  std::mutex mu;
  const size_t block = 128;
  const size_t nrays = opt.rays + opt.near_vertex_rays;
  const size_t nblocks = (nrays + block - 1) / block;
  util::parallel_for(nblocks, opt.threads, [&](size_t b) {
    ru::num::SoftScope scope(opt.fmt);
    WatertightResult loc;
    size_t cand_sum = 0;
    for (size_t i = b * block; i < std::min(nrays, (b + 1) * block); ++i) {
      const Ray r = make_ray(P, i, opt.rays, opt.seed);
      const std::vector<int> cand = candidates(P, r);
      cand_sum += cand.size();
      const uint64_t ovf0 = ru::num::soft_stats().overflow;
      size_t slow = 0;
      const int hits = mode == 1   ? count_hits<float>(P, r, cand, opt, &slow)
                       : mode == 2 ? count_hits<double>(P, r, cand, opt, &slow)
                                   : count_hits<Soft>(P, r, cand, opt, &slow);
      loc.overflow_rays += ru::num::soft_stats().overflow != ovf0;
      int exact_hits = 0;
      for (int t : cand) {
        const auto& tri = mesh.tris[t];
        exact_hits += exact_tri(r.a, r.d, P.v[tri[0]], P.v[tri[1]], P.v[tri[2]], 0.0, 1.5).hit;
      }
      const int crossings = oracle_crossings(r.a, r.d, P.v, mesh.tris, cand, 0.0, 1.5, opt.oracle_plant);
      WatertightCounts& c = r.near_vertex ? loc.near_vertex : r.vertex ? loc.vertex : loc.edge;
      ++c.rays;
      c.leaks += hits < crossings;
      c.double_hits += hits > crossings;
      c.oracle_not_one += crossings != 1;
      if (opt.exact) c.tests += cand.size(), c.slow_tests += slow;
      loc.near_edge_rays += r.near_edge;
      loc.inexact_aim += r.inexact;
      loc.exact_misses += exact_hits == 0 && !r.near_vertex;  // a near-vertex target may lie off the surface
    }
    std::lock_guard<std::mutex> lock(mu);
    for (auto [dst, src] : {std::pair{&res.edge, &loc.edge}, std::pair{&res.vertex, &loc.vertex},
                            std::pair{&res.near_vertex, &loc.near_vertex}}) {
      dst->rays += src->rays;
      dst->leaks += src->leaks;
      dst->double_hits += src->double_hits;
      dst->oracle_not_one += src->oracle_not_one;
      dst->tests += src->tests;
      dst->slow_tests += src->slow_tests;
    }
    res.near_edge_rays += loc.near_edge_rays;
    res.inexact_aim += loc.inexact_aim;
    res.exact_misses += loc.exact_misses;
    res.overflow_rays += loc.overflow_rays;
    total_cand += cand_sum;
    done += std::min(nrays, (b + 1) * block) - b * block;
    if (opt.progress) opt.progress(done, nrays);
  });
  res.candidates_per_ray = nrays ? static_cast<double>(total_cand) / static_cast<double>(nrays) : 0;
  return res;
}

}  // namespace ru::units
