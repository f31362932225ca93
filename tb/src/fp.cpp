// rayunits tb: floating-point adapter and vector sources (see fp.hpp).
#include "rayunits/tb/fp.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "rayunits/num/patterns.hpp"

namespace ru::tb {

using ru::num::Format;
using ru::num::Op;

const FpUnitSpec* fp_unit_spec(const std::string& unit) {
  static const FpUnitSpec specs[] = {
      {"fp_add", {{"add", Op::Add}, {"sub", Op::Sub}}, 1, false},
      {"fp_mul", {{"mul", Op::Mul}}, 0, false},
      {"fp_div", {{"div", Op::Div}}, 0, false},
      {"fp_sqrt", {{"sqrt", Op::Sqrt}}, 0, false, true},
      {"fp_fma", {{"fma", Op::Fma, 0}, {"fms", Op::Fma, 1}, {"fnms", Op::Fma, 2}, {"fnma", Op::Fma, 3}}, 2, false,
       false, true},
      {"fp_cmp", {{"lt", Op::Lt}, {"le", Op::Le}, {"eq", Op::Eq}, {"min", Op::Min}, {"max", Op::Max}}, 3, false},
      {"fp_dot3", {{"dot3", Op::Fma}}, 0, true},
  };
  for (const auto& s : specs)
    if (unit == s.unit) return &s;
  return nullptr;
}

Format fp_format(const ConfigDesc& cfg) {
  Format f;
  f.exp_bits = static_cast<int>(cfg.param("ExpW", -1));
  f.frac_bits = static_cast<int>(cfg.param("FracW", -1));
  f.subnormals = cfg.param("Subnormals", 1) != 0;
  const int64_t r = cfg.param("Round", 0);
  if (r < 0 || r > 3) throw ru::num::FormatError(cfg.full_name() + ": Round must be 0..3");
  f.round = static_cast<ru::num::Round>(r);
  f.validate();
  return f;
}

std::string fp_format_name(const Format& f) { return f.name() + " " + ru::num::round_name(f.round); }

// ---------------------------------------------------------------------------------------------

FpAdapter::FpAdapter(const FpUnitSpec& spec, const Format& f, int stages)
    : spec_(spec), f_(f), stages_(stages), W_(f.width()) {
  FieldInfo op{spec.op_bits ? "op_i" : "op", spec.op_bits ? spec.op_bits : 1, FieldKind::Enum, {}};
  for (const auto& o : spec.ops) op.enum_names.push_back(o.name);
  ins_.push_back(op);
  if (spec.dot3) {
    for (const char* n : {"a0", "a1", "a2", "b0", "b1", "b2"}) ins_.push_back({n, W_, FieldKind::Float, {}});
  } else {
    ins_.push_back({"a_i", W_, FieldKind::Float, {}});
    if (!spec.unary) ins_.push_back({"b_i", W_, FieldKind::Float, {}});
    if (spec.ternary) ins_.push_back({"c_i", W_, FieldKind::Float, {}});
  }
  outs_.push_back({"y_o", W_, FieldKind::Float, {}});
  outs_.push_back({"flags_o", 5, FieldKind::Flags, {}});
}

std::string FpAdapter::describe() const {
  return std::string(spec_.unit) + " " + fp_format_name(f_);
}

void FpAdapter::bind(const PortMap& pm) {
  if (spec_.op_bits) {
    op_ = pm.get("op_i");
    if (op_.bits() != spec_.op_bits) throw std::runtime_error(std::string(spec_.unit) + ": op_i width mismatch");
  }
  a_ = pm.get("a_i");
  if (!spec_.unary) b_ = pm.get("b_i");
  if (spec_.ternary) c_ = pm.get("c_i");
  y_ = pm.get("y_o");
  flags_ = pm.get("flags_o");
  const int wa = spec_.dot3 ? 3 * W_ : W_;
  if (a_.bits() != wa || (!spec_.unary && b_.bits() != wa) || (spec_.ternary && c_.bits() != W_) ||
      y_.bits() != W_ || flags_.bits() != 5)
    throw std::runtime_error(describe() + ": port widths do not match the format");
}

static void pack3(const uint64_t* x, int W, uint64_t* w) {
  w[0] = w[1] = w[2] = 0;
  for (int i = 0; i < 3; ++i) {
    const int pos = i * W, wi = pos / 64, sh = pos % 64;
    w[wi] |= x[i] << sh;
    if (sh && sh + W > 64) w[wi + 1] |= x[i] >> (64 - sh);
  }
}

void FpAdapter::drive(const Record& in) {
  if (spec_.op_bits) op_.set(in.v[0]);
  if (spec_.dot3) {
    uint64_t w[3];
    pack3(&in.v[1], W_, w);
    a_.set_words(w, 3);
    pack3(&in.v[4], W_, w);
    b_.set_words(w, 3);
  } else {
    a_.set(in.v[1]);
    if (!spec_.unary) b_.set(in.v[2]);
    if (spec_.ternary) c_.set(in.v[3]);
  }
}

void FpAdapter::read(Record& out) {
  out.v[0] = y_.get();
  out.v[1] = flags_.get();
}

void FpAdapter::model(const Record& in, Record& out) {
  ru::num::Result r;
  if (spec_.dot3) {
    r = ru::num::dot3(f_, &in.v[1], &in.v[4]);
  } else if (spec_.ternary) {  // fp_fma: op_i flips the sign of a (the product) and/or of c
    const FpOpDesc& o = spec_.ops[in.v[0]];
    const uint64_t a = (o.neg & 2) ? ru::num::neg(f_, in.v[1]) : in.v[1];
    const uint64_t c = (o.neg & 1) ? ru::num::neg(f_, in.v[3]) : in.v[3];
    r = ru::num::apply(f_, o.op, a, in.v[2], c);
  } else {
    r = ru::num::apply(f_, spec_.ops[in.v[0]].op, in.v[1], spec_.unary ? 0 : in.v[2]);
  }
  out.v[0] = r.bits;
  out.v[1] = r.flags;
}

std::string fp_text(const Format& f0, uint64_t v) {
  Format f = f0;
  f.subnormals = true;  // show the encoded value, also for flush-to-zero formats
  using ru::num::Class;
  const Class c = ru::num::classify(f, v);
  switch (c) {
    case Class::QNaN: return (v & f.sign_bit()) ? "-qNaN" : "qNaN";
    case Class::SNaN: return (v & f.sign_bit()) ? "-sNaN" : "sNaN";
    case Class::PosInf: return "+inf";
    case Class::NegInf: return "-inf";
    case Class::PosZero: return "+0";
    case Class::NegZero: return "-0";
    default: break;
  }
  const int digits = static_cast<int>(std::ceil((f.frac_bits + 1) * 0.30103)) + 2;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits > 17 ? 17 : digits, ru::num::to_double(f, v));
  std::string s = buf;
  if (c == Class::PosSubnormal || c == Class::NegSubnormal) s += ", subnormal";
  return s;
}

