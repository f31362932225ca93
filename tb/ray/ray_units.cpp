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
  const synth::UnitConfig uc = unit_config(cfg);  // the registry decodes and range-checks the parameters
  c.f = uc.fmt;
  c.stages = uc.stages;
  const int64_t cons = cfg.param("OptConservative", 0);
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
// Adapter: the registry's, with the planted errors in its golden model

synth::UnitConfig ray_unit_config(const RayConfig& c) {
  synth::UnitConfig u;
  u.fmt = c.f;
  u.stages = c.stages;
  if (c.unit == Unit::Box) {
    u.params["OptConservative"] = c.dcons ? 2 : c.conservative ? 1 : 0;
    return u;
  }
  if (c.unit == Unit::Robust) {
    u.params["OptTieBreak"] = c.tie_break;
    u.params["OptRecip"] = c.recip;
  }
  u.params["OptEpsTest"] = c.eps_test;
  u.params["EpsBits"] = static_cast<long long>(c.eps_bits);
  u.params["OptVolOut"] = c.vol_out;
  return u;
}

std::unique_ptr<RegistryAdapter> ray_adapter(const RayConfig& c, Mutant m) {
  const char* unit = c.unit == Unit::Box ? "ray_box" : c.unit == Unit::Robust ? "ray_tri_robust" : "ray_tri_mt";
  const synth::UnitConfig rtl = ray_unit_config(c);
  RayConfig mc = c;
  switch (m) {
    case Mutant::None:
    case Mutant::InputLsb: break;
    case Mutant::Rounding: mc.f.round = ru::num::Round::RTZ; break;  // every op rounds toward zero
    case Mutant::ModeSwap:
      mc.conservative = c.dcons || !c.conservative;  // plain <-> conservative, d-conservative -> conservative
      mc.dcons = false;
      mc.tie_break = !c.tie_break;
      mc.recip = !c.recip;
      break;
  }
  synth::UnitConfig model = ray_unit_config(mc);
  model.stages = rtl.stages;
  auto ad = std::make_unique<RegistryAdapter>(synth::find_unit(unit), rtl, model);
  if (m == Mutant::InputLsb) ad->set_model_input_hook([](Record& in) { in.v[4] ^= 1; });  // rdir.y / d.y
  if (m != Mutant::None) ad->set_note(std::string("[planted: ") + mutant_name(m) + "]");
  return ad;
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
    t.adapter = [rc] { return ray_adapter(rc); };
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
    const uint64_t o = in.v[k], inv = in.v[3 + k], lo = in.v[8 + k], hi = in.v[11 + k];  // registry order
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
  auto ad = ray_adapter(x.c);
  RayConfig cv = x.c;
  cv.vol_out = true;
  auto advol = ray_adapter(cv);  // volumes for the coverage count
  Mix m;
  Record out;
  for (const Record& r : recs) {
    ad->model(r, out);
    ++m.n;
    m.hits += out.v[0] & 1;
    if (x.box()) {
      box_coverage(x.c, r, m);
      continue;
    }
    if (out.v[1] < 5) ++m.why[out.v[1]];
    advol->model(r, out);
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
        auto ad = ray_adapter(x.c);
        ArraySource src(&recs);
        const RunStats st = run(*dut, *ad, src, o);
        ASSERT_TRUE(st.ok()) << "control run failed:\n" << st.errors.front().report;
      }
      auto dut = x.cfg->make(DutOptions{seed, false});
      auto ad = ray_adapter(x.c, m);
      ArraySource src(&recs);
      const RunStats st = run(*dut, *ad, src, o);
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
      auto ad = ray_adapter(x.c);
      ArraySource src(&recs);
      const RunStats st = run(*dut, *ad, src, o);
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
