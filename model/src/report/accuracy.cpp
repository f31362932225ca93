// Report section "accuracy" (issue 2 §4): relative error of add, mul, div, dot3 per format.
#include "rayunits/report/accuracy.hpp"

#include <mpfr.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "rayunits/num/format.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::report {

namespace num = ru::num;

const char* acc_op_name(AccOp op) {
  static const char* n[] = {"add", "mul", "div", "dot3"};
  return n[static_cast<int>(op)];
}
int acc_op_inputs(AccOp op) { return op == AccOp::Dot3 ? 6 : 2; }

namespace {
// splitmix64: a fixed, portable generator so a seed means the same workload everywhere.
struct Rng : util::SplitMix64 {
  using util::SplitMix64::SplitMix64;
  // uniform integer in [0, n) (multiply-shift; bias < n / 2^64, immaterial here)
  uint64_t below(uint64_t n) { return util::bounded_mulshift(*this, n); }
};

std::string fmt_e(double v, int digits = 2) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*e", digits, v);
  return buf;
}
}  // namespace

Workload make_workload(long samples, uint64_t seed, int emin, int emax) {
  Workload w;
  w.samples = samples;
  Rng rng(seed);
  const uint64_t span = static_cast<uint64_t>(emax - emin + 1);
  for (int k = 0; k < kAccOps; ++k) {
    const size_t n = static_cast<size_t>(samples) * acc_op_inputs(static_cast<AccOp>(k));
    w.in[k].resize(n);
    for (size_t i = 0; i < n; ++i) {
      int e = emin + static_cast<int>(rng.below(span));
      double m = 1.0 + std::ldexp(static_cast<double>(rng.next() >> 12), -52);
      double x = std::ldexp(m, e);
      w.in[k][i] = (rng.next() & 1) ? -x : x;
    }
  }
  return w;
}

void compute_reference(Workload& w, const Context* ctx) {
  constexpr long kChunk = 4096;
  constexpr mpfr_prec_t kPrec = 256;
  for (int k = 0; k < kAccOps; ++k) {
    w.hi[k].assign(static_cast<size_t>(w.samples), 0.0);
    w.lo[k].assign(static_cast<size_t>(w.samples), 0.0);
  }
  const long chunks = (w.samples + kChunk - 1) / kChunk;
  auto job = [&](size_t job_index) {
    const int k = static_cast<int>(job_index % kAccOps);
    const long c = static_cast<long>(job_index / kAccOps);
    const AccOp op = static_cast<AccOp>(k);
    mpfr_t a, b, r, t;
    mpfr_inits2(kPrec, a, b, r, t, static_cast<mpfr_ptr>(nullptr));
    const long end = std::min(w.samples, (c + 1) * kChunk);
    std::string err;
    for (long i = c * kChunk; i < end && err.empty(); ++i) {
      const double* x = &w.in[k][static_cast<size_t>(i) * acc_op_inputs(op)];
      int inexact = 0;
      mpfr_set_d(a, x[0], MPFR_RNDN);  // exact: 53 <= 256 bits
      mpfr_set_d(b, x[1], MPFR_RNDN);
      switch (op) {
        case AccOp::Add: inexact = mpfr_add(r, a, b, MPFR_RNDN); break;
        case AccOp::Mul: inexact = mpfr_mul(r, a, b, MPFR_RNDN); break;
        case AccOp::Div: mpfr_div(r, a, b, MPFR_RNDN); break;  // rel. error < 2^-255
        case AccOp::Dot3:
          inexact |= mpfr_mul(r, a, b, MPFR_RNDN);
          for (int j = 1; j < 3; ++j) {
            mpfr_set_d(a, x[2 * j], MPFR_RNDN);
            mpfr_set_d(b, x[2 * j + 1], MPFR_RNDN);
            inexact |= mpfr_mul(t, a, b, MPFR_RNDN);
            inexact |= mpfr_add(r, r, t, MPFR_RNDN);
          }
          break;
      }
      if (inexact) {
        // Only possible for inputs far outside the workload's exponent span.
        err = std::string("internal: the exact reference for ") + acc_op_name(op) +
              " needs more than 256 bits (workload exponent span too wide)";
        break;
      }
      double hi = mpfr_get_d(r, MPFR_RNDN);
      mpfr_sub_d(t, r, hi, MPFR_RNDN);
      w.hi[k][static_cast<size_t>(i)] = hi;
      w.lo[k][static_cast<size_t>(i)] = mpfr_get_d(t, MPFR_RNDN);
    }
    mpfr_clears(a, b, r, t, static_cast<mpfr_ptr>(nullptr));
    if (!err.empty()) throw ReportError(err);
  };
  const size_t jobs = static_cast<size_t>(chunks) * kAccOps;
  if (ctx) {
    ctx->parallel_for(jobs, "exact reference (MPFR), chunks", job);
  } else {
    for (size_t j = 0; j < jobs; ++j) job(j);
  }
  mpfr_free_cache();
}

