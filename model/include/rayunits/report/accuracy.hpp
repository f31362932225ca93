// Report section "accuracy": average and maximum relative error of add, mul, div and dot3 over
// a grid of formats (E x M) on a workload of random values spanning a typical scene's
// exponents (Kensler, Fig. 3.5: -33..18), with overflow/underflow counts per cell.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rayunits/report/report.hpp"

namespace ru::report {

// The section function (registered in model/cli/report_sections.cpp).
// Parameters (--param key=value): accuracy.emin / accuracy.emax (workload exponent span,
// default -33 / 18); the sample count per cell is --samples (default kAccuracyDefaultSamples).
std::string accuracy_section(Context& ctx);

constexpr long kAccuracyDefaultSamples = 200000;

// ---- pieces exposed for tests -----------------------------------------------------------
enum class AccOp : int { Add = 0, Mul = 1, Div = 2, Dot3 = 3 };
constexpr int kAccOps = 4;
const char* acc_op_name(AccOp op);
int acc_op_inputs(AccOp op);  // 2, or 6 for dot3 (a0 b0 a1 b1 a2 b2)

// Deterministic workload: for each op, `samples` input tuples of doubles ±m·2^e with e
// uniform in [emin, emax], m uniform in [1, 2) (52 random fraction bits), random sign.
struct Workload {
  long samples = 0;
  std::vector<double> in[kAccOps];  // samples * acc_op_inputs(op) values
  std::vector<double> hi[kAccOps], lo[kAccOps];  // exact result ~ hi + lo (|lo| <= ulp(hi)/2)
};
Workload make_workload(long samples, uint64_t seed, int emin, int emax);
// Fills hi/lo with MPFR (precision 256: exact for add/mul/dot3 on this workload, which is
// checked, and relative error < 2^-250 for div). Runs chunk jobs through fn-style parallelism
// when ctx is non-null.
void compute_reference(Workload& w, const Context* ctx);

struct CellStats {
  long used = 0;          // samples in the statistics
  double sum_rel = 0;     // sum of relative errors
  double max_rel = 0;
  long worst = -1;        // sample index of max_rel
  long overflow = 0;      // samples where an operation (or rounding an input) overflowed
  long underflow = 0;     // ... raised underflow
  long out_of_range = 0;  // ... raised overflow or underflow
  long nan = 0;           // NaN results (e.g. INF-INF after overflow): not in the statistics
  long zero_exact = 0;    // exact result 0: relative error undefined, not in the statistics
  double mean() const { return used ? sum_rel / static_cast<double>(used) : 0.0; }
};
// Rounds the inputs into eXmY (RNE, subnormals), runs the op in the format and compares with
// the exact result. An INF result counts as the largest finite value of its sign (Kensler §3.7).
CellStats evaluate_cell(const Workload& w, AccOp op, int exp_bits, int frac_bits);

}  // namespace ru::report
