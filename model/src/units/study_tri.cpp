// Exact-arithmetic error study of the signed volumes (units/study.hpp).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

#include "rayunits/units/exact.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/study.hpp"
#include "rayunits/util/parallel.hpp"

namespace ru::units {

using ru::num::Format;
using ru::num::FormatError;
using ru::num::Soft;

void VolStat::add(const VolStat& o) {
  sum_rel += o.sum_rel;
  n += o.n;
  nan += o.nan;
  inf += o.inf;
  exact_zero += o.exact_zero;
  sign_err += o.sign_err;
}

void parse_range(const std::string& text, const char* what, int& lo, int& hi) {
  auto num = [&](const std::string& s) {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos)
      throw FormatError(std::string(what) + " range '" + text + "': expected N or LO:HI with integers");
    return std::stoi(s);
  };
  const size_t c = text.find(':');
  if (c == std::string::npos) {
    lo = hi = num(text);
  } else {
    lo = num(text.substr(0, c));
    hi = num(text.substr(c + 1));
  }
  if (lo > hi) throw FormatError(std::string(what) + " range '" + text + "': LO > HI");
}

std::vector<Format> format_grid(int exp_lo, int exp_hi, int frac_lo, int frac_hi, int max_width,
                                bool subnormals) {
  std::vector<Format> out;
  for (int e = exp_lo; e <= exp_hi; ++e)
    for (int m = frac_lo; m <= frac_hi; ++m) {
      Format f{e, m, subnormals, ru::num::Round::RNE};
      f.validate();  // throws a one-line FormatError (e.g. exponent 1, fraction 60)
      if (f.width() <= max_width) out.push_back(f);
    }
  if (out.empty())
    throw FormatError("no format of the grid has at most " + std::to_string(max_width) + " bits");
  return out;
}