CellStats evaluate_cell(const Workload& w, AccOp op, int exp_bits, int frac_bits) {
  num::Format f;
  f.exp_bits = exp_bits;
  f.frac_bits = frac_bits;
  f.subnormals = true;
  f.round = num::Round::RNE;
  f.validate();
  const double maxf = num::to_double(f, f.max_finite());
  const int k = static_cast<int>(op);
  const int nin = acc_op_inputs(op);
  CellStats s;
  uint64_t v[6];
  for (long i = 0; i < w.samples; ++i) {
    const double* x = &w.in[k][static_cast<size_t>(i) * nin];
    uint8_t flags = 0;
    for (int j = 0; j < nin; ++j) {
      num::Result r = num::from_double(f, x[j]);
      v[j] = r.bits;
      flags |= r.flags;
    }
    num::Result r;
    switch (op) {
      case AccOp::Add: r = num::add(f, v[0], v[1]); break;
      case AccOp::Mul: r = num::mul(f, v[0], v[1]); break;
      case AccOp::Div: r = num::div(f, v[0], v[1]); break;
      case AccOp::Dot3: {
        const uint64_t a[3] = {v[0], v[2], v[4]}, b[3] = {v[1], v[3], v[5]};
        r = num::dot3(f, a, b);
        break;
      }
    }
    flags |= r.flags;
    if (flags & num::kOverflow) ++s.overflow;
    if (flags & num::kUnderflow) ++s.underflow;
    if (flags & (num::kOverflow | num::kUnderflow)) ++s.out_of_range;
    double c = num::to_double(f, r.bits);
    if (std::isnan(c)) {
      ++s.nan;
      continue;
    }
    if (std::isinf(c)) c = c > 0 ? maxf : -maxf;
    const double hi = w.hi[k][static_cast<size_t>(i)], lo = w.lo[k][static_cast<size_t>(i)];
    if (hi == 0) {
      ++s.zero_exact;
      continue;
    }
    // |c - (hi+lo)| / |hi+lo|: c - hi is exact when c and hi are within a factor 2 (Sterbenz);
    // otherwise every step is a rounding with relative error 2^-53 of an error >= 1/2.
    const double rel = std::fabs((c - hi) - lo) / std::fabs(hi);
    ++s.used;
    s.sum_rel += rel;
    if (rel > s.max_rel || s.worst < 0) {
      s.max_rel = rel;
      s.worst = i;
    }
  }
  return s;
}

