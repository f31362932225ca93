// rayunits units: an exact GMP oracle for ray_tri_exact, written independently of it.
//
// It counts the crossings of the symbolically perturbed ray a(eps) = a + (eps, eps^2, eps^3),
// direction d, with the exact triangles (format values read as rationals). For a triangle
// (p0, p1, p2) and each of its directed edges (pi, pj) the orientation
//     D(delta) = det[pi - a - delta, pj - a - delta, d]
// is affine in delta (the delta-delta terms cancel: det[delta, delta, d] = 0), so its sign at
// delta = (eps, eps^2, eps^3) is the sign of the first non-zero of D(0), D(ex) - D(0),
// D(ey) - D(0), D(ez) - D(0), each determinant evaluated by cofactor expansion. The perturbed
// line crosses the triangle iff the three orientations are non-zero and equal; the crossing
// counts when t = n.(p0 - a) / n.d, n = (p1 - p0) x (p2 - p0), lies strictly in (t_min, t_max)
// (exact, unperturbed). No code is shared with ray_tri_exact (not even the lexicographic edge
// order): the two agree only if both are right.
#pragma once

#include <array>
#include <vector>

#include "rayunits/units/vec.hpp"

namespace ru::units {

enum class OraclePlant : uint8_t {
  None = 0,
  NoPerturbation,  // planted error: a zero orientation counts as inside (closed triangles)
  ReversedOrder,   // planted error: tie terms in the order z, y, x (a different perturbation)
};

// Does the perturbed ray cross this triangle with t in (t_min, t_max)? Non-finite input: false.
bool oracle_crosses(const Vec3d& a, const Vec3d& d, const Vec3d& p0, const Vec3d& p1, const Vec3d& p2,
                    double t_min, double t_max, OraclePlant plant = OraclePlant::None);

// Number of crossings with the listed triangles of (verts, tris).
int oracle_crossings(const Vec3d& a, const Vec3d& d, const std::vector<Vec3d>& verts,
                     const std::vector<std::array<int, 3>>& tris, const std::vector<int>& which, double t_min,
                     double t_max, OraclePlant plant = OraclePlant::None);

}  // namespace ru::units
