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
// near-vertex rays (near_vertex_rays of them, after the edge and vertex rays): the target is a
// mesh vertex moved by -3..3 ulps of the format in each coordinate (not all 0), so the ray passes
// within a few ulps of the vertex.
// Every ray is also given to the exact crossing oracle (units/crossing_oracle.hpp: the
// symbolically perturbed ray against the exact triangles, same candidates): leak = fewer
// triangles hit than the oracle's crossings, double hit = more (on a convex mesh the oracle
// counts 1, so this is "no hit" / "two or more"). An exact rational test of the same candidates
// (closed triangles, no perturbation) confirms every edge and vertex ray really hits the surface
// (exact_misses must be 0; near-vertex targets may lie off the surface and are not counted).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "rayunits/num/format.hpp"
#include "rayunits/units/mesh.hpp"
#include "rayunits/units/crossing_oracle.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/ray_tri_exact.hpp"

namespace ru::units {

struct WatertightOptions {
  ru::num::Format fmt;
  bool robust = true;  // false: Moller-Trumbore
  bool exact = false;  // ray_tri_exact (the exactly-once unit; robust/tri are ignored)
  TriOptions tri;
  ExactTriOptions exact_opt;                  // planted errors (tests only)
  OraclePlant oracle_plant = OraclePlant::None;  // planted errors (tests only)
  size_t rays = 10000;  // half edge rays, half vertex rays
  size_t near_vertex_rays = 0;  // in addition to `rays`
  uint64_t seed = 1;
  int threads = 2;
  std::function<void(size_t done, size_t total)> progress;
  // A ray-triangle unit given as a function of its inputs in the format (e.g. a datapath graph of
  // dp/search.hpp): when set it is the unit tested (robust/tri/exact are ignored), run in Soft.
  using Vs = Vec3<ru::num::Soft>;
  std::function<bool(const Vs& a, const Vs& d, const Vs& p0, const Vs& p1, const Vs& p2, ru::num::Soft t_min,
                     ru::num::Soft t_max)>
      unit;
};

struct WatertightCounts {
  size_t rays = 0, leaks = 0, double_hits = 0;
  size_t oracle_not_one = 0;           // rays the oracle crosses 0 or >= 2 times
  size_t tests = 0, slow_tests = 0;    // ray_tri_exact: unit tests, and those the exact path decided
};

struct WatertightResult {
  WatertightCounts edge, vertex, near_vertex;
  size_t near_edge_rays = 0;   // edge rays whose target is only within rounding of the edge
  size_t inexact_aim = 0;      // rays whose d could not be made exact (target missed by rounding)
  size_t exact_misses = 0;     // rays the exact test says hit nothing (must be 0)
  size_t overflow_rays = 0;    // rays whose unit computations raised overflow
  double candidates_per_ray = 0;
  size_t triangles = 0, vertices = 0;
  WatertightCounts total() const {
    WatertightCounts t;
    for (const WatertightCounts* c : {&edge, &vertex, &near_vertex}) {
      t.rays += c->rays, t.leaks += c->leaks, t.double_hits += c->double_hits;
      t.oracle_not_one += c->oracle_not_one, t.tests += c->tests, t.slow_tests += c->slow_tests;
    }
    return t;
  }
};

// Throws MeshError if the mesh is not closed, ru::num::FormatError if its vertices overflow
// the format.
WatertightResult run_watertight(const Mesh& mesh, const WatertightOptions& opt);

}  // namespace ru::units
