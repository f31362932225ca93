// rayunits dp: a search over ray-triangle formulations on area x error (issue 18 §2,
// docs/DATAPATH.md "The search").
//
// A candidate is a TriGenome: one choice per "move" over algebraically equivalent formulations of
// the ray-triangle test (Kensler §3.2-3.4 signed volumes, or Moller-Trumbore). tri_graph() turns a
// genome into a datapath Graph (dp/ir.hpp), which is at once the candidate's golden model, its
// exact-rational model and its netlist of FP units. Fig. 3.6 and Moller-Trumbore are genomes
// (fig36_genome(), mt_genome()): their graphs are ray_tri_robust_graph() / ray_tri_mt_graph()
// node for node (tests/dp/search_test.cpp).
//
// Fitness is a vector, all minimized:
//   area_um2  the cost model: the FP units' areas at the target clock from the cell-library flow's
//             characterized rows (synth/results/cell) plus registers, multiplexers and gates from
//             the liberty (an ESTIMATE, checked against full synthesis of the final front);
//   mean_rel  the largest of the mean relative errors of t, beta, gamma over the workload's
//             records the exact test hits (exact rationals on the candidate's rounded inputs);
//   max_rel   the largest relative error of t, beta, gamma over those records;
//   misses    watertightness leaks on a closed mesh (fewer hits than the exact crossing oracle of
//             units/crossing_oracle.hpp counts) + false misses on the workload (against the exact
//             test, units/exact.hpp): holes in an image;
//   extras    double hits on the mesh + false hits on the workload: what any-hit shading,
//             transparency and parity counting cannot take.
// (Leaks and double hits are separate objectives: Fig. 3.6 trades one for the other with its
// tie-break, and neither is worth any number of the other.)
// The search keeps the Pareto front of these five objectives with NSGA-II (pagmo 2), one
// generation per step, a per-generation seed, a content-hash cache of evaluations and a state
// file after every generation: same seed, same front, whatever the number of threads; a stopped
// run resumes from its last generation.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rayunits/dp/formulas.hpp"
#include "rayunits/dp/ir.hpp"
#include "rayunits/num/format.hpp"
#include "rayunits/synth/cell.hpp"
#include "rayunits/units/exact.hpp"
#include "rayunits/units/mesh.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::dp {


// ---- cost model ------------------------------------------------------------------------------

// One FP unit configuration the model chose for a kind at the target clock.
struct UnitChoice {
  std::string unit;  // fp_add, fp_mul, fp_div, fp_cmp, fp_fma
  int stages = 0;
  double area_um2 = 0, period_ps = 0;
  std::string point;  // the row's "point" (its file stem), for the record
};

struct CostBreakdown {
  double area_um2 = 0;  // units + registers + muxes + gates
  double units_um2 = 0, reg_um2 = 0, mux_um2 = 0, gate_um2 = 0;
  long reg_bits = 0;  // flip-flops: unit output registers and delay lines
  int latency = 0;    // cycles from inputs to outputs
  double period_ps = 0;  // the slowest unit's period (above the target when a unit cannot meet it)
  std::map<std::string, int> ops;  // op_counts()
};

class CostModel {
 public:
  // From cell-flow rows (synthesis row schema, synth/README.md) of the library `lib`: per kind
  // (fp_add, fp_mul, fp_div, fp_cmp, and fp_fma when `fma`) the smallest-area row of the format (rounding and
  // subnormals as fmt) whose measured period (period_ps: clock minus slack, through the register
  // harness) meets period_ps and whose rtl_hash is the current RTL's. `row_paths`: files or
  // directories of *.jsonl (CheckedInRows::load). When a kind has no such row and `measure_file`
  // is not empty, the kind is characterized now (`rayunits synth <unit> --flow LIB --clock P`
  // for Stages s, s+1, ... until one meets the clock, then one more) and the rows are appended to
  // measure_file, so a rerun finds them. A kind none of whose rows meets the clock takes its
  // fastest row (progress says so; CostBreakdown::period_ps shows the slower clock). Without any
  // current row of a kind: throws synth::SynthError with one line naming the kind and format.
  // With `wide` (mixed-precision searches): also every kind in the wide format (units() keys
  // "fp_add@wide", ...) and ru_fp_cvt both ways ("fp_cvt@up": into the wide format, "fp_cvt@down").
  static CostModel build(const std::vector<std::string>& row_paths, const synth::CellLibrary& lib,
                         const num::Format& fmt, double period_ps, const std::string& measure_file = "",
                         const std::function<void(const std::string&)>& progress = {}, bool fma = false,
                         const std::optional<num::Format>& wide = std::nullopt);
  // The schedule (a wide node's registers are the wide format's width): an FP unit node starts when its last operand is ready and its value is ready
  // (stages + 1) cycles later (its output register); selects, gates, neg/abs and constants take no
  // cycle. A value held past the cycle it is ready, for a later consumer or the output alignment,
  // costs a delay line of (cycles x bits) flip-flops (one per value: consumers tap it). Selects
  // cost W multiplexers, Boolean nodes one 2-input gate each.
  CostBreakdown cost(const Graph& g) const;

  const std::map<std::string, UnitChoice>& units() const { return units_; }
  double period_ps() const { return period_ps_; }
  const num::Format& format() const { return fmt_; }
  double ff_um2 = 0, mux_um2 = 0, gate_um2 = 0;  // liberty areas: DFFPOSX1, MUX2X1, AND2X2
  nlohmann::json to_json() const;

