// rayunits units: error studies over (exponent bits, fraction bits) grids.
//
// study_tri  (dissertation §3.7-3.9, Tables 3.2-3.4): for every format of the grid and every
//   class of equivalent scalar triple products (units/formulas.hpp), the average relative
//   error of V, Va and V0..2 against the exact rational values of the trace's (double)
//   inputs; inputs are rounded into the format first (RNE), then every operation is rounded.
//   A +-INF result counts as +-(largest finite value) (§3.7); a NaN result is counted apart
//   and left out of the average; records whose exact volume is 0 are left out of that
//   volume's average (relative error undefined). Also: sign errors of V0..2 per class and for
//   Fig. 3.6's lexicographic choice, and wrong hit decisions of ray_tri_robust / ray_tri_mt
//   against the exact test. Relative errors are computed in double from the exact value
//   rounded to double (error <= 2^-52 relative, far below every reported figure).
// study_box: false misses / false hits of the plain and conservative ray-box test against the
//   exact slab test on the same (format-rounded) inputs, and of the plain, conservative and
//   d-conservative modes against the ray direction d; optionally with adversarial pairs per format.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rayunits/num/fp.hpp"
#include "rayunits/units/formulas.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::units {

// Formats of a grid: exponents x fractions with 1 + E + M <= max_width (the dissertation
// evaluated 32-bit formats at most). Throws ru::num::FormatError on an invalid range.
std::vector<ru::num::Format> format_grid(int exp_lo, int exp_hi, int frac_lo, int frac_hi,
                                         int max_width, bool subnormals);
// Parses "6:11" or "7" into [lo, hi]; throws ru::num::FormatError naming `what`.
void parse_range(const std::string& text, const char* what, int& lo, int& hi);

struct VolStat {
  double sum_rel = 0;      // sum of relative errors (finite results, INF clamped)
  uint64_t n = 0;          // terms in sum_rel
  uint64_t nan = 0;        // NaN results (not in the average)
  uint64_t inf = 0;        // INF results (clamped to the largest finite value)
  uint64_t exact_zero = 0; // exact value 0 (skipped)
  uint64_t sign_err = 0;   // sign(computed) != sign(exact), NaN read as 0 (V0..2 only)
  double avg() const { return n ? sum_rel / static_cast<double>(n) : 0.0; }
  void add(const VolStat& o);
};

struct TriCell {
  ru::num::Format fmt;
  std::vector<VolStat> cls[3];  // per VolKind, per class (V012: summed over k = 0, 1, 2)
  VolStat fig36;                // V0..2 with Fig. 3.6's choice of Eq. 3.5 / 3.6 per edge
  uint64_t robust_false_hit = 0, robust_false_miss = 0, mt_false_hit = 0, mt_false_miss = 0;
  ru::num::SoftStats flags;     // every Soft op of the cell (formulas and both units)
  double seconds = 0;
};

struct TriStudyOptions {
  std::vector<ru::num::Format> formats;
  int threads = 2;
  bool decisions = true;  // also run ray_tri_robust / ray_tri_mt and count wrong decisions
  // Progress: called after each finished cell (from worker threads, serialized).
  std::function<void(size_t done, size_t total, const TriCell&)> progress;
};

struct TriStudy {
  std::vector<TriCell> cells;  // in the order of options.formats
  size_t records = 0;          // used records
  size_t skipped = 0;          // records with non-finite inputs (not used)
  size_t exact_hits = 0;       // exact ray-triangle hits among used records
  uint64_t exact_zero[5] = {0, 0, 0, 0, 0};  // V, Va, V0, V1, V2 exactly zero
};

TriStudy study_tri(const std::vector<TriRecord>& recs, const TriStudyOptions& opt);

// The class estimates of one record in the thread's current Soft format: out[kind] gets one
// value per class (for V012, 3 x classes values: index k * classes + class), each already
// multiplied by its exact sign so it approximates the canonical volume. Used by study_tri and
// by tests that compare it with the literal evaluation of all 528 formulations.
void eval_classes(const TriRecord& r, std::vector<ru::num::Soft> out[3]);
// Literal evaluation of one formulation in the current Soft format (sign applied).
ru::num::Soft eval_formula(const TriRecord& r, VolKind kind, int k, const Stp& s);

// ------------------------------------------------------------------ box study
// Counts of one part of a box cell (or of the whole cell).
struct BoxCounts {
  uint64_t exact_hits = 0, records = 0;
  uint64_t plain_false_miss = 0, plain_false_hit = 0;
  uint64_t cons_false_miss = 0, cons_false_hit = 0;
  // Against the ray direction d (box_record_direction; oracle exact_slab_dir): the unit is given
  // inv = RNE(1/d) in the format, as the renderer computes it. dcons = BoxMode::DConservative.
  uint64_t dir_records = 0, dir_exact_hits = 0;
  uint64_t dir_plain_false_miss = 0, dir_plain_false_hit = 0, dir_cons_false_miss = 0, dir_cons_false_hit = 0;
  uint64_t dir_dcons_false_miss = 0, dir_dcons_false_hit = 0;
  BoxCounts& operator+=(const BoxCounts& o);
  BoxCounts operator-(const BoxCounts& o) const;
};
// One format: the counts (BoxCounts, inherited) are over all records, the given ones (trace or
// synthetic) and the adversarial ones; `adversarial` is the adversarial part alone.
struct BoxCell : BoxCounts {
  ru::num::Format fmt;
  BoxCounts adversarial;
  BoxCounts given() const { return *this - adversarial; }
  ru::num::SoftStats flags;
  double seconds = 0;
};
struct BoxStudyOptions {
  std::vector<ru::num::Format> formats;
  int threads = 2;
  // Per format, after the given records: `adversarial` records of AdversarialBoxGen(format,
  // adversarial_seed) (units/synthetic.hpp), generated for that format while it is studied.
  size_t adversarial = 0;
  uint64_t adversarial_seed = 2;
  // Called after each finished format (from worker threads, serialized).
  std::function<void(size_t done, size_t total, const BoxCell&)> progress;
  // Called about every 2^20 pairs (summed over all formats and threads, serialized) with the
  // pairs done so far and the total (formats x (given + adversarial)).
  std::function<void(uint64_t done, uint64_t total)> pair_progress;
};
std::vector<BoxCell> study_box(const std::vector<BoxRecord>& recs, const BoxStudyOptions& opt);

// A box record rounded into the current Soft format (SoftScope, RNE): the unit's inputs and their
// values as doubles for the exact tests. false when the record is outside the exact tests' domain:
// a non-finite o/lo/hi, a NaN inv/t_min/t_max, or geometry that overflows in the format (e.g. a
// 1e6 scene in e5). One rule for `study box` and the box property tests.
struct BoxInputs {
  Vec3<ru::num::Soft> o, inv, lo, hi;
  ru::num::Soft t_min, t_max;
  Vec3d od, invd, lod, hid;
};
bool box_inputs(const BoxRecord& r, BoxInputs& x);

// The direction a box record stands for in the current Soft format (SoftScope): d_k = the
// format's value nearest 1/inv_k (inv_k = +-INF: d_k = +-0), and the reciprocal the renderer
// gives the unit, inv_k = RNE(1/d_k) computed in the format. false if some d_k is not finite.
bool box_record_direction(const BoxRecord& r, Vec3<ru::num::Soft>& d, Vec3<ru::num::Soft>& inv);

}  // namespace ru::units
