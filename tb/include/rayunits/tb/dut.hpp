// rayunits tb: one configuration of a Verilated unit, behind a small interface.
//
// Every (unit, parameters) configuration is its own Verilated model (unique PREFIX, built by
// ru_tb_add_tests() in tb/cmake/RuTb.cmake). The CMake helper generates, per configuration, a
// tiny glue file that registers a ConfigDesc (unit name, configuration name, RTL parameters,
// tags) and a factory making a Dut. The harness and the adapters only see this interface.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rayunits/tb/port.hpp"

namespace ru::tb {

struct DutOptions {
  uint64_t seed = 1;   // seeds Verilator's --x-initial unique / --x-assign unique randomization
  bool trace = false;  // construct with tracing enabled (needed before trace_open())
};

class Dut {
 public:
  virtual ~Dut() = default;
  virtual void eval() = 0;
  virtual const PortMap& ports() const = 0;
  // FST tracing: trace_open() returns false when the model was built without TRACE_FST or the
  // Dut was made with trace=false.
  virtual bool trace_open(const std::string& path) = 0;
  virtual void trace_dump(uint64_t time) = 0;
  virtual void trace_close() = 0;
};

using DutFactory = std::function<std::unique_ptr<Dut>(const DutOptions&)>;

struct ConfigDesc {
  std::string unit;   // "fp_mul"
  std::string name;   // "e8m23_s3", "e5m10_ftz_s2_rtz"
  std::string prefix; // Verilator prefix, e.g. "Vfp_mul_e8m23_s3"
  std::map<std::string, int64_t> params;  // RTL parameter overrides (ExpW, FracW, Stages, ...)
  std::vector<std::string> tags;          // "exhaustive", "n=1000000", "long", ...
  DutFactory make;

  std::string full_name() const { return unit + "_" + name; }  // "fp_mul_e8m23_s3"
  int64_t param(const std::string& k, int64_t def) const {
    auto it = params.find(k);
    return it == params.end() ? def : it->second;
  }
  bool has_tag(const std::string& t) const;
  // Value of a "key=value" tag, or def.
  std::string tag_value(const std::string& key, const std::string& def) const;
};

// All configurations linked into this executable (filled by the generated glue files).
std::vector<ConfigDesc>& registered_configs();
struct ConfigRegistrar {
  explicit ConfigRegistrar(ConfigDesc d) { registered_configs().push_back(std::move(d)); }
};

}  // namespace ru::tb
