// Golden-model adapters and random vector generators of the registered units (unit_models.hpp).
#include "rayunits/synth/unit_models.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "rayunits/dp/formulas.hpp"
#include "rayunits/noise/fixed.hpp"
#include "rayunits/num/fp.hpp"
#include "rayunits/num/patterns.hpp"
#include "rayunits/units/int_units.hpp"
#include "rayunits/units/ray_box.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/ray_tri_cheap.hpp"
#include "rayunits/units/ray_tri_exact.hpp"
#include "rayunits/units/ray_tri_exact_gen.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::synth::models {

using num::Format;
using num::Soft;
using units::Vec3;

namespace {

int operands(FpShape s) {
  switch (s) {
    case FpShape::Unary: return 1;
    case FpShape::Binary: return 2;
    case FpShape::Ternary: return 3;
    case FpShape::Dot3:
    case FpShape::Dot3Fused: return 6;
  }
  return 0;
}

long long param(const UnitConfig& c, const char* name) {
  auto it = c.params.find(name);
  return it == c.params.end() ? 0 : it->second;
}

// Special values sprinkled into generated records (NaN, sNaN, +-INF, +-0, extremes).
struct Sprinkler {
  std::vector<uint64_t> sv;
  explicit Sprinkler(const Format& f) : sv(num::special_values(f)) {}
  void operator()(util::Xoshiro256ss& rng, uint64_t* in, int n, int permille) const {
    for (int i = 0; i < n; ++i)
      if (util::bounded_lemire(rng, 1000) < static_cast<uint64_t>(permille))
        in[i] = sv[util::bounded_lemire(rng, sv.size())];
  }
};

Format rne(Format f) {
  f.round = num::Round::RNE;
  return f;
}

}  // namespace

// ---- floating-point units ----------------------------------------------------------------------

GoldenEval fp_golden(const UnitConfig& c, FpShape shape, std::vector<FpOp> ops) {
  const Format f = c.fmt;
  const int n = operands(shape);
  const bool has_op = ops.size() > 1;
  return [f, n, shape, has_op, ops](const uint64_t* in, uint64_t* out) {
    // An op_i code the unit does not define (fp_cmp 5..7) has no specified result; the
    // generators never issue one, and the model reads it as the last op.
    const FpOp& o = ops[has_op ? std::min<uint64_t>(in[n], ops.size() - 1) : 0];
    num::Result r;
    if (shape == FpShape::Dot3) {
      r = num::dot3(f, &in[0], &in[3]);
    } else if (shape == FpShape::Dot3Fused) {
      r = num::dot3_fused(f, &in[0], &in[3]);
    } else if (shape == FpShape::Ternary) {
      const uint64_t a = (o.neg & 2) ? num::neg(f, in[0]) : in[0];
      const uint64_t cc = (o.neg & 1) ? num::neg(f, in[2]) : in[2];
      r = num::apply(f, o.op, a, in[1], cc);
    } else {
      r = num::apply(f, o.op, in[0], shape == FpShape::Unary ? 0 : in[1]);
    }
    out[0] = r.bits;
    out[1] = r.flags;
  };
}

InputGen fp_inputs(const UnitConfig& c, uint64_t seed, FpShape shape, int nops) {
  struct State {
    Format f;
    num::OperandGen gen;
    util::Xoshiro256ss rng;
    State(const Format& f, uint64_t seed) : f(f), gen(f, seed), rng(seed ^ 0xabcdef) {}
  };
  auto st = std::make_shared<State>(c.fmt, seed);
  const int n = operands(shape);
  return [st, shape, nops, n](uint64_t* in) {
    // The op is drawn first (also for one op: the stream of the testbench's former generator).
    const uint64_t op = (shape == FpShape::Dot3 || shape == FpShape::Dot3Fused) ? 0 : util::bounded_lemire(st->rng, static_cast<uint64_t>(nops));
    switch (shape) {
      case FpShape::Dot3:
        st->gen.triple(in[0], in[1], in[2]);
        st->gen.triple(in[3], in[4], in[5]);
        if (util::bounded_lemire(st->rng, 4) == 0) {  // a1*b1 = -(a0*b0): the sum cancels to a2*b2
          in[1] = in[0];
          in[4] = num::neg(st->f, in[3]);
        }
        break;
      case FpShape::Dot3Fused: {  // cancellation and alignment cases (OperandGen::dot3)
        uint64_t a[3], b[3];
        st->gen.dot3(a, b);
        for (int i = 0; i < 3; ++i) in[i] = a[i], in[3 + i] = b[i];
        break;
      }
      case FpShape::Ternary: st->gen.triple(in[0], in[1], in[2]); break;  // near ties, c ~ -a*b
      case FpShape::Unary:  // sqrt: exact squares and squares of rounding midpoints, or anything
        in[0] = util::bounded_lemire(st->rng, 2) ? st->gen.sqrt_case() : st->gen.next();
        break;
      case FpShape::Binary: st->gen.pair(in[0], in[1]); break;
    }
    if (nops > 1) in[n] = op;
  };
}

