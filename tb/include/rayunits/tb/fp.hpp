// rayunits tb: the test-plan layer shared by the floating-point units (ru_fp_add, ru_fp_mul,
// ru_fp_div, ru_fp_sqrt, ru_fp_fma, ru_fp_cmp, ru_fp_dot3): vector files and vector sources on
// top of the registry adapter (registry_adapter.hpp).
//
// Records are the registry's (synth::fields_for): the operands in port order (a b, a for fp_sqrt,
// a b c for fp_fma, a0 a1 a2 b0 b1 b2 for fp_dot3), then op_i for the units that have one
// (fp_add, fp_fma, fp_cmp). Output record: y_o, flags_o. Golden model: the registry's
// (ru::num::apply / ru::num::dot3 with the configuration's Format).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/tb/dut.hpp"
#include "rayunits/tb/harness.hpp"
#include "rayunits/tb/registry_adapter.hpp"

namespace ru::tb {

// What the FP plan needs to know about a floating-point unit, derived from its registry entry
// (its ports: the Float inputs are the operands, op_i's enum names the operations).
struct FpUnitSpec {
  const synth::UnitSpec* unit = nullptr;
  std::vector<std::string> ops;  // by op_i code; one entry (the unit's name without "fp_") if no op_i
  int op_field = -1;             // index of op_i in the input record, -1: the unit has no op_i
  int operands = 2;              // operand fields 0 .. operands-1
  bool dot3 = false;             // two packed 3-vectors
  bool unary() const { return operands == 1; }
  bool ternary() const { return operands == 3; }
};

// nullptr if `unit` is not a floating-point unit.
const FpUnitSpec* fp_unit_spec(const std::string& unit);

// The configuration's Format (ExpW, FracW, Subnormals, Round parameters). Throws FormatError.
ru::num::Format fp_format(const ConfigDesc& cfg);
// "e8m23 rne", "e5m10-ftz rtz"
std::string fp_format_name(const ru::num::Format& f);

// A format value for mismatch reports: "+inf", "-qNaN", "+0", or the decimal value with enough
// digits to identify it (", subnormal" appended for subnormal encodings, also in FTZ formats).
std::string fp_text(const ru::num::Format& f, uint64_t v);

// The registry adapter of an FP unit plus the vector-file syntax "<op> <operands...> -> <y> <flags>".
class FpAdapter final : public RegistryAdapter {
 public:
  FpAdapter(const FpUnitSpec& spec, const ru::num::Format& f, int stages);
  void parse_inputs(const std::vector<std::string>& tokens, Record& in) const override;
  void parse_outputs(const std::vector<std::string>& tokens, Record& out,
                     uint32_t& out_mask) const override;
  const FpUnitSpec& spec() const { return spec_; }
  const ru::num::Format& format() const { return config().fmt; }

 private:
  const FpUnitSpec& spec_;
};

// Vector sources. All are deterministic functions of their arguments.
// Every op x every pair of ru::num::special_values(f) (unary units: every special value;
// fp_fma: every triple of special values, the op cycling over the triples;
// fp_dot3: each pair placed in one product, the other operands drawn from the specials and
// OperandGen).
std::unique_ptr<VectorSource> fp_special_source(const FpUnitSpec& s, const ru::num::Format& f, uint64_t seed);
// n vectors of the unit's registry generator (UnitSpec::random_inputs,
// model/src/synth/unit_models.cpp): uniformly random op, operands from ru::num::OperandGen (weighted random and the
// hard cases of each operation; fp_sqrt: half of them OperandGen::sqrt_case, exact squares and
// squares of rounding midpoints; fp_fma: OperandGen::triple, products near ties, cancellation
// c ~ -a*b, exponent differences; fp_dot3: two triples, 1 in 4 with a cancelling product pair).
std::unique_ptr<VectorSource> fp_random_source(const FpUnitSpec& s, const ru::num::Format& f, uint64_t seed, uint64_t n);
// Every op x every pair of bit patterns (binary units; the format must be at most 12 bits wide),
// every bit pattern for unary units (at most 24 bits wide), every op x every triple for fp_fma
// (at most 8 bits wide).
std::unique_ptr<VectorSource> fp_exhaustive_source(const FpUnitSpec& s, const ru::num::Format& f);
uint64_t fp_exhaustive_count(const FpUnitSpec& s, const ru::num::Format& f);

}  // namespace ru::tb
