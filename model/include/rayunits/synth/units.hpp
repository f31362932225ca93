// rayunits: the unit registry, the one description of every hardware unit.
//
// Adding a unit is one table entry in model/src/synth/units.cpp: its name, RTL top module,
// source files (an rtl/*.f file list), the RTL parameters as functions of the requested
// configuration, its maximum useful Stages and its ports, both as small integer expressions
// over the format and the unit's parameters (see eval_expr()). Everything else is derived from
// that entry: wrapper generation, the Yosys flows, the FPGA harness, datasheets, sweeps, the
// TRaX latency limits, and -- through model/data/registry.json, which `rayunits registry
// --json` writes and a fast test keeps current -- the testbench port lists and the "smax"
// stage tokens of the CMake test matrices (tb/cmake/RuTb.cmake). The maximum useful Stages is
// also a fact of the RTL (each top module's `localparam MaxUsefulStages`); check_against_rtl()
// compares the two (ctest Registry.*). See docs/ARCHITECTURE.md, "How to add a unit".
#pragma once

#include <cstdint>
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
  // Segment weights of the automatic register placement (RTL parameter SegW, units with
  // UnitSpec::seg_weights_param): empty = the RTL's depth estimates; else one weight 1..255 per
  // segment (run_synth with placement "delay" sets them from STA).
  std::vector<int> seg_weights;
};

enum class PortDir { In, Out };
// What a port is for; the FPGA harness and the datasheet use it. Ready: in_ready_o of a unit with
// a handshake (UnitSpec::handshake): an input is accepted in a cycle with in_valid_i && in_ready_o.
enum class PortRole { Clock, Reset, Valid, Data, Ready };
// What a data port's value (each of its elements) is: raw bits (fixed point, a hit bit), a bit
// pattern of the configuration's format, the five IEEE flags {i, z, o, u, x}, or an enumeration
// (op codes, reason codes: `enum_names` by value). The testbench prints values by it and draws
// random values by it.
enum class FieldKind : uint8_t { Bits, Float, Flags, Enum };

struct PortSpec {
  std::string name;
  PortDir dir = PortDir::In;
  PortRole role = PortRole::Data;
  // Bits, an expression for eval_expr() ("1", "W", "3*W", "FracBits+IntBits"); the value is >= 1.
  // Vector operands are packed {x2, x1, x0} with x0 in the low bits (`doc` says which).
  std::string width;
  std::string doc;  // one line for the datasheet
  // Data ports: the port packs `elems` elements of width/elems bits, element 0 in the low bits;
  // each element is one field of the golden model's records (see fields_for()), named
  // elem_names[i] (or <port>[i]).
  int elems = 1;
  FieldKind kind = FieldKind::Bits;
  std::vector<std::string> elem_names;
  std::vector<std::string> enum_names;  // FieldKind::Enum
};

// One value of a golden-model record: an element of a data port.
struct Field {
  std::string name;  // "a_i", "org.x", "V0"
  std::string port;  // "a_i", "org_i", "vol_o"
  int elem = 0;      // element index inside the port (0 = low bits)
  int bits = 1;      // <= 64
  FieldKind kind = FieldKind::Bits;
  std::vector<std::string> enum_names;
};

