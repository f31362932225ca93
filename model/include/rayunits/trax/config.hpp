// rayunits trax: configuration of the TRaX-style processor model (issue 7), read from TOML.
//
// The schema (every key optional; the defaults are default_config(), documented key by key in
// model/data/trax/default.toml and docs/TRAX.md):
//   [chip]      tms, tps_per_tm, clock_mhz ("sta" or MHz), format, tri, box, noise, texture, traversal, bvh,
//               leaf_size, fp_registers_per_thread, int_registers_per_thread, local_store_bytes,
//               framebuffer_bytes_per_pixel, scene_storage, box_format, fma
//   [units.NAME] latency, count, width, area (um2 or "synth") | area_nand2 (an estimate in
//               NAND2-eq)   NAME in unit_names() (per TM: count pipelined units, each accepting
//               `width` operations per cycle, results after `latency`)
//   [atomic]    latency                          (one chip-wide atomic-increment unit, 1/cycle)
//   [local_store] latency
//   [l1], [l2]  size, banks, line, latency, ways (L1 per TM, L2 shared); [l1] interleave (line | word)
//   [dram]      latency, bytes_per_cycle
//   [area]      feature_um, sram_cell_f2, sram_cell_aspect, wire_pitch_f, array_efficiency,
//               regfile_read_ports, regfile_write_ports, address_bits (the memory model:
//               CACTI's SRAM cell and its growth per port, docs/TRAX.md "Memories")
//   [energy]    sram_pj_64b_8kib, sram_capacity_exponent, dram_pj_per_bit (memory access energy:
//               Horowitz, ISSCC 2014, 45 nm; docs/TRAX.md "Memory access energy")
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
  FpFma,      // fused multiply-add / multiply-subtract (chip.fma = true; ru_fp_fma)
  Conv,       // float <-> int conversion
  Int,        // integer add/logic, sign flips (neg, abs), address arithmetic
  Branch,     // branches
  Box,        // ray-box unit (units/ray_box.hpp)
  Tri,        // ray-triangle unit (units/ray_tri.hpp, robust or mt)
  Noise,      // noise unit (noise/fixed.hpp)
  Texture,    // procedural texture unit (noise/texture.hpp; chip.texture = "unit")
  kCount
};
constexpr int kUnits = static_cast<int>(Unit::kCount);
const char* unit_name(Unit u);  // "fp_add", ... (the TOML table names)
std::string unit_names();       // "fp_add, fp_mul, ..."

struct UnitCfg {
  int latency = 1;  // cycles from issue to result (>= 1); 0 = "rtl" (box, tri, noise): rtl_latency()
  int count = 1;    // units per TM
  int width = 1;    // operations accepted per unit per cycle
  // um2 (cell area) per unit; kAreaSynth = "synth": from the area table (cell-flow rows);
  // kAreaNand2: the estimate area_nand2 (NAND2-eq) x the NAND2X1 area (resolve_config)
  double area = 0;
  double area_nand2 = 0;  // TOML area_nand2: an estimate in NAND2-equivalents
  double fmax_mhz = 0;    // resolved: the STA Fmax of the unit's row (0: not timed)
};
constexpr double kAreaSynth = -1;  // TOML area = "synth"
constexpr double kAreaNand2 = -2;  // TOML area_nand2 = N
constexpr int kLatencyRtl = 0;     // TOML latency = "rtl"
constexpr double kClockSta = -1;   // TOML chip.clock_mhz = "sta"

struct CacheCfg {
  uint64_t size = 0;  // bytes
  int banks = 1;      // line-interleaved; one access per bank per cycle
  int line = 64;      // bytes
  int latency = 1;    // hit latency (cycles)
  int ways = 1;       // associativity (LRU)
  // L1 only: how addresses map to banks: false = line-interleaved (bank = line address mod banks),
  // true = word-interleaved (bank = 4-byte word address mod banks, simtrax's L1Cache)
  bool word_interleave = false;
};

