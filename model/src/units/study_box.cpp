// False-miss / false-hit study of the plain, conservative and d-conservative ray-box test (units/study.hpp).
#include <chrono>
#include <cmath>
#include <mutex>

#include "rayunits/units/exact.hpp"
#include "rayunits/units/ray_box.hpp"
#include "rayunits/units/study.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/util/parallel.hpp"

namespace ru::units {

using ru::num::Format;
using ru::num::Soft;

namespace {

// One record into `c` (the thread's SoftScope is the cell's format).
void count_record(const BoxRecord& r, BoxCounts& c) {
  BoxInputs x;
  if (!box_inputs(r, x)) return;
  const auto& [o, inv, lo, hi, tmin, tmax, od, invd, lod, hid] = x;
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
  if (!box_record_direction(r, d, dinv)) return;
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

// `tick(n)` reports n more pairs done (every kTick pairs and at the end).
constexpr size_t kTick = size_t(1) << 20;

BoxCell run_cell(const Format& fmt, const std::vector<BoxRecord>& recs, const BoxStudyOptions& opt,
                 const std::function<void(uint64_t)>& tick) {
  const auto t0 = std::chrono::steady_clock::now();
  ru::num::SoftScope scope(fmt);
  BoxCell c;
  c.fmt = fmt;
  BoxCounts given;
  size_t since = 0;
  auto step = [&] {
    if (++since == kTick) {
      tick(since);
      since = 0;
    }
  };
  for (const BoxRecord& r : recs) {
    count_record(r, given);
    step();
  }
  AdversarialBoxGen gen(fmt, opt.adversarial_seed);
  for (size_t i = 0; i < opt.adversarial; ++i) {
    count_record(gen.next(), c.adversarial);
    step();
  }
  if (since) tick(since);
  static_cast<BoxCounts&>(c) = given;
  c += c.adversarial;
  c.flags = ru::num::soft_stats();
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

}  // namespace

bool box_inputs(const BoxRecord& r, BoxInputs& x) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(r.o[k]) || std::isnan(r.inv[k]) || !std::isfinite(r.lo[k]) || !std::isfinite(r.hi[k]))
      return false;
  if (std::isnan(r.t_min) || std::isnan(r.t_max)) return false;
  x.o = vcast<Soft>(r.o), x.inv = vcast<Soft>(r.inv), x.lo = vcast<Soft>(r.lo), x.hi = vcast<Soft>(r.hi);
  x.t_min = Soft::from_double(r.t_min), x.t_max = Soft::from_double(r.t_max);
  x.od = vdouble(x.o), x.invd = vdouble(x.inv), x.lod = vdouble(x.lo), x.hid = vdouble(x.hi);
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(x.od[k]) || !std::isfinite(x.lod[k]) || !std::isfinite(x.hid[k])) return false;
  return true;
}

bool box_record_direction(const BoxRecord& r, Vec3<Soft>& d, Vec3<Soft>& inv) {
  for (int k = 0; k < 3; ++k) {
    d[k] = std::isinf(r.inv[k]) ? Soft::from_double(std::copysign(0.0, r.inv[k])) : Soft::from_double(1.0 / r.inv[k]);
    if (!std::isfinite(d[k].to_double())) return false;
    inv[k] = Soft::from_double(1.0) / d[k];
  }
  return true;
}

namespace {
template <class F>
void each_count(BoxCounts& a, const BoxCounts& b, F f) {
  uint64_t* x[] = {&a.exact_hits, &a.records, &a.plain_false_miss, &a.plain_false_hit, &a.cons_false_miss,
                   &a.cons_false_hit, &a.dir_records, &a.dir_exact_hits, &a.dir_plain_false_miss,
                   &a.dir_plain_false_hit, &a.dir_cons_false_miss, &a.dir_cons_false_hit, &a.dir_dcons_false_miss,
                   &a.dir_dcons_false_hit};
  const uint64_t y[] = {b.exact_hits, b.records, b.plain_false_miss, b.plain_false_hit, b.cons_false_miss,
                        b.cons_false_hit, b.dir_records, b.dir_exact_hits, b.dir_plain_false_miss,
                        b.dir_plain_false_hit, b.dir_cons_false_miss, b.dir_cons_false_hit, b.dir_dcons_false_miss,
                        b.dir_dcons_false_hit};
  static_assert(sizeof(BoxCounts) == sizeof y, "every BoxCounts field is listed");
  for (size_t i = 0; i < sizeof y / sizeof y[0]; ++i) f(*x[i], y[i]);
}
}  // namespace

BoxCounts& BoxCounts::operator+=(const BoxCounts& o) {
  each_count(*this, o, [](uint64_t& a, uint64_t b) { a += b; });
  return *this;
}

BoxCounts BoxCounts::operator-(const BoxCounts& o) const {
  BoxCounts r = *this;
  each_count(r, o, [](uint64_t& a, uint64_t b) { a -= b; });
  return r;
}

std::vector<BoxCell> study_box(const std::vector<BoxRecord>& recs, const BoxStudyOptions& opt) {
  std::vector<BoxCell> cells(opt.formats.size());
  std::mutex mu;
  size_t done = 0;
  const uint64_t total_pairs = static_cast<uint64_t>(opt.formats.size()) * (recs.size() + opt.adversarial);
  uint64_t pairs_done = 0;
  const std::function<void(uint64_t)> tick = [&](uint64_t n) {
    std::lock_guard<std::mutex> lock(mu);
    pairs_done += n;
    if (opt.pair_progress) opt.pair_progress(pairs_done, total_pairs);
  };
  util::parallel_for(opt.formats.size(), opt.threads, [&](size_t i) {
    BoxCell c = run_cell(opt.formats[i], recs, opt, tick);
    std::lock_guard<std::mutex> lock(mu);
    cells[i] = c;
    ++done;
    if (opt.progress) opt.progress(done, opt.formats.size(), cells[i]);
  });
  return cells;
}

}  // namespace ru::units
