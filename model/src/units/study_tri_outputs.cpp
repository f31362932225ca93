// Error of t, beta, gamma and wrong decisions of the ray-triangle units (units/study_outputs.hpp).
#include <algorithm>
#include <cmath>
#include <mutex>

#include "rayunits/units/exact.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/ray_tri_cheap.hpp"
#include "rayunits/units/study_outputs.hpp"
#include "rayunits/util/parallel.hpp"

namespace ru::units {

using ru::num::Format;
using ru::num::Soft;

const char* out_unit_name(OutUnit u) {
  switch (u) {
    case OutUnit::Literal: return "fig36";
    case OutUnit::Recip: return "recip";
    case OutUnit::Deferred: return "deferred";
    case OutUnit::Mt: return "mt";
  }
  return "?";
}

namespace {

struct ExactOut {
  bool hit = false;
  double v[3] = {0, 0, 0};  // t, beta, gamma (rounded toward zero to double); valid when hit
  int8_t s[3] = {0, 0, 0};  // their exact signs
};

bool finite_record(const TriRecord& r) {
  const Vec3d* v[5] = {&r.a, &r.d, &r.p0, &r.p1, &r.p2};
  for (const Vec3d* p : v)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite((*p)[k])) return false;
  return !std::isnan(r.t_min) && !std::isnan(r.t_max);
}

void accum(RelStat& st, const Soft& v, double e, int es, double maxf) {
  if (es == 0 || e == 0.0) {
    ++st.exact_zero;
    return;
  }
  double x = v.to_double();
  if (std::isnan(x)) {
    ++st.nan;
    return;
  }
  if (std::isinf(x)) {
    ++st.inf;
    x = std::copysign(maxf, x);
  }
  st.sum_rel += std::fabs(x - e) / std::fabs(e);
  ++st.n;
}

OutCell run_cell(const Format& fmt, const std::vector<TriRecord>& recs, const std::vector<size_t>& used,
                 const std::vector<ExactOut>& ex) {
  ru::num::SoftScope scope(fmt);
  OutCell c;
  c.fmt = fmt;
  const double maxf = ru::num::to_double(fmt, fmt.max_finite());
  for (size_t n = 0; n < used.size(); ++n) {
    const TriRecord& r = recs[used[n]];
    const ExactOut& x = ex[n];
    const Vec3<Soft> a = vcast<Soft>(r.a), d = vcast<Soft>(r.d), p0 = vcast<Soft>(r.p0), p1 = vcast<Soft>(r.p1),
                     p2 = vcast<Soft>(r.p2);
    const Soft t0 = Soft::from_double(r.t_min), t1 = Soft::from_double(r.t_max);
    const TriResult<Soft> res[kOutUnits] = {
        ray_tri_robust(a, d, p0, p1, p2, t0, t1), ray_tri_robust_recip(a, d, p0, p1, p2, t0, t1),
        ray_tri_robust_deferred(a, d, p0, p1, p2, t0, t1), ray_tri_mt(a, d, p0, p1, p2, t0, t1)};
    for (int u = 0; u < kOutUnits; ++u) {
      c.false_hit[u] += res[u].hit && !x.hit;
      c.false_miss[u] += !res[u].hit && x.hit;
      if (x.hit) {
        const Soft* o[3] = {&res[u].t, &res[u].beta, &res[u].gamma};
        for (int k = 0; k < 3; ++k) accum(c.err[u][k], *o[k], x.v[k], x.s[k], maxf);
      }
    }
    const TriResult<Soft>&l = res[0], &df = res[2];
    c.deferred_outputs_differ += l.t.bits != df.t.bits || l.beta.bits != df.beta.bits ||
                                 l.gamma.bits != df.gamma.bits;
  }
  return c;
}

}  // namespace

OutStudy study_tri_outputs(const std::vector<TriRecord>& recs, const OutStudyOptions& opt) {
  OutStudy st;
  std::vector<size_t> used;
  for (size_t i = 0; i < recs.size(); ++i) {
    if (finite_record(recs[i]))
      used.push_back(i);
    else
      ++st.skipped;
  }
  st.records = used.size();
  std::vector<ExactOut> ex(used.size());
  const size_t block = 256;
  util::parallel_for((used.size() + block - 1) / block, opt.threads, [&](size_t b) {
    for (size_t n = b * block; n < std::min(used.size(), (b + 1) * block); ++n) {
      const TriRecord& r = recs[used[n]];
      const ExactTriHit h = exact_tri(r.a, r.d, r.p0, r.p1, r.p2, r.t_min, r.t_max);
      ex[n].hit = h.hit;
      if (h.hit) {
        const mpq_class* q[3] = {&h.t, &h.beta, &h.gamma};
        for (int k = 0; k < 3; ++k) {
          ex[n].v[k] = q[k]->get_d();
          ex[n].s[k] = static_cast<int8_t>(sgn(*q[k]));
        }
      }
    }
  });
  for (const ExactOut& x : ex) st.exact_hits += x.hit;
  st.cells.resize(opt.formats.size());
  std::mutex mu;
  size_t done = 0;
  util::parallel_for(opt.formats.size(), opt.threads, [&](size_t i) {
    OutCell c = run_cell(opt.formats[i], recs, used, ex);
    std::lock_guard<std::mutex> lock(mu);
    st.cells[i] = std::move(c);
    ++done;
    if (opt.progress) opt.progress(done, opt.formats.size(), st.cells[i]);
  });
  return st;
}

}  // namespace ru::units
