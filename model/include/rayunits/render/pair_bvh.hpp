// The native (float / double) renderer's node layout and its packet box test (issue 6 §6,
// speed). Internal to the model library: not a stable API.
//
// Layout: the renderer's traversal tests both children of every interior node it visits, so
// the children's boxes are stored together in their parent, one cache line per node for float:
//     b[k] = { lo_k(left), lo_k(right), hi_k(left), hi_k(right) }     k = x, y, z
// Test: packet_box_test() runs the ray-box unit's dataflow (units/ray_box.hpp) for one child
// and four rays, one ray per vector lane. It gives the golden model's bits in every lane it
// decides, by the argument of units::detail::ray_box_native_plain, lane by lane:
//   * each lane is the model's two IEEE operations (plane - o_k) * inv_k in the same order
//     (lanes are independent scalar operations; the build uses -ffp-contract=off);
//   * a lane with no NaN among its six products has no NaN among its o, inv, lo, hi (each
//     enters one of them), so the model's any_nan is false and minNum/maxNum see no NaN
//     (t_min and t_max are checked once per packet by the caller);
//   * without NaNs min/max are associative and commutative in the total order -0 < +0, and a
//     nonzero extreme has a single bit pattern, so "a > b ? a : b" (maxps) gives the model's
//     bits; only a zero extreme could differ in sign;
//   * hit: the same three comparisons on the same values.
// Lanes with a NaN product or a zero enter / exit are handed back (*bad) and the caller asks
// the golden model. tests/render (PacketTraversal.*) checks the packet traversal against the
// one-ray traversal on every ray, special values included.
#pragma once
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

