// rayunits tb: the adapter layer shared by the floating-point units (ru_fp_add, ru_fp_mul,
// ru_fp_div, ru_fp_sqrt, ru_fp_fma, ru_fp_cmp, ru_fp_dot3) and their vector sources.
//
// Input record: field 0 is the operation (the op_i code; units without op_i have one op),
// then the operands: a, b for the binary units, a for the unary fp_sqrt, a b c for fp_fma, a0 a1 a2 b0 b1 b2 for
// fp_dot3 (driven packed as a_i = {a2, a1, a0}, b_i = {b2, b1, b0}). Output record: y_o, flags_o.
// Golden model: ru::num::apply / ru::num::dot3 with the configuration's Format.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/tb/dut.hpp"
#include "rayunits/tb/harness.hpp"

namespace ru::tb {

struct FpOpDesc {
  const char* name;   // file/CLI name ("add", "lt", "dot3")
  ru::num::Op op;     // model operation (ignored for dot3)
  uint8_t neg = 0;    // fp_fma: bit 0 negates c, bit 1 negates a (so a*b) before ru::num::fma
};

struct FpUnitSpec {
  const char* unit;            // "fp_add"
  std::vector<FpOpDesc> ops;   // indexed by the op_i code
  int op_bits = 0;             // width of op_i; 0: the unit has no op_i port
  bool dot3 = false;
  bool unary = false;          // one operand a_i, no b_i port (fp_sqrt)
  bool ternary = false;        // three operands a_i, b_i, c_i (fp_fma)
  int operands() const { return dot3 ? 6 : unary ? 1 : ternary ? 3 : 2; }
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

class FpAdapter final : public UnitAdapter {
 public:
  FpAdapter(const FpUnitSpec& spec, const ru::num::Format& f, int stages);
  std::string describe() const override;
  const std::vector<FieldInfo>& inputs() const override { return ins_; }
  const std::vector<FieldInfo>& outputs() const override { return outs_; }
  void bind(const PortMap& ports) override;
  void drive(const Record& in) override;
  void read(Record& out) override;
  void model(const Record& in, Record& out) override;
  std::string decimal(const FieldInfo& f, uint64_t v) const override;
  void parse_inputs(const std::vector<std::string>& tokens, Record& in) const override;
  void parse_outputs(const std::vector<std::string>& tokens, Record& out,
                     uint32_t& out_mask) const override;

  const FpUnitSpec& spec() const { return spec_; }
  const ru::num::Format& format() const { return f_; }

 private:
  const FpUnitSpec& spec_;
  ru::num::Format f_;
  int stages_;
  std::vector<FieldInfo> ins_, outs_;
  Port op_, a_, b_, c_, y_, flags_;
  int W_;
};

// Vector sources. All are deterministic functions of their arguments.
// Every op x every pair of ru::num::special_values(f) (unary units: every special value;
// fp_fma: every triple of special values, the op cycling over the triples;
// fp_dot3: each pair placed in one product, the other operands drawn from the specials and
// OperandGen).
std::unique_ptr<VectorSource> fp_special_source(const FpUnitSpec& s, const ru::num::Format& f, uint64_t seed);
// n vectors: uniformly random op, operands from ru::num::OperandGen (weighted random and the
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
