// tb/texture: the test plan of the unit texture (ru_texture, the procedural texture unit of issue
// 15 §2) on the shared scoreboard. The unit has a handshake (in_ready_o): a request of n octaves
// (oct_i clamped to 1..Octaves) occupies the sequencer for K = ceil(n / Units) cycles and its
// result leaves K + Stages + RootStages cycles after acceptance, results in acceptance order. The scoreboard
// checks every result bit against the golden model (noise::FixedTexture) and, in every cycle,
// in_ready_o and out_valid_o against TextureTiming below (the rules of rtl/ru_texture.sv's
// header), so each result's cycle is checked exactly.
//
// Per configuration (UnitSpec tests / long_tests): the generic plan (tb/src/registry_plan.cpp:
// the registry generator's random requests -- whole-range words, every mode incl. the unused
// codes, octave counts 0..15 with full ones weighted -- with random traffic and resets, and the
// harness's planted errors with the selftest tag) plus:
//   per_mode    each mode with full octave counts, back to back
//   lattice     points on and next to lattice planes (fractions 0, 1, 255 of the noise grid)
//               where wood's square root and the octave shifts meet their edge cases
#include <gtest/gtest.h>

#include <algorithm>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "rayunits/noise/texture.hpp"
#include "rayunits/synth/unit_models.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/tb/registry_adapter.hpp"
#include "rayunits/tb/testing.hpp"

namespace ru::tb {
namespace {

// Input fields: x_i, y_i, z_i, mode_i, oct_i.
class TextureTiming final : public HandshakeTiming {
 public:
  TextureTiming(int units, int octaves, int latency) : units_(units), octaves_(octaves), latency_(latency) {}
  bool ready() const override { return busy_ == 0; }
  bool step(uint64_t cycle, const Record* acc) override {
    if (busy_ > 0) --busy_;
    if (acc) {
      const int n = std::clamp(static_cast<int>(acc->v[4]), 1, octaves_);
      const int k = noise::texture_groups(n, units_);
      busy_ = k - 1;
      due_.push_back(cycle + static_cast<uint64_t>(k + latency_));
    }
    const bool out = !due_.empty() && due_.front() == cycle;
    if (out) due_.pop_front();
    return out;
  }
  void reset() override {
    due_.clear();
    busy_ = 0;
  }

 private:
  int units_, octaves_, latency_;
  int busy_ = 0;  // cycles the sequencer is still busy after this one
  std::deque<uint64_t> due_;
};

void texture_plan(const ConfigDesc& cfg) {
  const synth::UnitSpec& u = synth::find_unit(cfg.unit);
  const synth::UnitConfig uc = unit_config(cfg);
  const noise::TextureConfig tc = synth::models::texture_config(uc);
  const int units = static_cast<int>(synth::param_value(u, uc, "Units"));
  const int root = static_cast<int>(synth::param_value(u, uc, "RootStages"));
  RegistryPlanHooks h;
  h.timing = true;
  const int worst = noise::texture_groups(tc.octaves, units) + uc.stages + root;
  h.options = [units, tc, worst, root](RunOptions& o) {
    o.max_latency = worst + 1;
    o.timing = [units, tc, root](const RunOptions& ro) {
      return std::make_unique<TextureTiming>(units, tc.octaves, ro.stages + root + ro.inject.latency_delta);
    };
  };
  registry_plan(cfg, h);
  const std::string suite = (cfg.has_tag("long") ? "Long_" : "") + cfg.full_name();
  const uint64_t mask = (1ull << tc.in_w()) - 1;
  // every mode, full octave counts, random points
  register_test(suite, "per_mode", [cfg, h, tc, mask] {
    ScoreboardTest t = registry_test(cfg, "per_mode", 0, h);
    util::Xoshiro256ss g(mix_seed(global_options().seed, "per_mode"));
    std::vector<Record> v;
    for (int m = 0; m < noise::kTextureModes; ++m)
      for (int i = 0; i < 600; ++i) {
        Record r{};
        for (int a = 0; a < 3; ++a) r.v[a] = g.next() & mask;
        r.v[3] = static_cast<uint64_t>(m);
        r.v[4] = static_cast<uint64_t>(tc.octaves);
        v.push_back(r);
      }
    t.source = [v] { return std::make_unique<ArraySource>(v); };
    t.opt.traffic = Traffic::BackToBack;
    expect_clean(t.name, run_scoreboard(t), v.size());
  });
  // points on and next to the noise lattice planes (fraction words 0, 1, 2^B - 1 in every octave's
  // view), small and extreme coordinates, every mode and octave count
  register_test(suite, "lattice", [cfg, h, tc, mask] {
    ScoreboardTest t = registry_test(cfg, "lattice", 0, h);
    util::Xoshiro256ss g(mix_seed(global_options().seed, "lattice"));
    const int f = tc.in_frac();
    std::vector<Record> v;
    for (int i = 0; i < 4000; ++i) {
      Record r{};
      for (int a = 0; a < 3; ++a) {
        const uint64_t cell = g.next() % 16, k = g.next() % 4;
        const int64_t sgn = (g.next() & 1) ? -1 : 1;
        const int64_t fr = k == 0 ? 0 : k == 1 ? 1 : k == 2 ? (int64_t{1} << f) - 1 : static_cast<int64_t>(g.next() & ((1ull << f) - 1));
        r.v[a] = static_cast<uint64_t>(sgn * static_cast<int64_t>(cell << f) + fr) & mask;
      }
      if (i % 50 == 0) r.v[i % 3] = mask >> 1;           // the largest positive word
      if (i % 50 == 1) r.v[i % 3] = (mask >> 1) + 1;     // the most negative one
      r.v[3] = g.next() % noise::kTextureModes;
      r.v[4] = 1 + g.next() % static_cast<uint64_t>(tc.octaves);
      v.push_back(r);
    }
    t.source = [v] { return std::make_unique<ArraySource>(v); };
    expect_clean(t.name, run_scoreboard(t), v.size());
  });
}

PlanRegistrar r_texture("texture", texture_plan);

}  // namespace
}  // namespace ru::tb
