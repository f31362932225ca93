// The renderer's per-pixel machinery (issue 6), shared with the TRaX processor model (issue 7):
// the scene data converted into the arithmetic type (Prepared), the tracer (ray generation,
// traversal with the unit golden models, shading, noise materials) and prepare(). Moved here
// unchanged from model/src/render/renderer.cpp so that the processor model runs the SAME
// shading code with its instruction-recording arithmetic type; only two hooks were added:
//   * KernelHooks<T>: when `enabled`, Tracer<T>::intersect is replaced by
//     KernelHooks<T>::intersect (the processor model's own traversal, which issues the ray-box
//     and ray-triangle units as single instructions) and KernelHooks<T>::noise sees every
//     noise result (one NOISE instruction); the default (disabled) changes nothing.
//   * Tracer<T>::primary_dir(px, py) (the per-pixel ray direction; render_t computes it per
//     pixel with the same operations as before) and pixel_value() (the clamp to [0, 1]).
// Internal to the model library: not a stable API.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "rayunits/bvh/bvh.hpp"
#include "rayunits/bvh/median.hpp"
#include "rayunits/noise/fixed.hpp"
#include "rayunits/noise/reference.hpp"
#include "rayunits/render/render.hpp"
#include "rayunits/units/ray_box.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::render::kernel {

using num::fp_abs;
using num::fp_cast;
using num::fp_max;
using num::fp_min;
using num::fp_to_double;
using units::Vec3;

// Customisation point for instrumented arithmetic types (see the comment at the top).
template <class T>
struct KernelHooks {
  static constexpr bool enabled = false;
};

// Colour channel of a pixel as stored in Image: NaN -> 0, clamped to [0, 1].
inline float pixel_value(double v) {
  return static_cast<float>(std::isnan(v) ? 0.0 : std::min(1.0, std::max(0.0, v)));
}

template <class T>
struct TriT {
  Vec3<T> p0, p1, p2;
};

template <class T>
struct NodeT {
  Vec3<T> lo, hi;
  int32_t left = -1, right = -1;
  uint32_t first = 0, count = 0;
  uint8_t axis = 0;
};