// ---- fp_cvt ------------------------------------------------------------------------------------

uint64_t low_bits(uint64_t x, int bits) { return bits >= 64 ? x : x & ((1ull << bits) - 1); }

namespace {
int64_t sign_extend(uint64_t x, int bits) {
  const uint64_t v = low_bits(x, bits);
  if (bits >= 64 || !((v >> (bits - 1)) & 1)) return static_cast<int64_t>(v);
  return static_cast<int64_t>(v | ~((1ull << bits) - 1));
}
}  // namespace

CvtFormats cvt_formats(const UnitConfig& c) {
  const UnitSpec& u = find_unit("fp_cvt");
  CvtFormats v;
  v.f = c.fmt;
  v.g.exp_bits = static_cast<int>(param_value(u, c, "InExpW"));
  v.g.frac_bits = static_cast<int>(param_value(u, c, "InFracW"));
  v.g.subnormals = param_value(u, c, "InSubnormals") != 0;
  v.g.round = c.fmt.round;
  v.int_w = static_cast<int>(param_value(u, c, "IntW"));
  return v;
}

GoldenEval fp_cvt_golden(const UnitConfig& c) {
  const CvtFormats v = cvt_formats(c);
  return [v](const uint64_t* in, uint64_t* out) {
    const uint64_t a = in[0], op = in[1] & 3;
    if (op <= 1) {
      const num::Result r = op == 0 ? num::convert(v.f, v.g, low_bits(a, v.g.width()))
                                    : num::from_int(v.f, sign_extend(a, v.int_w));
      out[0] = r.bits;
      out[1] = r.flags;
    } else {
      const num::IntResult r =
          num::to_int(v.f, low_bits(a, v.f.width()), op == 3 ? num::Round::RTZ : v.f.round, v.int_w);
      out[0] = low_bits(static_cast<uint64_t>(r.value), v.int_w);
      out[1] = r.flags;
    }
  };
}

