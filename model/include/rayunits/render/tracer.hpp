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
#include "rayunits/render/pair_bvh.hpp"
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

template <class T>
constexpr bool kNative = std::is_same_v<T, float> || std::is_same_v<T, double>;

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
  // Native types: the same tree with both children's boxes in their parent (pair_bvh.hpp),
  // what the native traversal reads; empty when the tree cannot be encoded that way.
  std::vector<PairNode<T>> pairs;
  Kid root_kid;
  struct Mat {
    scene::MaterialKind kind;
    Vec3<T> c1, c2;
    T freq;  // frequency / unit: texture coordinate = hit point * freq
    int octaves;
  };
  std::vector<Mat> mats;
  struct Vol {  // scene::Volume in T (has_volume false: none)
    Vec3<T> lo, hi, color;
    T freq, density, bias, inv_steps;
    int steps = 0, octaves = 0;
  };
  bool has_volume = false;
  Vol vol;
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
  uint64_t primary = 0, shadow = 0, box = 0, tri = 0, noise = 0, texture = 0, shading = 0;
};

template <class T>
class Tracer {
 public:
  Tracer(const Prepared<T>& p, const RenderOptions& o)
      : P(p), opt(o), stack_(static_cast<size_t>(p.depth) + 2), pbstack_(kNative<T> ? static_cast<size_t>(p.depth) + 2 : 0), noise_ref_(noise::builtin_tables(), 64),
        fixed_(noise::default_config(o.noise == NoiseMode::FixedTrunc ? noise::NoiseDatapath::kTrunc
                                                                         : noise::NoiseDatapath::kFull)),
        texture_(texture_config(o.noise)) {
    if (o.texture == TextureImpl::Unit && o.noise == NoiseMode::Float)
      throw std::invalid_argument("the texture unit needs a fixed noise model (--noise fixed-trunc or fixed), not float");
  }

  Counters cnt;
  TraceSink* trace = nullptr;

  struct Ray {
    Vec3<T> o, d, inv;
  };

  // The shading's multiply-adds (RenderOptions::fma): fused (fp_fma / fp_fms, ru_fp_fma, one
  // rounding) or a product and a sum, each rounded -- the vector form a*s + c, the dot product
  // ((x + y) + z; fused: fma(z, fma(y, x))) and the cross product (left product minus right
  // product; fused: fms(left, right rounded)); the scalar sites write both forms out, the
  // unfused one exactly as before issue 16 (the same instructions in the same order).
  Vec3<T> vmadd(const Vec3<T>& a, const T& s, const Vec3<T>& c) const {
    if (!opt.fma) return vadd(c, vscale(a, s));  // the three products, then the three sums
    return {fp_fma(a.x, s, c.x), fp_fma(a.y, s, c.y), fp_fma(a.z, s, c.z)};
  }
  T dot(const Vec3<T>& u, const Vec3<T>& v) const {
    return opt.fma ? fp_fma(u.z, v.z, fp_fma(u.y, v.y, u.x * v.x)) : units::dot(u, v);
  }
  Vec3<T> cross(const Vec3<T>& u, const Vec3<T>& v) const {
    if (!opt.fma) return units::cross(u, v);
    return {fp_fms(u.y, v.z, u.z * v.y), fp_fms(u.z, v.x, u.x * v.z), fp_fms(u.x, v.y, u.y * v.x)};
  }

  // Primary ray direction through pixel centre (px, py) = (x + 0.5, y + 0.5).
  Vec3<T> primary_dir(const T& px, const T& py) const {
    const Vec3<T> row = vmadd(P.v, py, P.c);
    return vmadd(P.u, px, row);
  }

  Ray make_ray(const Vec3<T>& o, const Vec3<T>& d) const {
    return {o, d, {P.one / d.x, P.one / d.y, P.one / d.z}};
  }

