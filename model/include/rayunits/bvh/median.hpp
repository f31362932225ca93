// Mirth's longest-axis spatial-median BVH build (§2.1), over any arithmetic type T.
//
// The reduced-precision renders of Tables 3.5/3.6 built this tree with the reduced-precision
// library too, so every operation here (box extents, the split position, the centroids and
// the comparisons) is done in T; node boxes are min/max selections, exact in any type.
// Requirements on T: +, -, *, / and < between T values; `cvt(double)` makes a T constant,
// `dbl(T)` gives back the (exactly representable) double value of a T.
#pragma once
#include <algorithm>
#include <array>
#include <numeric>
#include <vector>

#include "rayunits/bvh/bvh.hpp"

namespace ru::bvh {

// v[i] holds triangle i's vertices in T: {p0x, p0y, p0z, p1x, ..., p2z}.
template <class T, class Cvt, class Dbl>
Bvh build_median_generic(const std::vector<std::array<T, 9>>& v, int max_tris_per_leaf, Cvt cvt, Dbl dbl) {
  Bvh b;
  const size_t n = v.size();
  b.prims.resize(n);
  std::iota(b.prims.begin(), b.prims.end(), 0u);
  if (n == 0) {
    b.nodes.push_back(Node{});
    return b;
  }
  const T half = cvt(0.5), three = cvt(3.0);
  auto tmin = [](const T& a, const T& c) { return c < a ? c : a; };
  auto tmax = [](const T& a, const T& c) { return a < c ? c : a; };
  struct Job { int32_t node; uint32_t first, last; };
  std::vector<Job> stack;
  b.nodes.push_back(Node{});
  stack.push_back({0, 0, static_cast<uint32_t>(n)});
  while (!stack.empty()) {
    Job j = stack.back();
    stack.pop_back();
    std::array<T, 3> lo, hi;
    for (int c = 0; c < 3; ++c) lo[c] = hi[c] = v[b.prims[j.first]][c];
    for (uint32_t i = j.first; i < j.last; ++i)
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) {
          lo[c] = tmin(lo[c], v[b.prims[i]][3 * k + c]);
          hi[c] = tmax(hi[c], v[b.prims[i]][3 * k + c]);
        }
    Node& nd = b.nodes[j.node];
    nd.box.lo = {dbl(lo[0]), dbl(lo[1]), dbl(lo[2])};
    nd.box.hi = {dbl(hi[0]), dbl(hi[1]), dbl(hi[2])};
    if (static_cast<int>(j.last - j.first) < max_tris_per_leaf) {
      nd.first = j.first;
      nd.count = j.last - j.first;
      continue;
    }
    std::array<T, 3> diag = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    const int axis = (diag[1] < diag[0] && diag[2] < diag[0]) ? 0 : (diag[2] < diag[1]) ? 1 : 2;
    const T position = (lo[axis] + hi[axis]) * half;
    auto mid_it = std::partition(b.prims.begin() + j.first, b.prims.begin() + j.last, [&](uint32_t t) {
      const T c = (v[t][axis] + v[t][3 + axis] + v[t][6 + axis]) / three;
      return !(position < c);  // centroid <= position goes left
    });
    uint32_t split = static_cast<uint32_t>(mid_it - b.prims.begin());
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
  return b;
}

}  // namespace ru::bvh
