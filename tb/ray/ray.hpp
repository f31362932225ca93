// rayunits tb/ray: adapters and vector sources of the intersection units ru_ray_box,
// ru_ray_tri_robust and ru_ray_tri_mt (issue 4 section 2), plugged into the generic
// cycle-by-cycle scoreboard (tb/include/rayunits/tb/harness.hpp).
//
// Records are the registry's (synth::fields_for: data ports in declaration order, vectors split
// into their elements; one uint64_t bit pattern of the configuration's format per field):
//   ray_box   in:  org.xyz rdir.xyz tmin tmax bmin.xyz bmax.xyz; driven as org_i = {z, y, x}, ...
//             out: hit_o, t_enter_o, t_exit_o
//   ray_tri_* in:  a.xyz d.xyz p0.xyz p1.xyz p2.xyz tmin tmax (the order of a TriRecord)
//             out: hit_o, why_o, t_o, beta_o, gamma_o, V, Va, V0, V1, V2 (vol_o = {V2, V1, V0,
//                  Va, V}; constant 0 unless OptVolOut = 1)
// Golden models: the registry's (model/src/synth/unit_models.cpp: ru::units::ray_box /
// ray_tri_robust / ray_tri_mt with ru::num::Soft in the configuration's Format).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/tb/dut.hpp"
#include "rayunits/tb/harness.hpp"
#include "rayunits/tb/registry_adapter.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::tb::ray {

enum class Unit : uint8_t { Box, Robust, Mt };

// A configuration's parameters (RTL parameter overrides of the ConfigDesc).
struct RayConfig {
  Unit unit = Unit::Box;
  ru::num::Format f;       // ExpW, FracW, Subnormals, Round
  int stages = 0;          // = the unit's latency
  bool conservative = false;   // ray_box OptConservative != 0 (directed rounding)
  bool dcons = false;          // ray_box OptConservative == 2 (conservative against d)
  bool tie_break = false;      // ray_tri_robust OptTieBreak
  bool eps_test = false;       // OptEpsTest
  uint64_t eps_bits = 0;       // EpsBits
  bool vol_out = false;        // OptVolOut
  bool recip = false;          // ray_tri_robust OptRecip (ray_tri_robust_recip)
};
// Throws std::runtime_error / FormatError on a bad configuration.
RayConfig ray_config(const ConfigDesc& cfg);
std::string describe(const RayConfig& c);  // "ray_tri_robust e8m23 rne Stages=3 tie-break"

// Planted errors in the golden model (the checker must report them).
enum class Mutant : uint8_t {
  None,
  Rounding,      // the model rounds toward zero instead of to nearest (every op)
  InputLsb,      // the model sees the least significant bit of one input flipped
  ModeSwap,      // ray_box: plain <-> conservative, d-conservative -> conservative;
                 // ray_tri_robust: tie-break and OptRecip toggled
};
const char* mutant_name(Mutant m);

// The registry configuration of a RayConfig (its RTL parameters).
synth::UnitConfig ray_unit_config(const RayConfig& c);
// The registry adapter (fields, ports, golden model: registry_adapter.hpp) of the configuration,
// with the planted error `m` in its golden model.
std::unique_ptr<RegistryAdapter> ray_adapter(const RayConfig& c, Mutant m = Mutant::None);

// ---- vectors ---------------------------------------------------------------------------------
// Every generator is deterministic in (format, seed, count). Doubles are rounded into the
// format to nearest even (the unit's own rounding mode does not apply to its inputs).

// Records from trace records (each double rounded into the format).
std::vector<Record> box_records(const ru::num::Format& f, const std::vector<ru::units::BoxRecord>& v);
std::vector<Record> tri_records(const ru::num::Format& f, const std::vector<ru::units::TriRecord>& v);

// The synthetic workloads of units/synthetic.hpp at scales 1, 1e-6 and 1e+6 and with a 2^+-16
// spread per packet, interleaved; n records.
std::vector<Record> box_synthetic(const ru::num::Format& f, uint64_t seed, size_t n);
std::vector<Record> tri_synthetic(const ru::num::Format& f, uint64_t seed, size_t n);

// Random rays/boxes/triangles at mixed scales (exponents spread over the format's range),
// integer-grid cases (exact zeros, ties), random special values (zeros, subnormals, INF, NaN,
// extremes) sprinkled into ~4 % of the fields.
std::vector<Record> box_random(const ru::num::Format& f, uint64_t seed, size_t n);
std::vector<Record> tri_random(const ru::num::Format& f, uint64_t seed, size_t n);

// The defined extremes (docs/UNITS.md): 1e-6/1e+6 scales, grazing and axis-parallel rays with
// reciprocal +-INF, rays on slab planes (0*INF), flat/inverted boxes, rays exactly through box
// corners/edges/faces and triangle edges/vertices, degenerate and sliver triangles, rays
// starting on the triangle plane, t == t_min/t_max, NaN/INF in every field, overflowing
// volumes, values at the underflow threshold (flush-to-zero bounds), |V| around eps.
std::vector<Record> box_extremes(const ru::num::Format& f, uint64_t seed);
std::vector<Record> tri_extremes(const ru::num::Format& f, uint64_t seed, uint64_t eps_bits);

// A trace file: RU_RAY_TRACE (a captured trace) if set, else a synthetic trace written to
// `tmp_path` with units::TraceWriter and read back with units::read_trace. Returns the
// records of the requested kind (at most n) and sets `what` to a description.
std::vector<Record> trace_records(const ru::num::Format& f, bool box, const std::string& tmp_path,
                                  size_t n, std::string& what);

}  // namespace ru::tb::ray