InputGen fp_cvt_inputs(const UnitConfig& c, uint64_t seed) {
  struct State {
    CvtFormats v;
    num::OperandGen gf, gg;
    util::Xoshiro256ss rng;
    State(const CvtFormats& v, uint64_t seed) : v(v), gf(v.f, seed), gg(v.g, seed ^ 0x9e37), rng(seed ^ 0xc0417) {}
    uint64_t below(uint64_t n) { return util::bounded_lemire(rng, n); }
    // i2f: an integer of int_w bits (two's complement, low int_w bits)
    uint64_t integer() {
      const int w = v.int_w, p = v.f.frac_bits + 1;
      const uint64_t hi = low_bits(~0ull >> (65 - w), 64);  // 2^(w-1) - 1
      uint64_t mag;
      switch (below(6)) {
        case 0: {  // the range ends and their neighbours
          const uint64_t e[] = {0, 1, 2, hi, hi - 1, hi + 1 /* 2^(w-1): the most negative */};
          mag = e[below(6)];
          break;
        }
        case 1: mag = (1ull << below(static_cast<uint64_t>(w - 1))) + (below(3) - 1); break;  // 2^k - 1, 2^k, 2^k + 1
        case 2: {  // F's rounding ties and their neighbours: an odd (p+1)-bit number, shifted
          if (w - 1 <= p + 1) {
            mag = rng() & hi;
            break;
          }
          const uint64_t odd = (1ull << p) | (rng() & ((1ull << p) - 1)) | 1;
          const int sh = static_cast<int>(below(static_cast<uint64_t>(w - 1 - (p + 1)) + 1));
          mag = (odd << sh) + (below(3) - 1);
          break;
        }
        default: {  // every bit length
          const int k = static_cast<int>(below(static_cast<uint64_t>(w)));
          mag = k == 0 ? 0 : (rng() & (~0ull >> (64 - k))) | (1ull << (k - 1));
          break;
        }
      }
      mag &= low_bits(~0ull, w);
      return low_bits(below(2) ? 0 - mag : mag, w);
    }
    // f2i: a value of F near an integer or half-integer of any size up to 2^(int_w+2)
    uint64_t near_integer() {
      if (below(2)) return gf.next();
      const int w = v.int_w;
      double x;
      if (below(4) == 0) {  // the saturation bounds
        const double b = std::ldexp(1.0, w - 1);
        const double d[] = {0.0, -0.5, -1.0, 0.5, 1.0, -1.5};
        x = b + d[below(6)];
      } else {
        const int s = static_cast<int>(below(static_cast<uint64_t>(w + 6))) - 3;  // 2^-3 .. 2^(w+2)
        const double m = std::ldexp(static_cast<double>((rng() >> 11) | (1ull << 52)), -52);  // [1, 2)
        x = std::ldexp(m, s);
        switch (below(4)) {
          case 0: x = std::floor(x); break;
          case 1: x = std::floor(x) + 0.5; break;
          default: break;
        }
      }
      if (below(2)) x = -x;
      return num::from_double(rne(v.f), x).bits;
    }
  };
  auto st = std::make_shared<State>(cvt_formats(c), seed);
  const int aw = std::max({st->v.f.width(), st->v.g.width(), st->v.int_w});
  return [st, aw](uint64_t* in) {
    const uint64_t op = st->below(4);
    const uint64_t junk = low_bits(st->rng(), aw);  // the bits the op ignores
    int w;
    uint64_t a;
    switch (op) {
      case 0: a = st->gg.next(), w = st->v.g.width(); break;
      case 1: a = st->integer(), w = st->v.int_w; break;
      default: a = st->near_integer(), w = st->v.f.width(); break;
    }
    in[0] = (junk & ~low_bits(~0ull, w)) | a;
    in[1] = op;
  };
}

// ---- ray units ---------------------------------------------------------------------------------

GoldenEval ray_box_golden(const UnitConfig& c) {
  const Format f = c.fmt;
  const long long mode = param(c, "OptConservative");
  return [f, mode](const uint64_t* in, uint64_t* out) {
    num::SoftScope scope(f);
    auto S = [&](int i) { return Soft::from_bits(in[i]); };
    auto V = [&](int i) { return Vec3<Soft>{S(i), S(i + 1), S(i + 2)}; };
    using units::BoxMode;
    const auto r = units::ray_box(V(0), V(3), V(8), V(11), S(6), S(7),
                                  mode == 2 ? BoxMode::DConservative : mode == 1 ? BoxMode::Conservative : BoxMode::Plain);
    out[0] = r.hit;
    out[1] = r.t_enter.bits;
    out[2] = r.t_exit.bits;
  };
}

GoldenEval ray_tri_golden(const UnitConfig& c, bool robust) {
  const Format f = c.fmt;
  units::TriOptions opt;
  opt.tie_break = robust && param(c, "OptTieBreak") != 0;
  opt.eps_test = param(c, "OptEpsTest") != 0;
  opt.eps = num::to_double(f, static_cast<uint64_t>(param(c, "EpsBits")));
  const bool recip = robust && param(c, "OptRecip") != 0, vol = param(c, "OptVolOut") != 0;
  return [f, opt, robust, recip, vol](const uint64_t* in, uint64_t* out) {
    num::SoftScope scope(f);
    auto S = [&](int i) { return Soft::from_bits(in[i]); };
    auto V = [&](int i) { return Vec3<Soft>{S(i), S(i + 1), S(i + 2)}; };
    const auto r = !robust ? units::ray_tri_mt(V(0), V(3), V(6), V(9), V(12), S(15), S(16), opt)
                   : recip ? units::ray_tri_robust_recip(V(0), V(3), V(6), V(9), V(12), S(15), S(16), opt)
                           : units::ray_tri_robust(V(0), V(3), V(6), V(9), V(12), S(15), S(16), opt);
    out[0] = r.hit;
    out[1] = static_cast<uint64_t>(r.why);
    out[2] = r.t.bits;
    out[3] = r.beta.bits;
    out[4] = r.gamma.bits;
    const uint64_t v[5] = {r.V.bits, r.Va.bits, r.V0.bits, r.V1.bits, r.V2.bits};
    for (int i = 0; i < 5; ++i) out[5 + i] = vol ? v[i] : 0;  // vol_o is constant 0 without OptVolOut
  };
}

