// rayunits tb: the test plan of the conversion unit fp_cvt (rtl/ru_fp_cvt.sv). For each
// configuration <unit>_<cfg>, on top of the generic plan (random, reset, inject_*, Long_ random:
// tb/src/registry_plan.cpp, vectors from the registry's generator, models::fp_cvt_inputs):
//   special     every op x its source's special values: f2f the TestFloat-style special values
//               of G, f2i and f2i_rtz those of F, i2f the integer edges (0, +-1, the range ends,
//               +-2^k and +-2^k +- 1 for every k)
//   exhaustive  (tag) every op x every bit pattern of its source (G's width, IntW, F's width;
//               each at most 16 bits), the ignored bits of a_i zero
#include <gtest/gtest.h>

#include <algorithm>

#include "rayunits/num/patterns.hpp"
#include "rayunits/synth/unit_models.hpp"
#include "rayunits/tb/registry_adapter.hpp"
#include "rayunits/tb/testing.hpp"

namespace ru::tb {
namespace {

constexpr int kMaxExhaustiveBits = 16;

using synth::models::low_bits;

// Records {a_i, op_i} of the special test.
std::vector<Record> special_records(const synth::models::CvtFormats& v) {
  std::vector<Record> r;
  auto put = [&](uint64_t a, uint64_t op) {
    Record x;
    x.v[0] = a;
    x.v[1] = op;
    r.push_back(x);
  };
  for (uint64_t a : num::special_values(v.g)) put(a, 0);
  std::vector<uint64_t> ints = {0, 1, low_bits(~0ull, v.int_w)};
  for (int k = 1; k < v.int_w; ++k)
    for (int64_t d : {-1, 0, 1})
      for (bool neg : {false, true}) {
        const uint64_t m = (1ull << k) + static_cast<uint64_t>(d);
        ints.push_back(low_bits(neg ? 0 - m : m, v.int_w));
      }
  std::sort(ints.begin(), ints.end());
  ints.erase(std::unique(ints.begin(), ints.end()), ints.end());
  for (uint64_t a : ints) put(a, 1);
  for (uint64_t op : {2, 3})
    for (uint64_t a : num::special_values(v.f)) put(a, op);
  return r;
}

// Every op x every pattern of its source width.
class Exhaustive final : public VectorSource {
 public:
  explicit Exhaustive(const synth::models::CvtFormats& v) : w_{v.g.width(), v.int_w, v.f.width(), v.f.width()} {}
  bool next(Record& r) override {
    while (op_ < 4 && a_ >> w_[op_]) ++op_, a_ = 0;
    if (op_ >= 4) return false;
    r = Record{};
    r.v[0] = a_++;
    r.v[1] = op_;
    return true;
  }
  uint64_t total() const override {
    uint64_t n = 0;
    for (int w : w_) n += 1ull << w;
    return n;
  }

 private:
  int w_[4];
  uint64_t op_ = 0, a_ = 0;
};

void cvt_plan(const ConfigDesc& cfg) {
  registry_plan(cfg);
  const synth::UnitSpec* u = &synth::find_unit(cfg.unit);
  const synth::UnitConfig uc = unit_config(cfg);
  const synth::models::CvtFormats v = synth::models::cvt_formats(uc);
  const std::string suite = (cfg.has_tag("long") ? "Long_" : "") + cfg.full_name();
  auto make = [&cfg, u, uc, suite](const std::string& test) {
    ScoreboardTest t;
    t.cfg = &cfg;
    t.name = suite + "." + test;
    t.adapter = [u, uc] { return std::make_unique<RegistryAdapter>(*u, uc); };
    t.opt = make_options(cfg, t.name);
    return t;
  };
  register_test(suite, "special", [make, v] {
    ScoreboardTest t = make("special");
    const std::vector<Record> recs = special_records(v);
    t.source = [recs] { return std::make_unique<ArraySource>(recs); };
    expect_clean(t.name, run_scoreboard(t), recs.size());
  });
  if (cfg.has_tag("exhaustive")) {
    register_test(suite, "exhaustive", [make, v] {
      ScoreboardTest t = make("exhaustive");
      if (std::max({v.g.width(), v.int_w, v.f.width()}) > kMaxExhaustiveBits)
        FAIL() << "exhaustive: a source wider than " << kMaxExhaustiveBits << " bits";
      t.source = [v] { return std::make_unique<Exhaustive>(v); };
      t.opt.reset_every = 20000;
      expect_clean(t.name, run_scoreboard(t), Exhaustive(v).total());
    });
  }
}

PlanRegistrar r_cvt("fp_cvt", cvt_plan);

}  // namespace
}  // namespace ru::tb
