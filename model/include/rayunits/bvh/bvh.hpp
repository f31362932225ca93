// Bounding volume hierarchy over triangles: binned-SAH build, the Mirth longest-axis
// spatial-median build (§2.1), the true SAH cost (§5.1), refitting, and validation.
//
// Nodes are linked by index (not implicitly laid out) so that tree rotations (rotate.hpp) can
// relink subtrees in place. Boxes are kept in double here; the renderer converts the tree to
// its arithmetic type (render/accel.hpp), where the boxes are recomputed exactly in that type.
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "rayunits/scene/scene.hpp"

namespace ru::bvh {

using scene::Vec3;

struct Aabb {
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity()};
  void grow(const Vec3& p) {
    lo = scene::vmin(lo, p);
    hi = scene::vmax(hi, p);
  }
  void grow(const Aabb& b) {
    lo = scene::vmin(lo, b.lo);
    hi = scene::vmax(hi, b.hi);
  }
  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  double area() const {  // surface area; 0 for an empty box
    if (empty()) return 0.0;
    Vec3 d = hi - lo;
    return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  bool contains(const Aabb& b) const {
    return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && hi.x >= b.hi.x && hi.y >= b.hi.y &&
           hi.z >= b.hi.z;
  }
  bool operator==(const Aabb& o) const { return lo == o.lo && hi == o.hi; }
};
inline Aabb merge(Aabb a, const Aabb& b) {
  a.grow(b);
  return a;
}

struct Node {
  Aabb box;
  int32_t left = -1, right = -1;  // children of an interior node; -1 in leaves
  uint32_t first = 0, count = 0;  // leaf: primitives prims[first .. first+count)
  uint8_t axis = 0;               // split axis: traversal visits `left` first when the ray's
                                  // direction along it is non-negative
  bool leaf() const { return left < 0; }
};

struct Bvh {
  std::vector<Node> nodes;
  std::vector<uint32_t> prims;  // triangle indices referenced by leaves
  int32_t root = 0;
  int depth() const;
  size_t leaf_count() const;
};

// SAH constants: C = Ct + Ci*N for a leaf, Ct + (S_L C_L + S_R C_R)/S for an interior node.
struct SahParams {
  double ct = 1.0;  // traversal step
  double ci = 1.0;  // primitive intersection
};

struct BuildOptions {
  int max_leaf = 4;  // leaves hold at most this many triangles (1 for animations, §5.6)
  int bins = 16;     // binned SAH: bins per axis
  SahParams sah;
};

std::vector<Aabb> triangle_boxes(const scene::Scene& s);

// Binned SAH build (Wald 2007 style): at every node the centroid range of each axis is cut
// into `bins` bins, and the cheapest of the bins-1 planes (or a leaf, when the node is small
// enough and that is cheaper) is taken.
Bvh build_sah(const std::vector<Aabb>& prim_boxes, const BuildOptions& opt = {});
inline Bvh build_sah(const scene::Scene& s, const BuildOptions& opt = {}) {
  return build_sah(triangle_boxes(s), opt);
}

// Mirth's build (§2.1): split at the midpoint of the longest axis of the node's box, by
// triangle centroid; when that leaves one side empty, split the list in half; a node with
// fewer than `max_tris_per_leaf` (Mirth: 4) triangles becomes a leaf. Arithmetic in double;
// render/accel.hpp has the same algorithm over any arithmetic type.
Bvh build_median(const scene::Scene& s, int max_tris_per_leaf = 4);

// True SAH cost of the tree (the root's C), computed bottom-up.
double sah_cost(const Bvh& b, const SahParams& p = {});

// Recomputes every box bottom-up from the primitive boxes (refitting, §5.6).
void refit(Bvh& b, const std::vector<Aabb>& prim_boxes);

// "" when the tree is well formed: every primitive referenced exactly once, every node
// reachable once, every box equal to the union of its children / its primitives' boxes.
std::string validate(const Bvh& b, const std::vector<Aabb>& prim_boxes);

}  // namespace ru::bvh
