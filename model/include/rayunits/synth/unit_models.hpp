// The golden-model adapters and random vector generators of the registered units (the registry
// entries in model/src/synth/units.cpp name them; the tools reach them through UnitSpec::golden
// and UnitSpec::random_inputs), and the one mapping of trace records to the ray units' input
// fields (also used by the ray testbench's sources). Each binds the bit-accurate model of
// model/include/rayunits/{num,units,noise} to the record layout fields_for() derives from the
// unit's ports.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "rayunits/dp/ir.hpp"
#include "rayunits/noise/texture.hpp"
#include "rayunits/num/format.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::synth::models {

// Floating-point units. `ops` are the operations by op_i code (one entry: the unit has no op_i,
// the op field is absent); `neg` per op: bit 0 negates c, bit 1 negates a (so a*b) — fp_fma.
struct FpOp {
  num::Op op;
  uint8_t neg = 0;
};
enum class FpShape : uint8_t { Unary, Binary, Ternary, Dot3, Dot3Fused };
// Records: operands in port order (a b c, or a0 a1 a2 b0 b1 b2), then op_i if the unit has one.
GoldenEval fp_golden(const UnitConfig& c, FpShape shape, std::vector<FpOp> ops);
InputGen fp_inputs(const UnitConfig& c, uint64_t seed, FpShape shape, int nops);

// fp_cvt: a op -> y flags. The second format G (InExpW, InFracW, InSubnormals; rounding unused)
// and IntW come from the configuration's parameters (their registry defaults when unset).
struct CvtFormats {
  num::Format f, g;
  int int_w = 32;
};
CvtFormats cvt_formats(const UnitConfig& c);
// The low `bits` bits of x (bits >= 64: x).
uint64_t low_bits(uint64_t x, int bits);
GoldenEval fp_cvt_golden(const UnitConfig& c);
// Uniform op; the bits of a_i the op ignores are random. f2f: OperandGen of G; i2f: integers of
// every bit length, the range ends, powers of two and F's rounding ties and midpoints; f2i:
// half OperandGen of F, half values near integers and half-integers over [2^-3, 2^(IntW+2)],
// the range ends included.
InputGen fp_cvt_inputs(const UnitConfig& c, uint64_t seed);

// A trace record as the unit's input fields, each value rounded to nearest into `f`:
// ray_box org.xyz rdir.xyz tmin tmax bmin.xyz bmax.xyz (14 fields), ray_tri_* a.xyz d.xyz p0.xyz
// p1.xyz p2.xyz tmin tmax (17 fields).
void box_fields(const num::Format& f, const units::BoxRecord& r, uint64_t* in);
void tri_fields(const num::Format& f, const units::TriRecord& r, uint64_t* in);

// ray_box: org.xyz rdir.xyz tmin tmax bmin.xyz bmax.xyz -> hit t_enter t_exit
GoldenEval ray_box_golden(const UnitConfig& c);
InputGen ray_box_inputs(const UnitConfig& c, uint64_t seed);
// ray_tri_robust / ray_tri_mt: a.xyz d.xyz p0.xyz p1.xyz p2.xyz tmin tmax
//   -> hit why t beta gamma V Va V0 V1 V2 (the volumes 0 unless OptVolOut = 1)
GoldenEval ray_tri_golden(const UnitConfig& c, bool robust);
InputGen ray_tri_inputs(const UnitConfig& c, uint64_t seed);
// ru_ray_tri_exact: units::ray_tri_exact<Soft> (the RTL's filter) -> hit, why, t, beta, gamma, slow.
GoldenEval ray_tri_exact_golden(const UnitConfig& c);
// Alternately ray_tri_inputs' records (synthetic scenes: the fast path decides nearly all) and
// units::ExactTriGen's (grids, vertices, extremes: the side path's cases).
InputGen ray_tri_exact_inputs(const UnitConfig& c, uint64_t seed);
// A design of the datapath IR (dp/formulas.hpp, by name) as the golden model of its emitted module
// (rayunits dp emit): the graph evaluated in Soft, one output field per graph output (a Boolean
// output is 0/1).
GoldenEval dp_golden(const UnitConfig& c, std::shared_ptr<const dp::Graph> g);
// noise: x y z -> value
GoldenEval noise_golden(const UnitConfig& c);
GoldenEval noise_trunc_golden(const UnitConfig& c);  // the truncated datapath (ru_noise_trunc)
InputGen noise_inputs(const UnitConfig& c, uint64_t seed);
// The procedural texture unit (ru_texture, noise::FixedTexture): inputs x, y, z, mode, octaves.
noise::TextureConfig texture_config(const UnitConfig& c);
GoldenEval texture_golden(const UnitConfig& c);
InputGen texture_inputs(const UnitConfig& c, uint64_t seed);

// The integer units (units/int_units.hpp): int_alu a_i b_i op_i -> y_o; branch a_i b_i pc_i off_i
// op_i -> taken_o y_o. Generators: edge words (0, +-1, the signed/unsigned range ends, powers of
// two, shift amounts around IntW) mixed with random words; equal operands often (eq, min/max ties).
GoldenEval int_alu_golden(const UnitConfig& c);
InputGen int_alu_inputs(const UnitConfig& c, uint64_t seed);
GoldenEval branch_golden(const UnitConfig& c);
InputGen branch_inputs(const UnitConfig& c, uint64_t seed);

}  // namespace ru::synth::models
