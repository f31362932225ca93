// rayunits bench fp: ops/s of the bit-exact model vs MPFR doing the same format emulation, vs a
// minimal double-backed peer emulator and vs native float.
//
// These are timed per format and operation, alternating, in thread CPU time:
//   model    ru::num::add/mul/div/fma/sqrt on bit patterns (bits + flags out);
//   peer     FlexFloat/CPFloat-style: doubles in, compute in double, round once to nearest
//            (Peer below; correct for + - * / sqrt when 2(M+1)+2 <= 53, no flags, RNE only);
//   float    native float loops over the same values (vectorized);
//   MPFR     operands already held as mpfr_t at precision M+1, emin/emax set for the format:
//            the operation, mpfr_subnormalize, the flags -- the cheapest possible MPFR step;
//   MPFR+cv  the same plus mpfr_set_d of the operands and mpfr_get_d of the result (exact
//            conversions): values in, value + flags out, the model's interface. Default
//            baseline of the ratio line (--baseline resident switches to MPFR).
// The project's MPFR test oracle (ru::num::mpfr_apply: bits in/out, every special case) is
// timed too, for information. Model and MPFR+cv are checked to give the same values first.
#include <mpfr.h>

#include <algorithm>
#include <ctime>
#include <functional>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/num/batch.hpp"
#include "rayunits/num/format.hpp"
#include "rayunits/num/mpfr_ref.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::cli {
namespace {

using ru::num::Format;
using ru::num::Op;

volatile uint64_t g_sink;

const char* isa_name(ru::num::BatchIsa i) {
  switch (i) {
    case ru::num::BatchIsa::Avx512: return "AVX-512, 8 lanes";
    case ru::num::BatchIsa::Avx2: return "AVX2, 4 lanes";
    default: return "none, scalar";
  }
}

struct Operands {
  std::vector<uint64_t> a, b, c;  // bit patterns
  std::vector<double> da, db, dc;  // the same values as doubles
  std::vector<uint64_t> s;        // |a| (sqrt operands)
  std::vector<double> ds;
  std::vector<float> fa, fb, fc, fs;  // the same values as floats (exact when E <= 8, M <= 23)
};

using util::splitmix64;

// Exponent span of the operands: [-span, span] keeps every product, quotient and fma result
// normal (no overflow/underflow), so both sides do the same ordinary work.
int operand_span(const Format& f) { return std::max(0, std::min(8, (f.emax() - 2) / 2)); }

// Random normal values with exponents in [-span, span], random fraction bits, random sign.
Operands make_operands(const Format& f, size_t n, uint64_t seed) {
  Operands o;
  uint64_t s = seed;
  const int span = operand_span(f);
  auto one = [&](std::vector<uint64_t>& bits, std::vector<double>& d) {
    int e = static_cast<int>(splitmix64(s) % static_cast<uint64_t>(2 * span + 1)) - span;
    uint64_t frac = splitmix64(s) & f.frac_mask();
    uint64_t sign = (splitmix64(s) & 1) ? f.sign_bit() : 0;
    uint64_t v = sign | (static_cast<uint64_t>(e + f.bias()) << f.frac_bits) | frac;
    bits.push_back(v);
    d.push_back(ru::num::to_double(f, v));
  };
  for (size_t i = 0; i < n; ++i) {
    one(o.a, o.da);
    one(o.b, o.db);
    one(o.c, o.dc);
    o.s.push_back(o.a.back() & ~f.sign_bit());
    o.ds.push_back(std::fabs(o.da.back()));
  }
  for (size_t i = 0; i < n; ++i) {
    o.fa.push_back(static_cast<float>(o.da[i]));
    o.fb.push_back(static_cast<float>(o.db[i]));
    o.fc.push_back(static_cast<float>(o.dc[i]));
    o.fs.push_back(static_cast<float>(o.ds[i]));
  }
  return o;
}

mpfr_rnd_t mpfr_mode(ru::num::Round r) {
  switch (r) {
    case ru::num::Round::RNE: return MPFR_RNDN;
    case ru::num::Round::RTZ: return MPFR_RNDZ;
    case ru::num::Round::RDN: return MPFR_RNDD;
    case ru::num::Round::RUP: return MPFR_RNDU;
  }
  return MPFR_RNDN;
}

// One pass of the batch API (num/batch.hpp) over all operand sets: arrays in, arrays out.
void batch_pass(const Format& f, Op op, const Operands& o, std::vector<uint64_t>& y, std::vector<uint8_t>& fl) {
  const size_t n = o.a.size();
  y.resize(n);
  fl.resize(n);
  uint8_t all = 0;
  switch (op) {
    case Op::Add: all = ru::num::add_n(f, o.a.data(), o.b.data(), y.data(), fl.data(), n); break;
    case Op::Mul: all = ru::num::mul_n(f, o.a.data(), o.b.data(), y.data(), fl.data(), n); break;
    case Op::Div: all = ru::num::div_n(f, o.a.data(), o.b.data(), y.data(), fl.data(), n); break;
    case Op::Sqrt: all = ru::num::sqrt_n(f, o.s.data(), y.data(), fl.data(), n); break;
    default: all = ru::num::fma_n(f, o.a.data(), o.b.data(), o.c.data(), y.data(), fl.data(), n); break;
  }
  g_sink = g_sink + y[n / 2] + all;
}

// One pass of the model over all operand sets.
void model_pass(const Format& f, Op op, const Operands& o) {
  uint64_t sink = 0;
  const size_t n = o.a.size();
  switch (op) {
    case Op::Add:
      for (size_t i = 0; i < n; ++i) {
        auto r = ru::num::add(f, o.a[i], o.b[i]);
        sink += r.bits ^ r.flags;
      }
      break;
    case Op::Mul:
      for (size_t i = 0; i < n; ++i) {
        auto r = ru::num::mul(f, o.a[i], o.b[i]);
        sink += r.bits ^ r.flags;
      }
      break;
    case Op::Div:
      for (size_t i = 0; i < n; ++i) {
        auto r = ru::num::div(f, o.a[i], o.b[i]);
        sink += r.bits ^ r.flags;
      }
      break;
    case Op::Sqrt:
      for (size_t i = 0; i < n; ++i) {
        auto r = ru::num::sqrt(f, o.s[i]);
        sink += r.bits ^ r.flags;
      }
      break;
    default:
      for (size_t i = 0; i < n; ++i) {
        auto r = ru::num::fma(f, o.a[i], o.b[i], o.c[i]);
        sink += r.bits ^ r.flags;
      }
      break;
  }
  g_sink = g_sink + sink;
}

// The peer: a minimal double-backed emulator in the style of FlexFloat / CPFloat. Values are
// held as doubles; each operation is computed in double and rounded once to the format: round to
// nearest even at M+1 bits, or at the subnormal quantum 2^(emin-M) below the smallest normal, and
// values beyond the largest finite become INF. Correct for + - * / sqrt when 2(M+1)+2 <= 53 --
// and no more: no other rounding mode, no flags, no FTZ, NaN/zero signs not canonicalised.
class Peer {
 public:
  explicit Peer(const Format& f)
      : low_(52 - f.frac_bits),
        maxv_(ru::num::to_double(f, f.max_finite())),
        min_normal_(std::ldexp(1.0, f.emin())),
        magic_(std::ldexp(1.0, f.emin() - f.frac_bits + 52)) {}
  double round(double x) const {
    const double ax = std::fabs(x);
    if (ax < min_normal_) {  // subnormal range: x + magic rounds (RNE) at ulp(magic) = 2^(emin-M)
      const double m = std::copysign(magic_, x);
      return (x + m) - m;
    }
    uint64_t u;
    std::memcpy(&u, &x, 8);
    u += ((1ull << (low_ - 1)) - 1) + ((u >> low_) & 1);  // round to nearest even at M+1 bits
    u &= ~((1ull << low_) - 1);
    double r;
    std::memcpy(&r, &u, 8);
    return std::fabs(r) > maxv_ ? std::copysign(HUGE_VAL, x) : r;
  }

