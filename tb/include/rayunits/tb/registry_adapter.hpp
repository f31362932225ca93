// rayunits tb: the one adapter between the scoreboard and any registered unit.
//
// Everything comes from the unit registry (model/include/rayunits/synth/units.hpp): the input and
// output records are the fields of the unit's data ports (synth::fields_for: ports in declaration
// order, packed vector ports split into their elements, element 0 in the low bits), the ports
// are bound by name and their widths checked against the registry, and the expected outputs are
// the registry's golden model (UnitSpec::golden) of the configuration. A unit's test plan may
// add vector sources and printing on top (tb/units/fp_units.cpp, tb/ray, tb/noise); a unit
// without a plan gets the generic one (tb/src/registry_plan.cpp).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "rayunits/synth/units.hpp"
#include "rayunits/tb/dut.hpp"
#include "rayunits/tb/harness.hpp"

namespace ru::tb {

// The registry configuration a test configuration stands for (its RTL parameters).
// Throws synth::SynthError / num::FormatError (one line) on an unknown unit or a bad parameter.
synth::UnitConfig unit_config(const ConfigDesc& cfg);

class RegistryAdapter : public UnitAdapter {
 public:
  // The golden model runs with `model` (normally == rtl; a planted error runs another one).
  RegistryAdapter(const synth::UnitSpec& u, const synth::UnitConfig& rtl);
  RegistryAdapter(const synth::UnitSpec& u, const synth::UnitConfig& rtl, const synth::UnitConfig& model);

  std::string describe() const override;  // "ray_box e8m23 rne Stages=3 OptConservative=1"
  const std::vector<FieldInfo>& inputs() const override { return ins_; }
  const std::vector<FieldInfo>& outputs() const override { return outs_; }
  void bind(const PortMap& ports) override;
  void drive(const Record& in) override;
  void read(Record& out) override;
  void model(const Record& in, Record& out) override;
  std::string decimal(const FieldInfo& f, uint64_t v) const override;

  const synth::UnitSpec& unit() const { return u_; }
  const synth::UnitConfig& config() const { return rtl_; }
  int input_index(const std::string& field) const;   // -1 if absent
  int output_index(const std::string& field) const;  // -1 if absent
  // Planted errors: called on a copy of every input before the golden model sees it.
  void set_model_input_hook(std::function<void(Record&)> h) { hook_ = std::move(h); }
  // Appended to describe() (e.g. "[planted: rounding]").
  void set_note(std::string n) { note_ = std::move(n); }

 private:
  struct Group {  // one data port: its fields are [first, first + n)
    std::string port;
    int first = 0, n = 1, bits = 1;
    Port p;
  };
  const synth::UnitSpec& u_;
  synth::UnitConfig rtl_, mcfg_;
  synth::GoldenEval golden_;
  std::vector<FieldInfo> ins_, outs_;
  std::vector<Group> in_groups_, out_groups_;
  std::function<void(Record&)> hook_;
  std::string note_;
};

// n random input records from the unit's registry generator (UnitSpec::random_inputs).
std::unique_ptr<VectorSource> registry_random_source(const synth::UnitSpec& u, const synth::UnitConfig& c,
                                                     uint64_t seed, uint64_t n);

// The generic test plan of one configuration, registry_plan(), is declared in testing.hpp.

}  // namespace ru::tb