// The golden model of one configuration, bound once (tables built, parameters decoded):
// in[i] is the value of input field i, out[j] receives output field j (fields_for() order:
// data ports in declaration order, elements low first). Values are bit patterns in the low
// `bits` bits. Bit-accurate: the RTL must equal it on every bit (tb/README.md).
using GoldenEval = std::function<void(const std::uint64_t* in, std::uint64_t* out)>;
// Random input records for one configuration and seed (deterministic): fills every input field.
using InputGen = std::function<void(std::uint64_t* in)>;

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
  std::string design_file;  // a datapath design given at run time ($RU_DP_DESIGNS/<stem>.dp), else empty
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
  // The maximum useful Stages (every internal cut position registered; the RTL accepts more and
  // puts the extra registers at the output, which buys no speed, so synth/gen refuse it): an
  // eval_expr() expression, e.g. "L+4". Must equal the RTL's localparam MaxUsefulStages.
  std::string max_stages_expr;
  int max_stages(const UnitConfig& c) const;
  // Latency in cycles of a configuration: every unit's latency is exactly its Stages -- except a
  // unit with a handshake, for which Stages is the smallest latency (see `handshake`).
  int latency(const UnitConfig& c) const { return min_latency ? min_latency(c) : c.stages; }
  // A handshake unit whose smallest latency is not its Stages (ru_texture: one group, the noise
  // units' Stages and RootStages); empty: Stages.
  std::function<int(const UnitConfig&)> min_latency;
  // The unit has in_ready_o (PortRole::Ready) and a variable latency: a result leaves Stages
  // cycles after its input or later, results in input order (ru_ray_tri_exact: a test that needs
  // the exact side path waits for it, and the ones behind it wait too). The scoreboard checks
  // such a unit in order, the handshake included (tb/README.md, "Units with a handshake").
  bool handshake = false;
  // Formats the RTL accepts (on top of num::Format's own range check).
  int min_exp = num::Format::kMinExp, max_exp = num::Format::kMaxExp;
  int min_frac = num::Format::kMinFrac, max_frac = num::Format::kMaxFrac;
  // false: the generic flow runs `synth -noshare` (Yosys' SAT-based resource sharing takes
  // hours on the ray-triangle units; it only merges mutually exclusive shifters/adders).
  bool synth_share = true;
  // The RTL has a SegW parameter (packed 8-bit segment weights of its cut placement,
  // ru_pipe_pkg::pick_w): one segment per cut position + 1, i.e. max_stages + 1 segments.
  bool seg_weights_param = false;
  // Further constraints between parameters; throws SynthError. May be empty.
  std::function<void(const UnitConfig&)> check;
  // The golden-model adapter (model/src/synth/unit_models.cpp): binds the unit's bit-accurate
  // model to a configuration. Used by the testbench (tb/src/registry_adapter.cpp) and the TRaX
  // co-simulation; every registered unit has one (Registry.EveryUnitHasAModel).
  std::function<GoldenEval(const UnitConfig&)> golden;
  // The unit's random vector generator (weighted towards its hard cases: specials, ties,
  // cancellation, edges): what the generic test plan drives (tb/src/registry_plan.cpp).
  std::function<InputGen(const UnitConfig&, std::uint64_t seed)> random_inputs;
  // The fast RTL test matrix (tb/cmake/RuTb.cmake configuration tokens, "e8m23:smax+1:selftest",
  // "s4:FracBits=5") and the long one (label long, built with -DRU_TB_LONG=ON). CMake builds
  // tb_<name> (and tb_<name>_long) from them through model/data/registry.json.
  std::vector<std::string> tests, long_tests;
  // Verilated models of this unit are large (ray units): built at the tb's "large model"
  // optimisation level, without FST tracing unless asked (tb/CMakeLists.txt).
  bool large_model = false;
};

// Evaluates a registry expression: integers, + - * / ( ), max(x, y), and the names
//   E = ExpW, M = FracW, W = 1+E+M, L = csa_levels(M+1) (carry-save levels of the significand
//   multiplier, ru_fp_pkg::csa_levels), and every extra parameter of the unit by name.
// Format names are only defined for units that use a format. Throws SynthError (one line) on a
// syntax error or an unknown name.
long long eval_expr(const std::string& expr, const UnitSpec& u, const UnitConfig& c);
// ru_fp_pkg::csa_levels: carry-save (3:2) levels that reduce n partial products to two.
int csa_levels(int n);

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

// The golden-model record layout of a configuration: the fields of the data ports of direction
// `dir`, in port order, each port's elements low first. Throws SynthError if an element is wider
// than 64 bits or a width is not a multiple of the element count.
std::vector<Field> fields_for(const UnitSpec& u, const UnitConfig& c, PortDir dir);

// The configuration an RTL parameter set stands for (the inverse of params_for(): ExpW, FracW,
// Subnormals, Round give the format, Stages the stages, the unit's extra parameters by name).
// Unknown parameter names throw SynthError; the result passes check_config() except that Stages
// may exceed the maximum useful Stages (the RTL puts extra registers at the output).
UnitConfig config_from_params(const UnitSpec& u, const std::map<std::string, long long>& params);

// The RTL parameters of the configuration, in order (fixed ones, then extra ones).
std::vector<std::pair<std::string, long long>> params_for(const UnitSpec& u, const UnitConfig& c);

// The registry as JSON (units, parameters with ranges, ports with width expressions, the maximum
// useful Stages expression, sources): what CMake reads at configure time
// (model/data/registry.json). Deterministic.
std::string registry_json(const std::vector<UnitSpec>& units);

// What the RTL itself says about a configuration's pipeline, read from the top module's
// localparams by `verilator --xml-only` (Verilator must be on PATH or $RU_VERILATOR).
struct RtlStageFacts {
  int max_useful_stages = -1;  // localparam MaxUsefulStages
  int out_regs = -1;           // localparam OutRegs: registers placed at the output
};
RtlStageFacts rtl_stage_facts(const UnitSpec& u, const UnitConfig& c, const std::string& rtl_dir);

// Compares a registry entry with its RTL for each configuration's format/parameters (the
// configurations' own stages are ignored): elaborates the unit at the registry's maximum useful
// Stages (MaxUsefulStages must equal it, and OutRegs must be 0) and one past it (OutRegs must be
// exactly 1). Returns one line per disagreement, naming the unit and the format
// ("fp_add e8m23: registry max Stages 4, RTL MaxUsefulStages 5"); empty when they agree.
std::vector<std::string> check_against_rtl(const UnitSpec& u, const std::vector<UnitConfig>& configs,
                                           const std::string& rtl_dir);

// The SystemVerilog text of the wrapper module (parameters fixed, same ports as the unit).
// Deterministic: no timestamps, no host names.
std::string wrapper_verilog(const UnitSpec& u, const UnitConfig& c);

}  // namespace ru::synth