template <class T>
Vec3<T> vadd(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
Vec3<T> vscale(const Vec3<T>& a, const T& s) {
  return {a.x * s, a.y * s, a.z * s};
}
template <class T>
Vec3<T> vneg(const Vec3<T>& a) {
  return {-a.x, -a.y, -a.z};
}
template <class T>
units::Vec3d vdbl(const Vec3<T>& v) {
  return {fp_to_double(v.x), fp_to_double(v.y), fp_to_double(v.z)};
}
template <class T>
Vec3<T> vcast(const scene::Vec3& v) {
  return {fp_cast<T>(v.x), fp_cast<T>(v.y), fp_cast<T>(v.z)};
}

struct MaterialD {
  scene::MaterialKind kind;
};

// Everything the render needs, converted into T.
template <class T>
struct Prepared {
  std::vector<TriT<T>> tris;      // in leaf order
  std::vector<uint32_t> tri_mat;  // material of each (leaf-ordered) triangle
  std::vector<NodeT<T>> nodes;
  int32_t root = 0;
  int depth = 1;
  struct Mat {
    scene::MaterialKind kind;
    Vec3<T> c1, c2;
    T freq;  // frequency / unit: texture coordinate = hit point * freq
  };
  std::vector<Mat> mats;
  Vec3<T> eye, c, u, v, light;
  T eps, shadow_min, shadow_max, ka, kd, zero, one, half, two;
};

// The tested pairs, in the trace format of units/trace.hpp.
struct TraceSink {
  units::TraceWriter* w = nullptr;
  uint64_t limit = 0, written = 0;
  bool truncated = false;
  bool room() {
    if (!w) return false;
    if (limit && written >= limit) {
      truncated = true;
      return false;
    }
    ++written;
    return true;
  }
};

struct Counters {
  uint64_t primary = 0, shadow = 0, box = 0, tri = 0, noise = 0;
};

template <class T>
class Tracer {
 public:
  Tracer(const Prepared<T>& p, const RenderOptions& o)
      : P(p), opt(o), stack_(static_cast<size_t>(p.depth) + 2), noise_ref_(noise::builtin_tables(), 64),
        fixed_(noise::FixedConfig{}) {}

  Counters cnt;
  TraceSink* trace = nullptr;

  struct Ray {
    Vec3<T> o, d, inv;
  };

  // Primary ray direction through pixel centre (px, py) = (x + 0.5, y + 0.5).
  Vec3<T> primary_dir(const T& px, const T& py) const {
    const Vec3<T> row = vadd(P.c, vscale(P.v, py));
    return vadd(row, vscale(P.u, px));
  }

  Ray make_ray(const Vec3<T>& o, const Vec3<T>& d) const {
    return {o, d, {P.one / d.x, P.one / d.y, P.one / d.z}};
  }

  // Closest hit in (tmin, tmax) (any hit when `any`): returns the leaf-order triangle or -1.
  // Native types: the unit models are inlined into the traversal loop (GCC `flatten`), so the
  // ray's loop-invariant work (NaN checks of origin and reciprocal) is hoisted out of it; the
  // operations and their order are the models' own.
  int64_t intersect(const Ray& r, const T& tmin, T& tmax, bool any) {
    if constexpr (KernelHooks<T>::enabled)
      return KernelHooks<T>::intersect(*this, r, tmin, tmax, any);
    else if constexpr (std::is_same_v<T, float> || std::is_same_v<T, double>)
      return intersect_flat(r, tmin, tmax, any);
    else
      return intersect_impl(r, tmin, tmax, any);
  }
  __attribute__((flatten)) int64_t intersect_flat(const Ray& r, const T& tmin, T& tmax, bool any) {
    return intersect_impl(r, tmin, tmax, any);
  }
  // One ray-box unit test (and its trace record).
  bool box_test(const Ray& r, const NodeT<T>& n, const T& tmin, const T& tmax, T* t_enter) {
    ++cnt.box;
    if (trace && trace->room())
      trace->w->write(units::BoxRecord{vdbl(r.o), vdbl(r.inv), vdbl(n.lo), vdbl(n.hi), fp_to_double(tmin),
                                       fp_to_double(tmax)});
    const auto res = units::ray_box(r.o, r.inv, n.lo, n.hi, tmin, tmax, opt.box);
    *t_enter = res.t_enter;
    return res.hit;
  }

  // Traversal: an interior node tests both children's boxes; of two hit children the one on
  // the ray's side of the split axis is visited next and the other is pushed; a node popped
  // later is skipped when its entry lies beyond the closest hit found meanwhile (one
  // comparison in T). The child visited next is kept in a register instead of being pushed
  // and popped at once (the same order and the same operations: it gets the same skip test,
  // which cannot succeed, as a hit box has t_enter <= t_exit <= tmax and tmax has not changed
  // since its test).
  int64_t intersect_impl(const Ray& ray, const T& tmin_in, T& tmax_out, bool any) {
    // Local copies (stores to the stack cannot alias them: the ray stays in registers);
    // tmax_out is updated together with tmax.
    const Ray r = ray;
    const T tmin = tmin_in;
    T tmax = tmax_out;
    int64_t hit = -1;
    size_t sp = 0;
    T te;
    if (!box_test(r, P.nodes[P.root], tmin, tmax, &te)) return -1;
    int32_t node = P.root;  // next node to visit (its box was hit)
    for (;;) {
      const NodeT<T>& n = P.nodes[node];
      if (n.left >= 0) {
        T tl, tr;
        const bool hl = box_test(r, P.nodes[n.left], tmin, tmax, &tl);
        const bool hr = box_test(r, P.nodes[n.right], tmin, tmax, &tr);
        if (hl || hr) {
          T t_next;
          if (hl && hr) {
            // Visit order from the node's split axis and the sign of the ray direction along
            // it (Mirth's signs[axis]; after rotations the axis comes from reorder_children, §5.5).
            if (num::fp_signbit(r.d[n.axis])) {
              stack_[sp++] = {n.left, tl};
              node = n.right;
              t_next = tr;
            } else {
              stack_[sp++] = {n.right, tr};
              node = n.left;
              t_next = tl;
            }
          } else {
            node = hl ? n.left : n.right;
            t_next = hl ? tl : tr;
          }
          // The check a popped entry gets (never true here, see above; kept so that the
          // sequence of operations, e.g. Soft comparisons counted in SoftStats, is unchanged).
          if (!(hit >= 0 && tmax < t_next)) continue;
        }
      } else {
        for (uint32_t i = n.first; i < n.first + n.count; ++i) {
          const TriT<T>& t = P.tris[i];
          ++cnt.tri;
          if (trace && trace->room())
            trace->w->write(units::TriRecord{vdbl(r.o), vdbl(r.d), vdbl(t.p0), vdbl(t.p1), vdbl(t.p2),
                                             fp_to_double(tmin), fp_to_double(tmax)});
          if constexpr (std::is_same_v<T, Probe>) {
            if (detail::probe_sink) {
              for (const Vec3<T>* v : {&r.o, &r.d, &t.p0, &t.p1, &t.p2})
                for (int k = 0; k < 3; ++k) detail::probe_sink->inputs.add((*v)[k].v);
            }
          }
          bool h;
          T th;
          if (opt.tri == TriAlgo::Robust) {
            auto res = units::ray_tri_robust(r.o, r.d, t.p0, t.p1, t.p2, tmin, tmax);
            h = res.hit;
            th = res.t;
          } else {
            auto res = units::ray_tri_mt(r.o, r.d, t.p0, t.p1, t.p2, tmin, tmax);
            h = res.hit;
            th = res.t;
          }
          if (h) {
            tmax = th;
            tmax_out = th;
            hit = i;
            if (any) return hit;
          }
        }
      }
      // Next: the top of the stack, skipping entries beyond the closest hit.
      for (;;) {
        if (sp == 0) return hit;
        --sp;
        if (hit >= 0 && tmax < stack_[sp].t_enter) continue;
        node = stack_[sp].node;
        break;
      }
    }
  }

  T noise_at(const Vec3<T>& q) {
    ++cnt.noise;
    const double x = fp_to_double(q.x), y = fp_to_double(q.y), z = fp_to_double(q.z);
    double v;
    if (opt.noise == NoiseMode::Float) {
      v = noise_ref_.half(x, y, z);
    } else {  // the hardware unit works in half-resolution cells: half(p) = 2 half_cell(p/2)
      v = 2.0 * fixed_.to_real(fixed_.eval(fixed_.quantize(0.5 * x), fixed_.quantize(0.5 * y), fixed_.quantize(0.5 * z)));
    }
    T res = fp_cast<T>(v);
    if constexpr (KernelHooks<T>::enabled) KernelHooks<T>::noise(q, res);
    return res;
  }

  // Sum over 4 octaves of |noise(2^o q)| / 2^o.
  T turbulence(const Vec3<T>& q) {
    T sum = P.zero, amp = P.one, f = P.one;
    for (int o = 0; o < 4; ++o) {
      sum = sum + fp_abs(noise_at(vscale(q, f))) * amp;
      f = f * P.two;
      amp = amp * P.half;
    }
    return sum;
  }

  Vec3<T> material_color(uint32_t m, const Vec3<T>& p) {
    const auto& M = P.mats[m];
    if (M.kind == scene::MaterialKind::Constant) return M.c1;
    const Vec3<T> q = vscale(p, M.freq);
    T f;
    switch (M.kind) {
      case scene::MaterialKind::Marble: {  // triangle wave across x, perturbed by turbulence
        const T s = (q.x + turbulence(q) * fp_cast<T>(3.0)) * P.half;
        f = fp_abs((s - fp_floor(s)) * P.two - P.one);
        break;
      }
      case scene::MaterialKind::Wood: {  // rings around the vertical axis, perturbed by noise
        const T r = fp_sqrt(q.x * q.x + q.y * q.y) + noise_at(q) * P.half;
        const T g = r * P.two;
        f = g - fp_floor(g);
        f = f * f;
        break;
      }
      default: {  // turbulence
        f = turbulence(q) * fp_cast<T>(1.5);
        if (P.one < f) f = P.one;
        break;
      }
    }
    return vadd(M.c2, vscale(units::vsub(M.c1, M.c2), f));
  }

  // Colour of the pixel whose primary ray direction is d.
  Vec3<T> shade_pixel(const Vec3<T>& d) {
    ++cnt.primary;
    const Ray r = make_ray(P.eye, d);
    T t = fp_cast<T>(HUGE_VAL);
    const int64_t hit = intersect(r, P.eps, t, false);
    if (hit < 0) return {P.zero, P.zero, P.zero};
    const TriT<T>& tri = P.tris[hit];
    const Vec3<T> p = vadd(r.o, vscale(r.d, t));
    Vec3<T> N = units::cross(units::vsub(tri.p1, tri.p0), units::vsub(tri.p2, tri.p0));
    if (P.zero < units::dot(N, r.d)) N = vneg(N);  // face the viewer (a sign flip, no rounding)
    const Vec3<T> C = material_color(P.tri_mat[hit], p);
    Vec3<T> color = vscale(C, P.ka);
    const Vec3<T> ld = units::vsub(P.light, p);
    T illum = units::dot(N, ld);
    if (!(P.zero < illum)) return color;
    if (opt.shadows) {
      ++cnt.shadow;
      const Ray s = make_ray(p, ld);
      T tmax = P.shadow_max;
      if (intersect(s, P.shadow_min, tmax, true) >= 0) return color;
    }
    illum = illum / (fp_sqrt(units::dot(ld, ld)) * fp_sqrt(units::dot(N, N)));
    return vadd(color, vscale(C, illum * P.kd));
  }

  const Prepared<T>& P;
  const RenderOptions& opt;

 private:
  struct Entry {
    int32_t node;
    T t_enter;
  };
  std::vector<Entry> stack_;
  noise::NoiseRef noise_ref_;
  noise::FixedNoise fixed_;
};

template <class T>
Prepared<T> prepare(const scene::Scene& s, const RenderOptions& opt, RenderStats* st) {
  Prepared<T> P;
  const size_t n = s.tris.size();
  // Triangles rounded into T (the scene "in the format").
  std::vector<TriT<T>> tris(n);
  for (size_t i = 0; i < n; ++i)
    tris[i] = {vcast<T>(s.tris[i].p[0]), vcast<T>(s.tris[i].p[1]), vcast<T>(s.tris[i].p[2])};
  bvh::Bvh topo;
  if (opt.topology) {
    topo = *opt.topology;
  } else if (opt.bvh == BvhKind::Median) {
    std::vector<std::array<T, 9>> v(n);
    for (size_t i = 0; i < n; ++i) {
      const Vec3<T>* p[3] = {&tris[i].p0, &tris[i].p1, &tris[i].p2};
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) v[i][3 * k + c] = (*p[k])[c];
    }
    topo = bvh::build_median_generic(v, opt.leaf_size, [](double x) { return fp_cast<T>(x); },
                                     [](const T& x) { return fp_to_double(x); });
  } else {  // SAH split planes chosen in double over the rounded triangles' boxes
    std::vector<bvh::Aabb> boxes(n);
    for (size_t i = 0; i < n; ++i)
      for (const Vec3<T>* p : {&tris[i].p0, &tris[i].p1, &tris[i].p2})
        boxes[i].grow(scene::Vec3{fp_to_double(p->x), fp_to_double(p->y), fp_to_double(p->z)});
    bvh::BuildOptions bo;
    bo.max_leaf = opt.leaf_size;
    topo = bvh::build_sah(boxes, bo);
  }
  if (topo.prims.size() != n) throw std::invalid_argument("BVH topology does not match the scene");
  // Leaf-ordered triangles; boxes recomputed bottom-up in T (min/max: exact).
  P.tris.resize(n);
  P.tri_mat.resize(n);
  P.nodes.resize(topo.nodes.size());
  P.root = topo.root;
  uint32_t next = 0;
  std::function<int(int32_t)> rec = [&](int32_t id) -> int {
    const bvh::Node& b = topo.nodes[id];
    NodeT<T>& nd = P.nodes[id];
    nd.axis = b.axis;
    if (b.leaf()) {
      nd.first = next;
      nd.count = b.count;
      for (uint32_t i = 0; i < b.count; ++i) {
        const uint32_t src = topo.prims[b.first + i];
        P.tris[next] = tris[src];
        P.tri_mat[next] = s.tris[src].material;
        const TriT<T>& t = P.tris[next];
        for (const Vec3<T>* p : {&t.p0, &t.p1, &t.p2})
          for (int c = 0; c < 3; ++c) {
            nd.lo[c] = (i == 0 && p == &t.p0) ? (*p)[c] : fp_min(nd.lo[c], (*p)[c]);
            nd.hi[c] = (i == 0 && p == &t.p0) ? (*p)[c] : fp_max(nd.hi[c], (*p)[c]);
          }
        ++next;
      }
      return 1;
    }
    int dl = rec(b.left), dr = rec(b.right);
    NodeT<T>& nd2 = P.nodes[id];
    nd2.left = b.left;
    nd2.right = b.right;
    for (int c = 0; c < 3; ++c) {
      nd2.lo[c] = fp_min(P.nodes[b.left].lo[c], P.nodes[b.right].lo[c]);
      nd2.hi[c] = fp_max(P.nodes[b.left].hi[c], P.nodes[b.right].hi[c]);
    }
    return 1 + std::max(dl, dr);
  };
  if (n > 0) P.depth = rec(topo.root);
  for (const auto& m : s.materials)
    P.mats.push_back({m.kind, vcast<T>(m.color), vcast<T>(m.color2), fp_cast<T>(m.frequency / s.unit)});
  // Camera (Mirth's pinhole): per-frame constants computed in double and rounded once into T.
  const auto& cam = s.camera;
  const scene::Vec3 w = scene::normalize(cam.look_at - cam.eye);
  const double scale = 2.0 * std::tan(0.5 * cam.fov_deg * 3.14159265358979323846 / 180.0) / opt.height;
  const scene::Vec3 u = scene::normalize(scene::cross(w, cam.up)) * scale;  // right
  const scene::Vec3 v = scene::normalize(scene::cross(w, u)) * scale;       // down (image rows)
  const scene::Vec3 c = w - u * (0.5 * opt.width) - v * (0.5 * opt.height);
  const double len = scene::length(s.camera.look_at - s.camera.eye);
  (void)len;
  P.eye = vcast<T>(cam.eye);
  P.c = vcast<T>(c);
  P.u = vcast<T>(u);
  P.v = vcast<T>(v);
  P.light = vcast<T>(s.light);
  P.eps = fp_cast<T>(s.epsilon());  // primary rays: t in scene units (|d| ~ 1)
  P.shadow_min = fp_cast<T>(1e-3);  // shadow rays: t = fraction of the way to the light
  P.shadow_max = fp_cast<T>(1.0 - 1e-3);
  P.ka = fp_cast<T>(0.1);
  P.kd = fp_cast<T>(0.9);
  P.zero = num::fp_from_bits<T>(0);
  P.one = fp_cast<T>(1.0);
  P.half = fp_cast<T>(0.5);
  P.two = fp_cast<T>(2.0);
  if (st) st->bvh_nodes = topo.nodes.size();
  if (st) st->sah_cost = bvh::sah_cost(topo);
  return P;
}


}  // namespace ru::render::kernel
