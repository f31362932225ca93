// rayunits units: error of the outputs t, beta, gamma of the ray-triangle units against exact
// rationals, per format, and their wrong hit decisions (issue 14 §3: the cheaper robust
// variants of units/ray_tri_cheap.hpp beside Fig. 3.6 taken literally and Moller-Trumbore).
//
// For every format of the grid every record is rounded into the format (RNE) and run through
// ray_tri_robust (Fig. 3.6, 3 divisions), ray_tri_robust_recip (1 reciprocal + 3 mul),
// ray_tri_robust_deferred (interval test by t*V products, then Fig. 3.6's divisions) and
// ray_tri_mt. Output errors are averaged over the records the exact test hits (the outputs
// only matter there): |computed - exact| / |exact| with exact t = Va/V, beta = V1/V,
// gamma = V2/V of the record's double inputs (GMP), +-INF clamped to the largest finite value,
// NaN counted apart, exact zeros (a ray through an edge) left out. Decisions are compared with
// the exact test on the record's double inputs (units/exact.hpp), as study_tri does.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "rayunits/num/fp.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::units {

enum class OutUnit : int { Literal = 0, Recip = 1, Deferred = 2, Mt = 3 };
constexpr int kOutUnits = 4;
const char* out_unit_name(OutUnit u);

struct RelStat {
  double sum_rel = 0;
  uint64_t n = 0, nan = 0, inf = 0, exact_zero = 0;
  double avg() const { return n ? sum_rel / static_cast<double>(n) : 0.0; }
};

struct OutCell {
  ru::num::Format fmt;
  RelStat err[kOutUnits][3];  // [unit][t, beta, gamma]
  uint64_t false_hit[kOutUnits] = {0, 0, 0, 0}, false_miss[kOutUnits] = {0, 0, 0, 0};
  uint64_t deferred_outputs_differ = 0;  // deferred's t/beta/gamma bits != literal's (must stay 0)
};

struct OutStudyOptions {
  std::vector<ru::num::Format> formats;
  int threads = 2;
  std::function<void(size_t done, size_t total, const OutCell&)> progress;
};

struct OutStudy {
  std::vector<OutCell> cells;
  size_t records = 0, skipped = 0, exact_hits = 0;
};

OutStudy study_tri_outputs(const std::vector<TriRecord>& recs, const OutStudyOptions& opt);

}  // namespace ru::units