std::string FpAdapter::decimal(const FieldInfo& fi, uint64_t v) const {
  switch (fi.kind) {
    case FieldKind::Float: return fp_text(f_, v);
    case FieldKind::Flags: return ru::num::flags_letters(static_cast<uint8_t>(v));
    default: return UnitAdapter::decimal(fi, v);
  }
}

void FpAdapter::parse_inputs(const std::vector<std::string>& tok, Record& in) const {
  if (tok.empty()) throw std::runtime_error("empty vector");
  in = Record{};
  int code = -1;
  for (size_t i = 0; i < spec_.ops.size(); ++i)
    if (tok[0] == spec_.ops[i].name) code = static_cast<int>(i);
  if (code < 0) {
    std::string names;
    for (const auto& o : spec_.ops) names += std::string(names.empty() ? "" : ", ") + o.name;
    throw std::runtime_error("unknown op '" + tok[0] + "' for " + spec_.unit + " (accepted: " + names + ")");
  }
  const size_t n = static_cast<size_t>(spec_.operands());
  if (tok.size() != n + 1)
    throw std::runtime_error(tok[0] + " takes " + std::to_string(n) + " operands, got " + std::to_string(tok.size() - 1));
  in.v[0] = static_cast<uint64_t>(code);
  for (size_t i = 0; i < n; ++i) in.v[1 + i] = ru::num::parse_operand(f_, tok[1 + i]);
}