 private:
  std::map<std::string, UnitChoice> units_;
  num::Format fmt_;
  std::optional<num::Format> wide_;
  double period_ps_ = 0;
};

// ---- workload and fitness --------------------------------------------------------------------

// What a candidate is measured on: trace records rounded into the format with their exact hit,
// t, beta, gamma (computed once), and a closed mesh for the watertightness counts.
struct Workload {
  num::Format fmt;
  std::vector<std::array<double, 17>> in;  // rounded inputs (graph input order)
  std::vector<char> exact_hit;
  std::vector<std::array<mpq_class, 3>> exact_tbg;  // exact t, beta, gamma where exact_hit
  size_t skipped = 0;  // records with an input the format cannot hold (overflow to INF)
  units::Mesh mesh;
  size_t mesh_rays = 0;  // edge + vertex rays (half each) and as many near-vertex rays
  uint64_t seed = 1;
  std::string hash;  // content hash of all of the above (part of the evaluation cache key)
};
Workload make_workload(const std::vector<units::TriRecord>& recs, const num::Format& fmt, units::Mesh mesh,
                       size_t mesh_rays, uint64_t seed);

struct Fitness {
  CostBreakdown cost;
  double mean_rel = 0, max_rel = 0;
  std::array<double, 3> mean_tbg{}, max_tbg{};  // per output t, beta, gamma
  uint64_t nan = 0;          // NaN outputs where the exact test hits (counted at relative error 1)
  uint64_t false_hits = 0, false_misses = 0;  // decisions differing from the exact test on the workload
  uint64_t leaks = 0, double_hits = 0;  // on the mesh, against the crossing oracle
  uint64_t misses() const { return leaks + false_misses; }
  uint64_t extras() const { return double_hits + false_hits; }
  static constexpr int kObjectives = 5;
  // area, mean_rel, max_rel, misses, extras, and with_period the design's clock period (the
  // slowest unit's): a sixth objective where designs differ in it (searches with fused moves: an
  // fp_fma that cannot meet the clock slows the designs that use it)
  std::vector<double> objectives(bool with_period = false) const;
};
nlohmann::json to_json(const Fitness& f);
Fitness fitness_from_json(const nlohmann::json& j);

// Every figure of one candidate (single-threaded; the search runs candidates in parallel).
Fitness evaluate_fitness(const Graph& g, const Workload& w, const CostModel& cm);

// ---- the ray-box designs (issue 18 §2, "the same for the ray-box unit") -----------------------

// Ray-box records rounded into the format (RNE) with the exact slab test on those values.
struct BoxWorkload {
  num::Format fmt;
  std::vector<std::array<double, 14>> in;  // graph input order (box_inputs)
  std::vector<units::ExactBox> exact;
  size_t skipped = 0;  // records whose origin or box overflows the format (or a NaN input)
  std::string hash;
};
BoxWorkload make_box_workload(const std::vector<units::BoxRecord>& recs, const num::Format& fmt);
// The ray-box figures in the Fitness fields: mean/max relative error of t_enter and t_exit
// (mean_tbg[0..1]) where the exact test hits and the exact value is finite and not 0; false_misses
// (boxes the exact test hits and the design misses: holes for a traversal) and false_hits (extra
// traversal work); no mesh counts (leaks, double_hits 0).
Fitness evaluate_box_fitness(const Graph& g, const BoxWorkload& w, const CostModel& cm);

// ---- the search ------------------------------------------------------------------------------

struct SearchOptions {
  std::string out_dir;      // state.json, evaluations.jsonl, front.json, front.csv, designs/
  TriGenome start;          // the initial population: start and mutations of it
  std::string start_name;   // as given (recorded)
  bool fused = false;       // also move over fused multiply-adds (TriGenome::fuse; the cost model needs fp_fma)
  // Mixed moves (TriGenome::wide) when either is > 0: the wide format is the unit's widened by these
  // exponent and fraction bits (the cost model needs that format's rows and fp_cvt's).
  int wide_de = 0, wide_dm = 0;
  int population = 24;      // a multiple of 4, >= 8 (NSGA-II)
  int generations = 20;
  uint64_t seed = 1;
  int threads = 2;
  std::function<void(const std::string&)> progress;
};

struct Candidate {
  TriGenome genome;
  std::string name;  // the design's name when it is not a TriGenome (ray-box: box_genome_name)
  Fitness fit;
  std::string key;  // evaluation cache key (hash of graph text and workload/cost model)
};

struct SearchResult {
  std::vector<Candidate> front;  // non-dominated, sorted by area then genome name
  int generations_run = 0;       // this call (0 when the state file was already complete)
  size_t evaluations = 0, cache_hits = 0;
};

// Runs (or resumes) the search. `context` describes the workload and cost model (recorded in the
// state file; a state file with another context or other options is an error, not overwritten).
SearchResult run_search(const SearchOptions& opt, const Workload& w, const CostModel& cm,
                        const nlohmann::json& context);

// Non-dominated candidates of a set (minimization of objectives()); duplicates by key kept once.
std::vector<Candidate> pareto_front(const std::vector<Candidate>& all, bool with_period = false);
// The epsilon-box front (Laumanns et al. 2002) of a front: every objective on a log scale in boxes
// of ratio 1 + eps (counts as 1 + count), the non-dominated boxes, one design per box (the
// smallest area, then the name): the designs a search reports and verifies. Differences below
// eps (a few leaks among thousands of rays, 1 % of area) do not make another reported design.
std::vector<Candidate> epsilon_front(const std::vector<Candidate>& front, double eps, bool with_period = false);

}  // namespace ru::dp
