// rayunits units: watertightness of ray_tri_robust / ray_tri_mt on closed meshes.
//
// The mesh's vertices are rounded into the format once (shared vertices stay shared). Rays
// start inside the mesh and pass EXACTLY through a target on the surface:
//   vertex rays: the target is a mesh vertex;
//   edge rays:   the target is a point p0 + s (p1 - p0) of a mesh edge, s = k / 2^j (j <= 4),
//                that is representable in the format (checked with rationals); random edges
//                are tried until one has such a point (up to 64 edges; edges whose points are
//                representable are thus favoured); if none is found the last edge's rounded
//                midpoint is used and the ray is counted "near-edge".
// The origin is the target moved inward (against the average normal of the incident faces,
// with a random tilt) by ~0.3 of the shortest incident edge, rounded into the format; d is the
// exact difference target - origin (checked representable; otherwise another tilt is tried),
// so a + 1 * d is the target exactly. t_min = 0, t_max = 1.5.
// Each ray is tested against every triangle whose bounding sphere (radius x 1.5) comes near
// the segment [a, a + 1.5 d] (in double; the others are too far to be hit at any width).
// leak = no triangle hit; double hit = two or more triangles hit. An exact rational test of
// the same candidates confirms every ray really hits the surface (exact_misses must be 0).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "rayunits/num/format.hpp"
#include "rayunits/units/mesh.hpp"
#include "rayunits/units/ray_tri.hpp"

namespace ru::units {

struct WatertightOptions {
  ru::num::Format fmt;
  bool robust = true;  // false: Moller-Trumbore
  TriOptions tri;
  size_t rays = 10000;  // half edge rays, half vertex rays
  uint64_t seed = 1;
  int threads = 2;
  std::function<void(size_t done, size_t total)> progress;
};

struct WatertightCounts {
  size_t rays = 0, leaks = 0, double_hits = 0;
};

struct WatertightResult {
  WatertightCounts edge, vertex;
  size_t near_edge_rays = 0;   // edge rays whose target is only within rounding of the edge
  size_t inexact_aim = 0;      // rays whose d could not be made exact (target missed by rounding)
  size_t exact_misses = 0;     // rays the exact test says hit nothing (must be 0)
  size_t overflow_rays = 0;    // rays whose unit computations raised overflow
  double candidates_per_ray = 0;
  size_t triangles = 0, vertices = 0;
  WatertightCounts total() const {
    return {edge.rays + vertex.rays, edge.leaks + vertex.leaks, edge.double_hits + vertex.double_hits};
  }
};

// Throws MeshError if the mesh is not closed, ru::num::FormatError if its vertices overflow
// the format.
WatertightResult run_watertight(const Mesh& mesh, const WatertightOptions& opt);

}  // namespace ru::units
