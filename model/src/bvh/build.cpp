// BVH construction (binned SAH, Mirth median split), SAH cost, refit, validation.
#include <algorithm>
#include <cmath>
#include <functional>

#include "rayunits/bvh/bvh.hpp"
#include "rayunits/bvh/median.hpp"

namespace ru::bvh {

std::vector<Aabb> triangle_boxes(const scene::Scene& s) {
  std::vector<Aabb> out(s.tris.size());
  for (size_t i = 0; i < s.tris.size(); ++i)
    for (const auto& p : s.tris[i].p) out[i].grow(p);
  return out;
}

int Bvh::depth() const {
  if (nodes.empty()) return 0;
  int best = 0;
  std::vector<std::pair<int32_t, int>> st{{root, 1}};
  while (!st.empty()) {
    auto [n, d] = st.back();
    st.pop_back();
    best = std::max(best, d);
    if (!nodes[n].leaf()) {
      st.push_back({nodes[n].left, d + 1});
      st.push_back({nodes[n].right, d + 1});
    }
  }
  return best;
}

size_t Bvh::leaf_count() const {
  size_t c = 0;
  std::vector<int32_t> st{root};
  while (!st.empty()) {
    int32_t n = st.back();
    st.pop_back();
    if (nodes[n].leaf()) ++c;
    else {
      st.push_back(nodes[n].left);
      st.push_back(nodes[n].right);
    }
  }
  return c;
}

namespace {

struct SahBuilder {
  const std::vector<Aabb>& pb;
  const BuildOptions& opt;
  std::vector<Vec3> cent;
  Bvh b;

  struct Bin {
    Aabb box;
    uint32_t n = 0;
  };

  void make_leaf(int32_t node, uint32_t first, uint32_t last) {
    b.nodes[node].first = first;
    b.nodes[node].count = last - first;
  }

  void run() {
    const uint32_t n = static_cast<uint32_t>(pb.size());
    cent.resize(n);
    for (uint32_t i = 0; i < n; ++i) cent[i] = (pb[i].lo + pb[i].hi) * 0.5;
    b.prims.resize(n);
    for (uint32_t i = 0; i < n; ++i) b.prims[i] = i;
    b.nodes.push_back(Node{});
    if (n == 0) return;
    struct Job { int32_t node; uint32_t first, last; };
    std::vector<Job> stack{{0, 0, n}};
    const int nb = std::max(2, opt.bins);
    std::vector<Bin> bins(nb);
    std::vector<Aabb> right_box(nb);
    std::vector<uint32_t> right_n(nb);
    while (!stack.empty()) {
      Job j = stack.back();
      stack.pop_back();
      Aabb box, cbox;
      for (uint32_t i = j.first; i < j.last; ++i) {
        box.grow(pb[b.prims[i]]);
        cbox.grow(cent[b.prims[i]]);
      }
      b.nodes[j.node].box = box;
      const uint32_t count = j.last - j.first;
      if (count <= 1) {
        make_leaf(j.node, j.first, j.last);
        continue;
      }
      const double area = box.area();
      double best_cost = HUGE_VAL;
      int best_axis = -1, best_plane = 0;
      for (int axis = 0; axis < 3; ++axis) {
        const double lo = cbox.lo[axis], ext = cbox.hi[axis] - lo;
        if (!(ext > 0)) continue;
        for (auto& bn : bins) bn = Bin{};
        const double k = nb / ext;
        for (uint32_t i = j.first; i < j.last; ++i) {
          int bi = std::min(nb - 1, static_cast<int>((cent[b.prims[i]][axis] - lo) * k));
          bins[bi].box.grow(pb[b.prims[i]]);
          ++bins[bi].n;
        }
        Aabb acc;
        uint32_t accn = 0;
        for (int i = nb - 1; i > 0; --i) {
          acc.grow(bins[i].box);
          accn += bins[i].n;
          right_box[i] = acc;
          right_n[i] = accn;
        }
        Aabb left;
        uint32_t ln = 0;
        for (int i = 1; i < nb; ++i) {
          left.grow(bins[i - 1].box);
          ln += bins[i - 1].n;
          if (ln == 0 || right_n[i] == 0) continue;
          double c = left.area() * ln + right_box[i].area() * right_n[i];
          if (c < best_cost) {
            best_cost = c;
            best_axis = axis;
            best_plane = i;
          }
        }
      }
      const double leaf_cost = opt.sah.ci * count;
      const double split_cost =
          best_axis < 0 ? HUGE_VAL : opt.sah.ct + opt.sah.ci * (area > 0 ? best_cost / area : 0.0);
      if (static_cast<int>(count) <= opt.max_leaf && leaf_cost <= split_cost) {
        make_leaf(j.node, j.first, j.last);
        continue;
      }
      uint32_t split;
      int axis = best_axis;
      if (best_axis >= 0) {
        const double lo = cbox.lo[axis], k = nb / (cbox.hi[axis] - lo);
        auto it = std::partition(b.prims.begin() + j.first, b.prims.begin() + j.last, [&](uint32_t t) {
          return std::min(nb - 1, static_cast<int>((cent[t][axis] - lo) * k)) < best_plane;
        });
        split = static_cast<uint32_t>(it - b.prims.begin());
      } else {  // all centroids coincide: halve the list
        axis = 0;
        split = (j.first + j.last) / 2;
      }
      if (split == j.first || split == j.last) split = (j.first + j.last) / 2;
      const int32_t l = static_cast<int32_t>(b.nodes.size());
      b.nodes.push_back(Node{});
      b.nodes.push_back(Node{});
      b.nodes[j.node].left = l;
      b.nodes[j.node].right = l + 1;
      b.nodes[j.node].axis = static_cast<uint8_t>(axis);
      stack.push_back({l + 1, split, j.last});
      stack.push_back({l, j.first, split});
    }
  }
};

}  // namespace

Bvh build_sah(const std::vector<Aabb>& prim_boxes, const BuildOptions& opt) {
  SahBuilder sb{prim_boxes, opt, {}, {}};
  sb.run();
  return std::move(sb.b);
}

Bvh build_median(const scene::Scene& s, int max_tris_per_leaf) {
  std::vector<std::array<double, 9>> v(s.tris.size());
  for (size_t i = 0; i < s.tris.size(); ++i)
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) v[i][3 * k + c] = s.tris[i].p[k][c];
  return build_median_generic(v, max_tris_per_leaf, [](double x) { return x; }, [](double x) { return x; });
}

