// The registry's golden-model adapters and vector generators (UnitSpec::golden, random_inputs;
// model/src/synth/unit_models.cpp): every unit has them, records fit the fields the ports give,
// and the FP adapters' op mapping (op_i codes, fma negations, record order) agrees with an
// independent oracle: native IEEE single precision on this host.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "rayunits/synth/units.hpp"

namespace {

using namespace ru::synth;
using ru::num::Format;

UnitConfig cfg_for(const UnitSpec& u, const char* fmt) {
  UnitConfig c;
  if (u.uses_format) c.fmt = Format::parse(fmt);
  return c;
}

uint64_t mask(int bits) { return bits >= 64 ? ~0ull : (1ull << bits) - 1; }

TEST(Registry, EveryUnitHasAModelAndAGeneratorWithinItsFields) {
  for (const UnitSpec& u : units()) {
    ASSERT_TRUE(u.golden) << u.name << " has no golden model";
    ASSERT_TRUE(u.random_inputs) << u.name << " has no random vector generator";
    EXPECT_FALSE(u.tests.empty()) << u.name << " has no fast test matrix";
    for (const char* fmt : {"e5m10", "e8m23", "e11m52"}) {
      const UnitConfig c = cfg_for(u, fmt);
      const auto in = fields_for(u, c, PortDir::In), out = fields_for(u, c, PortDir::Out);
      ASSERT_LE(in.size(), 24u);
      ASSERT_LE(out.size(), 24u);
      const GoldenEval g = u.golden(c);
      const InputGen gen = u.random_inputs(c, 7);
      std::vector<uint64_t> x(in.size()), y(out.size());
      size_t nonzero = 0;
      for (int n = 0; n < 300; ++n) {
        gen(x.data());
        for (size_t i = 0; i < in.size(); ++i) {
          ASSERT_EQ(x[i] & ~mask(in[i].bits), 0u) << u.name << " " << fmt << ": generator overflows " << in[i].name;
          if (in[i].kind == FieldKind::Enum) {
            ASSERT_LT(x[i], in[i].enum_names.size()) << u.name << ": undefined " << in[i].name << " code";
          }
        }
        g(x.data(), y.data());
        for (size_t j = 0; j < out.size(); ++j) {
          ASSERT_EQ(y[j] & ~mask(out[j].bits), 0u) << u.name << " " << fmt << ": model overflows " << out[j].name;
          nonzero += y[j] != 0;
        }
      }
      EXPECT_GT(nonzero, 0u) << u.name << " " << fmt << ": the model never produced a non-zero output";
    }
  }
}

TEST(Registry, FieldsSplitPackedPortsLowElementFirst) {
  const UnitSpec& box = find_unit("ray_box");
  const auto in = fields_for(box, cfg_for(box, "e8m23"), PortDir::In);
  ASSERT_EQ(in.size(), 14u);
  EXPECT_EQ(in[0].name, "org.x");
  EXPECT_EQ(in[2].name, "org.z");
  EXPECT_EQ(in[6].name, "tmin_i");  // a scalar port is one field named after it
  EXPECT_EQ(in[8].name, "bmin.x");
  EXPECT_EQ(in[8].port, "bmin_i");
  EXPECT_EQ(in[8].bits, 32);
  const UnitSpec& tri = find_unit("ray_tri_robust");
  const auto out = fields_for(tri, cfg_for(tri, "e5m10"), PortDir::Out);
  ASSERT_EQ(out.size(), 10u);
  EXPECT_EQ(out[1].kind, FieldKind::Enum);
  EXPECT_EQ(out[5].name, "V");
  EXPECT_EQ(out[9].name, "V2");
  EXPECT_EQ(out[9].elem, 4);
}

TEST(Registry, ConfigFromParamsInvertsParamsFor) {
  for (const UnitSpec& u : units()) {
    UnitConfig c = cfg_for(u, "e7m16");
    c.fmt.round = ru::num::Round::RDN;
    c.stages = u.max_stages(c) + 1;  // one past the maximum is accepted (the tb runs it)
    for (const auto& p : u.extra_params) {
      c.params[p.name] = p.hi > p.def ? p.def + 1 : p.def;
      if (u.check) {  // a value the unit's constraints refuse (texture Units 5): its lowest instead
        try {
          u.check(c);
        } catch (const SynthError&) {
          c.params[p.name] = p.lo;
        }
      }
    }
    std::map<std::string, long long> m;
    for (const auto& [k, v] : params_for(u, c)) m[k] = v;
    const UnitConfig back = config_from_params(u, m);
    EXPECT_EQ(params_for(u, back), params_for(u, c)) << u.name;
    m["NoSuchParam"] = 1;
    EXPECT_THROW(config_from_params(u, m), SynthError) << u.name;
  }
}

float f32(uint64_t b) {
  const uint32_t w = static_cast<uint32_t>(b);
  float f;
  std::memcpy(&f, &w, 4);
  return f;
}
uint64_t bits(float f) {
  uint32_t w;
  std::memcpy(&w, &f, 4);
  return w;
}
bool same(float got, float want) { return (std::isnan(got) && std::isnan(want)) || bits(got) == bits(want); }

// The native oracle of each FP unit's op codes, over the registry's record (operands, then op).
TEST(Registry, FpGoldenModelsAgreeWithNativeFloat) {
  struct Case {
    const char* unit;
    std::function<float(const std::vector<float>& x, uint64_t op)> ref;
  };
  const std::vector<Case> cases = {
      {"fp_add", [](const std::vector<float>& x, uint64_t op) { return op ? x[0] - x[1] : x[0] + x[1]; }},
      {"fp_mul", [](const std::vector<float>& x, uint64_t) { return x[0] * x[1]; }},
      {"fp_div", [](const std::vector<float>& x, uint64_t) { return x[0] / x[1]; }},
      {"fp_sqrt", [](const std::vector<float>& x, uint64_t) { return std::sqrt(x[0]); }},
      {"fp_fma", [](const std::vector<float>& x, uint64_t op) {
         return std::fma((op & 2) ? -x[0] : x[0], x[1], (op & 1) ? -x[2] : x[2]);
       }},
  };
  for (const Case& k : cases) {
    const UnitSpec& u = find_unit(k.unit);
    const UnitConfig c = cfg_for(u, "e8m23");
    const auto in = fields_for(u, c, PortDir::In);
    const GoldenEval g = u.golden(c);
    const InputGen gen = u.random_inputs(c, 11);
    std::vector<uint64_t> x(in.size()), y(2);
    int checked = 0;
    for (int n = 0; n < 20000; ++n) {
      gen(x.data());
      std::vector<float> xf;
      uint64_t op = 0;
      for (size_t i = 0; i < in.size(); ++i) {
        if (in[i].kind == FieldKind::Float) xf.push_back(f32(x[i]));
        if (in[i].port == "op_i") op = x[i];
      }
      g(x.data(), y.data());
      const float want = k.ref(xf, op);
      ASSERT_TRUE(same(f32(y[0]), want)) << k.unit << " op " << op << ": model " << std::hex << y[0] << ", native "
                                         << bits(want);
      ++checked;
    }
    EXPECT_EQ(checked, 20000);
  }
}

}  // namespace