struct Config {
  // [chip]
  int tms = 4, tps_per_tm = 32;
  // MHz, or kClockSta: the slowest used unit's STA Fmax at its Stages (area table rows)
  double clock_mhz = kClockSta;
  std::string format = "e8m23";   // eXmY[-ftz] or float (= e8m23)
  std::string tri = "robust";     // robust | mt
  std::string box = "plain";      // plain | conservative
  // fixed-trunc (ru_noise_trunc, the default since issue 15) | fixed (ru_noise, the baseline) |
  // float (NoiseRef::half, no hardware unit)
  std::string noise = "fixed-trunc";
  // shader: materials sum octaves on the TPs around NOISE instructions | unit: one TEXTURE
  // instruction per material sample on ru_texture (needs a fixed noise)
  std::string texture = "shader";
  std::string traversal = "stack";  // stack | stackless
  std::string bvh = "sah";        // sah | median
  int leaf_size = 4;
  // Register files per thread (area model; the summary reports the registers actually live):
  // FP registers hold values of the format (its width), integer registers 32 bits.
  int fp_registers_per_thread = 96;
  int int_registers_per_thread = 32;
  int local_store_bytes = 512;     // per thread (area model; the stack must fit)
  int framebuffer_bytes_per_pixel = 4;
  // Scene data in memory: "format" = BVH boxes, vertices, materials and camera packed at the
  // format's width (value k of a record at bit k x width); "word" = each value in a 32-bit word
  // (64-bit above 32 bits), the layout before issue 16.
  std::string scene_storage = "format";
  // BVH node boxes in a narrower format (render::RenderOptions::box_format: bounds rounded
  // outward; with scene_storage = "format" a node's box is packed at that width); "" = format.
  std::string box_format;
  // The kernel's multiply-adds as fused multiply-adds on the fp_fma unit (render::RenderOptions::
  // fma: one rounding each); false: FMUL + FADD, and no fp_fma unit on the chip.
  bool fma = false;
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
  // [area] the memory model (docs/TRAX.md "Memories"): CACTI 6.5's SRAM cell (146 F^2, aspect
  // 1.46, technology files of HP Labs' CACTI) grown by two local wire pitches per extra port in
  // each direction (CACTI's Mat), divided by an array efficiency (periphery; an assumption).
  double feature_um = 0.18;        // F of the cell library (osu018: 0.18 um)
  double sram_cell_f2 = 146;       // single-ported 6T cell, F^2
  double sram_cell_aspect = 1.46;  // cell height / width
  double wire_pitch_f = 2.5;       // local wire pitch, F
  double array_efficiency = 0.5;   // bit-cell area / array area (assumption)
  int regfile_read_ports = 2, regfile_write_ports = 1;  // a TP's register files
  int address_bits = 32;           // cache tags: address bits - index - offset, + a valid bit
  // [energy] memory access energy (docs/TRAX.md "Memory access energy"; an estimate at the
  // published 45 nm / 0.9 V node, not osu018's): an SRAM access of w bits to an array of C bytes
  // costs sram_pj_64b_8kib x (C / 8 KiB)^sram_capacity_exponent x w / 64 pJ -- Horowitz (ISSCC
  // 2014, "Computing's energy problem"): 64-bit reads of 8 KB, 32 KB and 1 MB SRAMs 10, 20 and
  // 100 pJ, fitted by the square root within 13 %; DRAM 1.3 nJ per 64 bits (the low end of his
  // 1.3-2.6 nJ) = 20.3125 pJ per bit.
  double sram_pj_64b_8kib = 10;
  double sram_capacity_exponent = 0.5;
  double dram_pj_per_bit = 20.3125;
  // resolved (resolve_config, not a TOML key): um2 of one NAND2-eq, the NAND2X1 cell area the
  // area table read from its liberty (memories and NAND2-eq unit estimates are charged with it)
  double nand2_um2 = 0;

  const UnitCfg& unit(Unit u) const { return units[static_cast<int>(u)]; }
  UnitCfg& unit(Unit u) { return units[static_cast<int>(u)]; }
  int threads() const { return tms * tps_per_tm; }
  int value_bits() const;   // bits of one value of the format (FP registers, scene_storage = "format")
  int value_bytes() const;  // bytes of one word (scene_storage = "word"): 4 (<= 32 bits) or 8
  // Throws ConfigError naming the offending key (source = file name for the message).
  void validate(const std::string& source = "built-in defaults") const;
};

// simtrax-like defaults (docs/TRAX.md): 4 TMs x 32 TPs at 1 GHz, FP add/mul latency 2 with one
// adder and one multiplier per 8 threads, divide/sqrt 16, everything else 1; L1 32 KB 4 banks
// 64 B lines 1 cycle, L2 512 KB 8 banks 3 cycles.
Config default_config();

