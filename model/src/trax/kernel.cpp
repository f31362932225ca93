// The ray-tracing kernel of the TRaX model: the renderer's own Tracer (render/tracer.hpp)
// instantiated with the recording type TVal; its traversal is replaced (KernelHooks) by the
// processor's traversal below, which issues the ray-box and ray-triangle units as single
// instructions and models node loads, branches and the stack in the local store.
#include <algorithm>
#include <stdexcept>

#include "rayunits/render/tracer.hpp"
#include "rayunits/trax/thread.hpp"
#include "rayunits/trax/trax.hpp"

namespace ru::trax {
using render::kernel::NodeT;
using render::kernel::Prepared;
using render::kernel::Tracer;
using units::Vec3;
using Ray = Tracer<TVal>::Ray;
int64_t traverse(Tracer<TVal>& tr, const Ray& r, const TVal& tmin, TVal& tmax, bool any);
bool software_noise();
const noise::FixedNoise& chip_noise();
const noise::FixedTexture& chip_texture();
uint32_t emit_software_noise(Thread& t, const Vec3<TVal>& q);
}  // namespace ru::trax

namespace ru::render::kernel {
template <>
struct KernelHooks<ru::trax::TVal> {
  static constexpr bool enabled = true;
  static int64_t intersect(Tracer<trax::TVal>& tr, const trax::Ray& r, const trax::TVal& tmin, trax::TVal& tmax,
                           bool any) {
    return trax::traverse(tr, r, tmin, tmax, any);
  }
  // One NOISE instruction on the texture coordinate (the value is the renderer's).
  static void noise(const Vec3<trax::TVal>& q, trax::TVal& res) {
    trax::Thread* t = trax::Thread::current();
    if (!t) return;
    if (trax::software_noise()) {
      res.reg = t->mark_fp(trax::emit_software_noise(*t, q));
      return;
    }
    res.reg = t->mark_fp(t->emit(trax::Op::Noise, {trax::detail::use(q.x), trax::detail::use(q.y), trax::detail::use(q.z)}));
    if (t->keep_operands()) {
      // The hardware unit's words, exactly as Tracer::noise_at feeds FixedNoise (noise = fixed-trunc
      // or fixed; with noise = float there is no hardware unit and the record is not co-simulated).
      const noise::FixedNoise& fx = trax::chip_noise();
      const int in_w = fx.config().frac_bits + fx.config().int_bits, out_w = fx.config().out_w;
      const uint64_t in_mask = (1ull << in_w) - 1, out_mask = (1ull << out_w) - 1;
      const int64_t x = fx.quantize(0.5 * fp_to_double(q.x)), y = fx.quantize(0.5 * fp_to_double(q.y)),
                    z = fx.quantize(0.5 * fp_to_double(q.z));
      const uint64_t w[trax::kNoiseIn + trax::kNoiseOut] = {
          static_cast<uint64_t>(x) & in_mask, static_cast<uint64_t>(y) & in_mask, static_cast<uint64_t>(z) & in_mask,
          static_cast<uint64_t>(fx.eval(x, y, z)) & out_mask};
      t->attach(w, trax::kNoiseIn + trax::kNoiseOut);
    }
  }
  // One TEXTURE instruction (chip.texture = "unit"): the octave count rides along (occupancy).
  static void texture(int mode, int n, const Vec3<trax::TVal>& q, trax::TVal& res) {
    trax::Thread* t = trax::Thread::current();
    if (!t) return;
    res.reg = t->mark_fp(t->emit(trax::Op::Texture, {trax::detail::use(q.x), trax::detail::use(q.y), trax::detail::use(q.z)}));
    t->stream().code.back().aux = static_cast<uint8_t>(n);
    if (t->keep_operands()) {
      // the unit's words, exactly as Tracer::texture_at feeds FixedTexture
      const noise::FixedTexture& fx = trax::chip_texture();
      const uint64_t in_mask = (1ull << fx.config().in_w()) - 1, out_mask = (1ull << fx.config().out_w()) - 1;
      const int64_t x = fx.quantize(0.5 * fp_to_double(q.x)), y = fx.quantize(0.5 * fp_to_double(q.y)),
                    z = fx.quantize(0.5 * fp_to_double(q.z));
      const uint64_t w[trax::kTextureIn + trax::kTextureOut] = {
          static_cast<uint64_t>(x) & in_mask, static_cast<uint64_t>(y) & in_mask, static_cast<uint64_t>(z) & in_mask,
          static_cast<uint64_t>(mode), static_cast<uint64_t>(n),
          static_cast<uint64_t>(fx.eval(static_cast<noise::TextureMode>(mode), n, x, y, z)) & out_mask};
      t->attach(w, trax::kTextureIn + trax::kTextureOut);
    }
  }
};
}  // namespace ru::render::kernel

