// rayunits tb: test plan of the noise units ru_noise (rtl/ru_noise.sv, unit `noise`) and
// ru_noise_trunc (rtl/ru_noise_trunc.sv, unit `noise_trunc`) against the bit-accurate model
// ru::noise::FixedNoise (the registry's golden model; NoiseDatapath kFull or kTrunc), on the
// generic cycle-by-cycle scoreboard (tb/README.md). The same plan for both units.
//
// Configuration parameters: FracBits, IntBits, OutW (RTL defaults 8, 8, 10) and Stages.
// Ports: x_i, y_i, z_i (IntBits+FracBits bits each), value_o (OutW bits).
// Tests per configuration (suite noise_<cfg>; Long_noise_<cfg> for long configurations):
//   random      uniformly random words over the whole input range (negative coordinates, both
//               table ends, input wrap-around included)            20,000 (long: 10^6)
//   negative    coordinates with negative integer parts, down to the most negative word
//   grid        dense sweeps: x through 4 cells at every LSB (y, z fixed), and a 3D grid with
//               4 points per cell over 8 x 8 x 8 cells around the origin (negative and positive)
//   wrap        cells 254, 255, 0, 1 of the tables (and 256, 257 when IntBits > 8), the largest
//               and smallest words, and x vs x + 256 cells
//   cell        fractional inputs of one cell (cell x = 255: the hash-table wrap), see
//               cell_source(): all of them when 3 FracBits <= 15, else every (fx, fy) with four
//               fz (FracBits <= 8); Long_noise_<cfg>.cell: all 2^(3 FracBits) up to 2^24 (the
//               whole cell at the default FracBits = 8), 2^24 random fractions beyond
//   reset       random vectors with a reset every ~40 cycles
//   inject_*    (configurations tagged selftest) planted errors the harness must report
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>

#include "rayunits/noise/fixed.hpp"
#include "rayunits/tb/harness.hpp"
#include "rayunits/tb/registry_adapter.hpp"
#include "rayunits/tb/testing.hpp"

namespace ru::tb {
namespace {

using ru::noise::FixedConfig;
using ru::noise::FixedNoise;

// The unit of a datapath and back.
const char* unit_name(const FixedConfig& c) { return c.datapath == ru::noise::NoiseDatapath::kTrunc ? "noise_trunc" : "noise"; }

FixedConfig noise_config(const ConfigDesc& cfg) {
  // parameters not set take the registry's defaults
  const synth::UnitSpec& u = synth::find_unit(cfg.unit);
  const synth::UnitConfig uc = unit_config(cfg);
  FixedConfig c;
  c.frac_bits = static_cast<int>(synth::param_value(u, uc, "FracBits"));
  c.int_bits = static_cast<int>(synth::param_value(u, uc, "IntBits"));
  c.out_w = static_cast<int>(synth::param_value(u, uc, "OutW"));
  c.datapath = cfg.unit == "noise_trunc" ? ru::noise::NoiseDatapath::kTrunc : ru::noise::NoiseDatapath::kFull;
  c.validate();
  return c;
}

synth::UnitConfig noise_unit_config(const FixedConfig& c, int stages) {
  synth::UnitConfig u;
  u.stages = stages;
  u.params = {{"FracBits", c.frac_bits}, {"IntBits", c.int_bits}, {"OutW", c.out_w}};
  return u;
}

// The registry adapter (ports, records, golden model ru::noise::FixedNoise: registry_adapter.hpp),
// printing values as coordinates and noise values.
class NoiseAdapter final : public RegistryAdapter {
 public:
  NoiseAdapter(const FixedConfig& c, int stages)
      : RegistryAdapter(synth::find_unit(unit_name(c)), noise_unit_config(c, stages)), model_(c) {}
  std::string decimal(const FieldInfo& f, std::uint64_t v) const override {
    char b[64];
    if (f.name == "value_o") {
      std::int64_t s = static_cast<std::int64_t>(v << (64 - f.bits)) >> (64 - f.bits);
      std::snprintf(b, sizeof b, "%lld = N %.9g", static_cast<long long>(s), model_.to_real(s));
    } else {
      std::snprintf(b, sizeof b, "u = %.9g cells", model_.input_real(static_cast<std::int64_t>(v)));
    }
    return b;
  }