 private:
  int low_;
  double maxv_, min_normal_, magic_;
};

void peer_pass(const Peer& p, Op op, const Operands& o) {
  uint64_t sink = 0;
  const size_t n = o.da.size();
  auto out = [&](double r) {
    uint64_t u;
    std::memcpy(&u, &r, 8);
    sink += u;
  };
  switch (op) {
    case Op::Add: for (size_t i = 0; i < n; ++i) out(p.round(o.da[i] + o.db[i])); break;
    case Op::Mul: for (size_t i = 0; i < n; ++i) out(p.round(o.da[i] * o.db[i])); break;
    case Op::Div: for (size_t i = 0; i < n; ++i) out(p.round(o.da[i] / o.db[i])); break;
    case Op::Sqrt: for (size_t i = 0; i < n; ++i) out(p.round(std::sqrt(o.ds[i]))); break;
    default: break;  // no fused multiply-add in the peer (double a*b+c rounds twice)
  }
  g_sink = g_sink + sink;
}

// Native float on the same values (loops the compiler vectorizes; results stored).
std::vector<float> g_fout;
void float_pass(Op op, const Operands& o) {
  const size_t n = o.fa.size();
  g_fout.resize(n);
  float* r = g_fout.data();
  const float *a = o.fa.data(), *b = o.fb.data(), *c = o.fc.data(), *s = o.fs.data();
  switch (op) {
    case Op::Add: for (size_t i = 0; i < n; ++i) r[i] = a[i] + b[i]; break;
    case Op::Mul: for (size_t i = 0; i < n; ++i) r[i] = a[i] * b[i]; break;
    case Op::Div: for (size_t i = 0; i < n; ++i) r[i] = a[i] / b[i]; break;
    case Op::Sqrt: for (size_t i = 0; i < n; ++i) r[i] = __builtin_sqrtf(s[i]); break;
    default: for (size_t i = 0; i < n; ++i) r[i] = std::fma(a[i], b[i], c[i]); break;
  }
  g_sink = g_sink + static_cast<uint64_t>(r[n / 2] != 0);
}

// The lean MPFR emulation; out (optional) receives the result values.
class MpfrLoop {
 public:
  explicit MpfrLoop(const Format& f) : f_(f), rnd_(mpfr_mode(f.round)) {
    old_emin_ = mpfr_get_emin();
    old_emax_ = mpfr_get_emax();
    mpfr_inits2(f.frac_bits + 1, a_, b_, c_, r_, static_cast<mpfr_ptr>(nullptr));
  }
  ~MpfrLoop() {
    for (auto* v : {&ra_, &rb_, &rc_, &rs_})
      for (auto& x : *v) mpfr_clear(x.m);
    mpfr_clears(a_, b_, c_, r_, static_cast<mpfr_ptr>(nullptr));
    mpfr_set_emin(old_emin_);
    mpfr_set_emax(old_emax_);
  }
  // MPFR significands are in [1/2, 1): the format's largest finite value is below 2^(emax+1)
  // and its smallest subnormal is 2^(emin-M) = 1/2 * 2^(emin-M+1).
  void set_range() {
    mpfr_set_emin(f_.emin() - f_.frac_bits + 1);
    mpfr_set_emax(f_.emax() + 1);
  }
  // Operands already held as mpfr_t (loaded once): per operation only the operation itself,
  // mpfr_subnormalize and the flags. The fastest way to run a computation in MPFR emulation.
  void load(const Operands& o) {
    auto fill = [&](std::vector<Num>& v, const std::vector<double>& d) {
      v.resize(d.size());
      for (size_t i = 0; i < d.size(); ++i) {
        mpfr_init2(v[i].m, f_.frac_bits + 1);
        mpfr_set_d(v[i].m, d[i], MPFR_RNDN);
      }
    };
    fill(ra_, o.da);
    fill(rb_, o.db);
    fill(rc_, o.dc);
    fill(rs_, o.ds);
  }
  void resident_pass(Op op) {
    set_range();
    uint64_t sink = 0;
    const size_t n = ra_.size();
    for (size_t i = 0; i < n; ++i) {
      mpfr_clear_flags();
      int t;
      switch (op) {
        case Op::Add: t = mpfr_add(r_, ra_[i].m, rb_[i].m, rnd_); break;
        case Op::Mul: t = mpfr_mul(r_, ra_[i].m, rb_[i].m, rnd_); break;
        case Op::Div: t = mpfr_div(r_, ra_[i].m, rb_[i].m, rnd_); break;
        case Op::Sqrt: t = mpfr_sqrt(r_, rs_[i].m, rnd_); break;
        default: t = mpfr_fma(r_, ra_[i].m, rb_[i].m, rc_[i].m, rnd_); break;
      }
      t = mpfr_subnormalize(r_, t, rnd_);
      sink += static_cast<uint64_t>(mpfr_flags_save()) + static_cast<uint64_t>(t);
    }
    g_sink = g_sink + sink;
  }

