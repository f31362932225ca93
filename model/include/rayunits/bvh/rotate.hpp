// Kensler's tree rotations (dissertation chapter 5).
//
// At an interior node N with children L, R and grandchildren LL, LR, RL, RR six exchanges are
// considered: the four rotations L<->RL, L<->RR, R<->LL, R<->LR and the two grandchild swaps
// LL<->RL, LL<->RR. An exchange leaves N's box unchanged, so it changes the global cost by
// (change of N's local cost) * S_N / S_root; with C = Ct + (S_L C_L + S_R C_R)/S the change
// reduces to Ct times the change in the summed surface area of the rebuilt child(ren).
#pragma once
#include <cstdint>
#include <vector>

#include "rayunits/bvh/bvh.hpp"

namespace ru::bvh {

struct RotateStats {
  int passes = 0;
  uint64_t rotations = 0;  // exchanges applied
  double cost_before = 0, cost_after = 0;
  double seconds = 0;
  std::vector<double> cost_per_pass;  // global SAH cost after each pass (Fig. 5.3 / 5.4)
};

// Hill climbing (§5.3): repeated postorder passes applying, at each node, the exchange that
// lowers its local cost most, until a pass finds none (or max_passes).
RotateStats hill_climb(Bvh& b, const SahParams& p = {}, int max_passes = 1000);

// Simulated annealing schedule of §5.4: T(i) = max(0, -sin(2 pi i / f)) (N - i) h / N.
struct AnnealOptions {
  int iterations = 1250;  // N
  int frequency = 50;     // f
  // h. The dissertation used 0.8 .. 2.2 with Manta's cost constants; with Ct = Ci = 1 and
  // de = the change of the node's C, h >= 0.5 randomises the tree faster than the 25 cold
  // passes per period repair it (arch: cost 18.3 -> 700), 0.1 .. 0.2 works (docs/RENDER.md).
  double heat = 0.15;
  uint64_t seed = 1;
  bool keep_best = true;  // return the best tree seen at the end of any pass
  int max_quench_passes = 1000;
};
double anneal_temperature(const AnnealOptions& o, int i);

// Simulated annealing (§5.4): like hill climbing, but an exchange that is worse than the best
// one found so far at the node is still taken with probability exp(-de/T) (de: difference in
// the node's local cost); after the schedule, quench with T = 0 until converged.
RotateStats anneal(Bvh& b, const SahParams& p = {}, const AnnealOptions& o = {});

// §5.5: re-derive every interior node's split axis and child order: the axis with the largest
// gap between the end of one child's extent and the start of the other's (or, with no gap,
// the least overlap); the child that comes first along it becomes `left`.
void reorder_children(Bvh& b);

// §5.6: one postorder pass that refits every box to the new primitive boxes and, at each
// node, applies the best cost-lowering exchange (a single hill-climbing step). Returns the
// number of exchanges applied.
uint64_t refit_rotate(Bvh& b, const std::vector<Aabb>& prim_boxes, const SahParams& p = {});

}  // namespace ru::bvh
