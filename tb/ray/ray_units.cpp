// rayunits tb/ray: adapters and test plans of ray_box, ray_tri_robust, ray_tri_mt.
//
// For each configuration <unit>_<cfg> (suite; Long_<unit>_<cfg> for long configurations):
//   synthetic   the synthetic workloads (units/synthetic.hpp) at scales 1, 2^+-16, 1e-6, 1e+6
//   random      mixed-scale random rays/triangles/boxes, grid cases, sprinkled special values
//   extremes    the defined extremes of docs/UNITS.md (ray.hpp lists them)
//   trace       a trace file through units::read_trace (RU_RAY_TRACE=FILE: a captured trace)
//   reset       random vectors with a reset every ~40 cycles (dropped and replayed)
//   mutant_*    (configurations tagged "selftest") planted errors in the golden model and in
//               the expected latency; the scoreboard must report each of them
// and Long_<unit>_<cfg>.random / .synthetic with many more vectors (label long).
#include <gtest/gtest.h>

#include <cstdio>
#include <iostream>
#include <sstream>

#include "ray.hpp"
#include "rayunits/tb/fp.hpp"  // fp_text
#include "rayunits/num/fp.hpp"
#include "rayunits/tb/testing.hpp"
#include "rayunits/units/ray_box.hpp"
#include "rayunits/units/ray_tri_cheap.hpp"