  void pass(Op op, const Operands& o, double* out) {
    set_range();
    uint64_t sink = 0;
    const size_t n = o.da.size();
    for (size_t i = 0; i < n; ++i) {
      mpfr_clear_flags();
      mpfr_set_d(a_, o.da[i], MPFR_RNDN);  // exact: the value has M+1 bits
      mpfr_set_d(b_, o.db[i], MPFR_RNDN);
      int t;
      switch (op) {
        case Op::Add: t = mpfr_add(r_, a_, b_, rnd_); break;
        case Op::Mul: t = mpfr_mul(r_, a_, b_, rnd_); break;
        case Op::Div: t = mpfr_div(r_, a_, b_, rnd_); break;
        case Op::Sqrt:
          mpfr_set_d(c_, o.ds[i], MPFR_RNDN);
          t = mpfr_sqrt(r_, c_, rnd_);
          break;
        default:
          mpfr_set_d(c_, o.dc[i], MPFR_RNDN);
          t = mpfr_fma(r_, a_, b_, c_, rnd_);
          break;
      }
      mpfr_subnormalize(r_, t, rnd_);
      double d = mpfr_get_d(r_, MPFR_RNDN);  // exact
      unsigned flags = mpfr_flags_save();
      if (out) out[i] = d;
      uint64_t bits;
      std::memcpy(&bits, &d, sizeof bits);
      sink += bits ^ flags;
    }
    g_sink = g_sink + sink;
  }