namespace ru::trax {
namespace {

using num::Soft;

uint64_t align(uint64_t x, uint64_t a) { return (x + a - 1) / a * a; }

// Scene memory layout (byte addresses). A record's values are packed at `bits` each: value k of
// a record at byte base + floor(k x bits / 8) (chip.scene_storage = "format": bits = the format's
// width; "word": bits = 32 (64 above 32-bit formats), every value in its own word).
//   node i: lo.xyz, hi.xyz (6 values), header (8 B: left/right or first/count, axis), parent
//     (8 B); "format": 4-byte aligned, "word": 16-byte aligned (the layout before issue 16)
//   triangle i: p0, p1, p2 (9 values, whole bytes) in leaf order; material j: c1, c2, freq
//   (7 values, stride 8); camera/light: eye, c, u, v, light (15 values), the volume (12);
//   frame buffer: bytes_per_pixel per pixel
// A load is charged to the cache line of the value's first byte (a packed value that crosses a
// line boundary is not charged a second line).
struct Layout {
  uint64_t bits = 32, node_base = 0x1000000, node_bytes = 48, box_bytes = 24, tri_base = 0, tri_bytes = 36,
           mat_base = 0, cam_base = 0, fb_base = 0x80000000ull;
  uint64_t box_bits = 32;  // a node's box values (chip.box_format's width, else bits)
  void set(uint64_t value_bits, uint64_t box_value_bits, bool word) {
    bits = value_bits;
    box_bits = box_value_bits;
    box_bytes = (6 * box_bits + 7) / 8;
    node_bytes = align(box_bytes + 16, word ? 16 : 4);
    tri_bytes = bytes(9);
  }
  uint64_t bytes(int n) const { return (n * bits + 7) / 8; }             // n packed values, whole bytes
  uint64_t at(uint64_t base, int k) const { return base + k * bits / 8; }  // value k of a record
  uint64_t box_at(int64_t i, int k) const { return node(i) + k * box_bits / 8; }  // box value k of node i
  uint64_t node(int64_t i) const { return node_base + static_cast<uint64_t>(i) * node_bytes; }
  uint64_t header(int64_t i) const { return node(i) + box_bytes; }
  uint64_t parent(int64_t i) const { return node(i) + box_bytes + 8; }
  uint64_t tri(int64_t i) const { return tri_base + static_cast<uint64_t>(i) * tri_bytes; }
};

struct Ctx {
  const Config* cfg = nullptr;
  Layout L;
  bool stackless = false;
  std::vector<int32_t> parent;
  struct Entry {
    int32_t node;
    TVal t;
  };
  std::vector<Entry> stack;
  bool soft_noise = false;
  const noise::FixedNoise* fixed_noise = nullptr;  // the chip's noise unit model (chip.noise)
  const noise::FixedTexture* texture = nullptr;    // the chip's texture unit model (its noise datapath)
  uint64_t noise_table_base = 0;
  uint64_t visits = 0, up_steps = 0, soft_noise_evals = 0;
  uint32_t max_stack = 0;
};
Ctx* g_ctx = nullptr;  // the running kernel (one simulation at a time per process)

Thread& th() { return *Thread::current(); }
uint32_t use(const TVal& v) { return detail::use(v); }
Vec3<Soft> soft(const Vec3<TVal>& v) { return {v.x.v, v.y.v, v.z.v}; }

// BOX: 6 loads of the node's box (address from addr_reg), one ray-box instruction, a branch.
bool box(Tracer<TVal>& tr, const Ray& r, int32_t node, uint32_t addr_reg, const TVal& tmin, const TVal& tmax,
         TVal* te) {
  const Ctx& C = *g_ctx;
  ++tr.cnt.box;
  const NodeT<TVal>& n = tr.P.nodes[node];
  uint32_t s[14];
  for (int k = 0; k < 3; ++k) {
    s[k] = use(r.o[k]);
    s[3 + k] = use(r.inv[k]);
  }
  for (int k = 0; k < 6; ++k) s[6 + k] = th().mark_fp(th().load(C.L.box_at(node, k), addr_reg));
  s[12] = use(tmin);
  s[13] = use(tmax);
  const auto res = units::ray_box(soft(r.o), soft(r.inv), soft(n.lo), soft(n.hi), tmin.v, tmax.v, tr.opt.box);
  const uint32_t reg = th().mark_fp(th().emit(Op::Box, s, 14));  // hit and t_enter
  if (th().keep_operands()) {
    const uint64_t w[kBoxIn + kBoxOut] = {
        r.o.x.v.bits,  r.o.y.v.bits,  r.o.z.v.bits,  r.inv.x.v.bits, r.inv.y.v.bits, r.inv.z.v.bits, n.lo.x.v.bits,
        n.lo.y.v.bits, n.lo.z.v.bits, n.hi.x.v.bits, n.hi.y.v.bits,  n.hi.z.v.bits,  tmin.v.bits,    tmax.v.bits,
        res.hit,       res.t_enter.bits, res.t_exit.bits};
    th().attach(w, kBoxIn + kBoxOut);
  }
  th().emit(Op::Branch, {reg}, false);
  te->v = res.t_enter;
  te->reg = reg;
  te->addr = 0;
  return res.hit;
}

// TRI: 9 loads of the vertices, one ray-triangle instruction, a branch.
bool tri(Tracer<TVal>& tr, const Ray& r, uint32_t i, uint32_t addr_reg, const TVal& tmin, const TVal& tmax,
         TVal* t) {
  const Ctx& C = *g_ctx;
  ++tr.cnt.tri;
  const auto& T = tr.P.tris[i];
  uint32_t s[17];
  for (int k = 0; k < 3; ++k) {
    s[k] = use(r.o[k]);
    s[3 + k] = use(r.d[k]);
  }
  for (int k = 0; k < 9; ++k) s[6 + k] = th().mark_fp(th().load(C.L.at(C.L.tri(i), k), addr_reg));
  s[15] = use(tmin);
  s[16] = use(tmax);
  const units::TriResult<Soft> res =
      tr.opt.tri == render::TriAlgo::Robust
          ? units::ray_tri_robust(soft(r.o), soft(r.d), soft(T.p0), soft(T.p1), soft(T.p2), tmin.v, tmax.v)
          : units::ray_tri_mt(soft(r.o), soft(r.d), soft(T.p0), soft(T.p1), soft(T.p2), tmin.v, tmax.v);
  const bool hit = res.hit;
  const Soft th_ = res.t;
  const uint32_t reg = th().mark_fp(th().emit(Op::Tri, s, 17));  // hit and t
  if (th().keep_operands()) {
    const uint64_t w[kTriIn + kTriOut] = {
        r.o.x.v.bits,  r.o.y.v.bits,  r.o.z.v.bits,  r.d.x.v.bits,  r.d.y.v.bits,  r.d.z.v.bits,
        T.p0.x.v.bits, T.p0.y.v.bits, T.p0.z.v.bits, T.p1.x.v.bits, T.p1.y.v.bits, T.p1.z.v.bits,
        T.p2.x.v.bits, T.p2.y.v.bits, T.p2.z.v.bits, tmin.v.bits,   tmax.v.bits,   res.hit,
        static_cast<uint64_t>(res.why), res.t.bits, res.beta.bits, res.gamma.bits};
    th().attach(w, kTriIn + kTriOut);
  }
  th().emit(Op::Branch, {reg}, false);
  t->v = th_;
  t->reg = reg;
  t->addr = 0;
  return hit;
}

// Leaf: every triangle (loop counter, TRI, branch); closest hit updates tmax (any: first hit).
// Returns true when an any-hit query is answered.
bool leaf(Tracer<TVal>& tr, const Ray& r, const NodeT<TVal>& n, uint32_t hdr, const TVal& tmin, TVal& tmax,
          bool any, int64_t& hit, uint32_t& hit_reg) {
  uint32_t ireg = hdr;
  for (uint32_t i = n.first; i < n.first + n.count; ++i) {
    TVal t;
    const bool h = tri(tr, r, i, ireg, tmin, tmax, &t);
    if (h) {
      tmax = t;
      hit = i;
      hit_reg = th().emit(Op::Int, {ireg});
      if (any) return true;
    }
    ireg = th().emit(Op::Int, {ireg});  // next triangle
    th().emit(Op::Branch, {ireg}, false);
  }
  return false;
}

// The renderer's traversal (Tracer::intersect_impl), step for step, on the processor: a stack
// of (node, t_enter) entries in the local store.
int64_t traverse_stack(Tracer<TVal>& tr, const Ray& r, const TVal& tmin, TVal& tmax, bool any) {
  Ctx& C = *g_ctx;
  const auto& P = tr.P;
  int64_t hit = -1;
  uint32_t hit_reg = 0;
  size_t sp = 0;
  uint32_t sp_reg = 0;
  auto push = [&](int32_t node, const TVal& t, uint32_t node_reg) {
    if (C.stack.size() <= sp) C.stack.resize(sp + 1);
    C.stack[sp] = {node, t};
    th().emit(Op::StoreLocal, {t.reg, node_reg, sp_reg}, false, 8 * sp);
    sp_reg = th().emit(Op::Int, {sp_reg});
    ++sp;
    C.max_stack = std::max<uint32_t>(C.max_stack, static_cast<uint32_t>(sp));
  };
  TVal te;
  if (!box(tr, r, P.root, 0, tmin, tmax, &te)) return -1;
  push(P.root, te, 0);
  while (sp) {
    th().emit(Op::Branch, {sp_reg}, false);
    --sp;
    sp_reg = th().emit(Op::Int, {sp_reg});
    const Ctx::Entry e = C.stack[sp];
    const uint32_t e_reg = th().emit(Op::LoadLocal, {sp_reg}, true, 8 * sp);
    TVal et = e.t;
    et.reg = e_reg;
    if (hit >= 0) {
      th().emit(Op::Branch, {hit_reg}, false);
      if (tmax < et) continue;  // FCMP + branch
    }
    ++C.visits;
    const NodeT<TVal>& n = P.nodes[e.node];
    const uint32_t hdr = th().load(C.L.header(e.node), e_reg);
    th().emit(Op::Branch, {hdr}, false);  // leaf?
    if (n.left < 0) {
      if (leaf(tr, r, n, hdr, tmin, tmax, any, hit, hit_reg)) return hit;
      continue;
    }
    const uint32_t al = th().emit(Op::Int, {hdr}), ar = th().emit(Op::Int, {hdr});
    TVal tl, trr;
    const bool hl = box(tr, r, n.left, al, tmin, tmax, &tl);
    const bool hr = box(tr, r, n.right, ar, tmin, tmax, &trr);
    if (hl && hr) {
      const uint32_t sgn = th().emit(Op::Int, {hdr, use(r.d.x), use(r.d.y), use(r.d.z)});  // sign of d[axis]
      th().emit(Op::Branch, {sgn}, false);
      if (num::fp_signbit(r.d[n.axis].v)) {
        push(n.left, tl, al);
        push(n.right, trr, ar);
      } else {
        push(n.right, trr, ar);
        push(n.left, tl, al);
      }
    } else if (hl) {
      push(n.left, tl, al);
    } else if (hr) {
      push(n.right, trr, ar);
    }
  }
  return hit;
}

// Stackless bit-trail traversal (seed 003, SLBVH §1.4.2, on a pointer BVH with parent links):
// one trail bit per level, 1 = nothing left to visit on this level. Going down to the near
// child of two hit children leaves the bit 0; with one hit child it is set. Backtracking walks
// up (a parent-pointer load per step) while the bit is 1, then sets it and continues at the
// far sibling, whose box is tested again with the current tmax (that test fails exactly when
// the stack traversal would skip the popped entry: tmax < t_enter, see docs/TRAX.md), so the
// same triangles are tested in the same order as the renderer's traversal.
int64_t traverse_stackless(Tracer<TVal>& tr, const Ray& r, const TVal& tmin, TVal& tmax, bool any) {
  Ctx& C = *g_ctx;
  const auto& P = tr.P;
  int64_t hit = -1;
  uint32_t hit_reg = 0;
  TVal te;
  if (!box(tr, r, P.root, 0, tmin, tmax, &te)) return -1;
  int32_t node = P.root;
  uint32_t node_reg = 0, trail_reg = 0, level_reg = 0;
  int level = 0;
  uint64_t trail = 0;
  auto near_first = [&](const NodeT<TVal>& n) { return !num::fp_signbit(r.d[n.axis].v); };  // left is near
  for (;;) {
    ++C.visits;
    const NodeT<TVal>& n = P.nodes[node];
    const uint32_t hdr = th().load(C.L.header(node), node_reg);
    th().emit(Op::Branch, {hdr}, false);  // leaf?
    bool down = false;
    if (n.left < 0) {
      if (leaf(tr, r, n, hdr, tmin, tmax, any, hit, hit_reg)) return hit;
    } else {
      const uint32_t al = th().emit(Op::Int, {hdr}), ar = th().emit(Op::Int, {hdr});
      TVal tl, trr;
      const bool hl = box(tr, r, n.left, al, tmin, tmax, &tl);
      const bool hr = box(tr, r, n.right, ar, tmin, tmax, &trr);
      if (hl || hr) {
        down = true;
        ++level;
        level_reg = th().emit(Op::Int, {level_reg});
        if (hl && hr) {
          const uint32_t sgn = th().emit(Op::Int, {hdr, use(r.d.x), use(r.d.y), use(r.d.z)});
          th().emit(Op::Branch, {sgn}, false);
          const bool left_near = near_first(n);
          node = left_near ? n.left : n.right;
          node_reg = left_near ? al : ar;
        } else {
          node = hl ? n.left : n.right;
          node_reg = hl ? al : ar;
          trail |= 1ull << level;
          trail_reg = th().emit(Op::Int, {trail_reg, level_reg});
        }
      }
    }
    if (down) continue;
    // Backtrack to the next far sibling whose box is still hit.
    for (;;) {
      for (;;) {  // climb while this level has nothing left
        const uint32_t bit = th().emit(Op::Int, {trail_reg, level_reg});
        th().emit(Op::Branch, {bit}, false);
        if (level == 0) return hit;
        if (!((trail >> level) & 1)) break;
        trail &= ~(1ull << level);
        trail_reg = th().emit(Op::Int, {trail_reg, level_reg});
        node_reg = th().load(C.L.parent(node), node_reg);
        node = C.parent[node];
        --level;
        level_reg = th().emit(Op::Int, {level_reg});
        ++C.up_steps;
      }
      trail |= 1ull << level;
      trail_reg = th().emit(Op::Int, {trail_reg, level_reg});
      const int32_t par = C.parent[node];
      const uint32_t par_reg = th().load(C.L.parent(node), node_reg);
      const uint32_t phdr = th().load(C.L.header(par), par_reg);
      const NodeT<TVal>& pn = P.nodes[par];
      const int32_t sib = pn.left == node ? pn.right : pn.left;
      const uint32_t sib_reg = th().emit(Op::Int, {phdr, node_reg});
      node = sib;
      node_reg = sib_reg;
      if (box(tr, r, sib, sib_reg, tmin, tmax, &te)) break;  // else culled: its level is done
    }
  }
}

// The renderer's data in T = Soft, re-typed as TVal values tagged with their addresses.
Prepared<TVal> tag(const Prepared<Soft>& S, const Layout& L) {
  Prepared<TVal> P;
  auto val = [](Soft v, uint64_t addr) {
    TVal t;
    t.v = v;
    t.addr = addr;
    return t;
  };
  auto vec = [&](const Vec3<Soft>& v, uint64_t addr) {
    return Vec3<TVal>{val(v.x, L.at(addr, 0)), val(v.y, L.at(addr, 1)), val(v.z, L.at(addr, 2))};
  };
  auto at = [&](uint64_t base, int k) { return L.at(base, k); };
  P.tris.resize(S.tris.size());
  for (size_t i = 0; i < S.tris.size(); ++i) {
    const uint64_t a = L.tri(static_cast<int64_t>(i));
    P.tris[i] = {vec(S.tris[i].p0, a), vec(S.tris[i].p1, at(a, 3)), vec(S.tris[i].p2, at(a, 6))};
  }
  P.tri_mat = S.tri_mat;
  P.nodes.resize(S.nodes.size());
  for (size_t i = 0; i < S.nodes.size(); ++i) {
    const auto& s = S.nodes[i];
    auto& n = P.nodes[i];
    n.lo = {val(s.lo.x, L.box_at(i, 0)), val(s.lo.y, L.box_at(i, 1)), val(s.lo.z, L.box_at(i, 2))};
    n.hi = {val(s.hi.x, L.box_at(i, 3)), val(s.hi.y, L.box_at(i, 4)), val(s.hi.z, L.box_at(i, 5))};
    n.left = s.left;
    n.right = s.right;
    n.first = s.first;
    n.count = s.count;
    n.axis = s.axis;
  }
  P.root = S.root;
  P.depth = S.depth;
  for (size_t m = 0; m < S.mats.size(); ++m) {
    const uint64_t a = at(L.mat_base, static_cast<int>(8 * m));
    P.mats.push_back({S.mats[m].kind, vec(S.mats[m].c1, a), vec(S.mats[m].c2, at(a, 3)), val(S.mats[m].freq, at(a, 6)),
                      S.mats[m].octaves});
  }
  P.eye = vec(S.eye, L.cam_base);
  P.c = vec(S.c, at(L.cam_base, 3));
  P.u = vec(S.u, at(L.cam_base, 6));
  P.v = vec(S.v, at(L.cam_base, 9));
  P.light = vec(S.light, at(L.cam_base, 12));
  if (S.has_volume) {  // the volume (Fig. 4.1's smoke) after the camera: 12 words
    const uint64_t a = at(L.cam_base, 15);
    P.has_volume = true;
    P.vol = {vec(S.vol.lo, a), vec(S.vol.hi, at(a, 3)), vec(S.vol.color, at(a, 6)), val(S.vol.freq, at(a, 9)),
             val(S.vol.density, at(a, 10)), val(S.vol.bias, at(a, 11)), val(S.vol.inv_steps, 0), S.vol.steps,
             S.vol.octaves};
  }
  // Scalar constants are immediates.
  for (auto [dst, src] : {std::pair{&P.eps, &S.eps}, {&P.shadow_min, &S.shadow_min}, {&P.shadow_max, &S.shadow_max},
                          {&P.ka, &S.ka}, {&P.kd, &S.kd}, {&P.zero, &S.zero}, {&P.one, &S.one}, {&P.half, &S.half},
                          {&P.two, &S.two}})
    *dst = val(*src, 0);
  return P;
}

class RenderWork : public WorkSource {
 public:
  RenderWork(Tracer<TVal>& tr, const Layout& L, const Config& c, render::Image& img)
      : tr_(tr), L_(L), cfg_(c), img_(img) {}
  uint64_t items() const override { return static_cast<uint64_t>(img_.width) * img_.height; }
  void generate(uint64_t item, Thread& t) override {
    const int x = static_cast<int>(item % img_.width), y = static_cast<int>(item / img_.width);
    // Pixel coordinates from the work item: y = item / W, x = item - y W, converted to float.
    const uint32_t ry = t.emit(Op::Int, {Thread::kItemReg});
    const uint32_t rx = t.emit(Op::Int, {Thread::kItemReg, ry});
    TVal px, py;
    px.v = Soft::from_double(x + 0.5);
    py.v = Soft::from_double(y + 0.5);
    px.reg = t.mark_fp(t.emit(Op::Conv, {rx}));
    py.reg = t.mark_fp(t.emit(Op::Conv, {ry}));
    const Vec3<TVal> d = tr_.primary_dir(px, py);
    const Vec3<TVal> c = tr_.shade_pixel(d);
    // Clamp to [0, 1] (max, min) and convert to 8 bits per channel; one frame-buffer store.
    uint32_t ch[3];
    float* out = img_.at(x, y);
    for (int k = 0; k < 3; ++k) {
      out[k] = render::kernel::pixel_value(c[k].v.to_double());
      const TVal zero = num::fp_cast<TVal>(0.0), one = num::fp_cast<TVal>(1.0);  // immediates
      const TVal clamped = fp_min(fp_max(c[k], zero), one);                       // two FCmp (max, min)
      ch[k] = t.emit(Op::Conv, {clamped.reg});
    }
    t.emit(Op::Store, {ch[0], ch[1], ch[2]}, false, L_.fb_base + item * cfg_.framebuffer_bytes_per_pixel);
  }

