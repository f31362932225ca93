// Shared test harness for the number-format suites: a reference-vs-DUT checker that prints
// format, op, rounding, operands (hex and decimal), expected, actual and flags and stops after
// a few errors; drivers for random / special / exhaustive operand sets; format grids; the native
// float/double wrappers (x86-64: one inline-asm block per operation with its own MXCSR, so the
// compiler can neither fold nor move the operation away from the flag read).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/num/mpfr_ref.hpp"
#include "rayunits/num/patterns.hpp"

namespace ru::num::testing {

// Own spellings (not the model's) so a bug in the model's printing cannot hide a mismatch.
std::string fmt_name(const Format& f);  // "e5m10", "e5m10-ftz"
const char* rnd_name(Round r);
const char* op_str(Op op);
int arity(Op op);
std::string flag_str(uint8_t flags);  // "izoux" subset, "-" for none
// "0x3c00 = 1 (0x1p+0)" / "0x7e00 = qNaN" ..., decoded here without flushing.
std::string describe(const Format& f, uint64_t bits);
bool bits_are_nan(const Format& f, uint64_t bits);
Format make_format(int E, int M, bool subnormals = true, Round r = Round::RNE);

inline constexpr Round kRounds[] = {Round::RNE, Round::RTZ, Round::RDN, Round::RUP};
inline constexpr Op kArithOps[] = {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::Sqrt, Op::Fma};
inline constexpr Op kCompareOps[] = {Op::Min, Op::Max, Op::Lt, Op::Le, Op::Eq};
inline constexpr Op kAllOps[] = {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::Sqrt, Op::Fma,
                                 Op::Min, Op::Max, Op::Lt,  Op::Le,  Op::Eq};

using OpFn = std::function<Result(const Format&, Op, uint64_t, uint64_t, uint64_t)>;

// The model, called through its individual entry points (add, sub, ... not apply()).
Result model_op(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c);
// The MPFR oracle.
Result oracle_op(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c);

enum class NanMatch {
  Exact,   // bits must be equal (the model and the oracle both return the canonical NaN)
  AnyNan,  // a NaN matches any NaN (native hardware propagates payloads)
};

class Checker {
 public:
  explicit Checker(std::string what, NanMatch nan = NanMatch::Exact, int max_errors = 5);
  // Compares one result; records (up to max_errors) a full description of a mismatch.
  bool check(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c, const Result& expected,
             const Result& actual);
  // Free-form mismatch (for conversions etc.).
  void fail(const std::string& message);
  void count() { ++checks_; }
  bool done() const { return errors_ >= static_cast<uint64_t>(max_errors_); }
  bool ok() const { return errors_ == 0; }
  uint64_t checks() const { return checks_; }
  uint64_t errors() const { return errors_; }
  std::string report() const;  // the recorded mismatches and a summary line

 private:
  std::string what_;
  NanMatch nan_;
  int max_errors_;
  uint64_t checks_ = 0, errors_ = 0;
  std::vector<std::string> messages_;
};

// Drivers. Each stops early once the checker is done.
// Random operand sets from OperandGen (next/pair/triple by arity).
void run_random(Checker& chk, const Format& f, Op op, uint64_t count, uint64_t seed, const OpFn& ref,
                const OpFn& dut);
// Uniformly random bit patterns (a splitmix64 stream, util/rng.hpp).
void run_uniform(Checker& chk, const Format& f, Op op, uint64_t count, uint64_t seed, const OpFn& ref,
                 const OpFn& dut);
// special_values x special_values (fma: x a selection of c values, plus specials for c).
void run_specials(Checker& chk, const Format& f, Op op, const OpFn& ref, const OpFn& dut);
// Every operand tuple of the format (fma: every triple; only sensible for tiny formats).
void run_exhaustive(Checker& chk, const Format& f, Op op, const OpFn& ref, const OpFn& dut);

// Format grids (pairs (E, M)).
std::vector<std::pair<int, int>> grid_formats();  // E {3,4,5,6,7,8,11} x M {1,2,3,7,10,16,23,30,52}
std::vector<std::pair<int, int>> small_formats(int min_width, int max_width);  // every valid (E,M)
// Off the grid: E = 2 (the smallest exponent) up to M = 52, E = 9, 10 with M = 52, others.
std::vector<std::pair<int, int>> edge_formats();
std::string em_param_name(const ::testing::TestParamInfo<std::pair<int, int>>& info);

// Scales a test count: RU_NUM_SCALE (a float, default 1) multiplies every count.
uint64_t scaled(uint64_t count);

// ---- native hardware -----------------------------------------------------------------------
// Executes op on float (W = 32) or double (W = 64) with rounding r, FTZ+DAZ when ftz, and
// returns the bits and the five flags raised by that one instruction.
bool native_supported(bool ftz);  // FTZ/DAZ needs x86 SSE
Result native_op(int width, Op op, uint64_t a, uint64_t b, uint64_t c, Round r, bool ftz);
// native_op for f = e8m23 / e11m52 (f.round, FTZ+DAZ when !f.subnormals) with the one documented
// difference between x86 and docs/FORMAT.md made explicit: fma(0, inf, qNaN) raises invalid in
// the format (IEEE 754 leaves it to the implementation; x86 does not raise it).
Result native_spec_op(const Format& f, Op op, uint64_t a, uint64_t b, uint64_t c);

}  // namespace ru::num::testing
