// rayunits units: every equivalent scalar-triple-product formulation of the five signed
// volumes (dissertation §3.3, §3.7): 36 for V, 384 for Va, 36 for each V_k.
//
// A formulation is (u x v) . w with u, v, w vectors of the volume (factored form, as the
// dissertation evaluates them):
//   V   (3 points p0 p1 p2 and the direction d): {u,v,w} = {d, two different triangle edges};
//       3 edge pairs x 3 choices of w x 2^2 edge directions = 36.
//   Va  (4 points p0 p1 p2 a): three tetrahedron edges that are not coplanar (16 of the 20
//       edge triples; the 4 face triangles are coplanar) x 3 choices of w x 2^3 directions = 384.
//   V_k (3 points a q1 q2 and d, (q1, q2) = (p_{k+1}, p_{k+2})): as V, 36. The same 36
//       formulations are used for V0, V1, V2 by cycling the vertices (that is why Table 3.4
//       reports the three together).
// The two cross-product operands are kept in one canonical order: swapping them negates the
// result exactly in IEEE arithmetic, so it is not counted as a different formulation.
// Likewise reversing an edge negates exactly under round-to-nearest: formulations that differ
// only in edge directions compute the same magnitude bit for bit (tests/units verifies it)
// and form one "class": 9 classes for V and V_k, 48 for Va. Ranking is done per class.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ru::units {

enum class VolKind : uint8_t { V = 0, Va = 1, Vk = 2 };
const char* vol_kind_name(VolKind k);  // "V", "Va", "V012"

// A vector operand: the direction d (i < 0), or point i minus point j of the volume's point
// list: V: {p0, p1, p2}; Va: {p0, p1, p2, a}; V_k: {a, q1, q2}.
struct StpTerm {
  int8_t i = -1, j = -1;
  bool is_d() const { return i < 0; }
};

struct Stp {
  StpTerm u, v, w;  // value = sign * (u x v) . w equals the canonical volume exactly
  int sign = 1;
  int cls = 0;  // class index (same edges and same w, any edge directions)
  // e.g. "[(p2 - p0) x (p1 - p2)] . d"; for V_k with k in 0..2 the points are named p_i,
  // with k = -1 they are named a, q1, q2. A leading "-" when sign = -1.
  std::string text(VolKind kind, int k = -1) const;
};

// All formulations of a volume in a fixed order (36, 384 or 36).
const std::vector<Stp>& stp_formulas(VolKind kind);
int stp_class_count(VolKind kind);  // 9, 48, 9
// A representative of each class (the member whose edges all run from the lower to the
// higher point index, e.g. a - q2, p0 - a), indexed by class.
const std::vector<Stp>& stp_class_reps(VolKind kind);

// Classes of the dissertation's equations:
//   Eq33:  V  = [(p2 - p0) x (p1 - p2)] . d
//   Eq34:  Va = [(p2 - p0) x (p2 - p1)] . (a - p2)
//   Eq35:  V_k = [(a - q2) x d] . (q1 - q2)
//   Eq36:  V_k = [(a - q1) x d] . (q1 - q2)
//   MtV:   V  = [d x (p2 - p0)] . (p1 - p0)           (Eq. 3.2, Moller-Trumbore)
//   MtVa:  Va = [(a - p0) x (p1 - p0)] . (p2 - p0)    (Eq. 3.2)
enum class KnownFormula { Eq33, Eq34, Eq35, Eq36, MtV, MtVa };
int known_formula_class(KnownFormula f);
VolKind known_formula_kind(KnownFormula f);
const char* known_formula_name(KnownFormula f);  // "Eq. 3.3", ...

// Finds the formulation with exactly these terms; -1 if there is none.
int find_stp(VolKind kind, StpTerm u, StpTerm v, StpTerm w);

}  // namespace ru::units