void FpAdapter::parse_outputs(const std::vector<std::string>& tok, Record& out, uint32_t& mask) const {
  if (tok.size() != 2) throw std::runtime_error("expected outputs are '<y> <flags>' ('?' leaves one unchecked)");
  out = Record{};
  mask = 0;
  if (tok[0] != "?") {
    out.v[0] = ru::num::parse_operand(f_, tok[0]);
    mask |= 1;
  }
  if (tok[1] != "?") {
    uint64_t fl = 0;
    if (tok[1] != "-") {
      for (char c : tok[1]) {
        switch (c) {
          case 'i': fl |= ru::num::kInvalid; break;
          case 'z': fl |= ru::num::kDivZero; break;
          case 'o': fl |= ru::num::kOverflow; break;
          case 'u': fl |= ru::num::kUnderflow; break;
          case 'x': fl |= ru::num::kInexact; break;
          default: throw std::runtime_error("bad flags '" + tok[1] + "': letters from 'izoux', or '-' for none");
        }
      }
    }
    out.v[1] = fl;
    mask |= 2;
  }
}

// ---------------------------------------------------------------------------------------------
// Sources

namespace {

class SpecialBinary final : public VectorSource {
 public:
  SpecialBinary(const FpUnitSpec& s, const Format& f)
      : nops_(s.ops.size()), unary_(s.unary), sv_(ru::num::special_values(f)) {}
  bool next(Record& r) override {
    if (i_ >= sv_.size()) return false;
    r.v[0] = op_;
    r.v[1] = sv_[i_];
    r.v[2] = unary_ ? 0 : sv_[j_];
    if (++op_ == nops_) {
      op_ = 0;
      if (unary_ || ++j_ == sv_.size()) j_ = 0, ++i_;
    }
    return true;
  }
  uint64_t total() const override { return nops_ * sv_.size() * (unary_ ? 1 : sv_.size()); }

 private:
  size_t nops_;
  bool unary_;
  std::vector<uint64_t> sv_;
  size_t i_ = 0, j_ = 0, op_ = 0;
};

class SpecialTernary final : public VectorSource {
 public:
  SpecialTernary(const FpUnitSpec& s, const Format& f) : nops_(s.ops.size()), sv_(ru::num::special_values(f)) {}
  bool next(Record& r) override {
    if (i_ >= sv_.size()) return false;
    r.v[0] = n_++ % nops_;
    r.v[1] = sv_[i_];
    r.v[2] = sv_[j_];
    r.v[3] = sv_[k_];
    if (++k_ == sv_.size()) {
      k_ = 0;
      if (++j_ == sv_.size()) j_ = 0, ++i_;
    }
    return true;
  }
  uint64_t total() const override { return sv_.size() * sv_.size() * sv_.size(); }

 private:
  size_t nops_;
  std::vector<uint64_t> sv_;
  size_t i_ = 0, j_ = 0, k_ = 0, n_ = 0;
};

class SpecialDot3 final : public VectorSource {
 public:
  SpecialDot3(const Format& f, uint64_t seed) : sv_(ru::num::special_values(f)), gen_(f, seed), rng_(seed ^ 0x5eed) {}
  bool next(Record& r) override {
    if (i_ >= sv_.size()) return false;
    const size_t k = (i_ + j_) % 3;
    r.v[0] = 0;
    for (int p = 0; p < 3; ++p) {
      r.v[1 + p] = pick();
      r.v[4 + p] = pick();
    }
    r.v[1 + k] = sv_[i_];
    r.v[4 + k] = sv_[j_];
    if (++j_ == sv_.size()) j_ = 0, ++i_;
    return true;
  }
  uint64_t total() const override { return sv_.size() * sv_.size(); }

