// rayunits: the registry of synthesizable units (what `rayunits synth` / `rayunits gen` know).
//
// Adding a unit (ray_box, ray_tri, ...) is one table entry in model/src/synth/units.cpp:
// its name, RTL top module, source files (or an rtl/*.f file list), the RTL parameters as
// functions of the requested configuration, the supported Stages range, and the port list with
// widths as functions of the configuration (number format + unit parameters). Everything else
// (wrapper generation, the Yosys flows, the FPGA harness, datasheets, sweeps) is derived from
// that entry. See synth/README.md, "Adding a unit".
#pragma once

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "rayunits/num/format.hpp"

namespace ru::synth {

// Every error of the synthesis flow / generator. what() is one line.
class SynthError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One point of a unit's design space.
struct UnitConfig {
  num::Format fmt;  // exponent/fraction bits, subnormals (false = -ftz), rounding mode
  int stages = 0;   // pipeline latency in cycles (0 = combinational)
  // Unit-specific parameters (UnitSpec::extra_params) given with --param Name=Value; a
  // parameter not in the map takes its default.
  std::map<std::string, long long> params;
};

enum class PortDir { In, Out };
// What a port is for; the FPGA harness and the datasheet use it.
enum class PortRole { Clock, Reset, Valid, Data };

using WidthFn = std::function<int(const UnitConfig&)>;

struct PortSpec {
  std::string name;
  PortDir dir;
  PortRole role;
  WidthFn width;    // bits, >= 1
  std::string doc;  // one line for the datasheet
};

struct ParamSpec {
  std::string name;                                   // RTL parameter name
  std::function<long long(const UnitConfig&)> value;  // value for a configuration
};

// A unit parameter the user may set with --param Name=Value (e.g. the noise unit's FracBits).
struct ExtraParam {
  std::string name;  // RTL parameter name
  long long def, lo, hi;
  std::string doc;
};

struct UnitSpec {
  std::string name;     // CLI name: "fp_mul"
  std::string top;      // RTL module: "ru_fp_mul"
  std::string summary;  // one line
  // Sources relative to the rtl/ directory, dependencies first. If `filelist` names an
  // existing file in rtl/, it is used instead (see resolve_sources()).
  std::string filelist;
  std::vector<std::string> sources;
  // Fixed RTL parameters (functions of the configuration); extra_params are passed too.
  std::vector<ParamSpec> params;
  std::vector<ExtraParam> extra_params;
  std::vector<PortSpec> ports;
  bool uses_format = true;  // false: --format/--round/--ftz do not apply (e.g. fixed point)
  int min_stages = 0;
  std::function<int(const UnitConfig&)> max_stages;
  // Formats the RTL accepts (on top of num::Format's own range check).
  int min_exp = num::Format::kMinExp, max_exp = num::Format::kMaxExp;
  int min_frac = num::Format::kMinFrac, max_frac = num::Format::kMaxFrac;
  // false: the generic flow runs `synth -noshare` (Yosys' SAT-based resource sharing takes
  // hours on the ray-triangle units; it only merges mutually exclusive shifters/adders).
  bool synth_share = true;
  // Further constraints between parameters; throws SynthError. May be empty.
  std::function<void(const UnitConfig&)> check;
};

// All registered units, in a stable order.
const std::vector<UnitSpec>& units();
// Throws SynthError "unknown unit 'x' (units: fp_add, fp_mul, ...)".
const UnitSpec& find_unit(std::string_view name);
std::string unit_names();  // "fp_add, fp_mul, ..."

// Value of an extra parameter in a configuration (its default when not set).
long long param_value(const UnitSpec& u, const UnitConfig& c, const std::string& name);

// Throws SynthError (one line) if the unit cannot be built in this configuration.
void check_config(const UnitSpec& u, const UnitConfig& c);

// Descriptive wrapper module name: ru_<unit>_e7m16_s3, then _<Name><value> for every extra
// parameter not at its default, then _rtz/_rdn/_rup for a non-RNE rounding mode and _ftz for
// flush-to-zero (by the request, so synth/RuGen.cmake can compute the same name at configure
// time). Units without a format: ru_<unit>_s3[_<Name><value>...].
std::string wrapper_name(const UnitSpec& u, const UnitConfig& c);

// The canonical arguments that build this configuration ("fp_mul --format e7m16 --stages 3
// --round rtz --ftz"); deterministic, used in generated headers and datasheets.
std::string config_args(const UnitSpec& u, const UnitConfig& c);

// The project's rtl/ directory: $RU_RTL_DIR if set, else <source dir>/rtl.
std::string default_rtl_dir();

struct Sources {
  std::vector<std::string> files;     // compile units, dependencies first (absolute paths)
  std::vector<std::string> includes;  // files pulled in by `include "..." (absolute paths)
};
// Every source of the unit. Reads rtl/<filelist> when it exists (one path per line, relative
// to the file list's directory; blank lines and // or # comments ignored; options such as
// +incdir+ are rejected), else the `sources` table. `include "name" lines in the sources are
// followed (looked up next to the including file). Throws SynthError naming a missing file.
Sources resolve_sources(const UnitSpec& u, const std::string& rtl_dir);

// FNV-1a 64 of the sources' names and contents ("0123456789abcdef"): identifies the RTL a
// result was obtained from (JSON `rtl_hash`; `synth-sweep --resume` reuses only matching rows).
std::string sources_hash(const Sources& s);

// Port widths for a configuration, in declaration order.
struct Port {
  std::string name;
  PortDir dir;
  PortRole role;
  int width;
  std::string doc;
};
std::vector<Port> ports_for(const UnitSpec& u, const UnitConfig& c);

// The RTL parameters of the configuration, in order (fixed ones, then extra ones).
std::vector<std::pair<std::string, long long>> params_for(const UnitSpec& u, const UnitConfig& c);

// The SystemVerilog text of the wrapper module (parameters fixed, same ports as the unit).
// Deterministic: no timestamps, no host names.
std::string wrapper_verilog(const UnitSpec& u, const UnitConfig& c);

}  // namespace ru::synth
