// rayunits: command-line options shared by `synth`, `gen` and `synth-sweep`.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/units.hpp"

namespace ru::synth {

// Walks argv; for each option it calls `own(opt, value_getter)` first (command-specific options),
// then the shared flow options below. Throws SynthError for unknown options / bad values.
//
// Shared flow options:
//   --rtl DIR          RTL sources (default: <repo>/rtl, or $RU_RTL_DIR)
//   --yosys PATH       yosys binary (default: yosys on PATH)
//   --nextpnr PATH     nextpnr-ice40 binary
//   --fpga             also place and route on iCE40 with nextpnr (Fmax)
//   --device hx8k|up5k iCE40 device (default hx8k)
//   --no-ice40         skip synth_ice40
//   --no-xilinx        skip synth_xilinx
//   --generic-only     skip both FPGA flows
//   --timeout S        kill a tool run after S seconds
//   --keep             keep the temp directory
struct ArgCursor {
  int argc;
  char** argv;
  int i;
  std::string opt;
  // The option's value: "--x=v" or the next argument. Throws if missing.
  std::string value();
};

bool parse_flow_option(ArgCursor& a, FlowOptions& o);

// Unit configuration options: --format eXmY[-ftz], --stages N, --round MODE, --ftz,
// --param Name=Value (repeatable; unit-specific parameters).
struct ConfigArgs {
  std::string format;  // empty until given
  int stages = -1;     // -1 until given
  std::string round;   // empty: rne
  bool ftz = false;
  std::map<std::string, long long> params;
};
bool parse_config_option(ArgCursor& a, ConfigArgs& c);
// Checks that --format (for units with a format) and --stages were given and builds the
// UnitConfig (FormatError on a bad format). Range checks are check_config()'s.
UnitConfig make_config(const UnitSpec& u, const ConfigArgs& c);

int parse_int(const std::string& opt, const std::string& v, int lo, int hi);
std::vector<std::string> split_list(const std::string& v);  // "a,b,,c" -> {a,b,c}

extern const char* const kFlowOptionsHelp;

}  // namespace ru::synth