  // Closest hit in (tmin, tmax) (any hit when `any`): returns the leaf-order triangle or -1.
  // Native types: the unit models are inlined into the traversal loop (GCC `flatten`), so the
  // ray's loop-invariant work (NaN checks of origin and reciprocal) is hoisted out of it; the
  // operations and their order are the models' own. (The renderer traces native rays in
  // packets, intersect_packet below, which falls back to this per ray.)
  int64_t intersect(const Ray& r, const T& tmin, T& tmax, bool any) {
    if constexpr (KernelHooks<T>::enabled)
      return KernelHooks<T>::intersect(*this, r, tmin, tmax, any);
    else if constexpr (kNative<T>)
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
  // One ray-triangle unit test of leaf-order triangle i (and its trace record): hit, and t.
  bool tri_test(const Ray& r, uint32_t i, const T& tmin, const T& tmax, T* t_hit) {
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
    if (opt.tri == TriAlgo::Robust) {
      const auto res = units::ray_tri_robust(r.o, r.d, t.p0, t.p1, t.p2, tmin, tmax);
      *t_hit = res.t;
      return res.hit;
    }
    const auto res = units::ray_tri_mt(r.o, r.d, t.p0, t.p1, t.p2, tmin, tmax);
    *t_hit = res.t;
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
          T th;
          if (tri_test(r, i, tmin, tmax, &th)) {
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

  // Up to four rays traced together (bit j of lanes: ray j present).
  struct Packet {
    Ray ray[4];
    T tmin[4], tmax[4];  // tmax: in, and the closest (any: the first) hit's t out
    int64_t hit[4] = {-1, -1, -1, -1};
    unsigned lanes = 0;
  };
  // The packet's rays, each exactly as intersect() would trace it alone. A packet is traversed
  // together when its rays share the signs of their directions (one octant): then the order in
  // which intersect_impl visits a ray's nodes (near child first by the sign of d[axis], the
  // other one from the stack) is one fixed depth-first order restricted to the nodes the ray's
  // boxes hit, so the packet visits the union of the rays' nodes in that order and each ray
  // sees its own tests in its own order (a ray is active at a node when it hit the node's box
  // and, for a node taken from the stack, its own skip test fails; a ray whose tmax changed
  // since the box test was active in between, so the skip test gives what it gives alone).
  // Otherwise (mixed octants, NaN directions or interval ends, a trace, conservative boxes)
  // every ray goes through intersect().
  void intersect_packet(Packet& pk, bool any) {
    bool together = !trace && !P.pairs.empty() && opt.box == units::BoxMode::Plain;
    int oct = -1;
    for (int j = 0; j < 4 && together; ++j) {
      if (!(pk.lanes >> j & 1u)) continue;
      const Ray& r = pk.ray[j];
      if (r.d.x != r.d.x || r.d.y != r.d.y || r.d.z != r.d.z || pk.tmin[j] != pk.tmin[j] ||
          pk.tmax[j] != pk.tmax[j]) {
        together = false;
        break;
      }
      const int o = int(num::fp_signbit(r.inv.x)) | int(num::fp_signbit(r.inv.y)) << 1 |
                    int(num::fp_signbit(r.inv.z)) << 2;
      if (oct >= 0 && o != oct) together = false;
      oct = o;
    }
    if (!together || oct < 0) {
      for (int j = 0; j < 4; ++j)
        if (pk.lanes >> j & 1u) pk.hit[j] = intersect(pk.ray[j], pk.tmin[j], pk.tmax[j], any);
      return;
    }
    switch (oct) {
      case 0: return packet_traverse<0>(pk, any);
      case 1: return packet_traverse<1>(pk, any);
      case 2: return packet_traverse<2>(pk, any);
      case 3: return packet_traverse<3>(pk, any);
      case 4: return packet_traverse<4>(pk, any);
      case 5: return packet_traverse<5>(pk, any);
      case 6: return packet_traverse<6>(pk, any);
      default: return packet_traverse<7>(pk, any);
    }
  }
  template <int Oct>
  __attribute__((flatten, noinline)) void packet_traverse(Packet& pk, bool any) {
    typedef typename PacketRays<T>::VT VT;
    // Absent lanes get a copy of a present ray (finite values; masked out everywhere).
    const int first_lane = __builtin_ctz(pk.lanes);
    PacketRays<T> pr;
    for (int j = 0; j < 4; ++j) {
      const int src = (pk.lanes >> j & 1u) ? j : first_lane;
      pr.set(j, pk.ray[src].o, pk.ray[src].inv, pk.tmin[src], pk.tmax[src]);
    }
    unsigned active = 0;
    for (int j = 0; j < 4; ++j) {
      T te;
      if ((pk.lanes >> j & 1u) && box_test(pk.ray[j], P.nodes[P.root], pk.tmin[j], pk.tmax[j], &te))
        active |= 1u << j;
    }
    unsigned done = 0;   // any: rays with a hit (finished)
    unsigned found = 0;  // rays with a hit so far
    size_t sp = 0;
    Kid cur = P.root_kid;
    while (active) {
      if (cur.cnt == 0) {
        const PairNode<T>& n = P.pairs[cur.idx];
        cnt.box += 2u * ((0x4332322132212110ull >> (4 * active)) & 15u);  // 2 x popcount of 4 bits
        VT te[2];
        unsigned h[2];
        for (int c = 0; c < 2; ++c) {
          unsigned bad;
          h[c] = packet_box_test<T, Oct>(n, c, pr, active, &te[c], &bad);
          for (unsigned m = bad; m; m &= m - 1) {
            const int j = __builtin_ctz(m);
            const Vec3<T> lo{n.b[0][c], n.b[1][c], n.b[2][c]}, hi{n.b[0][c + 2], n.b[1][c + 2], n.b[2][c + 2]};
            const auto res = units::ray_box(pk.ray[j].o, pk.ray[j].inv, lo, hi, pk.tmin[j], pk.tmax[j],
                                            units::BoxMode::Plain);
            if (res.hit) h[c] |= 1u << j;
            te[c][j] = res.t_enter;
          }
        }
        if (h[0] | h[1]) {
          if (h[0] && h[1]) {
            const int near = (Oct >> n.axis) & 1;  // = sign bit of d[axis] of every ray
            pbstack_[sp++] = {n.kid(1 - near), te[1 - near], h[1 - near]};
            cur = n.kid(near);
            active = h[near];
          } else {
            const int c = h[0] ? 0 : 1;
            cur = n.kid(c);
            active = h[c];
          }
          continue;
        }
      } else {
        for (uint32_t i = uint32_t(cur.idx); i < uint32_t(cur.idx) + cur.cnt && active; ++i)
          for (unsigned m = active; m; m &= m - 1) {
            const int j = __builtin_ctz(m);
            T th;
            if (tri_test(pk.ray[j], i, pk.tmin[j], pk.tmax[j], &th)) {
              pk.tmax[j] = th;
              pr.t_max[j] = th;
              pk.hit[j] = i;
              found |= 1u << j;
              if (any) {
                done |= 1u << j;
                active &= ~(1u << j);
              }
            }
          }
      }
      active = 0;
      while (sp > 0) {
        --sp;
        const auto& e = pbstack_[sp];
        const unsigned skip = found & packet_lt_mask(pr.t_max, e.t_enter);
        const unsigned m = e.mask & ~done & ~skip;
        if (m) {
          cur = e.kid;
          active = m;
          break;
        }
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

  // One request to the texture unit (TextureImpl::Unit): the point as its input words (u = q/2,
  // the noise unit's half-resolution coordinate), the value as a number of the format.
  T texture_at(noise::TextureMode m, int n, const Vec3<T>& q) {
    ++cnt.texture;
    cnt.noise += static_cast<uint64_t>(n);
    const std::int64_t x = texture_.quantize(0.5 * fp_to_double(q.x)), y = texture_.quantize(0.5 * fp_to_double(q.y)),
                       z = texture_.quantize(0.5 * fp_to_double(q.z));
    T res = fp_cast<T>(texture_.to_real(texture_.eval(m, n, x, y, z)));
    if constexpr (KernelHooks<T>::enabled) KernelHooks<T>::texture(static_cast<int>(m), n, q, res);
    return res;
  }

  // Sum over n octaves of noise(2^o q) / 2^o: turbulence with |noise| (the materials' octaves, 4
  // by default), fBm signed (the smoke's density; the texture unit's two modes).
  T octave_sum(const Vec3<T>& q, int n, bool absolute) {
    T sum = P.zero, amp = P.one, f = P.one;
    for (int o = 0; o < n; ++o) {
      const T v = noise_at(vscale(q, f));
      sum = opt.fma ? fp_fma(absolute ? fp_abs(v) : v, amp, sum) : sum + (absolute ? fp_abs(v) : v) * amp;
      f = f * P.two;
      amp = amp * P.half;
    }
    return sum;
  }
  T turbulence(const Vec3<T>& q, int n) { return octave_sum(q, n, true); }

  Vec3<T> material_color(uint32_t m, const Vec3<T>& p) {
    const auto& M = P.mats[m];
    if (M.kind == scene::MaterialKind::Constant) return M.c1;
    const Vec3<T> q = vscale(p, M.freq);
    ++cnt.shading;
    T f;
    if (opt.texture == TextureImpl::Unit) {
      const noise::TextureMode m = M.kind == scene::MaterialKind::Marble ? noise::TextureMode::kMarble
                                   : M.kind == scene::MaterialKind::Wood ? noise::TextureMode::kWood
                                                                         : noise::TextureMode::kGranite;
      f = texture_at(m, M.kind == scene::MaterialKind::Wood ? 1 : M.octaves, q);
      return vmadd(units::vsub(M.c1, M.c2), f, M.c2);
    }
    switch (M.kind) {
      case scene::MaterialKind::Marble: {  // triangle wave across x, perturbed by turbulence
        const T s = (opt.fma ? fp_fma(turbulence(q, M.octaves), fp_cast<T>(3.0), q.x)
                             : q.x + turbulence(q, M.octaves) * fp_cast<T>(3.0)) *
                    P.half;
        f = fp_abs(opt.fma ? fp_fms(s - fp_floor(s), P.two, P.one) : (s - fp_floor(s)) * P.two - P.one);
        break;
      }
      case scene::MaterialKind::Wood: {  // rings around the vertical axis, perturbed by noise
        const T r = opt.fma ? fp_fma(noise_at(q), P.half, fp_sqrt(fp_fma(q.y, q.y, q.x * q.x)))
                            : fp_sqrt(q.x * q.x + q.y * q.y) + noise_at(q) * P.half;
        const T g = r * P.two;
        f = g - fp_floor(g);
        f = f * f;
        break;
      }
      default: {  // turbulence
        f = turbulence(q, M.octaves) * fp_cast<T>(1.5);
        if (P.one < f) f = P.one;
        break;
      }
    }
    return vmadd(units::vsub(M.c1, M.c2), f, M.c2);
  }

  // The colour `behind` seen through the scene's volume (Fig. 4.1's smoke) along the primary ray
  // r up to t_hit: the part of the ray inside the box (slab test) in P.vol.steps equal steps,
  // each sampled at its midpoint: extinction a = min(1, density max(0, fbm + bias) dt), front to
  // back: colour += transmittance a C, transmittance *= 1 - a; then + transmittance behind.
  // A fixed number of steps per ray through the box (the noise calls do not depend on the data).
  Vec3<T> through_volume(const Ray& r, const T& t_hit, const Vec3<T>& behind) {
    if (!P.has_volume) return behind;
    const auto& V = P.vol;
    T t0 = P.zero, t1 = t_hit;
    for (int a = 0; a < 3; ++a) {
      const T ta = (V.lo[a] - r.o[a]) * r.inv[a], tb = (V.hi[a] - r.o[a]) * r.inv[a];
      t0 = fp_max(t0, fp_min(ta, tb));
      t1 = fp_min(t1, fp_max(ta, tb));
    }
    if (!(t0 < t1)) return behind;  // (its noise counts toward the pixel's shading sample)
    const T dt = (t1 - t0) * V.inv_steps;
    T tr = P.one, t = t0 + dt * P.half;
    Vec3<T> acc{P.zero, P.zero, P.zero};
    for (int i = 0; i < V.steps; ++i) {
      const Vec3<T> q = vscale(vmadd(r.d, t, r.o), V.freq);
      const T f = opt.texture == TextureImpl::Unit ? texture_at(noise::TextureMode::kFbm, V.octaves, q) : octave_sum(q, V.octaves, false);
      const T dens = f + V.bias;
      if (P.zero < dens) {
        T a = dens * V.density * dt;
        if (P.one < a) a = P.one;
        acc = vmadd(V.color, tr * a, acc);
        tr = tr * (P.one - a);
      }
      t = t + dt;
    }
    return vmadd(behind, tr, acc);
  }

  // The shading of a primary hit up to its shadow ray (shade_hit) and after it (shade_finish):
  // shade_pixel() runs both around one shadow-ray query, shade_quad() runs four of each around
  // one packet query. The operations and their order are those of one pixel either way.
  struct Shading {
    Vec3<T> color, C, N, ld;
    T illum;
    Ray shadow;  // set when opt.shadows
  };
  // false: the pixel's colour is final (sh->color); true: lit, shadow ray to be tested.
  bool shade_hit(const Ray& r, int64_t hit, const T& t, Shading* sh) {
    if (hit < 0) {
      sh->color = {P.zero, P.zero, P.zero};
      return false;
    }
    const TriT<T>& tri = P.tris[hit];
    const Vec3<T> p = vmadd(r.d, t, r.o);
    Vec3<T> N = cross(units::vsub(tri.p1, tri.p0), units::vsub(tri.p2, tri.p0));
    if (P.zero < dot(N, r.d)) N = vneg(N);  // face the viewer (a sign flip, no rounding)
    sh->N = N;
    sh->C = material_color(P.tri_mat[hit], p);
    sh->color = vscale(sh->C, P.ka);
    sh->ld = units::vsub(P.light, p);
    sh->illum = dot(N, sh->ld);
    if (!(P.zero < sh->illum)) return false;
    if (opt.shadows) {
      ++cnt.shadow;
      sh->shadow = make_ray(p, sh->ld);
    }
    return true;
  }
  Vec3<T> shade_finish(const Shading& sh, bool occluded) const {
    if (occluded) return sh.color;
    const T illum = sh.illum / (fp_sqrt(dot(sh.ld, sh.ld)) * fp_sqrt(dot(sh.N, sh.N)));
    return vmadd(sh.C, illum * P.kd, sh.color);
  }

  // Colour of the pixel whose primary ray direction is d.
  Vec3<T> shade_pixel(const Vec3<T>& d) {
    ++cnt.primary;
    const Ray r = make_ray(P.eye, d);
    T t = fp_cast<T>(HUGE_VAL);
    const int64_t hit = intersect(r, P.eps, t, false);
    Shading sh;
    if (!shade_hit(r, hit, t, &sh)) return through_volume(r, t, sh.color);
    bool occluded = false;
    if (opt.shadows) {
      T tmax = P.shadow_max;
      occluded = intersect(sh.shadow, P.shadow_min, tmax, true) >= 0;
    }
    return through_volume(r, t, shade_finish(sh, occluded));
  }

  // Native types: the colours of up to four pixels (bit j of `lanes`: direction d[j] is
  // present), primary and shadow rays traced as packets (intersect_packet). Each pixel gets
  // exactly shade_pixel(d[j]): the same operations on the same values, the same counts.
  void shade_quad(const Vec3<T>* d, unsigned lanes, Vec3<T>* out) {
    Packet pk;
    pk.lanes = lanes;
    for (int j = 0; j < 4; ++j)
      if (lanes >> j & 1u) {
        ++cnt.primary;
        pk.ray[j] = make_ray(P.eye, d[j]);
        pk.tmin[j] = P.eps;
        pk.tmax[j] = fp_cast<T>(HUGE_VAL);
      }
    intersect_packet(pk, false);
    Shading sh[4];
    Packet sp;
    sp.lanes = 0;
    for (int j = 0; j < 4; ++j)
      if (lanes >> j & 1u) {
        if (!shade_hit(pk.ray[j], pk.hit[j], pk.tmax[j], &sh[j])) {
          out[j] = sh[j].color;
        } else if (!opt.shadows) {
          out[j] = shade_finish(sh[j], false);
        } else {
          sp.lanes |= 1u << j;
          sp.ray[j] = sh[j].shadow;
          sp.tmin[j] = P.shadow_min;
          sp.tmax[j] = P.shadow_max;
        }
      }
    if (sp.lanes) {
      intersect_packet(sp, true);
      for (int j = 0; j < 4; ++j)
        if (sp.lanes >> j & 1u) out[j] = shade_finish(sh[j], sp.hit[j] >= 0);
    }
    if (P.has_volume)
      for (int j = 0; j < 4; ++j)
        if (lanes >> j & 1u) out[j] = through_volume(pk.ray[j], pk.tmax[j], out[j]);
  }

  const Prepared<T>& P;
  const RenderOptions& opt;

 private:
  struct Entry {
    int32_t node;
    T t_enter;
  };
  std::vector<Entry> stack_;
  struct PacketEntry {
    Kid kid;
    typename VecOf<T>::type t_enter;
    unsigned mask;
  };
  std::vector<PacketEntry> pbstack_;
  noise::NoiseRef noise_ref_;
  noise::FixedNoise fixed_;
  noise::FixedTexture texture_;
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
  if (!opt.box_format.empty()) {
    // Boxes stored in the narrower box format: each bound of the exact box rounded outward (a
    // monotone rounding, so children stay inside their parents), then widened exactly into T.
    const num::Format bf = num::Format::parse(opt.box_format);
    auto out = [&](T& x, bool up) {
      const double d = render::round_box_bound(bf, fp_to_double(x), up);
      x = fp_cast<T>(d);
      if (!(fp_to_double(x) == d))
        throw std::invalid_argument("box format " + opt.box_format + ": a bound is not a value of the render format");
    };
    for (auto& nd : P.nodes)
      for (int c = 0; c < 3; ++c) {
        out(nd.lo[c], false);
        out(nd.hi[c], true);
      }
  }
  if constexpr (kNative<T>) {
    if (n > 0) build_pairs<T>(P.nodes, P.root, &P.pairs, &P.root_kid);
  }
  for (const auto& m : s.materials)
    P.mats.push_back({m.kind, vcast<T>(m.color), vcast<T>(m.color2), fp_cast<T>(m.frequency / s.unit), m.octaves});
  if (s.volume) {
    const scene::Volume& v = *s.volume;
    P.has_volume = true;
    P.vol = {vcast<T>(v.lo), vcast<T>(v.hi), vcast<T>(v.color), fp_cast<T>(v.frequency / s.unit), fp_cast<T>(v.density),
             fp_cast<T>(v.bias), fp_cast<T>(1.0 / v.steps), v.steps, v.octaves};
  }
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