GoldenEval ray_tri_exact_golden(const UnitConfig& c) {
  const Format f = c.fmt;
  return [f](const uint64_t* in, uint64_t* out) {
    num::SoftScope scope(f);
    auto S = [&](int i) { return Soft::from_bits(in[i]); };
    auto V = [&](int i) { return Vec3<Soft>{S(i), S(i + 1), S(i + 2)}; };
    units::ExactTriOptions o;
    o.filter = units::ExactFilter::PermanentFormat;
    const auto r = units::ray_tri_exact(V(0), V(3), V(6), V(9), V(12), S(15), S(16), o);
    out[0] = r.hit;
    out[1] = static_cast<uint64_t>(r.why);
    out[2] = r.t.bits;
    out[3] = r.beta.bits;
    out[4] = r.gamma.bits;
    out[5] = r.path.slow() ? 1 : 0;
  };
}

GoldenEval dp_golden(const UnitConfig& c, std::shared_ptr<const dp::Graph> g) {
  const Format f = c.fmt;
  return [g, f](const uint64_t* in, uint64_t* out) {
    num::SoftScope scope(f);
    std::vector<Soft> x(g->inputs().size());
    for (size_t i = 0; i < x.size(); ++i) x[i] = Soft::from_bits(in[i]);
    const auto v = dp::evaluate<Soft>(*g, x);
    size_t j = 0;
    for (const auto& [name, n] : g->outputs())
      out[j++] = dp::op_is_bool(g->nodes()[n].op) ? (v[n].b ? 1 : 0) : v[n].v.bits;
  };
}

namespace {

// Batches of the synthetic workloads (units/synthetic.hpp) at a random scale 2^[-12, 12] per
// batch, rounded to the format (RNE), 1 % of the fields replaced by special values.
template <class Rec>
struct SynthStream {
  Format f;
  Sprinkler sp;
  util::Xoshiro256ss rng;
  std::vector<Rec> batch;
  size_t next = 0;
  uint64_t batches = 0;
  SynthStream(const Format& fmt, uint64_t seed) : f(rne(fmt)), sp(fmt), rng(seed) {}
  double scale() {
    const int e = static_cast<int>(util::bounded_lemire(rng, 25)) - 12;
    const int lim = std::max(1, f.emax() / 3 - 1);  // keep cubic volumes mostly finite
    return std::ldexp(1.0, std::clamp(e, -lim, lim));
  }
  // The next record: a new batch of make(seed, scale) when the current one is used up.
  template <class Make>
  const Rec& take(Make make) {
    if (next == batch.size()) {
      const uint64_t s = util::mix_seed(rng.next(), std::to_string(batches++));
      batch = make(s, scale());
      next = 0;
    }
    return batch[next++];
  }
};

}  // namespace

void box_fields(const Format& fmt, const units::BoxRecord& r, uint64_t* in) {
  const Format f = rne(fmt);
  auto q = [&](double x) { return num::from_double(f, x).bits; };
  for (int k = 0; k < 3; ++k) {
    in[k] = q(r.o[k]);
    in[3 + k] = q(r.inv[k]);
    in[8 + k] = q(r.lo[k]);
    in[11 + k] = q(r.hi[k]);
  }
  in[6] = q(r.t_min);
  in[7] = q(r.t_max);
}

void tri_fields(const Format& fmt, const units::TriRecord& r, uint64_t* in) {
  const Format f = rne(fmt);
  int i = 0;
  for (const units::Vec3d* v : {&r.a, &r.d, &r.p0, &r.p1, &r.p2})
    for (int k = 0; k < 3; ++k) in[i++] = num::from_double(f, (*v)[k]).bits;
  in[15] = num::from_double(f, r.t_min).bits;
  in[16] = num::from_double(f, r.t_max).bits;
}

InputGen ray_box_inputs(const UnitConfig& c, uint64_t seed) {
  auto st = std::make_shared<SynthStream<units::BoxRecord>>(c.fmt, seed);
  return [st](uint64_t* in) {
    box_fields(st->f, st->take([](uint64_t s, double scale) {
      units::SynthBoxOptions o;
      o.seed = s;
      o.boxes = 16;
      o.scale = scale;
      return units::synth_box(o);
    }), in);
    st->sp(st->rng, in, 14, 10);
  };
}

