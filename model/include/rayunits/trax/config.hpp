// rayunits trax: configuration of the TRaX-style processor model (issue 7), read from TOML.
//
// The schema (every key optional; the defaults are default_config(), documented key by key in
// model/data/trax/default.toml and docs/TRAX.md):
//   [chip]      tms, tps_per_tm, clock_mhz, format, tri, box, noise, traversal, bvh, leaf_size,
//               registers_per_thread, local_store_bytes, framebuffer_bytes_per_pixel
//   [units.NAME] latency, count, width, area     NAME in unit_names() (per TM: count pipelined
//               units, each accepting `width` operations per cycle, results after `latency`)
//   [atomic]    latency                          (one chip-wide atomic-increment unit, 1/cycle)
//   [local_store] latency
//   [l1], [l2]  size, banks, line, latency, ways (L1 per TM, L2 shared)
//   [dram]      latency, bytes_per_cycle
//   [area]      sram_bit, regfile_bit            (NAND2-equivalents per bit)
// A bad file gives ConfigError with one line naming the key: "trax config FILE: key
// 'l1.banks': must be a power of two in 1..1024 (got 3)"; unknown keys are errors too.
#pragma once
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace ru::trax {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Functional-unit classes. Per TM except that the atomic unit is chip-wide; memory
// instructions use the caches, not these.
enum class Unit : uint8_t {
  FpAdd = 0,  // add, sub
  FpMul,      // mul
  FpDiv,      // div (the "inverse" unit of TRaX)
  FpSqrt,     // square root
  FpCmp,      // compare, min, max
  Conv,       // float <-> int conversion
  Int,        // integer add/logic, sign flips (neg, abs), address arithmetic
  Branch,     // branches
  Box,        // ray-box unit (units/ray_box.hpp)
  Tri,        // ray-triangle unit (units/ray_tri.hpp, robust or mt)
  Noise,      // noise unit (noise/fixed.hpp)
  kCount
};
constexpr int kUnits = static_cast<int>(Unit::kCount);
const char* unit_name(Unit u);  // "fp_add", ... (the TOML table names)
std::string unit_names();       // "fp_add, fp_mul, ..."

struct UnitCfg {
  int latency = 1;  // cycles from issue to result (>= 1); 0 = "rtl" (box, tri, noise): rtl_latency()
  int count = 1;    // units per TM
  int width = 1;    // operations accepted per unit per cycle
  double area = 0;  // NAND2-equivalents per unit; kAreaSynth = "synth": from the area table
};
constexpr double kAreaSynth = -1;  // TOML area = "synth"
constexpr int kLatencyRtl = 0;     // TOML latency = "rtl"

struct CacheCfg {
  uint64_t size = 0;  // bytes
  int banks = 1;      // line-interleaved; one access per bank per cycle
  int line = 64;      // bytes
  int latency = 1;    // hit latency (cycles)
  int ways = 1;       // associativity (LRU)
};

struct Config {
  // [chip]
  int tms = 4, tps_per_tm = 32;
  double clock_mhz = 1000;
  std::string format = "e8m23";   // eXmY[-ftz] or float (= e8m23)
  std::string tri = "robust";     // robust | mt
  std::string box = "plain";      // plain | conservative
  std::string noise = "fixed";    // fixed (the hardware unit's model) | float (NoiseRef::half)
  std::string traversal = "stack";  // stack | stackless
  std::string bvh = "sah";        // sah | median
  int leaf_size = 4;
  int registers_per_thread = 128;  // architectural registers (area model)
  int local_store_bytes = 512;     // per thread (area model; the stack must fit)
  int framebuffer_bytes_per_pixel = 4;
  // [units.*]
  std::array<UnitCfg, kUnits> units{};
  // [atomic], [local_store]
  int atomic_latency = 1;
  int local_store_latency = 1;
  // [l1], [l2], [dram]
  CacheCfg l1{32768, 4, 64, 1, 1};
  CacheCfg l2{524288, 8, 64, 3, 1};
  int dram_latency = 100;
  double dram_bytes_per_cycle = 16;
  // [area]
  double sram_bit = 1.5;     // 6T cell / 4T NAND2
  double regfile_bit = 6.0;  // a flip-flop with read/write ports ~ 24 transistors

  const UnitCfg& unit(Unit u) const { return units[static_cast<int>(u)]; }
  UnitCfg& unit(Unit u) { return units[static_cast<int>(u)]; }
  int threads() const { return tms * tps_per_tm; }
  int value_bytes() const;  // bytes of one scene value in memory: 4 (<= 32 bits) or 8
  // Throws ConfigError naming the offending key (source = file name for the message).
  void validate(const std::string& source = "built-in defaults") const;
};

// simtrax-like defaults (docs/TRAX.md): 4 TMs x 32 TPs at 1 GHz, FP add/mul latency 2 with one
// adder and one multiplier per 8 threads, divide/sqrt 16, everything else 1; L1 32 KB 4 banks
// 64 B lines 1 cycle, L2 512 KB 8 banks 3 cycles.
Config default_config();

// The RTL Stages of the box / triangle / noise unit for this chip (TOML latency = "rtl"): the
// unit's chain of FP levels (rtl/ru_ray_box.sv, ru_ray_tri_robust.sv, ru_ray_tri_mt.sv), each
// level pipelined like the chip's own FP unit of that kind, so the unit runs at the chip's clock:
//   box            add + mul + 3 cmp
//   tri robust     4 add + 2 mul + div + cmp      (levels add mul add mul add add div cmp)
//   tri mt         5 add + 3 mul + div + cmp      (levels add mul add mul add add div mul add cmp)
//   noise          4 (Kensler's four-stage unit; ru_noise Stages 4)
// with add, mul, div, cmp = the configured latencies of fp_add, fp_mul, fp_div, fp_cmp
// (simtrax defaults 2, 2, 16, 1: box 7, robust 29, mt 33).
int rtl_latency(const Config& c, Unit u);

// Where a unit's area came from (resolve_config fills it for area = "synth").
struct AreaSource {
  std::string unit;     // "fp_add", "ray_tri_robust", ...
  std::string how;      // "measured" | "composed" | "estimate" | "configured"
  std::string detail;   // the synth command, or the composition
};

// Resolves "rtl" latencies and "synth" areas (model/data/trax/areas.json, or $RU_TRAX_AREAS):
// areas by (unit, format, Stages = latency): a measured row if present, else box / tri composed
// from the measured FP-unit rows of the format (box 6 add + 6 mul + 7 cmp; robust 43 add + 39
// mul + 3 div + 20 cmp; mt 24 add + 27 mul + 1 div + 5 cmp), fp_sqrt = fp_div (no RTL). A
// missing FP row throws ConfigError naming the unit, format and Stages.
Config resolve_config(const Config& c, std::vector<AreaSource>* sources = nullptr);

// Reads TOML text on top of `base`; `source` names the file in error messages.
Config parse_config(const std::string& toml_text, const std::string& source, const Config& base = default_config());
Config load_config(const std::string& path, const Config& base = default_config());

// The configuration as TOML (every key; parse_config(to_toml(c)) == c).
std::string to_toml(const Config& c);

}  // namespace ru::trax
