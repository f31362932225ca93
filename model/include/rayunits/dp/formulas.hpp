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

#include <array>
#include <string>
#include <vector>

#include "rayunits/dp/ir.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::dp {

// The family of ray-triangle formulations the search (dp/search.hpp) moves over; every design
// below is one of its genomes, and tri_graph() is the one place the graphs are written.
// The moves. Gene values are integers in [0, kTriGeneCount[i]).
struct TriGenome {
  int family = 0;     // 0 signed volumes (Kensler §3.2-3.4), 1 Moller-Trumbore (Eq. 3.2)
  int edge_form = 0;  // signed volumes, V_i of edge e_i = p_j - p_k, (j, k) = (1, 2), (2, 0), (0, 1):
                      //   0 ((a - m_i) x d) . e_i   (Fig. 3.6)
                      //   1 (d x e_i) . (a - m_i)
                      //   2 (e_i x (a - m_i)) . d
                      //   3 ((p_k - a) x (p_j - a)) . d   (no edge vector and no origin: a
                      //     neighbour traversing the edge the other way computes the exact negation)
  int origin = 0;     // m_i: 0 the lexicographically smaller end of the edge (Fig. 3.6: both
                      //   neighbours use the same point), 1 p_j, 2 p_k (vertex order: neighbours differ)
  int denom = 0;      // V: 0 (e1 x e0) . d (Fig. 3.6), 1 (e2 x e1) . d, 2 (e0 x e2) . d,
                      //   3 (V0 + V1) + V2 (no normal)
  int va = 0;         // Va: 0 N . (p2 - a) (Fig. 3.6), 1 N . (p0 - a), 2 N . (p1 - a) with N the
                      //   normal of `denom` (e1 x e0 when denom = 3), 3 ((p1 - a) x (p0 - a)) . (p2 - a)
  int divide = 0;     // 0 three divisions Va/V, V1/V, V2/V; 1 one reciprocal 1/V and three products
  int interval = 0;   // 0 t_min < t < t_max on the quotient; 1 Va against t_min V and t_max V
                      //   (sides chosen by the sign of V: the interval test does not wait for the division)
  int tie = 0;        // 1: Fig. 3.6's zero-volume tie-break (reject V_i = 0 on edges whose
                      //   first end is the lexicographic minimum)
  int dot = 0;        // association of every dot product: 0 (xx + yy) + zz, 1 xx + (yy + zz), 2 (xx + zz) + yy
  int fuse = 0;       // fused multiply-add (ru_fp_fma, one rounding): 0 none; 1 every dot product
                      //   as a chain of two fmas on one product (association `dot`: (xx + yy) + zz
                      //   is fma(z, z', fma(x, x', yy))); 2 also every cross-product component
                      //   u_y v_z - u_z v_y as fma(u_y, v_z, -(u_z v_y))
  int wide = 0;       // mixed precision (the graph's wide format, Graph::set_wide): 0 none; 1 every
                      //   dot product (the volumes V_i, V, Va) computed in the wide format from its
                      //   operands converted up and rounded back once; 2 also the cross products (the
                      //   differences converted up, the triple products wide to their one rounding);
                      //   3 all of it: every input converted up, the outputs rounded back
  // Moller-Trumbore uses divide, interval, dot, fuse and wide; the other genes are ignored (canonical()).
  // Not a gene: the wide format of wide > 0, the unit's widened by (wide_de, wide_dm) exponent and
  // fraction bits (a search's --mixed format; not in the name: one per search).
  int wide_de = 0, wide_dm = 0;
};
constexpr int kTriGenes = 11;
constexpr std::array<int, kTriGenes> kTriGeneCount = {2, 4, 3, 4, 4, 2, 2, 2, 3, 3, 4};
// The genes of a search without fused moves (rayunits search tri without --fused): the first nine,
// so that such a search is the one it was before the fuse gene existed (same random stream).
constexpr int kTriGenesUnfused = 9;
const std::array<const char*, kTriGenes>& tri_gene_names();