InputGen ray_tri_inputs(const UnitConfig& c, uint64_t seed) {
  auto st = std::make_shared<SynthStream<units::TriRecord>>(c.fmt, seed);
  return [st](uint64_t* in) {
    tri_fields(st->f, st->take([](uint64_t s, double scale) {
      units::SynthTriOptions o;
      o.seed = s;
      o.triangles = 16;
      o.scale = scale;
      return units::synth_tri(o);
    }), in);
    st->sp(st->rng, in, 17, 10);
  };
}

InputGen ray_tri_exact_inputs(const UnitConfig& c, uint64_t seed) {
  struct State {
    InputGen scene;
    units::ExactTriGen hard;
    int n = 0;
  };
  auto st = std::make_shared<State>(State{ray_tri_inputs(c, seed), units::ExactTriGen(c.fmt, seed ^ 0x5eed0e7ac7ull), 0});
  return [st](uint64_t* in) {
    const int i = st->n++;
    if (i % 2 == 0) return st->scene(in);
    const units::ExactTriRecord r = st->hard.next(i / 2);
    for (int k = 0; k < 17; ++k) in[k] = r.bits[k];
  };
}

// ---- noise -------------------------------------------------------------------------------------

namespace {
int param_or(const UnitConfig& c, const char* n, int def) {
  auto it = c.params.find(n);
  return it == c.params.end() ? def : static_cast<int>(it->second);
}
noise::FixedConfig noise_config(const UnitConfig& c) {
  noise::FixedConfig fc;
  auto p = [&](const char* n, int def) { return param_or(c, n, def); };
  fc.frac_bits = p("FracBits", fc.frac_bits);
  fc.int_bits = p("IntBits", fc.int_bits);
  fc.out_w = p("OutW", fc.out_w);
  fc.validate();
  return fc;
}
}  // namespace

namespace {
GoldenEval noise_model(noise::FixedConfig fc) {
  auto m = std::make_shared<noise::FixedNoise>(fc);
  const uint64_t mask = (1ull << m->config().out_w) - 1;
  return [m, mask](const uint64_t* in, uint64_t* out) {
    const int64_t v = m->eval(static_cast<int64_t>(in[0]), static_cast<int64_t>(in[1]), static_cast<int64_t>(in[2]));
    out[0] = static_cast<uint64_t>(v) & mask;
  };
}
}  // namespace

GoldenEval noise_golden(const UnitConfig& c) { return noise_model(noise_config(c)); }

GoldenEval noise_trunc_golden(const UnitConfig& c) {
  noise::FixedConfig fc = noise_config(c);
  fc.datapath = noise::NoiseDatapath::kTrunc;
  fc.validate();
  return noise_model(fc);
}

InputGen noise_inputs(const UnitConfig& c, uint64_t seed) {
  const noise::FixedConfig fc = noise_config(c);
  auto rng = std::make_shared<util::Xoshiro256ss>(seed);
  const uint64_t mask = (1ull << fc.in_w()) - 1;
  return [rng, mask](uint64_t* in) {
    for (int i = 0; i < 3; ++i) in[i] = rng->next() & mask;  // whole range: negative, both table ends, wrap
  };
}

// ---- texture -----------------------------------------------------------------------------------

noise::TextureConfig texture_config(const UnitConfig& c) {
  noise::TextureConfig tc;
  tc.noise = noise_config(c);
  tc.noise.datapath = param_or(c, "Trunc", 1) ? noise::NoiseDatapath::kTrunc : noise::NoiseDatapath::kFull;
  tc.octaves = param_or(c, "Octaves", tc.octaves);
  tc.lac_shift = param_or(c, "LacShift", tc.lac_shift);
  tc.gain_shift = param_or(c, "GainShift", tc.gain_shift);
  tc.out_frac = param_or(c, "OutF", tc.out_frac);
  tc.validate();
  return tc;
}

