// rayunits dp: today's ray-triangle units written in the datapath IR (issue 18 §1).
//
// Each graph is the dataflow of the hand-written golden model in units/ray_tri.hpp, operation
// for operation (the same operands, the same order inside vsub / cross / dot, the same
// lexicographic-min selection), so evaluate<T>() of the graph equals ray_tri_robust<T> /
// ray_tri_mt<T> / ray_tri_robust_recip<T> bit for bit (tests/dp/dp_test.cpp, at several
// formats, float and double).
//
// Inputs (17, in this order): ax ay az dx dy dz p0x p0y p0z p1x p1y p1z p2x p2y p2z tmin tmax.
// Outputs: hit (Boolean), t, beta, gamma, V, Va, V1, V2, and V0 for the robust unit.
#pragma once

#include <string>
#include <vector>

#include "rayunits/dp/ir.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::dp {

// Kensler Fig. 3.6 (units::ray_tri_robust; tie_break = TriOptions::tie_break; no eps test);
// reciprocal: the cheaper one-reciprocal variant units::ray_tri_robust_recip (1/V, then three
// multiplications). The levels of FP operations (Graph::fp_depth) are those of
// rtl/ru_ray_tri_robust.sv: a - m_i is selected from the three differences a - p_j.
Graph ray_tri_robust_graph(bool tie_break = false, bool reciprocal = false);
// Moller-Trumbore, Eq. 3.2 (units::ray_tri_mt; no eps test).
Graph ray_tri_mt_graph();

// The named designs (`rayunits dp list`): ray_tri_robust, ray_tri_robust_tie, ray_tri_robust_recip,
// ray_tri_mt. find_design throws IrError naming the known ones.
struct Design {
  std::string name, summary;
  Graph (*make)();
};
const std::vector<Design>& designs();
const Design& find_design(const std::string& name);

// The 17 input values of a ray-triangle record, in the graphs' input order.
std::vector<double> tri_inputs(const units::TriRecord& r);

}  // namespace ru::dp