 private:
  Tracer<TVal>& tr_;
  const Layout& L_;
  const Config& cfg_;
  render::Image& img_;
};

// The primary / shadow / diffuse-bounce workloads of the ray-coherence study (RunOptions).
class RayWork : public WorkSource {
 public:
  RayWork(Tracer<TVal>& tr, const Layout& L, const Config& c, render::Image& img, const std::string& mode)
      : tr_(tr), L_(L), cfg_(c), img_(img), mode_(mode) {}
  uint64_t items() const override { return static_cast<uint64_t>(img_.width) * img_.height; }
  uint64_t primary = 0, shadow = 0, bounce = 0;
  void generate(uint64_t item, Thread& t) override {
    const auto& P = tr_.P;
    const int x = static_cast<int>(item % img_.width), y = static_cast<int>(item / img_.width);
    const uint32_t ry = t.emit(Op::Int, {Thread::kItemReg});
    const uint32_t rx = t.emit(Op::Int, {Thread::kItemReg, ry});
    TVal px, py;
    px.v = Soft::from_double(x + 0.5);
    py.v = Soft::from_double(y + 0.5);
    px.reg = t.mark_fp(t.emit(Op::Conv, {rx}));
    py.reg = t.mark_fp(t.emit(Op::Conv, {ry}));
    const Vec3<TVal> d = tr_.primary_dir(px, py);
    ++primary;
    const Ray r = tr_.make_ray(P.eye, d);
    TVal tt = num::fp_cast<TVal>(HUGE_VAL);
    const int64_t hit = tr_.intersect(r, P.eps, tt, false);
    float* out = img_.at(x, y);
    out[0] = out[1] = out[2] = hit >= 0 ? 1.0f : 0.0f;
    uint32_t res = t.emit(Op::Int, {use(tt)});
    if (hit >= 0 && mode_ != "primary") {
      const Vec3<TVal> p = tr_.vmadd(r.d, tt, r.o);
      TVal tmax;
      if (mode_ == "shadow") {
        ++shadow;
        const Vec3<TVal> ld = units::vsub(P.light, p);
        const Ray s = tr_.make_ray(p, ld);
        tmax = P.shadow_max;
        tr_.intersect(s, P.shadow_min, tmax, true);
      } else {
        ++bounce;
        const auto& T = P.tris[hit];
        Vec3<TVal> N = tr_.cross(units::vsub(T.p1, T.p0), units::vsub(T.p2, T.p0));
        if (P.zero < tr_.dot(N, r.d)) N = render::kernel::vneg(N);
        // a per-pixel pseudo-random unit vector (immediates: a hardware random source)
        uint64_t h = (item + 1) * 0x9E3779B97F4A7C15ull;
        double v[3], n2 = 0;
        for (double& c : v) {
          h ^= h >> 29;
          h *= 0xBF58476D1CE4E5B9ull;
          c = double(h >> 11) / double(1ull << 53) * 2.0 - 1.0;
          n2 += c * c;
        }
        Vec3<TVal> rv;
        for (int k = 0; k < 3; ++k) rv[k] = num::fp_cast<TVal>(v[k] / std::sqrt(n2 > 0 ? n2 : 1.0));
        // direction = N / |N| + rv (cosine-like lobe), folded into the hemisphere of N
        const TVal inv_len = P.one / fp_sqrt(tr_.dot(N, N));
        Vec3<TVal> dir = tr_.vmadd(N, inv_len, rv);
        if (!(P.zero < tr_.dot(dir, N))) dir = N;
        const Ray b = tr_.make_ray(p, dir);
        tmax = num::fp_cast<TVal>(HUGE_VAL);
        tr_.intersect(b, P.shadow_min, tmax, false);
      }
      res = t.emit(Op::Int, {res, use(tmax)});
    }
    t.emit(Op::Store, {res}, false, L_.fb_base + item * cfg_.framebuffer_bytes_per_pixel);
  }