// Whether the configuration puts unit u on the chip at all: every unit class is there (and is
// instantiated when the kernel issues to it) except fp_fma without chip.fma. A unit not on the
// chip needs no area row, has no clock and is not co-simulated.
inline bool unit_on_chip(const Config& c, Unit u) { return u != Unit::FpFma || c.fma; }

// The RTL Stages of the box / triangle / noise unit for this chip (TOML latency = "rtl"): the
// unit's chain of FP levels (rtl/ru_ray_box.sv, ru_ray_tri_robust.sv, ru_ray_tri_mt.sv), each
// level pipelined like the chip's own FP unit of that kind, so the unit runs at the chip's clock:
//   box            add + mul + 3 cmp
//   tri robust     4 add + 2 mul + div + cmp      (levels add mul add mul add add div cmp)
//   tri mt         5 add + 3 mul + div + cmp      (levels add mul add mul add add div mul add cmp)
//   noise          4 (Kensler's four-stage unit; ru_noise_trunc / ru_noise Stages 4)
//   texture        4 (its noise units' Stages; a request of n octaves takes ceil(n / width) + 4)
// with add, mul, div, cmp = the configured latencies of fp_add, fp_mul, fp_div, fp_cmp
// (simtrax defaults 2, 2, 16, 1: box 7, robust 29, mt 33).
int rtl_latency(const Config& c, Unit u);

// The registry unit behind chip.noise: "noise_trunc" (fixed-trunc), "noise" (fixed); for
// noise = float (no hardware unit) the default's, "noise_trunc".
std::string noise_unit(const Config& c);

// Where a unit's area (and clock) came from (resolve_config fills it).
struct AreaSource {
  std::string unit;     // "fp_add", "ray_tri_robust", ...
  std::string how;      // "measured" | "composed" | "composed, scaled" | "estimate ..." | "configured"
  std::string detail;   // the synth command, or the composition
  double fmax_mhz = 0;  // STA Fmax of the row (0: not timed)
  std::string fmax_how; // "STA" (the row's netlist) | "estimate (...)" | "" (not timed)
};

// The chip clock for clock_mhz = "sta": the lowest fmax_mhz of the resolved units with
// used[u] (all units if used is empty) that have one. Throws ConfigError if none has one.
struct ChipClock {
  double mhz = 0;
  std::string unit;  // the limiting unit ("tri", ...)
  std::string how;   // one line: "STA: slowest used unit tri (ray_tri_robust e8m23 Stages 29) 72.8 MHz ..."
};
ChipClock sta_clock(const Config& resolved, const std::vector<AreaSource>& sources, const std::vector<bool>& used = {});

// The area table's path ($RU_TRAX_AREAS or model/data/trax/areas.json).
std::string area_table_path();

// The registry units the TRaX model takes from the area table (fp_add ... noise), and the
// latency (Stages) the chip configuration c gives unit u (its FP latency or its RTL latency;
// sets c.tri for the triangle units). Throws ConfigError for a unit not in the list.
const std::vector<std::string>& area_table_units();
int area_table_latency(Config& c, const std::string& unit);
// The chip's unit kind of a registry unit ("ray_tri_mt" -> Unit::Tri); ConfigError otherwise.
Unit area_table_unit(const std::string& unit);

// Resolves "rtl" latencies, "synth" / NAND2-eq areas (um2) and the "sta" clock from the area
// table (model/data/trax/areas.json, or $RU_TRAX_AREAS): areas by (unit, format, Stages =
// latency): a measured row if present (cell flow: area_um2 and fmax_mhz), else box / tri composed
// from the measured FP-unit rows of the format (box 6 add + 6 mul + 7 cmp; robust 43 add + 39
// mul + 3 div + 20 cmp; mt 24 add + 27 mul + 1 div + 5 cmp). A
// missing FP row, a malformed row or a missing table throws ConfigError with one line. The
// "sta" clock is resolved over every unit here; run_trax narrows it to the units the kernel used.
Config resolve_config(const Config& c, std::vector<AreaSource>* sources = nullptr);

// Reads TOML text on top of `base`; `source` names the file in error messages.
Config parse_config(const std::string& toml_text, const std::string& source, const Config& base = default_config());
Config load_config(const std::string& path, const Config& base = default_config());

// The configuration as TOML (every key; parse_config(to_toml(c)) == c).
std::string to_toml(const Config& c);

}  // namespace ru::trax