namespace {

// ---------------------------------------------------------------- class evaluation plans
// Vectors of a record: index 0 = d, 1 + edge(x, y) = P_x - P_y for 4-point indices x < y of
// {p0, p1, p2, a}, edges in the order (0,1) (0,2) (0,3) (1,2) (1,3) (2,3).
int edge_index(int x, int y) {
  static const int t[4][4] = {{-1, 0, 1, 2}, {0, -1, 3, 4}, {1, 3, -1, 5}, {2, 4, 5, -1}};
  return t[x][y];
}
const int kEdgeX[6] = {0, 0, 0, 1, 1, 2}, kEdgeY[6] = {1, 2, 3, 2, 3, 3};

struct Plan {
  int u7, v7, w7;  // u7 < v7
  bool neg;        // value = (neg ? -1 : 1) * dot(cross(vec[u7], vec[v7]), vec[w7])
};

struct Plans {
  std::vector<Plan> v, va, vk;  // vk: index k * classes + class
};

int map_point(VolKind kind, int idx, int k) {
  if (kind != VolKind::Vk) return idx;  // V: p0..p2; Va: p0, p1, p2, a = 0..3
  return idx == 0 ? 3 : (k + idx) % 3;  // V_k: a, q1 = p_{k+1}, q2 = p_{k+2}
}

Plan make_plan(VolKind kind, const Stp& s, int k) {
  auto term = [&](const StpTerm& t, bool& flip) {
    flip = false;
    if (t.is_d()) return 0;
    const int x = map_point(kind, t.i, k), y = map_point(kind, t.j, k);
    if (x < y) return 1 + edge_index(x, y);
    flip = true;
    return 1 + edge_index(y, x);
  };
  bool fu, fv, fw;
  Plan p;
  p.u7 = term(s.u, fu);
  p.v7 = term(s.v, fv);
  p.w7 = term(s.w, fw);
  bool forder = false;
  if (p.u7 > p.v7) {
    std::swap(p.u7, p.v7);
    forder = true;
  }
  p.neg = (s.sign < 0) ^ fu ^ fv ^ fw ^ forder;
  return p;
}

const Plans& plans() {
  static const Plans p = [] {
    Plans r;
    for (const Stp& s : stp_class_reps(VolKind::V)) r.v.push_back(make_plan(VolKind::V, s, 0));
    for (const Stp& s : stp_class_reps(VolKind::Va)) r.va.push_back(make_plan(VolKind::Va, s, 0));
    for (int k = 0; k < 3; ++k)
      for (const Stp& s : stp_class_reps(VolKind::Vk)) r.vk.push_back(make_plan(VolKind::Vk, s, k));
    return r;
  }();
  return p;
}

struct SoftRec {
  Vec3<Soft> a, d, p[3];
  Soft t_min, t_max;
};

SoftRec round_record(const TriRecord& r) {
  SoftRec s;
  s.a = vcast<Soft>(r.a);
  s.d = vcast<Soft>(r.d);
  s.p[0] = vcast<Soft>(r.p0);
  s.p[1] = vcast<Soft>(r.p1);
  s.p[2] = vcast<Soft>(r.p2);
  s.t_min = Soft::from_double(r.t_min);
  s.t_max = Soft::from_double(r.t_max);
  return s;
}

void eval_classes_soft(const SoftRec& s, std::vector<Soft> out[3]) {
  const Plans& P = plans();
  Vec3<Soft> vec[7];
  const Vec3<Soft>* pt[4] = {&s.p[0], &s.p[1], &s.p[2], &s.a};
  vec[0] = s.d;
  for (int e = 0; e < 6; ++e) vec[1 + e] = vsub(*pt[kEdgeX[e]], *pt[kEdgeY[e]]);
  Vec3<Soft> cr[7][7];
  bool have[7][7] = {};
  auto value = [&](const Plan& p) {
    if (!have[p.u7][p.v7]) {
      cr[p.u7][p.v7] = cross(vec[p.u7], vec[p.v7]);
      have[p.u7][p.v7] = true;
    }
    const Soft x = dot(cr[p.u7][p.v7], vec[p.w7]);
    return p.neg ? -x : x;
  };
  const std::vector<Plan>* lists[3] = {&P.v, &P.va, &P.vk};
  for (int kind = 0; kind < 3; ++kind) {
    out[kind].resize(lists[kind]->size());
    for (size_t c = 0; c < lists[kind]->size(); ++c) out[kind][c] = value((*lists[kind])[c]);
  }
}

struct ExactRec {
  double e[5];  // V, Va, V0, V1, V2 (rounded toward zero to double)
  int8_t s[5];  // exact signs
  bool hit;
};

void accum(VolStat& st, Soft v, double e, int es, double maxf, bool sign) {
  if (es == 0 || e == 0.0) {
    ++st.exact_zero;
    return;
  }
  double x = v.to_double();
  if (std::isnan(x)) {
    ++st.nan;
    if (sign) ++st.sign_err;
    return;
  }
  if (std::isinf(x)) {
    ++st.inf;
    x = std::copysign(maxf, x);
  }
  st.sum_rel += std::fabs(x - e) / std::fabs(e);
  ++st.n;
  if (sign) {
    const int sx = (x > 0) - (x < 0);
    if (sx != es) ++st.sign_err;
  }
}

TriCell run_cell(const Format& fmt, const std::vector<TriRecord>& recs, const std::vector<size_t>& used,
                 const std::vector<ExactRec>& ex, bool decisions) {
  const auto t0 = std::chrono::steady_clock::now();
  ru::num::SoftScope scope(fmt);
  TriCell cell;
  cell.fmt = fmt;
  const int ncls[3] = {stp_class_count(VolKind::V), stp_class_count(VolKind::Va),
                       stp_class_count(VolKind::Vk)};
  for (int k = 0; k < 3; ++k) cell.cls[k].assign(ncls[k], VolStat{});
  const double maxf = ru::num::to_double(fmt, fmt.max_finite());
  const int c35 = known_formula_class(KnownFormula::Eq35), c36 = known_formula_class(KnownFormula::Eq36);
  std::vector<Soft> out[3];
  for (size_t n = 0; n < used.size(); ++n) {
    const TriRecord& r = recs[used[n]];
    const ExactRec& x = ex[n];
    const SoftRec s = round_record(r);
    eval_classes_soft(s, out);
    for (int c = 0; c < ncls[0]; ++c) accum(cell.cls[0][c], out[0][c], x.e[0], x.s[0], maxf, false);
    for (int c = 0; c < ncls[1]; ++c) accum(cell.cls[1][c], out[1][c], x.e[1], x.s[1], maxf, false);
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < ncls[2]; ++c)
        accum(cell.cls[2][c], out[2][k * ncls[2] + c], x.e[2 + k], x.s[2 + k], maxf, true);
      // Fig. 3.6: the edge (q1, q2) uses its lexicographically smaller end point.
      const bool q1_min = lex_first_is_min(s.p[(k + 1) % 3], s.p[(k + 2) % 3]);
      accum(cell.fig36, out[2][k * ncls[2] + (q1_min ? c36 : c35)], x.e[2 + k], x.s[2 + k], maxf, true);
    }
    if (decisions) {
      const auto rb = ray_tri_robust(s.a, s.d, s.p[0], s.p[1], s.p[2], s.t_min, s.t_max);
      const auto mt = ray_tri_mt(s.a, s.d, s.p[0], s.p[1], s.p[2], s.t_min, s.t_max);
      cell.robust_false_hit += rb.hit && !x.hit;
      cell.robust_false_miss += !rb.hit && x.hit;
      cell.mt_false_hit += mt.hit && !x.hit;
      cell.mt_false_miss += !mt.hit && x.hit;
    }
  }
  cell.flags = ru::num::soft_stats();
  cell.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return cell;
}

