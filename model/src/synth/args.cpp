// Shared command-line options of `synth`, `gen` and `synth-sweep`.
#include "rayunits/synth/args.hpp"

#include <cerrno>
#include <cstdlib>

namespace ru::synth {

const char* const kFlowOptionsHelp =
    "flow options:\n"
    "  --fpga              also place and route on iCE40 with nextpnr-ice40 (Fmax; slow)\n"
    "  --device hx8k|up5k  iCE40 device (default hx8k)\n"
    "  --no-ice40          skip synth_ice40 LUT counts\n"
    "  --no-xilinx         skip synth_xilinx LUT/DSP counts\n"
    "  --generic-only      skip both FPGA flows (generic gates only)\n"
    "  --no-share          synth -noshare: no resource sharing (the ray-triangle units always)\n"
    "  --rtl DIR           RTL source directory (default <repo>/rtl or $RU_RTL_DIR)\n"
    "  --yosys PATH        yosys binary (default: yosys on PATH)\n"
    "  --nextpnr PATH      nextpnr-ice40 binary (default: on PATH)\n"
    "  --timeout S         kill a tool run after S seconds (default: no limit)\n"
    "  --keep              keep the temp directory with scripts and logs\n";

std::string ArgCursor::value() {
  std::string a = argv[i];
  size_t eq = a.find('=');
  if (a.rfind("--", 0) == 0 && eq != std::string::npos) return a.substr(eq + 1);
  if (i + 1 >= argc) throw SynthError(opt + " needs a value");
  return argv[++i];
}

int parse_int(const std::string& opt, const std::string& v, int lo, int hi) {
  errno = 0;
  char* end = nullptr;
  long x = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end || errno || x < lo || x > hi)
    throw SynthError(opt + " expects an integer in " + std::to_string(lo) + ".." + std::to_string(hi) +
                     ", got '" + v + "'");
  return static_cast<int>(x);
}

std::vector<std::string> split_list(const std::string& v) {
  std::vector<std::string> out;
  size_t b = 0;
  while (b <= v.size()) {
    size_t e = v.find(',', b);
    if (e == std::string::npos) e = v.size();
    if (e > b) out.push_back(v.substr(b, e - b));
    b = e + 1;
  }
  return out;
}

bool parse_flow_option(ArgCursor& a, FlowOptions& o) {
  const std::string& k = a.opt;
  if (k == "--rtl")
    o.rtl_dir = a.value();
  else if (k == "--yosys")
    o.yosys = a.value();
  else if (k == "--nextpnr")
    o.nextpnr = a.value();
  else if (k == "--fpga")
    o.pnr = o.ice40 = true;
  else if (k == "--device") {
    o.ice40_device = a.value();
    if (o.ice40_device != "hx8k" && o.ice40_device != "up5k")
      throw SynthError("--device expects hx8k or up5k, got '" + o.ice40_device + "'");
  } else if (k == "--no-ice40")
    o.ice40 = o.pnr = false;
  else if (k == "--no-xilinx")
    o.xilinx = false;
  else if (k == "--no-share")
    o.share = false;
  else if (k == "--generic-only")
    o.ice40 = o.pnr = o.xilinx = false;
  else if (k == "--timeout")
    o.timeout_s = parse_int(k, a.value(), 1, 1000000);
  else if (k == "--keep")
    o.keep_temp = true;
  else
    return false;
  return true;
}

bool parse_config_option(ArgCursor& a, ConfigArgs& c) {
  const std::string& k = a.opt;
  if (k == "--format")
    c.format = a.value();
  else if (k == "--stages")
    c.stages = parse_int(k, a.value(), 0, 1000);
  else if (k == "--round")
    c.round = a.value();
  else if (k == "--ftz")
    c.ftz = true;
  else if (k == "--param") {
    const std::string v = a.value();
    const size_t eq = v.find('=');
    if (eq == std::string::npos || eq == 0) throw SynthError("--param expects Name=Value, got '" + v + "'");
    c.params[v.substr(0, eq)] = parse_int("--param " + v.substr(0, eq), v.substr(eq + 1), -1000000, 1000000);
  } else
    return false;
  return true;
}

UnitConfig make_config(const UnitSpec& u, const ConfigArgs& a) {
  UnitConfig c;
  if (u.uses_format) {
    if (a.format.empty()) throw SynthError("--format eXmY is required (e.g. --format e7m16)");
    c.fmt = num::Format::parse(a.format);
    if (a.ftz) c.fmt.subnormals = false;
    if (!a.round.empty()) c.fmt.round = num::parse_round(a.round);
  } else if (!a.format.empty() || a.ftz || !a.round.empty()) {
    throw SynthError(u.name +
                     " has no floating-point format: --format/--round/--ftz do not apply (use --param)");
  }
  if (a.stages < 0) throw SynthError("--stages N is required (0 = combinational)");
  c.stages = a.stages;
  c.params = a.params;
  return c;
}

}  // namespace ru::synth