 private:
  Format f_;
  mpfr_rnd_t rnd_;
  mpfr_exp_t old_emin_, old_emax_;
  mpfr_t a_, b_, c_, r_;
  struct Num {
    mpfr_t m;
  };
  std::vector<Num> ra_, rb_, rc_, rs_;
};

void oracle_pass(const Format& f, Op op, const Operands& o, size_t n) {
  uint64_t sink = 0;
  for (size_t i = 0; i < n; ++i) {
    auto r = ru::num::mpfr_apply(f, op, op == Op::Sqrt ? o.s[i] : o.a[i], o.b[i], o.c[i]);
    sink += r.bits ^ r.flags;
  }
  g_sink = g_sink + sink;
}

// Times passes of A and B alternately (A B A B ...) so that a changing machine load hits both
// alike; each timed run repeats its pass until >= min_time s. Returns the median ns per
// operation of each.
// Time is the CPU time of this thread, so other processes on a busy machine do not count.
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Times the passes in turn (A B C A B C ...) so that a changing machine load hits all alike;
// each timed run repeats its pass until >= min_time s of CPU time. Returns the median ns per
// operation of each pass.
std::vector<double> median_ns(const std::vector<std::function<void()>>& passes, const std::vector<size_t>& ops,
                              int reps, double min_time) {
  std::vector<long> k;
  for (const auto& p : passes) {
    double t0 = thread_cpu_seconds();
    p();  // warm-up and calibration
    double one = thread_cpu_seconds() - t0;
    k.push_back(std::max(1L, static_cast<long>(std::ceil(min_time / std::max(one, 1e-9)))));
  }
  std::vector<std::vector<double>> ns(passes.size());
  for (int r = 0; r < reps; ++r)
    for (size_t j = 0; j < passes.size(); ++j) {
      double t = thread_cpu_seconds();
      for (long i = 0; i < k[j]; ++i) passes[j]();
      double s = thread_cpu_seconds() - t;
      ns[j].push_back(s * 1e9 / (static_cast<double>(k[j]) * static_cast<double>(ops[j])));
    }
  std::vector<double> med;
  for (auto& v : ns) {
    std::sort(v.begin(), v.end());
    med.push_back(v[v.size() / 2]);
  }
  return med;
}

int run_bench_fp(int argc, char** argv) {
  CLI::App app{
      "Benchmark: operations per second of the bit-exact model (ru::num) vs MPFR emulating the same "
      "format (precision M+1, emin/emax, mpfr_subnormalize), single thread, random normal operands. "
      "The last line is 'ratio add=X mul=Y div=Z fma=W' (model speed / MPFR speed; with several "
      "formats, the smallest ratio over them).",
      "rayunits bench fp"};
  std::vector<std::string> formats;
  std::string round_text = "rne";
  size_t n = 1 << 14;
  int reps = 7;
  double min_time = 0.05;
  bool oracle = true;
  uint64_t seed = 1;
  app.add_option("--format", formats, "format(s) to measure (default: e7m16 and e8m23)")->delimiter(',');
  app.add_option("--round", round_text, "rounding mode (default rne)");
  app.add_option("--n", n, "operand sets per pass (default 16384)");
  app.add_option("--reps", reps, "timed runs per measurement; the median is reported (default 7)");
  app.add_option("--min-time", min_time, "seconds per timed run, at least (default 0.05)");
  app.add_option("--seed", seed, "operand seed (default 1)");
  app.add_flag("--oracle,!--no-oracle", oracle, "also time the test oracle ru::num::mpfr_apply (default on)");
  std::string baseline = "convert";
  app.add_option("--baseline", baseline,
                 "MPFR variant of the ratio line: convert (default; operands in and result out as values, like the "
                 "model) or resident (operands already mpfr_t)");
  std::string isa_text = "auto";
  app.add_option("--batch-isa", isa_text,
                 "vector path of the batch column: auto (default: the best the CPU has), avx512, avx2 or scalar");
  if (!parse_args(app, argc, argv)) return 0;
  if (formats.empty()) formats = {"e7m16", "e8m23"};
  {
    using ru::num::BatchIsa;
    const BatchIsa isa = isa_text == "auto"     ? BatchIsa::Auto
                         : isa_text == "avx512" ? BatchIsa::Avx512
                         : isa_text == "avx2"   ? BatchIsa::Avx2
                         : isa_text == "scalar" ? BatchIsa::Scalar
                                                : throw UsageError("unknown --batch-isa '" + isa_text +
                                                                   "'; accepted: auto, avx512, avx2, scalar");
    if (!ru::num::set_batch_isa(isa)) throw UsageError("--batch-isa " + isa_text + ": this CPU does not have it");
  }
  if (baseline != "convert" && baseline != "resident")
    throw UsageError("unknown --baseline '" + baseline + "'; accepted: convert, resident");
  const bool resident = baseline == "resident";
  if (n < 1 || n > (1u << 24)) throw UsageError("--n must be 1..16777216");
  if (reps < 1 || reps > 1000) throw UsageError("--reps must be 1..1000");
  if (!(min_time > 0 && min_time <= 10)) throw UsageError("--min-time must be in (0, 10]");
  const ru::num::Round rm = ru::num::parse_round(round_text);
  std::vector<Format> fmts;
  for (const auto& s : formats) {
    Format f = Format::parse(s);
    f.round = rm;
    fmts.push_back(f);
  }

  // The ratio line keeps add/mul/div/fma (in that order); sqrt is in the table and the peer line.
  const Op ops[5] = {Op::Add, Op::Mul, Op::Div, Op::Fma, Op::Sqrt};
  double worst[5] = {1e300, 1e300, 1e300, 1e300, 1e300};
  double worst_peer[5] = {1e300, 1e300, 1e300, 1e300, 1e300}, worst_bpeer[5] = {1e300, 1e300, 1e300, 1e300, 1e300};
  std::printf(
      "bench fp: one thread, %zu random normal operand sets (exponents -8..8, fewer for E < 6; sqrt of |a|),\n"
      "rounding %s; each figure: million operations per CPU-second, median of %d runs (>= %.2f s each, the\n"
      "variants alternating, same operands). model = ru::num bit patterns in, bits + flags out; batch = the\n"
      "same through the batch API (num/batch.hpp: arrays in, arrays out, one format dispatch; vector path:\n"
      "%s). peer = a\n"
      "minimal double-backed emulator (FlexFloat/CPFloat style: doubles in, compute in double, round once\n"
      "to nearest at M+1 bits / the subnormal quantum, overflow to INF; no other modes, no flags; no fma).\n"
      "float = native float loops on the same values (vectorized by the compiler). MPFR = operands held as\n"
      "mpfr_t at precision M+1 with the format's emin/emax: operation + mpfr_subnormalize + flags. MPFR+cv =\n"
      "the same plus mpfr_set_d of the operands and mpfr_get_d of the result (values in, value + flags\n"
      "out, like the model). m/peer = model / peer, fl/m = float / model (model's slowdown), ratio =\n"
      "model / MPFR, ratio+cv = model / MPFR+cv. oracle = ru::num::mpfr_apply, the test oracle (bits\n"
      "in/out). The ratio lines use %s.\n\n",
      n, ru::num::round_name(rm), reps, min_time, isa_name(ru::num::batch_isa()), resident ? "MPFR (--baseline resident)" : "MPFR+cv (--baseline convert)");
  std::printf("%-8s %-5s %9s %9s %9s %9s %9s %9s %8s %8s %9s %9s %9s\n", "format", "op", "model", "batch", "peer", "float",
              "MPFR", "MPFR+cv", "m/peer", "fl/m", "ratio", "ratio+cv", "oracle");
  for (const Format& f : fmts) {
    Operands o = make_operands(f, n, seed);
    MpfrLoop mp(f);
    mp.load(o);
    const Peer peer(f);
    double ratio[5], rpeer[5], rbpeer[5] = {0, 0, 0, 0, 0};
    for (int k = 0; k < 5; ++k) {
      const Op op = ops[k];
      const bool has_peer = op != Op::Fma;
      // Same values on both sides, or the comparison means nothing.
      std::vector<double> ref(n);
      mp.pass(op, o, ref.data());
      size_t bad = 0;
      for (size_t i = 0; i < n; ++i) {
        ru::num::Result r = ru::num::apply(f, op, op == Op::Sqrt ? o.s[i] : o.a[i], o.b[i], o.c[i]);
        if (ru::num::to_double(f, r.bits) != ref[i]) ++bad;
      }
      if (bad)
        std::fprintf(stderr, "bench fp: warning: %s %s: model and MPFR differ on %zu of %zu operand sets\n",
                     f.name().c_str(), ru::num::op_name(op), bad, n);
      std::vector<uint64_t> by;
      std::vector<uint8_t> bfl;
      std::vector<std::function<void()>> passes = {[&] { model_pass(f, op, o); }, [&] { mp.resident_pass(op); },
                                                   [&] { mp.pass(op, o, nullptr); }, [&] { float_pass(op, o); },
                                                   [&] { batch_pass(f, op, o, by, bfl); }};
      std::vector<size_t> counts = {n, n, n, n, n};
      if (has_peer) {
        passes.push_back([&] { peer_pass(peer, op, o); });
        counts.push_back(n);
      }
      const size_t m = std::min<size_t>(n, 4096);
      if (oracle) {
        passes.push_back([&] { oracle_pass(f, op, o, m); });
        counts.push_back(m);
      }
      std::vector<double> t = median_ns(passes, counts, reps, min_time);
      char oracle_text[32] = "-", peer_text[32] = "-", mpeer_text[32] = "-";
      if (oracle) std::snprintf(oracle_text, sizeof oracle_text, "%.1f", 1e3 / t.back());
      rpeer[k] = 0;
      if (has_peer) {
        rpeer[k] = t[5] / t[0];
        rbpeer[k] = t[5] / t[4];
        worst_peer[k] = std::min(worst_peer[k], rpeer[k]);
        worst_bpeer[k] = std::min(worst_bpeer[k], rbpeer[k]);
        std::snprintf(peer_text, sizeof peer_text, "%.1f", 1e3 / t[5]);
        std::snprintf(mpeer_text, sizeof mpeer_text, "%.2fx", rpeer[k]);
      }
      ratio[k] = (resident ? t[1] : t[2]) / t[0];
      worst[k] = std::min(worst[k], ratio[k]);
      std::printf("%-8s %-5s %9.1f %9.1f %9s %9.1f %9.1f %9.1f %8s %7.1fx %8.1fx %8.1fx %9s\n", f.name().c_str(),
                  ru::num::op_name(op), 1e3 / t[0], 1e3 / t[4], peer_text, 1e3 / t[3], 1e3 / t[1], 1e3 / t[2],
                  mpeer_text, t[0] / t[3], t[1] / t[0], t[2] / t[0], oracle_text);
      std::fflush(stdout);
    }
    std::printf("ratio[%s] add=%.1f mul=%.1f div=%.1f fma=%.1f sqrt=%.1f\n", f.name().c_str(), ratio[0], ratio[1],
                ratio[2], ratio[3], ratio[4]);
    std::printf("peer[%s] model/peer add=%.2f mul=%.2f div=%.2f sqrt=%.2f batch/peer add=%.2f mul=%.2f div=%.2f sqrt=%.2f\n",
                f.name().c_str(), rpeer[0], rpeer[1], rpeer[2], rpeer[4], rbpeer[0], rbpeer[1], rbpeer[2], rbpeer[4]);
  }
  mpfr_free_cache();
  std::printf("peer model/peer add=%.2f mul=%.2f div=%.2f sqrt=%.2f batch/peer add=%.2f mul=%.2f div=%.2f sqrt=%.2f\n",
              worst_peer[0], worst_peer[1], worst_peer[2], worst_peer[4], worst_bpeer[0], worst_bpeer[1], worst_bpeer[2],
              worst_bpeer[4]);
  std::printf("ratio add=%.1f mul=%.1f div=%.1f fma=%.1f\n", worst[0], worst[1], worst[2], worst[3]);
  return 0;
}

}  // namespace

RU_COMMAND("bench fp", "benchmark the number-format model against MPFR (ops/s, ratio)", run_bench_fp);

}  // namespace ru::cli
