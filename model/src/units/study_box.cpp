// False-miss / false-hit study of the plain and conservative ray-box test (units/study.hpp).
#include <chrono>
#include <cmath>
#include <mutex>

#include "rayunits/units/exact.hpp"
#include "rayunits/units/ray_box.hpp"
#include "rayunits/units/study.hpp"
#include "rayunits/util/parallel.hpp"

namespace ru::units {

using ru::num::Format;
using ru::num::Soft;

namespace {

bool finite_geometry(const BoxRecord& r) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(r.o[k]) || std::isnan(r.inv[k]) || !std::isfinite(r.lo[k]) || !std::isfinite(r.hi[k]))
      return false;
  return !std::isnan(r.t_min) && !std::isnan(r.t_max);
}

BoxCell run_cell(const Format& fmt, const std::vector<BoxRecord>& recs) {
  const auto t0 = std::chrono::steady_clock::now();
  ru::num::SoftScope scope(fmt);
  BoxCell c;
  c.fmt = fmt;
  for (const BoxRecord& r : recs) {
    if (!finite_geometry(r)) continue;
    // The unit's inputs: the record rounded into the format (RNE).
    const Vec3<Soft> o = vcast<Soft>(r.o), inv = vcast<Soft>(r.inv), lo = vcast<Soft>(r.lo),
                     hi = vcast<Soft>(r.hi);
    const Soft tmin = Soft::from_double(r.t_min), tmax = Soft::from_double(r.t_max);
    const Vec3d od = vdouble(o), invd = vdouble(inv), lod = vdouble(lo), hid = vdouble(hi);
    // Overflow while rounding the geometry (e.g. 1e6 scenes in e5): outside the exact test's
    // domain; the record is not counted for this format.
    bool finite = true;
    for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(od[k]) && std::isfinite(lod[k]) && std::isfinite(hid[k]);
    if (!finite) continue;
    const bool exact = exact_slab(od, invd, lod, hid, tmin.to_double(), tmax.to_double()).hit;
    const bool plain = ray_box(o, inv, lo, hi, tmin, tmax, BoxMode::Plain).hit;
    const bool cons = ray_box(o, inv, lo, hi, tmin, tmax, BoxMode::Conservative).hit;
    ++c.records;
    c.exact_hits += exact;
    c.plain_false_miss += exact && !plain;
    c.plain_false_hit += !exact && plain;
    c.cons_false_miss += exact && !cons;
    c.cons_false_hit += !exact && cons;
    // The same box against the direction d the record stands for.
    Vec3<Soft> d, dinv;
    if (!box_record_direction(r, d, dinv)) continue;
    const bool dx = exact_slab_dir(od, vdouble(d), lod, hid, tmin.to_double(), tmax.to_double()).hit;
    const bool dp = ray_box(o, dinv, lo, hi, tmin, tmax, BoxMode::Plain).hit;
    const bool dc = ray_box(o, dinv, lo, hi, tmin, tmax, BoxMode::Conservative).hit;
    const bool dd = ray_box(o, dinv, lo, hi, tmin, tmax, BoxMode::DConservative).hit;
    ++c.dir_records;
    c.dir_exact_hits += dx;
    c.dir_plain_false_miss += dx && !dp;
    c.dir_plain_false_hit += !dx && dp;
    c.dir_cons_false_miss += dx && !dc;
    c.dir_cons_false_hit += !dx && dc;
    c.dir_dcons_false_miss += dx && !dd;
    c.dir_dcons_false_hit += !dx && dd;
  }
  c.flags = ru::num::soft_stats();
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

}  // namespace

bool box_record_direction(const BoxRecord& r, Vec3<Soft>& d, Vec3<Soft>& inv) {
  for (int k = 0; k < 3; ++k) {
    d[k] = std::isinf(r.inv[k]) ? Soft::from_double(std::copysign(0.0, r.inv[k])) : Soft::from_double(1.0 / r.inv[k]);
    if (!std::isfinite(d[k].to_double())) return false;
    inv[k] = Soft::from_double(1.0) / d[k];
  }
  return true;
}

std::vector<BoxCell> study_box(const std::vector<BoxRecord>& recs, const BoxStudyOptions& opt) {
  std::vector<BoxCell> cells(opt.formats.size());
  std::mutex mu;
  size_t done = 0;
  util::parallel_for(opt.formats.size(), opt.threads, [&](size_t i) {
    BoxCell c = run_cell(opt.formats[i], recs);
    std::lock_guard<std::mutex> lock(mu);
    cells[i] = c;
    ++done;
    if (opt.progress) opt.progress(done, opt.formats.size(), cells[i]);
  });
  return cells;
}

}  // namespace ru::units
