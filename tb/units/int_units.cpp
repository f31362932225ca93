// rayunits tb: the test plans of the integer units int_alu (rtl/ru_int_alu.sv) and branch
// (rtl/ru_branch.sv). For each configuration, on top of the generic plan (random, reset,
// inject_*, Long_ random: tb/src/registry_plan.cpp, vectors from models::int_alu_inputs /
// branch_inputs):
//   exhaustive  (tag) every input combination: every value of every input field of the registry
//               (int_alu: a, b, op_i; branch: a, b, pc, off, op_i; at most 2^20 records)
#include <gtest/gtest.h>

#include "rayunits/synth/unit_models.hpp"
#include "rayunits/tb/registry_adapter.hpp"
#include "rayunits/tb/testing.hpp"

namespace ru::tb {
namespace {

constexpr int kMaxExhaustiveBits = 20;

// Every combination of fields of the given widths, field 0 fastest.
class AllCombinations final : public VectorSource {
 public:
  explicit AllCombinations(std::vector<int> bits) : bits_(std::move(bits)), cur_(bits_.size(), 0) {}
  bool next(Record& r) override {
    if (done_) return false;
    r = Record{};
    for (size_t i = 0; i < cur_.size(); ++i) r.v[i] = cur_[i];
    size_t i = 0;
    while (i < cur_.size() && ++cur_[i] >> bits_[i]) cur_[i++] = 0;
    done_ = i == cur_.size();
    return true;
  }
  uint64_t total() const override {
    int n = 0;
    for (int b : bits_) n += b;
    return 1ull << n;
  }

 private:
  std::vector<int> bits_;
  std::vector<uint64_t> cur_;
  bool done_ = false;
};

void int_plan(const ConfigDesc& cfg) {
  registry_plan(cfg);
  if (!cfg.has_tag("exhaustive")) return;
  const synth::UnitSpec* u = &synth::find_unit(cfg.unit);
  const synth::UnitConfig uc = unit_config(cfg);
  std::vector<int> bits;  // every input field's width, from the registry (ports, parameters)
  for (const synth::Field& f : synth::fields_for(*u, uc, synth::PortDir::In)) bits.push_back(f.bits);
  const std::string suite = (cfg.has_tag("long") ? "Long_" : "") + cfg.full_name();
  register_test(suite, "exhaustive", [&cfg, u, uc, suite, bits] {
    ScoreboardTest t;
    t.cfg = &cfg;
    t.name = suite + ".exhaustive";
    t.adapter = [u, uc] { return std::make_unique<RegistryAdapter>(*u, uc); };
    t.opt = make_options(cfg, t.name);
    const AllCombinations all(bits);
    int n = 0;
    for (int b : bits) n += b;
    if (n > kMaxExhaustiveBits) FAIL() << "exhaustive: " << n << " input bits (at most " << kMaxExhaustiveBits << ")";
    t.source = [bits] { return std::make_unique<AllCombinations>(bits); };
    t.opt.reset_every = 20000;
    expect_clean(t.name, run_scoreboard(t), all.total());
  });
}

PlanRegistrar r_alu("int_alu", int_plan);
PlanRegistrar r_branch("branch", int_plan);

}  // namespace
}  // namespace ru::tb