 private:
  Tracer<TVal>& tr_;
  const Layout& L_;
  const Config& cfg_;
  render::Image& img_;
  std::string mode_;
};

}  // namespace

bool software_noise() { return g_ctx && g_ctx->soft_noise; }

const noise::FixedNoise& chip_noise() { return *g_ctx->fixed_noise; }
const noise::FixedTexture& chip_texture() { return *g_ctx->texture; }

// Software noise on the TPs (RunOptions::software_noise): the instruction sequence of the
// hardware unit's algorithm (docs/NOISE.md steps (1)-(13)) in the chip's FP format, with its
// dependencies and its table loads at the addresses the evaluation really uses (per-axis hash
// tables of 256 entries, 64-entry gradient table; FixedTrace gives the indices). The value is
// the hardware model's (timing only: a software version in the format would not give its bits).
//   per axis: u = 0.5 q (FMUL), floor (2 CONV), f = u - floor (FADD), 1 - f (FADD), squares
//             f^2, (1-f)^2 (2 FMUL), cell and cell + 1 (2 INT), two hash loads
//   per corner (8): hash xor (2 INT), 3 gradient loads, d = sum of squares (2 FADD),
//             t = 1 - d (FADD), t > 0 (FCMP + BRANCH), t^2, t^4, t^5 (3 FMUL),
//             w = 4 t^5 - 3 t^4 (2 FMUL + FADD), dot = offset . g (3 FMUL + 2 FADD),
//             w * dot (FMUL), running sum (FADD)
//   scale to the output (FMUL)
uint32_t emit_software_noise(Thread& t, const Vec3<TVal>& q) {
  Ctx& C = *g_ctx;
  ++C.soft_noise_evals;
  const noise::FixedNoise& fx = chip_noise();
  noise::FixedTrace tr{};
  fx.eval(fx.quantize(0.5 * q.x.v.to_double()), fx.quantize(0.5 * q.y.v.to_double()),
          fx.quantize(0.5 * q.z.v.to_double()), &tr);
  const uint64_t hash_base = C.noise_table_base, grad_base = C.noise_table_base + 3 * 256 * 4;
  uint32_t f[3], om[3], sq0[3], sq1[3], h0[3], h1[3];
  for (int a = 0; a < 3; ++a) {
    const uint32_t u = t.emit(Op::FMul, {use(q[a])});
    const uint32_t fl = t.emit(Op::Conv, {t.emit(Op::Conv, {u})});
    f[a] = t.emit(Op::FAdd, {u, fl});
    om[a] = t.emit(Op::FAdd, {f[a]});
    sq0[a] = t.emit(Op::FMul, {f[a], f[a]});
    sq1[a] = t.emit(Op::FMul, {om[a], om[a]});
    const uint32_t cell = t.emit(Op::Int, {fl});
    const uint32_t cell1 = t.emit(Op::Int, {cell});
    h0[a] = t.load(hash_base + (a * 256 + static_cast<uint64_t>(tr.cell[a])) * 4, cell);
    h1[a] = t.load(hash_base + (a * 256 + static_cast<uint64_t>((tr.cell[a] + 1) & 255)) * 4, cell1);
  }
  uint32_t sum = 0;
  for (int c = 0; c < 8; ++c) {
    const int bx = c & 1, by = (c >> 1) & 1, bz = (c >> 2) & 1;
    const uint32_t hx = bx ? h1[0] : h0[0], hy = by ? h1[1] : h0[1], hz = bz ? h1[2] : h0[2];
    const uint32_t hh = t.emit(Op::Int, {t.emit(Op::Int, {hx, hy}), hz});
    uint32_t g[3];
    for (int k = 0; k < 3; ++k) g[k] = t.load(grad_base + (static_cast<uint64_t>(tr.h[c]) * 3 + k) * 4, hh);
    const uint32_t d = t.emit(Op::FAdd, {t.emit(Op::FAdd, {bx ? sq1[0] : sq0[0], by ? sq1[1] : sq0[1]}),
                                         bz ? sq1[2] : sq0[2]});
    const uint32_t tt = t.emit(Op::FAdd, {d});
    t.emit(Op::Branch, {t.emit(Op::FCmp, {tt})}, false);
    const uint32_t t2 = t.emit(Op::FMul, {tt, tt});
    const uint32_t t4 = t.emit(Op::FMul, {t2, t2});
    const uint32_t t5 = t.emit(Op::FMul, {t4, tt});
    const uint32_t w = t.emit(Op::FAdd, {t.emit(Op::FMul, {t5}), t.emit(Op::FMul, {t4})});
    const uint32_t ox = bx ? om[0] : f[0], oy = by ? om[1] : f[1], oz = bz ? om[2] : f[2];
    const uint32_t dot = t.emit(Op::FAdd, {t.emit(Op::FAdd, {t.emit(Op::FMul, {ox, g[0]}), t.emit(Op::FMul, {oy, g[1]})}),
                                           t.emit(Op::FMul, {oz, g[2]})});
    const uint32_t contrib = t.emit(Op::FMul, {w, dot});
    sum = sum ? t.emit(Op::FAdd, {sum, contrib}) : contrib;
  }
  return t.emit(Op::FMul, {sum});
}

int64_t traverse(Tracer<TVal>& tr, const Ray& r, const TVal& tmin, TVal& tmax, bool any) {
  return g_ctx->stackless ? traverse_stackless(tr, r, tmin, tmax, any) : traverse_stack(tr, r, tmin, tmax, any);
}

render::RenderOptions render_options(const Config& c, int width, int height) {
  render::RenderOptions o;
  o.width = width;
  o.height = height;
  o.format = c.format == "float" ? "e8m23" : c.format;
  o.tri = render::parse_tri(c.tri);
  o.box = render::parse_box(c.box);
  o.bvh = render::parse_bvh(c.bvh);
  o.noise = render::parse_noise(c.noise);
  o.texture = render::parse_texture(c.texture);
  o.leaf_size = c.leaf_size;
  o.box_format = c.box_format;
  o.fma = c.fma;
  o.shadows = true;
  o.threads = 1;
  return o;
}

TraxResult run_trax(const scene::Scene& s, const Config& c, int width, int height, bool progress,
                    IssueObserver* observer) {
  RunOptions ro;
  ro.progress = progress;
  ro.observer = observer;
  return run_trax(s, c, width, height, ro);
}

TraxResult run_trax(const scene::Scene& s, const Config& c_in, int width, int height, const RunOptions& ro) {
  c_in.validate();
  if (ro.workload != "render" && ro.workload != "primary" && ro.workload != "shadow" && ro.workload != "diffuse")
    throw std::invalid_argument("unknown workload '" + ro.workload + "' (accepted: render, primary, shadow, diffuse)");
  std::vector<AreaSource> sources;
  const Config c = resolve_config(c_in, &sources);
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw std::invalid_argument("image size must be between 1x1 and 16384x16384");
  if (s.tris.empty()) throw std::invalid_argument("scene '" + s.name + "' has no triangles");
  const render::RenderOptions opt = render_options(c, width, height);
  const num::Format fmt = num::Format::parse(opt.format);
  num::SoftScope scope(fmt);

  TraxResult R;
  R.cfg = c;
  R.area_sources = sources;
  render::RenderStats rst;
  const Prepared<Soft> S = render::kernel::prepare<Soft>(s, opt, &rst);
  R.bvh_nodes = S.nodes.size();
  R.bvh_depth = S.depth;

  Ctx C;
  C.cfg = &c;
  C.stackless = c.traversal == "stackless";
  if (C.stackless && S.depth > 63)
    throw std::invalid_argument("stackless traversal: BVH depth " + std::to_string(S.depth) + " exceeds the 63-bit trail");
  Layout& L = C.L;
  const bool word = c.scene_storage == "word";
  const uint64_t vbits = word ? 8 * static_cast<uint64_t>(c.value_bytes()) : static_cast<uint64_t>(c.value_bits());
  L.set(vbits, word || c.box_format.empty() ? vbits : static_cast<uint64_t>(num::Format::parse(c.box_format).width()), word);
  L.tri_base = align(L.node(static_cast<int64_t>(S.nodes.size())), 4096);
  L.mat_base = align(L.tri(static_cast<int64_t>(S.tris.size())), 4096);
  L.cam_base = align(L.at(L.mat_base, static_cast<int>(8 * S.mats.size())), 4096);
  R.value_bits = L.bits;
  R.node_bytes = L.node_bytes;
  R.tri_bytes = L.tri_bytes;
  C.soft_noise = ro.software_noise;
  // the model the renderer's Tracer evaluates too (the same default_config of the datapath)
  static const noise::FixedNoise kTrunc{noise::default_config(noise::NoiseDatapath::kTrunc)},
      kFull{noise::default_config(noise::NoiseDatapath::kFull)};
  C.fixed_noise = c.noise == "fixed" ? &kFull : &kTrunc;
  static const noise::FixedTexture kTexTrunc{render::texture_config(render::NoiseMode::FixedTrunc)},
      kTexFull{render::texture_config(render::NoiseMode::Fixed)};
  C.texture = c.noise == "fixed" ? &kTexFull : &kTexTrunc;
  C.noise_table_base = align(L.at(L.cam_base, 27), 4096);  // camera 15 values, volume 12
  C.parent.assign(S.nodes.size(), -1);
  for (size_t i = 0; i < S.nodes.size(); ++i)
    if (S.nodes[i].left >= 0) {
      C.parent[S.nodes[i].left] = static_cast<int32_t>(i);
      C.parent[S.nodes[i].right] = static_cast<int32_t>(i);
    }
  const Prepared<TVal> P = tag(S, L);

  R.image.width = width;
  R.image.height = height;
  R.image.rgb.assign(static_cast<size_t>(width) * height * 3, 0.0f);
  Tracer<TVal> tracer(P, opt);
  RenderWork work(tracer, L, c, R.image);
  RayWork rays(tracer, L, c, R.image, ro.workload);
  WorkSource& ws = ro.workload == "render" ? static_cast<WorkSource&>(work) : rays;
  Ctx* saved = g_ctx;
  g_ctx = &C;
  try {
    R.sim = simulate(c, ws, ro.progress, ro.observer);
  } catch (...) {
    g_ctx = saved;
    throw;
  }
  g_ctx = saved;
  R.primary_rays = tracer.cnt.primary + rays.primary;
  R.shadow_rays = tracer.cnt.shadow + rays.shadow;
  R.bounce_rays = rays.bounce;
  R.software_noise_evals = C.soft_noise_evals;
  R.box_tests = tracer.cnt.box;
  R.tri_tests = tracer.cnt.tri;
  R.noise_evals = tracer.cnt.noise;
  R.texture_evals = tracer.cnt.texture;
  R.shading_samples = tracer.cnt.shading;
  R.node_visits = C.visits;
  R.up_steps = C.up_steps;
  R.max_stack = C.max_stack;
  R.area = area_estimate(c, R.sim, &sources);
  R.energy = energy_estimate(c, R.sim);
  if (c_in.clock_mhz == kClockSta) {
    // The clock of the chip that is built: the units the kernel used (the area model charges
    // exactly those), each at its STA Fmax; cycles do not depend on the clock.
    std::vector<bool> used(kUnits);
    for (int u = 0; u < kUnits; ++u) used[u] = R.sim.unit_ops[u] > 0;
    R.clock = sta_clock(c, sources, used);
    R.cfg.clock_mhz = R.clock.mhz;
  } else {
    R.clock.mhz = c.clock_mhz;
    R.clock.how = "configured (chip.clock_mhz)";
  }
  return R;
}

}  // namespace ru::trax