std::vector<int> to_vector(const TriGenome& g);  // kTriGenes values
// As written in result files (evaluations.jsonl, front.json, state.json): without the wide gene when it
// is 0 and then without the fuse gene when it is 0, so a search without fused or mixed moves writes
// the files it wrote before the genes existed.
std::vector<int> genes_record(const TriGenome& g);
// throws IrError for a wrong length or value; 9 or 10 genes (written before the fuse or wide gene, or
// with them 0) mean fuse 0, wide 0
TriGenome tri_genome(const std::vector<int>& v);
TriGenome canonical(const TriGenome& g);  // genes the family ignores set to 0
// "sv-f0-o0-d0-a0-q0-i0-t0-p0" / "mt-q1-i0-p0" (q divide, i interval, t tie, p dot association),
// then "-u1" / "-u2" when fuse is not 0 and "-w1" .. "-w3" when wide is not 0 (names without fused or
// mixed operations are what they were before)
std::string genome_name(const TriGenome& g);
TriGenome parse_genome_name(const std::string& s);  // throws IrError naming the accepted form
TriGenome fig36_genome();  // ray_tri_robust_graph(): Fig. 3.6 without its tie-break
TriGenome mt_genome();     // ray_tri_mt_graph()
// Start formulations by name: fig36, fig36_tie, fig36_recip, mt, worst (a deliberately worse one:
// vertex-order origins, Va as a second triple product, the interval by products, tie-break,
// xx + (yy + zz)), or a
// genome name.
TriGenome start_genome(const std::string& name);
Graph tri_graph(const TriGenome& g);

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
  std::string genome;  // its name in `rayunits search tri` (genome_name), the same graph
  std::string origin() const { return "design " + name + " = genome " + genome; }  // emit_sv's origin line
};
const std::vector<Design>& designs();
const Design& find_design(const std::string& name);

// The 17 input values of a ray-triangle record, in the graphs' input order.
std::vector<double> tri_inputs(const units::TriRecord& r);

// ---- ray-box formulations (issue 18 §2: "the same for the ray-box unit") ---------------------
// The slab test of units/ray_box.hpp. Inputs (14, in the order of ru_ray_box's ports and the
// registry's ray-box stimulus): ox oy oz ix iy iz tmin tmax lox loy loz hix hiy hiz (ix.. the
// reciprocal direction). Outputs: hit, t_enter, t_exit. Per axis the sign bit of inv picks the near
// and far planes (selects), tn / tf are the slab bounds, t_enter / t_exit their max / min with
// t_min / t_max, hit = t_enter <= t_exit, t_enter != +INF, t_exit != -INF and no NaN input.
// The moves (gene letter, values):
struct BoxGenome {
  int round = 0;  // r, conservative rounding placement: 0 none (the format's rounding); 1 the
                  //   difference and the product directed (Kensler's conservative unit, BoxMode::
                  //   Conservative: tn <= exact, tf >= exact); 2 the product only; 3 the difference only
  int form = 0;   // f: 0 (plane - o) * inv (ru_ray_box); 1 fma(plane, inv, -(o * inv)) with o * inv
                  //   once per axis (rounded up for tn and down for tf where the difference is directed:
                  //   two products)
  int tree = 0;   // m: 0 the balanced min/max tree of ru_ray_box, max(max(tn_x, tn_y), max(tn_z,
                  //   t_min)); 1 the model's chain max(max(max(t_min, tn_x), tn_y), tn_z) (a compare
                  //   level longer; minNum/maxNum are associative, so the same bits)
};
constexpr int kBoxGenes = 3;
constexpr std::array<int, kBoxGenes> kBoxGeneCount = {4, 2, 2};
std::string box_genome_name(const BoxGenome& g);        // "box-r1-f0-m0"
BoxGenome parse_box_genome_name(const std::string& s);  // throws IrError naming the accepted form
std::vector<BoxGenome> all_box_genomes();               // the 16 designs, in name order
Graph box_graph(const BoxGenome& g);
// The hand-written unit (units::ray_box, ru_ray_box): plain box-r0-f0-m0, OptConservative 1
// box-r1-f0-m0 (bit for bit in formats with subnormals; the FTZ bound replacement of the
// conservative unit is not in the graph).
BoxGenome box_plain_genome();
BoxGenome box_conservative_genome();
// The 14 input values of a ray-box record, in the graphs' input order.
std::vector<double> box_inputs(const units::BoxRecord& r);

}  // namespace ru::dp