 private:
  uint64_t pick() { return rng_.below(2) ? sv_[rng_.below(sv_.size())] : gen_.next(); }
  std::vector<uint64_t> sv_;
  ru::num::OperandGen gen_;
  Rng rng_;
  size_t i_ = 0, j_ = 0;
};

class RandomFp final : public VectorSource {
 public:
  RandomFp(const FpUnitSpec& s, const Format& f, uint64_t seed, uint64_t n)
      : s_(s), f_(f), gen_(f, seed), rng_(seed ^ 0xabcdef), n_(n) {}
  bool next(Record& r) override {
    if (i_ >= n_) return false;
    ++i_;
    if (s_.dot3) {
      r.v[0] = 0;
      gen_.triple(r.v[1], r.v[2], r.v[3]);
      gen_.triple(r.v[4], r.v[5], r.v[6]);
      if (rng_.below(4) == 0) {  // a1*b1 = -(a0*b0) exactly: the sum cancels to the third product
        r.v[2] = r.v[1];
        r.v[5] = ru::num::neg(f_, r.v[4]);
      }
    } else if (s_.ternary) {  // fma: products near ties, c ~ -a*b, exponent differences, specials
      r.v[0] = rng_.below(s_.ops.size());
      gen_.triple(r.v[1], r.v[2], r.v[3]);
    } else if (s_.unary) {  // sqrt: exact squares and squares of rounding midpoints, or anything
      r.v[0] = rng_.below(s_.ops.size());
      r.v[1] = rng_.below(2) ? gen_.sqrt_case() : gen_.next();
      r.v[2] = 0;
    } else {
      r.v[0] = rng_.below(s_.ops.size());
      gen_.pair(r.v[1], r.v[2]);
    }
    return true;
  }
  uint64_t total() const override { return n_; }

 private:
  const FpUnitSpec& s_;
  Format f_;
  ru::num::OperandGen gen_;
  Rng rng_;
  uint64_t n_, i_ = 0;
};

class ExhaustiveBinary final : public VectorSource {
 public:
  ExhaustiveBinary(const FpUnitSpec& s, const Format& f)
      : nops_(s.ops.size()), n_(1ull << f.width()), unary_(s.unary), ternary_(s.ternary) {}
  bool next(Record& r) override {
    if (a_ >= n_) return false;
    r.v[0] = op_;
    r.v[1] = a_;
    r.v[2] = b_;
    r.v[3] = c_;
    if (++op_ == nops_) {
      op_ = 0;
      if (!ternary_ || ++c_ == n_) {
        c_ = 0;
        if (unary_ || ++b_ == n_) b_ = 0, ++a_;
      }
    }
    return true;
  }
  uint64_t total() const override { return nops_ * n_ * (unary_ ? 1 : n_) * (ternary_ ? n_ : 1); }

 private:
  uint64_t nops_, n_;
  bool unary_, ternary_;
  uint64_t a_ = 0, b_ = 0, c_ = 0, op_ = 0;
};

}  // namespace

std::unique_ptr<VectorSource> fp_special_source(const FpUnitSpec& s, const Format& f, uint64_t seed) {
  if (s.dot3) return std::make_unique<SpecialDot3>(f, seed);
  if (s.ternary) return std::make_unique<SpecialTernary>(s, f);
  return std::make_unique<SpecialBinary>(s, f);
}

std::unique_ptr<VectorSource> fp_random_source(const FpUnitSpec& s, const Format& f, uint64_t seed, uint64_t n) {
  return std::make_unique<RandomFp>(s, f, seed, n);
}

uint64_t fp_exhaustive_count(const FpUnitSpec& s, const Format& f) {
  return s.ops.size() << ((s.unary ? 1 : s.ternary ? 3 : 2) * f.width());
}

std::unique_ptr<VectorSource> fp_exhaustive_source(const FpUnitSpec& s, const Format& f) {
  if (s.dot3) throw std::invalid_argument("fp_dot3 has six operands: no exhaustive source");
  const int max_w = s.unary ? 24 : s.ternary ? 8 : 12;
  if (f.width() > max_w)
    throw std::invalid_argument(f.name() + " is too wide for an exhaustive run (at most " + std::to_string(max_w) +
                                " bits)");
  return std::make_unique<ExhaustiveBinary>(s, f);
}

}  // namespace ru::tb