namespace ru::tb::ray {

using ru::num::Format;
using ru::num::Soft;
using ru::units::Vec3;

const char* mutant_name(Mutant m) {
  switch (m) {
    case Mutant::None: return "none";
    case Mutant::Rounding: return "rounding";
    case Mutant::InputLsb: return "input_lsb";
    case Mutant::ModeSwap: return "mode_swap";
  }
  return "?";
}

RayConfig ray_config(const ConfigDesc& cfg) {
  RayConfig c;
  if (cfg.unit == "ray_box") c.unit = Unit::Box;
  else if (cfg.unit == "ray_tri_robust") c.unit = Unit::Robust;
  else if (cfg.unit == "ray_tri_mt") c.unit = Unit::Mt;
  else throw std::runtime_error("tb/ray: unknown unit " + cfg.unit);
  c.f.exp_bits = static_cast<int>(cfg.param("ExpW", -1));
  c.f.frac_bits = static_cast<int>(cfg.param("FracW", -1));
  c.f.subnormals = cfg.param("Subnormals", 1) != 0;
  const int64_t r = cfg.param("Round", 0);
  if (r < 0 || r > 3) throw ru::num::FormatError(cfg.full_name() + ": Round must be 0..3");
  c.f.round = static_cast<ru::num::Round>(r);
  c.f.validate();
  c.stages = static_cast<int>(cfg.param("Stages", 0));
  const int64_t cons = cfg.param("OptConservative", 0);
  if (cons < 0 || cons > 2) throw std::runtime_error(cfg.full_name() + ": OptConservative must be 0..2");
  c.conservative = cons != 0;
  c.dcons = cons == 2;
  c.tie_break = cfg.param("OptTieBreak", 0) != 0;
  c.eps_test = cfg.param("OptEpsTest", 0) != 0;
  c.eps_bits = static_cast<uint64_t>(cfg.param("EpsBits", 0)) & c.f.mask();
  c.vol_out = cfg.param("OptVolOut", 0) != 0;
  c.recip = cfg.param("OptRecip", 0) != 0;
  return c;
}

std::string describe(const RayConfig& c) {
  std::ostringstream os;
  os << (c.unit == Unit::Box ? "ray_box" : c.unit == Unit::Robust ? "ray_tri_robust" : "ray_tri_mt") << " "
     << c.f.name() << " " << ru::num::round_name(c.f.round) << " Stages=" << c.stages;
  if (c.conservative) os << (c.dcons ? " d-conservative" : " conservative");
  if (c.tie_break) os << " tie-break";
  if (c.eps_test) os << " eps=" << hex(c.eps_bits, c.f.width());
  if (c.vol_out) os << " vol_out";
  if (c.recip) os << " recip";
  return os.str();
}

// ---------------------------------------------------------------------------------------------
// Adapter

namespace {

// Packs n W-bit fields (field 0 in the low bits) into 64-bit words.
void pack(const uint64_t* x, int n, int W, uint64_t* w, int nwords) {
  for (int i = 0; i < nwords; ++i) w[i] = 0;
  for (int i = 0; i < n; ++i) {
    const int pos = i * W, wi = pos / 64, sh = pos % 64;
    w[wi] |= x[i] << sh;
    if (sh && sh + W > 64) w[wi + 1] |= x[i] >> (64 - sh);
  }
}
void unpack(const uint64_t* w, int n, int W, uint64_t* x) {
  const uint64_t m = W >= 64 ? ~0ull : ((1ull << W) - 1);
  for (int i = 0; i < n; ++i) {
    const int pos = i * W, wi = pos / 64, sh = pos % 64;
    uint64_t v = w[wi] >> sh;
    if (sh && sh + W > 64) v |= w[wi + 1] << (64 - sh);
    x[i] = v & m;
  }
}


}  // namespace

RayAdapter::RayAdapter(const RayConfig& c, Mutant m) : c_(c), mut_(m), W_(c.f.width()) {
  auto vec = [&](const std::string& n) {
    for (const char* k : {".x", ".y", ".z"}) ins_.push_back({n + k, W_, FieldKind::Float, {}});
  };
  auto scalar = [&](const std::string& n) { ins_.push_back({n, W_, FieldKind::Float, {}}); };
  outs_.push_back({"hit_o", 1, FieldKind::Hex, {}});
  if (c_.unit == Unit::Box) {
    vec("org"), vec("rdir"), vec("bmin"), vec("bmax"), scalar("tmin"), scalar("tmax");
    outs_.push_back({"t_enter_o", W_, FieldKind::Float, {}});
    outs_.push_back({"t_exit_o", W_, FieldKind::Float, {}});
  } else {
    vec("a"), vec("d"), vec("p0"), vec("p1"), vec("p2"), scalar("tmin"), scalar("tmax");
    outs_.push_back({"why_o", 3, FieldKind::Enum, {"hit", "sign", "tie_break", "eps", "interval"}});
    outs_.push_back({"t_o", W_, FieldKind::Float, {}});
    outs_.push_back({"beta_o", W_, FieldKind::Float, {}});
    outs_.push_back({"gamma_o", W_, FieldKind::Float, {}});
    if (c_.vol_out)
      for (const char* n : {"V", "Va", "V0", "V1", "V2"}) outs_.push_back({n, W_, FieldKind::Float, {}});
  }
}

std::string RayAdapter::describe() const {
  std::string s = ray::describe(c_);
  if (mut_ != Mutant::None) s += std::string(" [planted: ") + mutant_name(mut_) + "]";
  return s;
}

void RayAdapter::bind(const PortMap& pm) {
  in_ports_.clear();
  in_groups_.clear();
  auto add = [&](const char* name, int n) {
    Port p = pm.get(name);
    if (p.bits() != n * W_) throw std::runtime_error(describe() + ": port " + name + " width mismatch");
    in_ports_.push_back(p);
    in_groups_.push_back(n);
  };
  hit_ = pm.get("hit_o");
  if (c_.unit == Unit::Box) {
    add("org_i", 3), add("rdir_i", 3), add("bmin_i", 3), add("bmax_i", 3), add("tmin_i", 1), add("tmax_i", 1);
    tenter_ = pm.get("t_enter_o");
    texit_ = pm.get("t_exit_o");
  } else {
    add("a_i", 3), add("d_i", 3), add("p0_i", 3), add("p1_i", 3), add("p2_i", 3), add("tmin_i", 1), add("tmax_i", 1);
    why_ = pm.get("why_o");
    t_ = pm.get("t_o");
    beta_ = pm.get("beta_o");
    gamma_ = pm.get("gamma_o");
    vol_ = pm.get("vol_o");
    if (vol_.bits() != 5 * W_ || t_.bits() != W_) throw std::runtime_error(describe() + ": output width mismatch");
  }
}

void RayAdapter::drive(const Record& in) {
  int field = 0;
  for (size_t g = 0; g < in_ports_.size(); ++g) {
    const int n = in_groups_[g];
    uint64_t w[4];
    pack(&in.v[field], n, W_, w, 4);
    in_ports_[g].set_words(w, 4);
    field += n;
  }
}

void RayAdapter::read(Record& out) {
  out.v[0] = hit_.get();
  if (c_.unit == Unit::Box) {
    out.v[1] = tenter_.get();
    out.v[2] = texit_.get();
    return;
  }
  out.v[1] = why_.get();
  out.v[2] = t_.get();
  out.v[3] = beta_.get();
  out.v[4] = gamma_.get();
  if (c_.vol_out) {
    uint64_t w[5] = {}, x[5];
    vol_.get_words(w);
    unpack(w, 5, W_, x);
    for (int i = 0; i < 5; ++i) out.v[5 + i] = x[i];
  }
}

void RayAdapter::model(const Record& in0, Record& out) {
  Record in = in0;
  Format f = c_.f;
  bool conservative = c_.conservative, dcons = c_.dcons, tie = c_.tie_break, recip = c_.recip;
  switch (mut_) {
    case Mutant::None: break;
    case Mutant::Rounding: f.round = ru::num::Round::RTZ; break;
    case Mutant::InputLsb: in.v[4] ^= 1; break;  // rdir.y / d.y
    case Mutant::ModeSwap:
      conservative = dcons || !conservative;
      dcons = false;
      tie = !tie;
      recip = !recip;
      break;
  }
  ru::num::SoftScope scope(f);
  auto S = [&](int i) { return Soft::from_bits(in.v[i]); };
  auto V = [&](int i) { return Vec3<Soft>{S(i), S(i + 1), S(i + 2)}; };
  if (c_.unit == Unit::Box) {
    using ru::units::BoxMode;
    const auto r = ru::units::ray_box(V(0), V(3), V(6), V(9), S(12), S(13),
                                      dcons ? BoxMode::DConservative : conservative ? BoxMode::Conservative : BoxMode::Plain);
    out.v[0] = r.hit;
    out.v[1] = r.t_enter.bits;
    out.v[2] = r.t_exit.bits;
    return;
  }
  ru::units::TriOptions opt;
  opt.tie_break = tie;
  opt.eps_test = c_.eps_test;
  opt.eps = ru::num::to_double(c_.f, c_.eps_bits);
  const auto r = c_.unit == Unit::Mt ? ru::units::ray_tri_mt(V(0), V(3), V(6), V(9), V(12), S(15), S(16), opt)
                 : recip ? ru::units::ray_tri_robust_recip(V(0), V(3), V(6), V(9), V(12), S(15), S(16), opt)
                         : ru::units::ray_tri_robust(V(0), V(3), V(6), V(9), V(12), S(15), S(16), opt);
  out.v[0] = r.hit;
  out.v[1] = static_cast<uint64_t>(r.why);
  out.v[2] = r.t.bits;
  out.v[3] = r.beta.bits;
  out.v[4] = r.gamma.bits;
  if (c_.vol_out) {
    out.v[5] = r.V.bits;
    out.v[6] = r.Va.bits;
    out.v[7] = r.V0.bits;
    out.v[8] = r.V1.bits;
    out.v[9] = r.V2.bits;
  }
}

std::string RayAdapter::decimal(const FieldInfo& fi, uint64_t v) const {
  if (fi.kind == FieldKind::Float) return fp_text(c_.f, v);
  return UnitAdapter::decimal(fi, v);
}

// ---------------------------------------------------------------------------------------------
// Test plan

namespace {

constexpr size_t kFastSynthetic = 4000, kFastRandom = 10000, kFastTrace = 2000, kFastReset = 2000;
constexpr size_t kLongSynthetic = 100000, kLongRandom = 200000;

struct Ctx {
  const ConfigDesc* cfg = nullptr;
  RayConfig c;
  std::string suite;
  uint64_t seed(const std::string& test) const { return mix_seed(global_options().seed, suite + "." + test); }
  ScoreboardTest make(const std::string& test) const {
    ScoreboardTest t;
    t.cfg = cfg;
    t.name = suite + "." + test;
    const RayConfig rc = c;
    t.adapter = [rc] { return std::make_unique<RayAdapter>(rc); };
    t.opt = make_options(*cfg, t.name);
    t.opt.stages = c.stages;  // the unit's latency is Stages
    t.opt.format = c.f.name() + " " + ru::num::round_name(c.f.round);
    return t;
  }
  bool box() const { return c.unit == Unit::Box; }
};

using Gen = std::function<std::vector<Record>(const Ctx&, uint64_t seed, size_t n)>;

std::vector<Record> gen_synthetic(const Ctx& x, uint64_t seed, size_t n) {
  return x.box() ? box_synthetic(x.c.f, seed, n) : tri_synthetic(x.c.f, seed, n);
}
std::vector<Record> gen_random(const Ctx& x, uint64_t seed, size_t n) {
  return x.box() ? box_random(x.c.f, seed, n) : tri_random(x.c.f, seed, n);
}
std::vector<Record> gen_extremes(const Ctx& x, uint64_t seed, size_t) {
  return x.box() ? box_extremes(x.c.f, seed) : tri_extremes(x.c.f, seed, x.c.eps_test ? x.c.eps_bits : 0);
}

// Counts of hits / misses by reason in the expected results, and coverage of the special
// paths (printed; the extremes tests require them), so that a vector set cannot silently
// degenerate into all misses or stop reaching a defined case.
struct Mix {
  size_t n = 0, hits = 0, why[5] = {0, 0, 0, 0, 0};
  size_t nan_bounds = 0;   // box: 0*INF slab bounds (ignored by minNum/maxNum)
  size_t ftz_fixups = 0;   // box conservative, FTZ: directed results replaced by +-min normal
  size_t zero_vols = 0;    // tri: records with an exactly zero V0, V1 or V2 (edges, vertices)
};

// Box coverage: recompute the slab bounds per axis with the format model.
void box_coverage(const RayConfig& c, const Record& in, Mix& m) {
  using ru::num::Round;
  const Format& f = c.f;
  bool nanb = false, fix = false;
  for (int k = 0; k < 3; ++k) {
    const uint64_t o = in.v[k], inv = in.v[3 + k], lo = in.v[6 + k], hi = in.v[9 + k];
    const bool neg = (inv & f.sign_bit()) != 0;
    const uint64_t nearp = neg ? hi : lo, farp = neg ? lo : hi;
    for (int side = 0; side < 2; ++side) {
      const uint64_t plane = side ? farp : nearp;
      Format fs = f, fm = f;
      if (c.conservative) {
        fs.round = side ? (neg ? Round::RDN : Round::RUP) : (neg ? Round::RUP : Round::RDN);
        fm.round = side ? Round::RUP : Round::RDN;
      }
      const auto wrong = [&](const ru::num::Result& r, Round rd) {
        const bool zero = (r.bits & ~f.sign_bit()) == 0, negz = (r.bits & f.sign_bit()) != 0;
        return (r.flags & ru::num::kUnderflow) && zero && ((rd == Round::RUP && !negz) || (rd == Round::RDN && negz));
      };
      ru::num::Result d = ru::num::sub(fs, plane, o);
      if (c.conservative && wrong(d, fs.round)) fix = true, d.bits = f.min_normal((d.bits & f.sign_bit()) != 0);
      uint64_t r = inv;  // d-conservative: the end of reciprocal_bounds(inv) the model takes
      if (c.dcons) {
        ru::num::SoftScope scope(f);
        Soft a, b;
        ru::units::reciprocal_bounds(Soft::from_bits(inv), a, b);
        const bool dneg = (d.bits & f.sign_bit()) != 0;
        r = (side ? !dneg : dneg) ? b.bits : a.bits;
      }
      ru::num::Result t = ru::num::mul(fm, d.bits, r);
      if (c.conservative && wrong(t, fm.round)) fix = true;
      if (ru::num::is_nan(f, t.bits) && !ru::num::is_nan(f, plane) && !ru::num::is_nan(f, o) &&
          !ru::num::is_nan(f, inv))
        nanb = true;
    }
  }
  m.nan_bounds += nanb;
  m.ftz_fixups += fix && !f.subnormals;
}

Mix model_mix(const Ctx& x, const std::vector<Record>& recs) {
  RayAdapter ad(x.c);
  RayConfig cv = x.c;
  cv.vol_out = true;
  RayAdapter advol(cv);  // volumes for the coverage count
  Mix m;
  Record out;
  for (const Record& r : recs) {
    ad.model(r, out);
    ++m.n;
    m.hits += out.v[0] & 1;
    if (x.box()) {
      box_coverage(x.c, r, m);
      continue;
    }
    if (out.v[1] < 5) ++m.why[out.v[1]];
    advol.model(r, out);
    const uint64_t mag = ~x.c.f.sign_bit() & x.c.f.mask();
    const bool zv = (out.v[8] & mag) == 0 || (out.v[9] & mag) == 0 || (x.c.unit == Unit::Robust && (out.v[7] & mag) == 0);
    m.zero_vols += zv;
  }
  return m;
}

void run_records(const Ctx& x, const std::string& test, const std::vector<Record>& recs, uint32_t reset_every,
                 const std::string& what) {
  const Mix m = model_mix(x, recs);
  std::ostringstream mix;
  mix << what << ": " << m.n << " vectors, " << m.hits << " hits";
  if (!x.box())
    mix << " (misses: sign " << m.why[1] << ", tie-break " << m.why[2] << ", eps " << m.why[3] << ", interval "
        << m.why[4] << "); " << m.zero_vols << " with an exactly zero V_i";
  else
    mix << "; " << m.nan_bounds << " with a 0*INF slab bound, " << m.ftz_fixups << " with an FTZ bound fix-up";
  std::cerr << "[" << x.suite << "." << test << "] " << mix.str() << "\n";
  ScoreboardTest t = x.make(test);
  auto shared = std::make_shared<std::vector<Record>>(recs);
  t.source = [shared] { return std::make_unique<ArraySource>(shared.get()); };
  t.opt.reset_every = reset_every;
  const RunStats st = run_scoreboard(t);
  std::cerr << "[" << t.name << "] seed=" << global_options().seed << ": " << st.checked << " results checked in "
            << st.cycles << " cycles (" << st.resets << " reset cycles, " << st.dropped
            << " dropped and re-issued), " << st.seconds << " s\n";
  EXPECT_TRUE(st.ok()) << st.errors.size() << " mismatch(es)" << (st.aborted ? " (stopped early)" : "")
                       << "; first:\n"
                       << (st.errors.empty() ? "" : st.errors.front().report);
  if (!st.aborted) {
    EXPECT_EQ(st.checked, recs.size()) << "every vector must be checked exactly once";
  }
  // Vector sets must exercise both outcomes (a unit stuck at 'miss' would pass otherwise).
  EXPECT_GT(m.hits, 0u) << what << ": no expected hit";
  EXPECT_LT(m.hits, m.n) << what << ": no expected miss";
  if (test == "extremes") {  // the defined cases must be reached
    if (x.box()) {
      EXPECT_GT(m.nan_bounds, 0u) << "no 0*INF slab bound";
      if (x.c.conservative && !x.c.f.subnormals) {
        EXPECT_GT(m.ftz_fixups, 0u) << "no FTZ bound fix-up";
      }
    } else {
      EXPECT_GT(m.zero_vols, 0u) << "no exactly zero edge volume";
      EXPECT_GT(m.why[4], 0u) << "no interval miss";
      if (x.c.tie_break) {
        EXPECT_GT(m.why[2], 0u) << "no tie-break miss";
      }
      if (x.c.eps_test) {
        EXPECT_GT(m.why[3], 0u) << "no eps miss";
      }
    }
  }
}

void add_gen_test(const Ctx& x, const std::string& suite, const std::string& test, Gen gen, size_t n,
                  uint32_t reset_every) {
  Ctx xx = x;
  xx.suite = suite;
  register_test(suite, test, [xx, test, gen, n, reset_every] {
    const uint64_t seed = xx.seed(test);
    const size_t count = vector_count(*xx.cfg, n);
    run_records(xx, test, gen(xx, seed, count), reset_every, test);
  });
}

// Planted errors: each must be reported by the scoreboard on the same vectors that pass
// unplanted (control run first).
void add_mutants(const Ctx& x) {
  std::vector<Mutant> ms = {Mutant::InputLsb};
  if (!(x.box() && x.c.conservative)) ms.push_back(Mutant::Rounding);  // all-directed: no RNE op
  if (x.c.unit != Unit::Mt) ms.push_back(Mutant::ModeSwap);
  for (Mutant m : ms) {
    const std::string test = std::string("mutant_") + mutant_name(m);
    register_test(x.suite, test, [x, m, test] {
      const uint64_t seed = x.seed(test);
      std::vector<Record> recs = gen_extremes(x, seed, 0);
      const auto rnd = gen_random(x, seed, 1000);
      recs.insert(recs.end(), rnd.begin(), rnd.end());
      RunOptions o = make_options(*x.cfg, x.suite + "." + test);
      o.stages = x.c.stages;
      o.quiet = true;
      o.max_errors = 1;
      {
        auto dut = x.cfg->make(DutOptions{seed, false});
        RayAdapter ad(x.c);
        ArraySource src(&recs);
        const RunStats st = run(*dut, ad, src, o);
        ASSERT_TRUE(st.ok()) << "control run failed:\n" << st.errors.front().report;
      }
      auto dut = x.cfg->make(DutOptions{seed, false});
      RayAdapter ad(x.c, m);
      ArraySource src(&recs);
      const RunStats st = run(*dut, ad, src, o);
      ASSERT_FALSE(st.errors.empty()) << "planted error '" << mutant_name(m) << "' went unnoticed on " << recs.size()
                                      << " vectors";
      EXPECT_EQ(st.errors[0].kind, Mismatch::Data);
      std::cerr << "[" << x.suite << "." << test << "] planted error caught at item " << st.errors[0].item
                << " (as expected):\n"
                << st.errors[0].report;
    });
  }
  for (int delta : {+1, -1}) {
    if (delta < 0 && x.c.stages == 0) continue;
    const std::string test = delta > 0 ? "mutant_latency_late" : "mutant_latency_early";
    register_test(x.suite, test, [x, delta, test] {
      const uint64_t seed = x.seed(test);
      const auto recs = gen_random(x, seed, 300);
      RunOptions o = make_options(*x.cfg, x.suite + "." + test);
      o.stages = x.c.stages;
      o.quiet = true;
      o.inject.latency_delta = delta;
      auto dut = x.cfg->make(DutOptions{seed, false});
      RayAdapter ad(x.c);
      ArraySource src(&recs);
      const RunStats st = run(*dut, ad, src, o);
      ASSERT_FALSE(st.errors.empty()) << "a one-cycle latency error went unnoticed";
      EXPECT_EQ(st.errors[0].kind, delta > 0 ? Mismatch::UnexpectedValid : Mismatch::MissingValid);
    });
  }
}

void ray_plan(const ConfigDesc& cfg) {
  Ctx x;
  x.cfg = &cfg;
  x.c = ray_config(cfg);
  const bool is_long = cfg.has_tag("long");
  x.suite = (is_long ? "Long_" : "") + cfg.full_name();
  const size_t k = is_long ? 10 : 1;
  add_gen_test(x, x.suite, "synthetic", gen_synthetic, k * kFastSynthetic, 3000);
  add_gen_test(x, x.suite, "random", gen_random, k * kFastRandom, 3000);
  add_gen_test(x, x.suite, "extremes", gen_extremes, 0, 3000);
  add_gen_test(x, x.suite, "reset", gen_random, k * kFastReset, 40);
  register_test(x.suite, "trace", [x] {
    const std::string path = "ray_trace_" + x.suite + ".rutrace";
    std::string what;
    const auto recs = trace_records(x.c.f, x.box(), path, vector_count(*x.cfg, kFastTrace), what);
    std::remove(path.c_str());
    run_records(x, "trace", recs, 3000, what);
  });
  if (!is_long) {
    const std::string ls = "Long_" + cfg.full_name();
    add_gen_test(x, ls, "random", gen_random, kLongRandom, 3000);
    add_gen_test(x, ls, "synthetic", gen_synthetic, kLongSynthetic, 3000);
  }
  if (cfg.has_tag("selftest")) add_mutants(x);
}

PlanRegistrar r_box("ray_box", ray_plan);
PlanRegistrar r_robust("ray_tri_robust", ray_plan);
PlanRegistrar r_mt("ray_tri_mt", ray_plan);

}  // namespace
}  // namespace ru::tb::ray
