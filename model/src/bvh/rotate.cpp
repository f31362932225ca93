// Tree rotations: hill climbing, simulated annealing, child reordering, refit + rotate.
#include "rayunits/bvh/rotate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

namespace ru::bvh {
namespace {

constexpr int kMoves = 6;
constexpr double kPi = 3.14159265358979323846;

// Postorder list of interior nodes (children before parents).
std::vector<int32_t> postorder_interior(const Bvh& b) {
  std::vector<int32_t> out, st{b.root};
  while (!st.empty()) {
    int32_t n = st.back();
    st.pop_back();
    if (b.nodes[n].leaf()) continue;
    out.push_back(n);
    st.push_back(b.nodes[n].left);
    st.push_back(b.nodes[n].right);
  }
  std::reverse(out.begin(), out.end());  // reversed preorder (node, then children) = parents last
  return out;
}

// Change of the weighted local cost S_N * C_N of node n for each exchange (HUGE_VAL when the
// exchange is not possible because the child on that side is a leaf).
void evaluate(const Bvh& b, int32_t n, double ct, double delta[kMoves]) {
  const Node& nd = b.nodes[n];
  const Node& L = b.nodes[nd.left];
  const Node& R = b.nodes[nd.right];
  for (int k = 0; k < kMoves; ++k) delta[k] = HUGE_VAL;
  const double aL = L.box.area(), aR = R.box.area();
  if (!R.leaf()) {
    const Aabb& RL = b.nodes[R.left].box;
    const Aabb& RR = b.nodes[R.right].box;
    delta[0] = ct * (merge(L.box, RR).area() - aR);  // L <-> RL: R' = {L, RR}
    delta[1] = ct * (merge(RL, L.box).area() - aR);  // L <-> RR: R' = {RL, L}
  }
  if (!L.leaf()) {
    const Aabb& LL = b.nodes[L.left].box;
    const Aabb& LR = b.nodes[L.right].box;
    delta[2] = ct * (merge(R.box, LR).area() - aL);  // R <-> LL: L' = {R, LR}
    delta[3] = ct * (merge(LL, R.box).area() - aL);  // R <-> LR: L' = {LL, R}
    if (!R.leaf()) {
      const Aabb& RL = b.nodes[R.left].box;
      const Aabb& RR = b.nodes[R.right].box;
      delta[4] = ct * (merge(RL, LR).area() + merge(LL, RR).area() - aL - aR);  // LL <-> RL
      delta[5] = ct * (merge(RR, LR).area() + merge(RL, LL).area() - aL - aR);  // LL <-> RR
    }
  }
}

void apply(Bvh& b, int32_t n, int move) {
  Node& nd = b.nodes[n];
  const int32_t l = nd.left, r = nd.right;
  Node& L = b.nodes[l];
  Node& R = b.nodes[r];
  switch (move) {
    case 0: std::swap(nd.left, R.left); R.box = merge(b.nodes[R.left].box, b.nodes[R.right].box); break;
    case 1: std::swap(nd.left, R.right); R.box = merge(b.nodes[R.left].box, b.nodes[R.right].box); break;
    case 2: std::swap(nd.right, L.left); L.box = merge(b.nodes[L.left].box, b.nodes[L.right].box); break;
    case 3: std::swap(nd.right, L.right); L.box = merge(b.nodes[L.left].box, b.nodes[L.right].box); break;
    case 4:
      std::swap(L.left, R.left);
      L.box = merge(b.nodes[L.left].box, b.nodes[L.right].box);
      R.box = merge(b.nodes[R.left].box, b.nodes[R.right].box);
      break;
    case 5:
      std::swap(L.left, R.right);
      L.box = merge(b.nodes[L.left].box, b.nodes[L.right].box);
      R.box = merge(b.nodes[R.left].box, b.nodes[R.right].box);
      break;
  }
}

// Improvements smaller than this fraction of the node's area are treated as no change, so
// that round-off cannot make the climber cycle between equivalent trees.
constexpr double kTiny = 1e-12;

// One pass; returns the number of exchanges applied. T = 0: hill climbing.
uint64_t pass(Bvh& b, double ct, double temperature, std::mt19937_64* rng) {
  uint64_t applied = 0;
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int32_t n : postorder_interior(b)) {
    double d[kMoves];
    evaluate(b, n, ct, d);
    const double an = b.nodes[n].box.area();
    const double tiny = -kTiny * an;
    int best = -1;
    double best_d = 0.0;
    for (int k = 0; k < kMoves; ++k) {
      if (d[k] == HUGE_VAL) continue;
      if (d[k] < best_d && (best >= 0 || d[k] < tiny)) {
        best = k;
        best_d = d[k];
      } else if (temperature > 0 && rng && an > 0) {
        const double de = (d[k] - best_d) / an;  // difference in the node's local cost C
        if (u01(*rng) < std::exp(-de / temperature)) {
          best = k;
          best_d = d[k];
        }
      }
    }
    if (best >= 0) {
      apply(b, n, best);
      ++applied;
    }
  }
  return applied;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

RotateStats hill_climb(Bvh& b, const SahParams& p, int max_passes) {
  auto t0 = std::chrono::steady_clock::now();
  RotateStats st;
  st.cost_before = sah_cost(b, p);
  if (!b.nodes.empty()) {
    for (int i = 0; i < max_passes; ++i) {
      uint64_t a = pass(b, p.ct, 0.0, nullptr);
      ++st.passes;
      st.rotations += a;
      st.cost_per_pass.push_back(sah_cost(b, p));
      if (a == 0) break;
    }
  }
  reorder_children(b);
  st.cost_after = sah_cost(b, p);
  st.seconds = seconds_since(t0);
  return st;
}

double anneal_temperature(const AnnealOptions& o, int i) {
  if (o.iterations <= 0 || i >= o.iterations) return 0.0;
  const double s = -std::sin(i * 2.0 * kPi / o.frequency);
  return std::max(0.0, s) * (o.iterations - i) * o.heat / o.iterations;
}

RotateStats anneal(Bvh& b, const SahParams& p, const AnnealOptions& o) {
  auto t0 = std::chrono::steady_clock::now();
  RotateStats st;
  st.cost_before = sah_cost(b, p);
  if (b.nodes.empty()) return st;
  std::mt19937_64 rng(o.seed);
  std::vector<Node> best_nodes = b.nodes;
  double best_cost = st.cost_before;
  int32_t best_root = b.root;
  auto end_of_pass = [&](uint64_t applied) {
    ++st.passes;
    st.rotations += applied;
    double c = sah_cost(b, p);
    st.cost_per_pass.push_back(c);
    if (o.keep_best && c < best_cost) {
      best_cost = c;
      best_nodes = b.nodes;
      best_root = b.root;
    }
  };
  for (int i = 0; i < o.iterations; ++i) end_of_pass(pass(b, p.ct, anneal_temperature(o, i), &rng));
  for (int q = 0; q < o.max_quench_passes; ++q) {  // quench: T = 0 until converged
    uint64_t a = pass(b, p.ct, 0.0, nullptr);
    end_of_pass(a);
    if (a == 0) break;
  }
  if (o.keep_best && best_cost < sah_cost(b, p)) {
    b.nodes = std::move(best_nodes);
    b.root = best_root;
  }
  reorder_children(b);
  st.cost_after = sah_cost(b, p);
  st.seconds = seconds_since(t0);
  return st;
}

void reorder_children(Bvh& b) {
  for (auto& nd : b.nodes) {
    if (nd.leaf()) continue;
    const Aabb& a = b.nodes[nd.left].box;
    const Aabb& c = b.nodes[nd.right].box;
    int best_axis = 0;
    double best_sep = -HUGE_VAL;
    bool a_first = true;
    for (int axis = 0; axis < 3; ++axis) {
      const double ab = c.lo[axis] - a.hi[axis];  // gap when a comes first
      const double ba = a.lo[axis] - c.hi[axis];  // gap when c comes first
      const double sep = std::max(ab, ba);
      if (sep > best_sep) {
        best_sep = sep;
        best_axis = axis;
        a_first = ab >= ba;
      }
    }
    nd.axis = static_cast<uint8_t>(best_axis);
    if (!a_first) std::swap(nd.left, nd.right);
  }
}

uint64_t refit_rotate(Bvh& b, const std::vector<Aabb>& prim_boxes, const SahParams& p) {
  if (b.nodes.empty()) return 0;
  // Postorder over all nodes: refit, then one hill-climbing step at the node.
  std::vector<int32_t> order, st{b.root};
  while (!st.empty()) {
    int32_t n = st.back();
    st.pop_back();
    order.push_back(n);
    if (!b.nodes[n].leaf()) {
      st.push_back(b.nodes[n].left);
      st.push_back(b.nodes[n].right);
    }
  }
  uint64_t applied = 0;
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    Node& nd = b.nodes[*it];
    if (nd.leaf()) {
      Aabb box;
      for (uint32_t i = 0; i < nd.count; ++i) box.grow(prim_boxes[b.prims[nd.first + i]]);
      nd.box = box;
      continue;
    }
    nd.box = merge(b.nodes[nd.left].box, b.nodes[nd.right].box);
    double d[kMoves];
    evaluate(b, *it, p.ct, d);
    int best = -1;
    double best_d = -kTiny * nd.box.area();
    for (int k = 0; k < kMoves; ++k)
      if (d[k] < best_d) {
        best = k;
        best_d = d[k];
      }
    if (best >= 0) {
      apply(b, *it, best);
      ++applied;
    }
  }
  reorder_children(b);
  return applied;
}

}  // namespace ru::bvh