bool finite_record(const TriRecord& r) {
  const Vec3d* v[5] = {&r.a, &r.d, &r.p0, &r.p1, &r.p2};
  for (const Vec3d* p : v)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite((*p)[k])) return false;
  return !std::isnan(r.t_min) && !std::isnan(r.t_max);
}

}  // namespace

void eval_classes(const TriRecord& r, std::vector<Soft> out[3]) { eval_classes_soft(round_record(r), out); }

Soft eval_formula(const TriRecord& r, VolKind kind, int k, const Stp& s) {
  const SoftRec sr = round_record(r);
  std::vector<const Vec3<Soft>*> pts;
  if (kind == VolKind::V) pts = {&sr.p[0], &sr.p[1], &sr.p[2]};
  if (kind == VolKind::Va) pts = {&sr.p[0], &sr.p[1], &sr.p[2], &sr.a};
  if (kind == VolKind::Vk) pts = {&sr.a, &sr.p[(k + 1) % 3], &sr.p[(k + 2) % 3]};
  auto term = [&](const StpTerm& t) { return t.is_d() ? sr.d : vsub(*pts[t.i], *pts[t.j]); };
  const Soft x = dot(cross(term(s.u), term(s.v)), term(s.w));
  return s.sign < 0 ? -x : x;
}

TriStudy study_tri(const std::vector<TriRecord>& recs, const TriStudyOptions& opt) {
  TriStudy st;
  std::vector<size_t> used;
  for (size_t i = 0; i < recs.size(); ++i) {
    if (finite_record(recs[i]))
      used.push_back(i);
    else
      ++st.skipped;
  }
  st.records = used.size();
  std::vector<ExactRec> ex(used.size());
  // Exact values, in blocks of records across the threads.
  const size_t block = 256;
  util::parallel_for((used.size() + block - 1) / block, opt.threads, [&](size_t b) {
    for (size_t n = b * block; n < std::min(used.size(), (b + 1) * block); ++n) {
      const TriRecord& r = recs[used[n]];
      const ExactTriHit h = exact_tri(r.a, r.d, r.p0, r.p1, r.p2, r.t_min, r.t_max);
      const mpq_class* v[5] = {&h.vol.V, &h.vol.Va, &h.vol.V0, &h.vol.V1, &h.vol.V2};
      for (int i = 0; i < 5; ++i) {
        ex[n].e[i] = v[i]->get_d();
        ex[n].s[i] = static_cast<int8_t>(sgn(*v[i]));
      }
      ex[n].hit = h.hit;
    }
  });
  for (const ExactRec& x : ex) {
    st.exact_hits += x.hit;
    for (int i = 0; i < 5; ++i) st.exact_zero[i] += x.s[i] == 0;
  }
  st.cells.resize(opt.formats.size());
  std::mutex mu;
  size_t done = 0;
  util::parallel_for(opt.formats.size(), opt.threads, [&](size_t i) {
    TriCell c = run_cell(opt.formats[i], recs, used, ex, opt.decisions);
    std::lock_guard<std::mutex> lock(mu);
    st.cells[i] = std::move(c);
    ++done;
    if (opt.progress) opt.progress(done, opt.formats.size(), st.cells[i]);
  });
  return st;
}

}  // namespace ru::units