// ------------------------------------------------------------------------------ the section
std::string accuracy_section(Context& ctx) {
  const auto& o = ctx.opts;
  const long samples = o.samples > 0 ? o.samples : kAccuracyDefaultSamples;
  int emin = -33, emax = 18;
  try {
    emin = std::stoi(ctx.param("accuracy.emin", "-33"));
    emax = std::stoi(ctx.param("accuracy.emax", "18"));
  } catch (const std::exception&) {
    throw ReportError("accuracy.emin / accuracy.emax must be integers");
  }
  if (emin > emax || emin < -60 || emax > 60)
    throw ReportError("accuracy workload exponent span must satisfy -60 <= emin <= emax <= 60");

  struct Cell {
    int e, m;
  };
  std::vector<Cell> cells;
  for (int m = o.frac_lo; m <= o.frac_hi; ++m)
    for (int e = o.exp_lo; e <= o.exp_hi; ++e)
      if (1 + e + m <= num::Format::kMaxWidth) cells.push_back({e, m});
  if (cells.empty()) throw ReportError("accuracy: the width grid has no valid format");

  char buf[256];
  std::snprintf(buf, sizeof buf, "workload: %ld samples per op, exponents %d..%d, seed %llu", samples, emin, emax,
                static_cast<unsigned long long>(o.seed));
  ctx.progress(buf);
  Workload w = make_workload(samples, o.seed, emin, emax);
  compute_reference(w, &ctx);

  std::vector<CellStats> stats(cells.size() * kAccOps);
  ctx.parallel_for(stats.size(), "cells x ops", [&](size_t j) {
    const Cell& c = cells[j / kAccOps];
    stats[j] = evaluate_cell(w, static_cast<AccOp>(j % kAccOps), c.e, c.m);
  });

  // CSV
  {
    std::ofstream csv(ctx.path("accuracy.csv"));
    csv << "exp_bits,frac_bits,format,op,samples,used,mean_rel_err,max_rel_err,overflow,underflow,out_of_range,nan,"
           "zero_exact,"
           "worst_inputs\n";
    for (size_t j = 0; j < stats.size(); ++j) {
      const Cell& c = cells[j / kAccOps];
      const AccOp op = static_cast<AccOp>(j % kAccOps);
      const CellStats& s = stats[j];
      std::string worst;
      if (s.worst >= 0)
        for (int q = 0; q < acc_op_inputs(op); ++q) {
          std::snprintf(buf, sizeof buf, "%s%.17g", q ? " " : "",
                        w.in[static_cast<int>(op)][static_cast<size_t>(s.worst) * acc_op_inputs(op) + q]);
          worst += buf;
        }
      std::snprintf(buf, sizeof buf, "%d,%d,e%dm%d,%s,%ld,%ld,%.6e,%.6e,%ld,%ld,%ld,%ld,%ld,", c.e, c.m, c.e,
                    c.m, acc_op_name(op), samples, s.used, s.mean(), s.max_rel, s.overflow, s.underflow,
                    s.out_of_range, s.nan,
                    s.zero_exact);
      csv << buf << worst << "\n";
      ctx.accuracy["e" + std::to_string(c.e) + "m" + std::to_string(c.m) + " " + acc_op_name(op)] = {
          s.mean(), s.max_rel, s.out_of_range};
    }
    csv.close();
    if (!csv) throw ReportError("cannot write " + ctx.path("accuracy.csv").string());
  }

  if (o.plots) {
    ctx.progress("plotting");
    ctx.run_python("plot_accuracy.py", {ctx.path("accuracy.csv").string(), ctx.dir.string()});
  }

  // Markdown
  std::ostringstream md;
  md << "Average and maximum relative error |computed − exact| / |exact| of `add`, `mul`, `div` and "
        "`dot3` (a0·b0 + a1·b1 + a2·b2 as `ru_fp_dot3` computes it: every product and sum rounded) "
        "for every format eXmY of the grid (RNE, subnormals on).\n\n"
     << "- **Workload** (built-in default): " << samples
     << " operand sets per operation, the same for every format; each operand is ±m·2^e with e uniform in "
     << emin << ".." << emax
     << " (the exponent span of a typical scene's ray and triangle coordinates, Kensler Fig. 3.5), m uniform in "
        "[1, 2) with 52 random bits, random sign; generator splitmix64, seed "
     << o.seed << ".\n"
     << "- **Method**: each operand (a double) is rounded into the format, as a scene would be, then the "
        "operation runs in the format (the bit-exact model, `ru::num`). The error is against the exact result "
        "on the unrounded operands, so it includes input rounding (as Kensler §3.7 measures). An INF result "
        "counts as the largest finite value of its sign (Kensler §3.7); NaN results and exact zeros are "
        "counted and left out of the statistics.\n"
     << "- **Exact reference**: MPFR at 256 bits — exact for add, mul and dot3 on this workload (every MPFR "
        "operation is checked to be exact), relative error < 2^-250 for div; the error is evaluated in "
        "double-double (relative accuracy of the reported error ~1e-15).\n"
     << "- **Overflow / underflow**: samples in which rounding an operand or any operation raised the flag "
        "(underflow: tiny and inexact, tininess after rounding).\n"
     << "- Data: [accuracy.csv](accuracy.csv) (one row per format and operation, with the inputs of the "
        "worst sample). For reference, the unit roundoff of one rounding is u = 2^-(M+1).\n\n";
  if (o.plots)
    md << "![average relative error](accuracy_mean.png)\n\n![maximum relative error](accuracy_max.png)\n\n"
          "![overflow and underflow](accuracy_range.png)\n\n![error vs fraction bits](accuracy_vs_m.png)\n\n";
  else
    md << "(Plots skipped: the report ran with --no-plots.)\n\n";

  std::vector<int> es;
  for (int e = o.exp_lo; e <= o.exp_hi; ++e) es.push_back(e);
  for (int k = 0; k < kAccOps; ++k) {
    md << "### " << acc_op_name(static_cast<AccOp>(k))
       << ": average / maximum relative error\n\n(† = some samples overflowed or underflowed)\n\n";
    std::vector<std::string> header = {"M \\ E"};
    for (int e : es) header.push_back(std::to_string(e));
    std::vector<std::vector<std::string>> rows;
    for (int m = o.frac_lo; m <= o.frac_hi; ++m) {
      std::vector<std::string> row = {std::to_string(m)};
      for (int e : es) {
        std::string cell = "";
        for (size_t ci = 0; ci < cells.size(); ++ci) {
          if (cells[ci].e != e || cells[ci].m != m) continue;
          const CellStats& s = stats[ci * kAccOps + k];
          cell = s.used ? fmt_e(s.mean(), 1) + " / " + fmt_e(s.max_rel, 1) : "n/a";
          if (s.overflow || s.underflow) cell += " †";
        }
        row.push_back(cell);
      }
      rows.push_back(row);
    }
    md << md_table(header, rows) << "\n";
  }

  md << "### Samples that overflowed / underflowed (summed over all M of the grid)\n\n";
  {
    std::vector<std::string> header = {"op"};
    for (int e : es) header.push_back("E=" + std::to_string(e));
    std::vector<std::vector<std::string>> rows;
    for (int k = 0; k < kAccOps; ++k) {
      std::vector<std::string> row = {acc_op_name(static_cast<AccOp>(k))};
      for (int e : es) {
        long ov = 0, un = 0, tot = 0;
        for (size_t ci = 0; ci < cells.size(); ++ci)
          if (cells[ci].e == e) {
            ov += stats[ci * kAccOps + k].overflow;
            un += stats[ci * kAccOps + k].underflow;
            tot += samples;
          }
        row.push_back(tot ? std::to_string(ov) + " / " + std::to_string(un) : "n/a");
      }
      rows.push_back(row);
    }
    md << md_table(header, rows) << "\n";
  }
  return md.str();
}

}  // namespace ru::report