// Fields: x_i, y_i, z_i, mode_i (3 bits: 5..7 act as fbm, as in the RTL), oct_i -> value_o.
GoldenEval texture_golden(const UnitConfig& c) {
  auto m = std::make_shared<noise::FixedTexture>(texture_config(c));
  const uint64_t mask = (1ull << m->config().out_w()) - 1;
  return [m, mask](const uint64_t* in, uint64_t* out) {
    const int mode = in[3] < static_cast<uint64_t>(noise::kTextureModes) ? static_cast<int>(in[3]) : 0;
    const int64_t v = m->eval(static_cast<noise::TextureMode>(mode), static_cast<int>(in[4]), static_cast<int64_t>(in[0]),
                              static_cast<int64_t>(in[1]), static_cast<int64_t>(in[2]));
    out[0] = static_cast<uint64_t>(v) & mask;
  };
}

// Whole-range words (negative, wrap), every mode (the unused codes too) and octave count (0 and
// beyond Octaves are clamped), weighted to the five modes and to full octave counts.
InputGen texture_inputs(const UnitConfig& c, uint64_t seed) {
  const noise::TextureConfig tc = texture_config(c);
  auto rng = std::make_shared<util::Xoshiro256ss>(seed);
  const uint64_t mask = (1ull << tc.in_w()) - 1;
  const int oct = tc.octaves;
  return [rng, mask, oct](uint64_t* in) {
    for (int i = 0; i < 3; ++i) in[i] = rng->next() & mask;
    const uint64_t r = rng->next();
    in[3] = (r & 15) < 14 ? (r >> 4) % 5 : (r >> 4) & 7;
    in[4] = ((r >> 8) & 3) == 0 ? (r >> 10) & 15 : static_cast<uint64_t>(oct);
  };
}

// ---- integer units -----------------------------------------------------------------------------

namespace {
// A w-bit operand: an edge word (0, +-1, the range ends, +-2^k, small shift amounts) or random.
uint64_t int_operand(util::Xoshiro256ss& rng, int w) {
  const uint64_t m = units::int_mask(w);
  switch (util::bounded_lemire(rng, 8)) {
    case 0: {
      const uint64_t edges[] = {0, 1, m, m >> 1, (m >> 1) + 1, 2};
      return edges[util::bounded_lemire(rng, 6)] & m;
    }
    case 1: return (1ull << util::bounded_lemire(rng, static_cast<uint64_t>(w))) & m;
    case 2: return (0 - (1ull << util::bounded_lemire(rng, static_cast<uint64_t>(w)))) & m;
    case 3: return util::bounded_lemire(rng, static_cast<uint64_t>(2 * w + 2));  // shift amounts around w
    default: return rng.next() & m;
  }
}
}  // namespace

GoldenEval int_alu_golden(const UnitConfig& c) {
  const int w = param_or(c, "IntW", 32);
  return [w](const uint64_t* in, uint64_t* out) { out[0] = units::int_alu(w, static_cast<unsigned>(in[2]), in[0], in[1]); };
}

InputGen int_alu_inputs(const UnitConfig& c, uint64_t seed) {
  const int w = param_or(c, "IntW", 32);
  auto rng = std::make_shared<util::Xoshiro256ss>(seed);
  return [rng, w](uint64_t* in) {
    in[0] = int_operand(*rng, w);
    in[1] = util::bounded_lemire(*rng, 8) == 0 ? in[0] : int_operand(*rng, w);
    in[2] = util::bounded_lemire(*rng, 16);  // every op code, the mov aliases 12..15 included
  };
}

GoldenEval branch_golden(const UnitConfig& c) {
  const int w = param_or(c, "IntW", 32), pw = param_or(c, "PcW", 32);
  return [w, pw](const uint64_t* in, uint64_t* out) {
    const units::BranchResult r = units::branch(w, pw, static_cast<unsigned>(in[4]), in[0], in[1], in[2], in[3]);
    out[0] = r.taken;
    out[1] = r.next;
  };
}

InputGen branch_inputs(const UnitConfig& c, uint64_t seed) {
  const int w = param_or(c, "IntW", 32), pw = param_or(c, "PcW", 32);
  auto rng = std::make_shared<util::Xoshiro256ss>(seed);
  return [rng, w, pw](uint64_t* in) {
    in[0] = int_operand(*rng, w);
    in[1] = util::bounded_lemire(*rng, 4) == 0 ? in[0] : int_operand(*rng, w);
    in[2] = int_operand(*rng, pw);
    in[3] = int_operand(*rng, pw);
    in[4] = util::bounded_lemire(*rng, 8);
  };
}

}  // namespace ru::synth::models