double sah_cost(const Bvh& b, const SahParams& p) {
  if (b.nodes.empty()) return 0.0;
  // Weighted cost w = S * C: leaf S (Ct + Ci N); interior Ct S + w_L + w_R. C_root = w / S.
  std::function<double(int32_t)> w = [&](int32_t n) -> double {
    const Node& nd = b.nodes[n];
    if (nd.leaf()) return nd.box.area() * (p.ct + p.ci * nd.count);
    return p.ct * nd.box.area() + w(nd.left) + w(nd.right);
  };
  const double s = b.nodes[b.root].box.area();
  const double total = w(b.root);
  return s > 0 ? total / s : p.ct + p.ci * b.nodes[b.root].count;
}

void refit(Bvh& b, const std::vector<Aabb>& prim_boxes) {
  std::function<void(int32_t)> rec = [&](int32_t n) {
    Node& nd = b.nodes[n];
    Aabb box;
    if (nd.leaf()) {
      for (uint32_t i = 0; i < nd.count; ++i) box.grow(prim_boxes[b.prims[nd.first + i]]);
    } else {
      rec(nd.left);
      rec(nd.right);
      box = merge(b.nodes[nd.left].box, b.nodes[nd.right].box);
    }
    b.nodes[n].box = box;
  };
  if (!b.nodes.empty()) rec(b.root);
}

std::string validate(const Bvh& b, const std::vector<Aabb>& prim_boxes) {
  if (b.nodes.empty()) return "no nodes";
  std::vector<int> seen_prim(prim_boxes.size(), 0), seen_node(b.nodes.size(), 0);
  std::vector<int32_t> st{b.root};
  size_t reached = 0;
  while (!st.empty()) {
    int32_t n = st.back();
    st.pop_back();
    if (n < 0 || static_cast<size_t>(n) >= b.nodes.size()) return "child index out of range";
    if (seen_node[n]++) return "node " + std::to_string(n) + " reached twice";
    ++reached;
    const Node& nd = b.nodes[n];
    Aabb box;
    if (nd.leaf()) {
      if (nd.count == 0 && prim_boxes.size() > 0) return "empty leaf " + std::to_string(n);
      if (static_cast<size_t>(nd.first) + nd.count > b.prims.size()) return "leaf range out of bounds";
      for (uint32_t i = 0; i < nd.count; ++i) {
        uint32_t t = b.prims[nd.first + i];
        if (t >= prim_boxes.size()) return "primitive index out of range";
        if (seen_prim[t]++) return "primitive " + std::to_string(t) + " referenced twice";
        box.grow(prim_boxes[t]);
      }
    } else {
      if (nd.right < 0) return "interior node without right child";
      st.push_back(nd.left);
      st.push_back(nd.right);
      box = merge(b.nodes[nd.left].box, b.nodes[nd.right].box);
    }
    if (!(box == nd.box)) return "box of node " + std::to_string(n) + " is not the union of its contents";
  }
  for (size_t t = 0; t < seen_prim.size(); ++t)
    if (!seen_prim[t]) return "primitive " + std::to_string(t) + " not in the tree";
  (void)reached;
  return "";
}

}  // namespace ru::bvh