namespace ru::render::kernel {

// A child reference: a leaf (cnt > 0: triangles [idx, idx + cnt) in leaf order) or an
// interior node (cnt == 0: idx is its PairNode).
struct Kid {
  int32_t idx = 0;
  uint32_t cnt = 0;
};

// 64 bytes for float (one cache line), 128 for double.
template <class T>
struct alignas(64) PairNode {
  T b[3][4];              // per axis: lo(L), lo(R), hi(L), hi(R)
  int32_t idx[2];         // left, right: Kid::idx
  uint8_t cnt[2] = {0, 0};  // Kid::cnt (leaves hold at most 64 triangles)
  uint8_t axis = 0;       // split axis (visit order)
  Kid kid(int c) const { return {idx[c], cnt[c]}; }
  void set_kid(int c, Kid k) {
    idx[c] = k.idx;
    cnt[c] = static_cast<uint8_t>(k.cnt);
  }
};
static_assert(sizeof(PairNode<float>) == 64, "one cache line");


// Four rays, one per lane (packets of render/tracer.hpp: Tracer::packet_traverse). VecOf<T> is
// the 4-lane vector for native T and a placeholder otherwise (so that the tracer's members
// can name it for every arithmetic type).
template <class T, bool = std::is_arithmetic_v<T>>
struct VecOf {
  struct type {};
};
template <class T>
struct VecOf<T, true> {
  typedef T type __attribute__((vector_size(4 * sizeof(T))));
};

template <class T>
struct PacketRays {
  typedef typename VecOf<T>::type VT;
  VT o[3], inv[3], t_min, t_max;
  template <class V>
  void set(int j, const V& o_, const V& inv_, T tmin, T tmax) {
    for (int k = 0; k < 3; ++k) {
      o[k][j] = o_[k];
      inv[k][j] = inv_[k];
    }
    t_min[j] = tmin;
    t_max[j] = tmax;
  }
};

template <class VT>
inline unsigned lane_mask(const VT& m) {
#if defined(__SSE__)
  if constexpr (sizeof(VT) == 16) {
    typedef float V4 __attribute__((vector_size(16)));
    return static_cast<unsigned>(__builtin_ia32_movmskps(reinterpret_cast<V4>(m)));
  } else
#endif
  {
    return (m[0] ? 1u : 0u) | (m[1] ? 2u : 0u) | (m[2] ? 4u : 0u) | (m[3] ? 8u : 0u);
  }
}

// Lanes where a < b.
template <class VT>
inline unsigned packet_lt_mask(const VT& a, const VT& b) {
  return lane_mask(a < b);
}

// Child c of n against the four rays, the unit's dataflow in every lane:
//   tn_k = (near_k - o_k) * inv_k,  tf_k = (far_k - o_k) * inv_k   (near/far: the mux by Oct)
//   enter = max(max(max(t_min, tn_x), tn_y), tn_z),  exit = min(min(min(t_max, tf_x), tf_y), tf_z)
//   hit = enter <= exit & enter != +INF & exit != -INF
// Returns the hit mask among `active`; *bad = the active lanes where a tn/tf is a NaN or enter /
// exit is a zero (the golden model decides those: see the argument at the top, lane by lane).
template <class T, int Oct>
inline unsigned packet_box_test(const PairNode<T>& n, int c, const PacketRays<T>& r, unsigned active,
                                typename PacketRays<T>::VT* t_enter, unsigned* bad) {
  typedef typename PacketRays<T>::VT VT;
  VT tn[3], tf[3];
  for (int k = 0; k < 3; ++k) {
    const bool neg = (Oct >> k) & 1;
    const T nearp = n.b[k][neg ? c + 2 : c], farp = n.b[k][neg ? c : c + 2];
    tn[k] = ((VT{} + nearp) - r.o[k]) * r.inv[k];
    tf[k] = ((VT{} + farp) - r.o[k]) * r.inv[k];
  }
  VT en = r.t_min > tn[0] ? r.t_min : tn[0];
  en = en > tn[1] ? en : tn[1];
  en = en > tn[2] ? en : tn[2];
  VT ex = r.t_max < tf[0] ? r.t_max : tf[0];
  ex = ex < tf[1] ? ex : tf[1];
  ex = ex < tf[2] ? ex : tf[2];
  constexpr T inf = std::numeric_limits<T>::infinity();
  const auto nan = (tn[0] != tn[0]) | (tn[1] != tn[1]) | (tn[2] != tn[2]) | (tf[0] != tf[0]) | (tf[1] != tf[1]) |
                   (tf[2] != tf[2]) | (en == T(0)) | (ex == T(0));
  const auto hit = (en <= ex) & (en != inf) & (ex != -inf);
  *t_enter = en;
  const unsigned b = lane_mask(nan) & active;
  *bad = b;
  return lane_mask(hit) & active & ~b;
}

// Builds the pair layout from the renderer's nodes (NodeT<T>: lo, hi, left, right, first,
// count, axis), interior nodes in depth-first order (a node's left child's pair follows it).
// Returns false (out empty) when the tree has an empty leaf, which Kid cannot encode: the
// traversal then takes the generic path.
template <class T, class Node>
bool build_pairs(const std::vector<Node>& nodes, int32_t root, std::vector<PairNode<T>>* out, Kid* root_out) {
  out->clear();
  if (nodes.empty()) return false;
  for (const Node& n : nodes)
    if (n.left < 0 && n.count == 0) return false;
  auto kid_of = [&](int32_t id) -> Kid {
    const Node& n = nodes[id];
    if (n.left < 0) return {static_cast<int32_t>(n.first), n.count};
    return {-1, 0};  // filled in when the node's pair is emitted
  };
  Kid& root_kid = *root_out;
  root_kid = kid_of(root);
  if (nodes[root].left < 0) return true;
  // Iterative pre-order: emit a pair, then its left subtree, then its right subtree.
  struct Item {
    int32_t id;
    int32_t parent_pair;
    int side;
  };
  std::vector<Item> st{{root, -1, 0}};
  while (!st.empty()) {
    const Item it = st.back();
    st.pop_back();
    const Node& n = nodes[it.id];
    const int32_t me = static_cast<int32_t>(out->size());
    out->emplace_back();
    if (it.parent_pair >= 0) (*out)[it.parent_pair].set_kid(it.side, {me, 0});
    else root_kid = {me, 0};
    PairNode<T>& p = out->back();
    p.axis = n.axis;
    const Node* ch[2] = {&nodes[n.left], &nodes[n.right]};
    for (int k = 0; k < 3; ++k) {
      p.b[k][0] = ch[0]->lo[k];
      p.b[k][1] = ch[1]->lo[k];
      p.b[k][2] = ch[0]->hi[k];
      p.b[k][3] = ch[1]->hi[k];
    }
    const int32_t kids[2] = {n.left, n.right};
    for (int c = 1; c >= 0; --c) {  // right pushed first: left emitted next
      if (nodes[kids[c]].left < 0) p.set_kid(c, kid_of(kids[c]));
      else st.push_back({kids[c], me, c});
    }
  }
  return true;
}

}  // namespace ru::render::kernel
