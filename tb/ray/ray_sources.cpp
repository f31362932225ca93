// rayunits tb/ray: vector generators of the intersection units (see ray.hpp).
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "rayunits/num/patterns.hpp"
#include "ray.hpp"
#include "rayunits/synth/unit_models.hpp"
#include "rayunits/units/synthetic.hpp"

namespace ru::tb::ray {

using ru::num::Format;
using ru::units::BoxRecord;
using ru::units::TriRecord;
using ru::units::Vec3d;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Format rne(Format f) {
  f.round = ru::num::Round::RNE;
  return f;
}

// Rounds doubles into the format (RNE) and fills records.
struct Conv {
  Format f;
  explicit Conv(const Format& fmt) : f(rne(fmt)) {}
  uint64_t operator()(double x) const { return ru::num::from_double(f, x).bits; }
  // The registry's field order (ru::synth::models::tri_fields / box_fields).
  Record tri(const TriRecord& r) const {
    Record R{};
    ru::synth::models::tri_fields(f, r, R.v);
    return R;
  }
  Record box(const BoxRecord& r) const {
    Record R{};
    ru::synth::models::box_fields(f, r, R.v);
    return R;
  }
};

Vec3d vadd(const Vec3d& a, const Vec3d& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3d vsubd(const Vec3d& a, const Vec3d& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3d vscale(const Vec3d& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
Vec3d vinv(const Vec3d& d) { return {1.0 / d.x, 1.0 / d.y, 1.0 / d.z}; }  // 1/+-0 = +-INF

// Largest |log2| of a coordinate scale that keeps cubic volumes finite in most cases.
int safe_log2(const Format& f) { return std::max(1, f.emax() / 3 - 1); }

class Gen {
 public:
  Gen(const Format& f, uint64_t seed) : f_(f), rng_(seed ^ (uint64_t(f.exp_bits) << 40) ^ (uint64_t(f.frac_bits) << 32)),
                                        specials_(ru::num::special_values(f)) {}
  double u(double lo, double hi) { return rng_.uniform(lo, hi); }
  uint64_t below(uint64_t n) { return rng_.below(n); }
  bool chance(int pct) { return rng_.below(100) < static_cast<uint64_t>(pct); }
  int irange(int lo, int hi) { return lo + static_cast<int>(rng_.below(static_cast<uint64_t>(hi - lo + 1))); }
  Vec3d u3(double lo, double hi) { return {u(lo, hi), u(lo, hi), u(lo, hi)}; }
  Vec3d i3(int lo, int hi) { return {double(irange(lo, hi)), double(irange(lo, hi)), double(irange(lo, hi))}; }
  Vec3d unit() { return rng_.unit_vector(); }
  uint64_t special() { return specials_[below(specials_.size())]; }
  // Random interval: mostly (0, INF), else a mix of finite, negative and infinite bounds.
  void interval(double& tmin, double& tmax, double scale) {
    tmin = 0.0, tmax = kInf;
    if (chance(65)) return;
    switch (below(6)) {
      case 0: tmin = -kInf; break;
      case 1: tmin = -u(0, 2) * scale; break;
      case 2: tmin = u(0, 1) * scale; break;
      default: break;
    }
    switch (below(4)) {
      case 0: tmax = u(0.5, 8) * scale; break;
      case 1: tmax = u(0, 1) * scale; break;
      default: break;
    }
  }
  // Replaces ~pct/1000 of the fields by special values.
  void sprinkle(Record& r, int nfields, int permille) {
    for (int i = 0; i < nfields; ++i)
      if (rng_.below(1000) < static_cast<uint64_t>(permille)) r.v[i] = special();
  }
  const Format& f() const { return f_; }

 private:
  Format f_;
  ru::units::Rng rng_;
  std::vector<uint64_t> specials_;
};

// Dyadic directions (exact in every format with >= 4 fraction bits).
const Vec3d kDirs[] = {{0, 0, -1},       {0.5, 0.25, -1},  {-0.375, 0.5, -1}, {1, -1, -1},
                       {-0.25, -0.75, -1}, {0.125, 0, -1}, {0, -0.5, -1},     {0.75, 0.5, -0.25}};

// Edges, vertices and interiors of a pair of grid triangles sharing the edge p1-p2 of T0.
void shared_edge_cases(std::vector<TriRecord>& out, double s, const Vec3d& off) {
  const Vec3d q0{0, 0, 0}, q1{2, 0, 0}, q2{0, 2, 0}, q3{2, 2, 0};
  const Vec3d targets[] = {{1, 1, 0},   {0.5, 1.5, 0}, {1.5, 0.5, 0}, {2, 0, 0},   {0, 2, 0},
                           {0, 0, 0},   {1, 0, 0},     {0, 1, 0},     {0.5, 0.5, 0}, {1.5, 1.5, 0},
                           {2, 1, 0},   {1, 2, 0},     {-0.5, 1, 0},  {1, 1.25, 0}};
  const Vec3d tris[][3] = {{q0, q1, q2}, {q1, q2, q0}, {q2, q0, q1}, {q0, q2, q1},
                           {q1, q3, q2}, {q3, q2, q1}, {q2, q1, q3}};
  struct Iv {
    double lo, hi;
  };
  const Iv ivs[] = {{0, kInf}, {0, 1}, {1, kInf}, {-kInf, kInf}, {0, 1.5}};
  int k = 0;
  for (const auto& t : tris) {
    for (const Vec3d& tg : targets) {
      const Vec3d& d = kDirs[k % 8];
      const Iv iv = ivs[(k / 8) % 5];
      ++k;
      TriRecord r;
      const Vec3d dd = (k % 3 == 0) ? vscale(d, -1) : d;  // back faces too
      r.d = vscale(dd, s);
      r.a = vadd(vscale(vsubd(tg, dd), s), off);  // t = 1 exactly
      r.p0 = vadd(vscale(t[0], s), off);
      r.p1 = vadd(vscale(t[1], s), off);
      r.p2 = vadd(vscale(t[2], s), off);
      r.t_min = iv.lo;
      r.t_max = iv.hi;
      out.push_back(r);
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------

std::vector<Record> box_records(const Format& f, const std::vector<BoxRecord>& v) {
  Conv c(f);
  std::vector<Record> out;
  out.reserve(v.size());
  for (const auto& r : v) out.push_back(c.box(r));
  return out;
}

std::vector<Record> tri_records(const Format& f, const std::vector<TriRecord>& v) {
  Conv c(f);
  std::vector<Record> out;
  out.reserve(v.size());
  for (const auto& r : v) out.push_back(c.tri(r));
  return out;
}

std::vector<Record> tri_synthetic(const Format& f, uint64_t seed, size_t n) {
  struct Part {
    double frac, scale, spread;
  };
  const Part parts[] = {{0.4, 1.0, 0}, {0.2, 1.0, 16}, {0.2, 1e-6, 0}, {0.2, 1e6, 0}};
  std::vector<TriRecord> all;
  uint64_t s = seed;
  for (const Part& p : parts) {
    ru::units::SynthTriOptions o;
    o.seed = ++s;
    o.triangles = static_cast<size_t>(std::ceil(p.frac * n / 16.0));
    o.scale = p.scale;
    o.log2_spread = p.spread;
    auto v = ru::units::synth_tri(o);
    all.insert(all.end(), v.begin(), v.end());
  }
  if (all.size() > n) all.resize(n);
  return tri_records(f, all);
}

std::vector<Record> box_synthetic(const Format& f, uint64_t seed, size_t n) {
  const double scales[] = {1.0, 1.0, 1e-6, 1e6};
  std::vector<BoxRecord> all;
  uint64_t s = seed;
  for (double sc : scales) {
    ru::units::SynthBoxOptions o;
    o.seed = ++s;
    o.boxes = static_cast<size_t>(std::ceil(0.25 * n / 16.0));
    o.scale = sc;
    auto v = ru::units::synth_box(o);
    all.insert(all.end(), v.begin(), v.end());
  }
  if (all.size() > n) all.resize(n);
  return box_records(f, all);
}

std::vector<Record> tri_random(const Format& f, uint64_t seed, size_t n) {
  Gen g(f, seed);
  Conv c(f);
  const int L = safe_log2(f);
  std::vector<Record> out;
  out.reserve(n);
  while (out.size() < n) {
    TriRecord r;
    double scale = 1;
    if (g.chance(30)) {  // integer grid: exact zero volumes, rays through edges and vertices
      r.p0 = g.i3(-4, 4), r.p1 = g.i3(-4, 4), r.p2 = g.i3(-4, 4);
      r.a = g.i3(-6, 6);
      r.d = g.i3(-2, 2);
      if (g.chance(50)) {  // aim at a grid point of the triangle's plane
        const double uu = 0.5 * g.irange(-1, 3), vv = 0.5 * g.irange(-1, 3);
        const Vec3d tg = vadd(r.p0, vadd(vscale(vsubd(r.p1, r.p0), uu), vscale(vsubd(r.p2, r.p0), vv)));
        r.d = vsubd(tg, r.a);
      }
      scale = 8;
    } else {  // mixed scales over the format's range
      const int k = g.irange(-L, L), j = g.irange(-6, 0), m = g.irange(-L / 2, L / 2);
      scale = std::exp2(k);
      const Vec3d ctr = vscale(g.u3(-1, 1), scale);
      r.p0 = vadd(ctr, vscale(g.u3(-1, 1), std::exp2(k + j)));
      r.p1 = vadd(ctr, vscale(g.u3(-1, 1), std::exp2(k + j)));
      r.p2 = vadd(ctr, vscale(g.u3(-1, 1), std::exp2(k + j)));
      r.a = vadd(ctr, vscale(g.unit(), std::exp2(k + g.irange(0, 4))));
      if (g.chance(70)) {
        const double uu = g.u(-0.25, 1.25), vv = g.u(-0.25, 1.25);
        const Vec3d tg = vadd(r.p0, vadd(vscale(vsubd(r.p1, r.p0), uu), vscale(vsubd(r.p2, r.p0), vv)));
        r.d = vscale(vsubd(tg, r.a), std::exp2(m - k));
      } else {
        r.d = vscale(g.unit(), std::exp2(m));
      }
      if (g.chance(10)) r.d[static_cast<int>(g.below(3))] = 0.0;
    }
    g.interval(r.t_min, r.t_max, 2.0);
    Record R = c.tri(r);
    g.sprinkle(R, 17, 15);
    out.push_back(R);
  }
  return out;
}

std::vector<Record> box_random(const Format& f, uint64_t seed, size_t n) {
  Gen g(f, seed);
  Conv c(f);
  const int L = std::max(1, f.emax() / 2 - 1);
  std::vector<Record> out;
  out.reserve(n);
  while (out.size() < n) {
    BoxRecord r;
    Vec3d d;
    if (g.chance(30)) {  // integer grid: rays through corners, edges, faces; slab planes
      Vec3d a = g.i3(-4, 4), b = g.i3(-4, 4);
      for (int k = 0; k < 3; ++k) {
        if (g.chance(85) && a[k] > b[k]) std::swap(a[k], b[k]);  // some boxes stay inverted
      }
      r.lo = a, r.hi = b;
      r.o = g.i3(-6, 6);
      d = g.i3(-2, 2);
      for (int k = 0; k < 3; ++k)
        if (d[k] == 0 && g.chance(50)) d[k] = -0.0;  // 1/-0 = -INF
      g.interval(r.t_min, r.t_max, 4.0);
    } else {
      const int k = g.irange(-L, L), m = g.irange(-L / 2, L / 2);
      const double s = std::exp2(k);
      const Vec3d ctr = vscale(g.u3(-1, 1), s);
      const Vec3d half = vscale(g.u3(0.01, 1), s * std::exp2(g.irange(-4, 0)));
      r.lo = vsubd(ctr, half), r.hi = vadd(ctr, half);
      r.o = vadd(ctr, vscale(g.unit(), s * std::exp2(g.irange(-1, 4))));
      const Vec3d tg = vadd(ctr, {half.x * g.u(-1.6, 1.6), half.y * g.u(-1.6, 1.6), half.z * g.u(-1.6, 1.6)});
      d = vscale(vsubd(tg, r.o), std::exp2(m - k));
      if (g.chance(10)) d[static_cast<int>(g.below(3))] = g.chance(50) ? 0.0 : -0.0;
      g.interval(r.t_min, r.t_max, std::exp2(k - m));
    }
    r.inv = vinv(d);
    Record R = c.box(r);
    g.sprinkle(R, 14, 15);
    out.push_back(R);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

std::vector<Record> tri_extremes(const Format& f, uint64_t seed, uint64_t eps_bits) {
  Gen g(f, seed);
  Conv c(f);
  std::vector<TriRecord> v;
  // 1. rays exactly through shared edges, vertices and interiors of grid triangles (all vertex
  //    rotations, both orientations, back faces, t == t_min / t_max), at scales 1, 2^-3, 1e-6,
  //    1e+6 and translated.
  shared_edge_cases(v, 1, {0, 0, 0});
  shared_edge_cases(v, 0.125, {3, -5, 0.5});
  shared_edge_cases(v, 1e-6, {0, 0, 0});
  shared_edge_cases(v, 1e6, {0, 0, 0});
  // 2. axis-parallel rays (d = +-e_k) aimed at random triangles; grazing rays (d in the plane)
  for (int i = 0; i < 96; ++i) {
    TriRecord r;
    r.p0 = g.u3(-1, 1), r.p1 = g.u3(-1, 1), r.p2 = g.u3(-1, 1);
    const int k = i % 3;
    const double sgn = (i / 3) % 2 ? -1.0 : 1.0;
    const double uu = g.u(-0.2, 1.0), vv = g.u(-0.2, 1.0);
    const Vec3d tg = vadd(r.p0, vadd(vscale(vsubd(r.p1, r.p0), uu), vscale(vsubd(r.p2, r.p0), vv)));
    r.d = {0, 0, 0};
    r.d[k] = sgn;
    r.a = tg;
    r.a[k] -= 3 * sgn;
    v.push_back(r);
  }
  for (int i = 0; i < 64; ++i) {  // grazing: triangle in z = 0, d = in-plane (+ tiny z)
    TriRecord r;
    r.p0 = {0, 0, 0}, r.p1 = {2, 0, 0}, r.p2 = {0, 2, 0};
    r.a = {-1, g.u(0, 1.5), (i % 4 == 0) ? 0.0 : std::ldexp(1.0, -g.irange(2, 30)) * ((i % 2) ? 1 : -1)};
    r.d = {1, g.u(-0.5, 0.5), (i % 8 < 4) ? 0.0 : std::ldexp(1.0, -g.irange(2, 30))};
    v.push_back(r);
  }
  // 3. degenerate triangles: repeated vertices, collinear vertices, all equal
  for (int i = 0; i < 48; ++i) {
    TriRecord r;
    const Vec3d p = g.i3(-3, 3), q = g.i3(-3, 3);
    switch (i % 4) {
      case 0: r.p0 = p, r.p1 = p, r.p2 = q; break;
      case 1: r.p0 = p, r.p1 = q, r.p2 = q; break;
      case 2: r.p0 = p, r.p1 = q, r.p2 = vsubd(vscale(q, 2), p); break;  // collinear
      default: r.p0 = p, r.p1 = p, r.p2 = p; break;
    }
    r.a = vadd(p, {0.5, 0.25, 4});
    r.d = vsubd(vscale(vadd(p, q), 0.5), r.a);
    v.push_back(r);
  }
  // 4. slivers 1e-7 wide (relative), rays inside, on and outside the sliver
  for (int i = 0; i < 48; ++i) {
    TriRecord r;
    const double w = 1e-7 * std::exp2(g.irange(-2, 2));
    r.p0 = {0, 0, 0}, r.p1 = {1, 0, 0}, r.p2 = {0.5, w, 0};
    const double ys[] = {0, w * 0.25, w * 0.5, w, 2 * w, -w * 0.1};
    r.a = {0.5 + g.u(-0.4, 0.4), ys[i % 6], 1};
    r.d = {0, 0, -1};
    if (i % 12 >= 6) r.d = {0.0625, 0, -1}, r.a.x -= 0.0625;
    v.push_back(r);
  }
  // 5. rays starting on the triangle plane (t = 0): t_min = 0 misses, t_min < 0 hits
  for (int i = 0; i < 48; ++i) {
    TriRecord r;
    r.p0 = g.i3(-3, 3), r.p1 = g.i3(-3, 3), r.p2 = g.i3(-3, 3);
    const double uu = 0.25 * g.irange(0, 2), vv = 0.25 * g.irange(0, 2);
    r.a = vadd(r.p0, vadd(vscale(vsubd(r.p1, r.p0), uu), vscale(vsubd(r.p2, r.p0), vv)));
    r.d = g.i3(-2, 2);
    r.t_min = (i % 2) ? -1.0 : 0.0;
    v.push_back(r);
  }
  // 6. overflowing and underflowing volumes: huge and tiny coordinates
  const double big = std::ldexp(1.0, f.emax() - 1), tiny = std::ldexp(1.0, f.emin() + 2);
  for (int i = 0; i < 32; ++i) {
    TriRecord r;
    const double s = (i % 2) ? big * g.u(0.25, 1) : tiny * g.u(1, 16);
    r.p0 = vscale(g.u3(-1, 1), s), r.p1 = vscale(g.u3(-1, 1), s), r.p2 = vscale(g.u3(-1, 1), s);
    r.a = vscale(g.u3(-1, 1), s);
    r.d = vsubd(vscale(vadd(r.p0, vadd(r.p1, r.p2)), 1.0 / 3), r.a);
    v.push_back(r);
  }
  // 7. |V| around eps (if an eps is set): V = s^2 (right triangle of leg s, d = -e_z)
  if (eps_bits) {
    const double eps = ru::num::to_double(f, eps_bits);
    for (int i = 0; i < 64; ++i) {
      TriRecord r;
      const double s = std::sqrt(eps) * std::exp2(g.u(-1.5, 1.5));
      r.p0 = {0, 0, 0}, r.p1 = {s, 0, 0}, r.p2 = {0, s, 0};
      r.a = {s * 0.25, s * 0.25, 1};
      r.d = {0, 0, (i % 2) ? -1.0 : 1.0};
      if (i % 4 >= 2) r.a.z = -1;
      v.push_back(r);
    }
  }
  std::vector<Record> out = tri_records(f, v);
  // 8. NaN, sNaN, +-INF and +-0 in every field of a hitting ray
  TriRecord base;
  base.p0 = {0, 0, 0}, base.p1 = {2, 0, 0}, base.p2 = {0, 2, 0};
  base.a = {0.5, 0.5, 1}, base.d = {0, 0, -1};
  const Record b = c.tri(base);
  const uint64_t specials[] = {f.qnan(), f.inf() | 1, f.inf(false), f.inf(true), f.neg_zero(), f.max_finite(true)};
  for (int i = 0; i < 17; ++i)
    for (uint64_t s : specials) {
      Record r = b;
      r.v[i] = s;
      out.push_back(r);
    }
  return out;
}

std::vector<Record> box_extremes(const Format& f, uint64_t seed) {
  Gen g(f, seed);
  Conv c(f);
  std::vector<BoxRecord> v;
  const Vec3d lo{-1, -0.5, 0}, hi{1, 1.5, 2};
  const double scales[] = {1.0, 1e-6, 1e6, 0.125};
  for (double s : scales) {
    // 1. rays aimed exactly at corners, edge midpoints and face centres (t = 1)
    for (int i = 0; i < 27; ++i) {
      const Vec3d tg{(i % 3) == 0 ? lo.x : (i % 3) == 1 ? 0.0 : hi.x,
                     (i / 3) % 3 == 0 ? lo.y : (i / 3) % 3 == 1 ? 0.5 : hi.y,
                     (i / 9) == 0 ? lo.z : (i / 9) == 1 ? 1.0 : hi.z};
      for (int j = 0; j < 3; ++j) {
        BoxRecord r;
        Vec3d d = kDirs[(i + j) % 8];
        if (j == 2) d = vscale(d, -1);
        r.lo = vscale(lo, s), r.hi = vscale(hi, s);
        r.o = vscale(vsubd(tg, d), s);
        r.inv = vinv(vscale(d, s));
        if (j == 1) r.t_max = 1.0;  // t_exit or t_enter == t_max exactly
        v.push_back(r);
      }
    }
    // 2. axis-parallel rays (inv = +-INF): inside, outside, and exactly on slab planes (0*INF)
    for (int i = 0; i < 48; ++i) {
      BoxRecord r;
      r.lo = vscale(lo, s), r.hi = vscale(hi, s);
      Vec3d d{g.u(-1, 1), g.u(-1, 1), g.u(-1, 1)};
      const int k = i % 3;
      d[k] = (i / 3) % 2 ? -0.0 : 0.0;
      if (i % 6 == 5) d[(k + 1) % 3] = 0.0;
      Vec3d o = {g.u(-1.2, 1.2), g.u(-0.7, 1.7), g.u(-0.2, 2.2)};
      const int which = (i / 6) % 4;  // on lo plane, on hi plane, outside, inside
      o[k] = which == 0 ? lo[k] : which == 1 ? hi[k] : which == 2 ? hi[k] + 0.5 : 0.5 * (lo[k] + hi[k]);
      r.o = vscale(vsubd(o, vscale(d, 3)), s);
      r.o[k] = o[k] * s;
      r.inv = vinv(vscale(d, s));
      v.push_back(r);
    }
    // 3. grazing rays along a face (origin on the face plane, direction parallel or nearly)
    for (int i = 0; i < 24; ++i) {
      BoxRecord r;
      r.lo = vscale(lo, s), r.hi = vscale(hi, s);
      Vec3d d{1, g.u(-0.3, 0.3), (i % 3 == 0) ? 0.0 : std::ldexp(1.0, -g.irange(4, 40)) * ((i % 2) ? 1 : -1)};
      r.o = vscale(Vec3d{-2, 0.5, (i % 2) ? lo.z : hi.z}, s);
      r.inv = vinv(vscale(d, s));
      v.push_back(r);
    }
  }
  // 4. flat boxes, inverted boxes, rays starting inside, degenerate intervals
  for (int i = 0; i < 64; ++i) {
    BoxRecord r;
    Vec3d a = g.i3(-3, 3), b = g.i3(-3, 3);
    for (int k = 0; k < 3; ++k)
      if (a[k] > b[k]) std::swap(a[k], b[k]);
    switch (i % 4) {
      case 0: b[i % 3] = a[i % 3]; break;  // flat
      case 1: std::swap(a[i % 3], b[i % 3]); break;  // inverted on one axis
      default: break;
    }
    r.lo = a, r.hi = b;
    r.o = (i % 8 < 4) ? vscale(vadd(a, b), 0.5) : g.i3(-5, 5);
    r.inv = vinv(g.i3(-2, 2));
    switch ((i / 4) % 4) {
      case 0: r.t_min = r.t_max = 1.0; break;
      case 1: r.t_min = 2.0, r.t_max = 1.0; break;
      case 2: r.t_min = -kInf, r.t_max = 0.0; break;
      default: break;
    }
    v.push_back(r);
  }
  // 5. the underflow threshold: differences and products near the smallest normal (directed
  //    rounding flushes to zero in FTZ formats; the conservative fix-up must replace it)
  const double mn = std::ldexp(1.0, f.emin());
  for (int i = 0; i < 160; ++i) {
    BoxRecord r;
    auto near_mn = [&] { return (g.chance(50) ? 1 : -1) * mn * (1.0 + g.irange(0, 16) / 16.0) * (g.chance(20) ? 0 : 1); };
    for (int k = 0; k < 3; ++k) {
      r.o[k] = near_mn();
      double a = near_mn(), b = near_mn();
      if (a > b) std::swap(a, b);
      r.lo[k] = a, r.hi[k] = b;
      const int e = g.irange(-8, 8);
      r.inv[k] = (g.chance(50) ? 1 : -1) * (g.chance(10) ? kInf : std::ldexp(1.0 + g.irange(0, 7) / 8.0, e));
    }
    if (i % 4 == 0) r.t_min = -kInf;
    v.push_back(r);
  }
  // 6. overflow: huge coordinates and reciprocals
  const double big = std::ldexp(1.0, f.emax() - 1);
  for (int i = 0; i < 48; ++i) {
    BoxRecord r;
    for (int k = 0; k < 3; ++k) {
      double a = big * g.u(-1.9, 1.9), b = big * g.u(-1.9, 1.9);
      if (a > b) std::swap(a, b);
      r.lo[k] = a, r.hi[k] = b;
      r.o[k] = big * g.u(-1.9, 1.9);
      r.inv[k] = (g.chance(50) ? 1 : -1) * std::ldexp(g.u(1, 2), g.irange(-4, f.emax() - 1));
    }
    v.push_back(r);
  }
  std::vector<Record> out = box_records(f, v);
  // 7. NaN, sNaN, +-INF and +-0 in every field of a hitting ray
  BoxRecord base;
  base.lo = lo, base.hi = hi, base.o = {0, 0.5, -1}, base.inv = vinv({0.25, 0.125, 1});
  const Record b = c.box(base);
  const uint64_t specials[] = {f.qnan(), f.inf() | 1, f.inf(false), f.inf(true), f.neg_zero(), f.pos_zero()};
  for (int i = 0; i < 14; ++i)
    for (uint64_t s : specials) {
      Record r = b;
      r.v[i] = s;
      out.push_back(r);
    }
  return out;
}

std::vector<Record> trace_records(const Format& f, bool box, const std::string& tmp_path, size_t n,
                                  std::string& what) {
  ru::units::Trace tr;
  const char* env = std::getenv("RU_RAY_TRACE");
  if (env && *env) {
    tr = ru::units::read_trace(env);
    what = std::string("captured trace ") + env;
  } else {
    ru::units::SynthTriOptions to;
    to.seed = 11;
    to.triangles = (n + 15) / 16;
    to.log2_spread = 4;
    ru::units::SynthBoxOptions bo;
    bo.seed = 12;
    bo.boxes = (n + 15) / 16;
    ru::units::TraceWriter w(tmp_path);
    // interleaved, as a renderer would write them
    const auto tris = ru::units::synth_tri(to);
    const auto boxes = ru::units::synth_box(bo);
    for (size_t i = 0; i < std::max(tris.size(), boxes.size()); ++i) {
      if (i < boxes.size()) w.write(boxes[i]);
      if (i < tris.size()) w.write(tris[i]);
    }
    w.close();
    tr = ru::units::read_trace(tmp_path);
    if (tr.tris.size() != tris.size() || tr.boxes.size() != boxes.size())
      throw std::runtime_error("trace round trip lost records: " + tmp_path);
    what = "synthetic trace " + tmp_path + " (written and read back)";
  }
  if (box) {
    if (tr.boxes.size() > n) tr.boxes.resize(n);
    return box_records(f, tr.boxes);
  }
  if (tr.tris.size() > n) tr.tris.resize(n);
  return tri_records(f, tr.tris);
}

}  // namespace ru::tb::ray