 private:
  FixedNoise model_;
};

// A source defined by a function of the vector index.
class FnSource final : public VectorSource {
 public:
  FnSource(std::uint64_t n, std::function<void(std::uint64_t, Record&)> f) : n_(n), f_(std::move(f)) {}
  bool next(Record& in) override {
    if (i_ >= n_) return false;
    in = Record{};
    f_(i_++, in);
    return true;
  }
  std::uint64_t total() const override { return n_; }

 private:
  std::uint64_t n_, i_ = 0;
  std::function<void(std::uint64_t, Record&)> f_;
};

struct Ctx {
  const ConfigDesc* cfg = nullptr;
  FixedConfig fc;
  int stages = 0;
  std::string suite;

  std::uint64_t mask() const { return (1ull << fc.in_w()) - 1; }
  std::uint64_t word(std::int64_t cell, std::int64_t frac) const {
    return static_cast<std::uint64_t>(cell * (std::int64_t{1} << fc.frac_bits) + frac) & mask();
  }
  std::uint64_t seed(const std::string& test) const { return mix_seed(global_options().seed, suite + "." + test); }
  ScoreboardTest make(const std::string& test) const {
    ScoreboardTest t;
    t.cfg = cfg;
    t.name = suite + "." + test;
    const FixedConfig c = fc;
    const int st = stages;
    t.adapter = [c, st] { return std::make_unique<NoiseAdapter>(c, st); };
    t.opt = make_options(*cfg, t.name);
    t.opt.format = c.describe();
    return t;
  }
};

using SourceFn = std::function<std::unique_ptr<VectorSource>()>;


void add(const Ctx& c, const std::string& suite, const std::string& test, std::function<SourceFn(const Ctx&)> src,
         std::uint32_t reset_every = 3000) {
  Ctx cc = c;
  cc.suite = suite;
  register_test(suite, test, [cc, test, src, reset_every] {
    ScoreboardTest t = cc.make(test);
    t.source = src(cc);
    t.opt.reset_every = reset_every;
    const std::uint64_t n = t.source()->total();
    expect_clean(t.name, run_scoreboard(t), n);
  });
}

// The registry's generator (UnitSpec::random_inputs: uniform words over the whole input range).
SourceFn random_source(const Ctx& c, std::uint64_t n, const std::string& test) {
  const std::uint64_t seed = c.seed(test);
  const synth::UnitConfig uc = noise_unit_config(c.fc, c.stages);
  const std::string unit = unit_name(c.fc);
  return [seed, uc, n, unit] { return registry_random_source(synth::find_unit(unit), uc, seed, n); };
}

SourceFn negative_source(const Ctx& c, std::uint64_t n) {
  const std::uint64_t seed = c.seed("negative"), m = c.mask();
  const int w = c.fc.in_w();
  return [seed, m, w, n] {
    auto rng = std::make_shared<Rng>(seed);
    return std::make_unique<FnSource>(n, [rng, m, w](std::uint64_t i, Record& r) {
      for (int a = 0; a < 3; ++a) {
        std::uint64_t v = rng->next() & m;
        switch ((i + a) % 4) {
          case 0: v |= 1ull << (w - 1); break;                            // any negative word
          case 1: v = (m - (rng->next() & 0x3ff)) & m; break;                // just below zero
          case 2: v = ((1ull << (w - 1)) + (rng->next() & 0x3ff)) & m; break;  // most negative
          default: break;                                                    // mixed signs
        }
        r.v[a] = v;
      }
    });
  };
}

SourceFn grid_source(const Ctx& c) {
  const Ctx cc = c;
  const std::int64_t one = std::int64_t{1} << c.fc.frac_bits;
  const std::uint64_t sweep = 4 * static_cast<std::uint64_t>(one) * 3;  // x, y and z sweeps
  const std::uint64_t grid = 32ull * 32 * 32;                          // 4 points per cell, 8 cells
  return [cc, one, sweep, grid] {
    return std::make_unique<FnSource>(sweep + grid, [cc, one, sweep](std::uint64_t i, Record& r) {
      if (i < sweep) {
        // one axis through cells -2..1 at every LSB, the others fixed
        const std::uint64_t axis = i / (4 * one), k = i % (4 * one);
        const std::uint64_t fixed1 = cc.word(5, one / 3), fixed2 = cc.word(-7, (2 * one) / 3);
        for (int a = 0; a < 3; ++a) r.v[a] = a == static_cast<int>(axis) ? cc.word(-2, static_cast<std::int64_t>(k)) : (a == 0 ? fixed1 : fixed2);
        return;
      }
      const std::uint64_t g = i - sweep;
      const std::int64_t step = one / 4;
      for (int a = 0; a < 3; ++a) {
        const std::int64_t p = static_cast<std::int64_t>((g >> (5 * a)) & 31);  // 0..31
        r.v[a] = cc.word(p / 4 - 4, (p % 4) * step + (a + 1) % (step > 1 ? step : 1));
      }
    });
  };
}

SourceFn wrap_source(const Ctx& c) {
  const Ctx cc = c;
  const std::uint64_t seed = c.seed("wrap");
  const std::int64_t one = std::int64_t{1} << c.fc.frac_bits;
  std::vector<std::int64_t> cells = {254, 255, 0, 1, -1, -2};
  if (c.fc.int_bits > 8) cells.insert(cells.end(), {256, 257, -256, -257});
  const std::uint64_t n = 6000;
  return [cc, seed, one, cells, n] {
    auto rng = std::make_shared<Rng>(seed);
    return std::make_unique<FnSource>(n, [cc, rng, one, cells](std::uint64_t i, Record& r) {
      const std::uint64_t m = cc.mask(), top = 1ull << (cc.fc.in_w() - 1);
      switch (i % 6) {
        case 0:
        case 1:
        case 2:
          for (int a = 0; a < 3; ++a)
            r.v[a] = cc.word(cells[rng->below(cells.size())], static_cast<std::int64_t>(rng->below(one)));
          break;
        case 3:  // extremes of the input range
          for (int a = 0; a < 3; ++a) {
            const std::uint64_t e[4] = {top - 1, top, m, 0};
            r.v[a] = (e[rng->below(4)] ^ (rng->below(4))) & m;
          }
          break;
        default:  // fractions at 0, 1 LSB, 1/2 and 1 - 1 LSB next to a table boundary
          for (int a = 0; a < 3; ++a) {
            const std::int64_t f[4] = {0, 1, one / 2, one - 1};
            r.v[a] = cc.word(cells[rng->below(cells.size())], f[rng->below(4)]);
          }
      }
    });
  };
}

// One cell (x in cell 255, the last table entry: its next-hash wraps to entry 0). Fractions:
//   3B <= 15, or full and 3B <= 24: all 2^(3B);
//   else B <= 8: every (fx, fy) with fz in {0, 1, 1/2, 1 - 1 LSB};
//   else 256 x 256 values of (fx, fy) spread over the cell (every 2^(B-8)-th LSB plus a varying
//   offset) with the same four fz; full (long): 2^24 uniformly random fractions.
SourceFn cell_source(const Ctx& c, bool full) {
  const Ctx cc = c;
  const int B = c.fc.frac_bits;
  const std::uint64_t one = 1ull << B;
  enum Mode { kAll, kPlane, kSpread, kRandom };
  const Mode mode = (3 * B <= 15 || (full && 3 * B <= 24)) ? kAll : full ? kRandom : B <= 8 ? kPlane : kSpread;
  const std::uint64_t n = mode == kAll ? one * one * one : mode == kPlane ? one * one * 4 : mode == kSpread ? 256 * 256 * 4 : 1ull << 24;
  const std::uint64_t seed = c.seed("cell");
  return [cc, one, mode, n, B, seed] {
    auto rng = std::make_shared<Rng>(seed);
    return std::make_unique<FnSource>(n, [cc, one, mode, B, rng](std::uint64_t i, Record& r) {
      const std::uint64_t zs[4] = {0, 1, one / 2, one - 1};
      std::uint64_t fx, fy, fz;
      switch (mode) {
        case kAll:
          fx = i % one, fy = (i / one) % one, fz = i / (one * one);
          break;
        case kPlane:
          fx = i % one, fy = (i / one) % one, fz = zs[i / (one * one)];
          break;
        case kSpread: {
          const std::uint64_t s = 1ull << (B - 8), a = i % 256, b = (i / 256) % 256;
          fx = a * s + (a * 37 + b) % s, fy = b * s + (b * 53 + a) % s, fz = zs[i / 65536];
          break;
        }
        default:
          fx = rng->below(one), fy = rng->below(one), fz = rng->below(one);
      }
      r.v[0] = cc.word(255, static_cast<std::int64_t>(fx));
      r.v[1] = cc.word(-1, static_cast<std::int64_t>(fy));
      r.v[2] = cc.word(100, static_cast<std::int64_t>(fz));
    });
  };
}

// The planted harness errors (tb/include/rayunits/tb/testing.hpp), plus a planted model error.
void add_selftests(const Ctx& c) {
  SelftestPlan p;
  p.suite = c.suite;
  p.stages = c.stages;
  p.make = [c](const std::string& test) { return c.make(test); };
  p.seed = [c](const std::string& test) { return c.seed(test); };
  p.random = [c](const std::string& test, uint64_t n) { return random_source(c, n, test); };
  p.out_bits = {c.fc.out_w};
  add_harness_selftests(p);
  // A planted model error: the RTL against a model whose gradient table has one component off
  // by one LSB must mismatch (the scoreboard sees table errors, not only output bit flips).
  const std::string note = "(planted error: the MISMATCH report below is expected)\n";
  register_test(c.suite, "inject_table", [c, note] {
    ScoreboardTest t = c.make("inject_table");
    t.source = random_source(c, 3000, "inject_table");
    const FixedConfig fc = c.fc;
    const int st_ = c.stages;
    t.adapter = [fc, st_] {
      struct Bad final : public UnitAdapter {
        NoiseAdapter good;
        FixedNoise bad;
        Bad(const FixedConfig& f, int s, const ru::noise::TableSet& tab) : good(f, s), bad(f, tab) {}
        std::string describe() const override { return good.describe() + " (planted table error)"; }
        const std::vector<FieldInfo>& inputs() const override { return good.inputs(); }
        const std::vector<FieldInfo>& outputs() const override { return good.outputs(); }
        void bind(const PortMap& p) override { good.bind(p); }
        void drive(const Record& in) override { good.drive(in); }
        void read(Record& out) override { good.read(out); }
        void model(const Record& in, Record& out) override {
          out.v[0] = static_cast<std::uint64_t>(bad.eval(static_cast<std::int64_t>(in.v[0]), static_cast<std::int64_t>(in.v[1]),
                                                         static_cast<std::int64_t>(in.v[2]))) &
                     good.outputs()[0].mask();
        }
      };
      ru::noise::TableSet tab = ru::noise::builtin_tables();
      tab.grad64_q16[9][2] += 1 << (16 - FixedNoise(fc).grad_frac_bits());  // one LSB of the unit's table
      return std::unique_ptr<UnitAdapter>(new Bad(fc, st_, tab));
    };
    std::cerr << note;
    const RunStats st = run_scoreboard(t);
    ASSERT_FALSE(st.errors.empty()) << "a wrong gradient-table entry went unnoticed";
    EXPECT_EQ(st.errors[0].kind, Mismatch::Data);
  });
}

void noise_plan(const ConfigDesc& cfg) {
  Ctx c;
  c.cfg = &cfg;
  c.fc = noise_config(cfg);
  c.stages = static_cast<int>(cfg.param("Stages", 0));
  const bool is_long = cfg.has_tag("long");
  c.suite = (is_long ? "Long_" : "") + cfg.full_name();
  const std::uint64_t nrand = vector_count(cfg, is_long ? 1000000 : 20000);
  add(c, c.suite, "random", [nrand](const Ctx& x) { return random_source(x, nrand, "random"); });
  add(c, c.suite, "negative", [](const Ctx& x) { return negative_source(x, 5000); });
  add(c, c.suite, "grid", [](const Ctx& x) { return grid_source(x); });
  add(c, c.suite, "wrap", [](const Ctx& x) { return wrap_source(x); });
  add(c, c.suite, "cell", [is_long](const Ctx& x) { return cell_source(x, is_long); }, 50000);
  add(c, c.suite, "reset", [](const Ctx& x) { return random_source(x, 5000, "reset"); }, 40);
  if (!is_long) {
    add(c, "Long_" + cfg.full_name(), "random", [](const Ctx& x) { return random_source(x, 1000000, "random"); });
    if (3 * c.fc.frac_bits > 15)
      add(c, "Long_" + cfg.full_name(), "cell", [](const Ctx& x) { return cell_source(x, true); }, 500000);
  }
  if (cfg.has_tag("selftest")) add_selftests(c);
}

PlanRegistrar r_noise("noise", noise_plan);
PlanRegistrar r_noise_trunc("noise_trunc", noise_plan);

}  // namespace
}  // namespace ru::tb
