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
  // Built once from the registry: every unit whose name starts with "fp_".
  static const std::vector<FpUnitSpec> specs = [] {
    std::vector<FpUnitSpec> v;
    for (const synth::UnitSpec& u : synth::units()) {
      if (u.name.rfind("fp_", 0) != 0) continue;
      FpUnitSpec s;
      s.unit = &u;
      synth::UnitConfig c;
      c.fmt = Format::parse("e8m23");
      const auto fields = synth::fields_for(u, c, synth::PortDir::In);
      s.operands = 0;
      for (size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].kind == synth::FieldKind::Float) ++s.operands;
        if (fields[i].port == "op_i") {
          s.op_field = static_cast<int>(i);
          s.ops = fields[i].enum_names;
        }
      }
      s.dot3 = s.operands == 6;
      if (s.op_field < 0) s.ops = {u.name.substr(3)};
      v.push_back(std::move(s));
    }
    return v;
  }();
  for (const auto& s : specs)
    if (unit == s.unit->name) return &s;
  return nullptr;
}

Format fp_format(const ConfigDesc& cfg) { return unit_config(cfg).fmt; }  // the registry's decoding

std::string fp_format_name(const Format& f) { return f.name() + " " + ru::num::round_name(f.round); }

// ---------------------------------------------------------------------------------------------

namespace {
synth::UnitConfig fp_config(const Format& f, int stages) {
  synth::UnitConfig c;
  c.fmt = f;
  c.stages = stages;
  return c;
}
}  // namespace

FpAdapter::FpAdapter(const FpUnitSpec& spec, const Format& f, int stages)
    : RegistryAdapter(*spec.unit, fp_config(f, stages)), spec_(spec) {}

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

void FpAdapter::parse_inputs(const std::vector<std::string>& tok, Record& in) const {
  if (tok.empty()) throw std::runtime_error("empty vector");
  in = Record{};
  int code = -1;
  for (size_t i = 0; i < spec_.ops.size(); ++i)
    if (tok[0] == spec_.ops[i]) code = static_cast<int>(i);
  if (code < 0) {
    std::string names;
    for (const auto& o : spec_.ops) names += (names.empty() ? "" : ", ") + o;
    throw std::runtime_error("unknown op '" + tok[0] + "' for " + spec_.unit->name + " (accepted: " + names + ")");
  }
  const size_t n = static_cast<size_t>(spec_.operands);
  if (tok.size() != n + 1)
    throw std::runtime_error(tok[0] + " takes " + std::to_string(n) + " operands, got " + std::to_string(tok.size() - 1));
  if (spec_.op_field >= 0) in.v[spec_.op_field] = static_cast<uint64_t>(code);
  for (size_t i = 0; i < n; ++i) in.v[i] = ru::num::parse_operand(format(), tok[1 + i]);
}

void FpAdapter::parse_outputs(const std::vector<std::string>& tok, Record& out, uint32_t& mask) const {
  if (tok.size() != 2) throw std::runtime_error("expected outputs are '<y> <flags>' ('?' leaves one unchecked)");
  out = Record{};
  mask = 0;
  if (tok[0] != "?") {
    out.v[0] = ru::num::parse_operand(format(), tok[0]);
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

// Records in the registry layout: operands at 0..operands-1, the op code at op_field (if any).
void put_op(const FpUnitSpec& s, Record& r, uint64_t op) {
  if (s.op_field >= 0) r.v[s.op_field] = op;
}

class SpecialBinary final : public VectorSource {
 public:
  SpecialBinary(const FpUnitSpec& s, const Format& f)
      : s_(s), nops_(s.ops.size()), unary_(s.unary()), sv_(ru::num::special_values(f)) {}
  bool next(Record& r) override {
    if (i_ >= sv_.size()) return false;
    r = Record{};
    put_op(s_, r, op_);
    r.v[0] = sv_[i_];
    if (!unary_) r.v[1] = sv_[j_];
    if (++op_ == nops_) {
      op_ = 0;
      if (unary_ || ++j_ == sv_.size()) j_ = 0, ++i_;
    }
    return true;
  }
  uint64_t total() const override { return nops_ * sv_.size() * (unary_ ? 1 : sv_.size()); }

 private:
  const FpUnitSpec& s_;
  size_t nops_;
  bool unary_;
  std::vector<uint64_t> sv_;
  size_t i_ = 0, j_ = 0, op_ = 0;
};

class SpecialTernary final : public VectorSource {
 public:
  SpecialTernary(const FpUnitSpec& s, const Format& f) : s_(s), nops_(s.ops.size()), sv_(ru::num::special_values(f)) {}
  bool next(Record& r) override {
    if (i_ >= sv_.size()) return false;
    r = Record{};
    put_op(s_, r, n_++ % nops_);
    r.v[0] = sv_[i_];
    r.v[1] = sv_[j_];
    r.v[2] = sv_[k_];
    if (++k_ == sv_.size()) {
      k_ = 0;
      if (++j_ == sv_.size()) j_ = 0, ++i_;
    }
    return true;
  }
  uint64_t total() const override { return sv_.size() * sv_.size() * sv_.size(); }

 private:
  const FpUnitSpec& s_;
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
    r = Record{};
    for (int p = 0; p < 3; ++p) {
      r.v[p] = pick();
      r.v[3 + p] = pick();
    }
    r.v[k] = sv_[i_];
    r.v[3 + k] = sv_[j_];
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

// Every op x every operand tuple, as a mixed-radix counter: op fastest, then the operands from
// the last to the first (so a binary unit runs a-major, b, op-minor).
class ExhaustiveTuples final : public VectorSource {
 public:
  ExhaustiveTuples(const FpUnitSpec& s, const Format& f)
      : s_(s), nops_(s.ops.size()), n_(1ull << f.width()), k_(s.operands), total_(fp_exhaustive_count(s, f)) {}
  bool next(Record& r) override {
    if (i_ >= total_) return false;
    r = Record{};
    uint64_t v = i_++;
    put_op(s_, r, v % nops_);
    v /= nops_;
    for (int p = k_ - 1; p >= 0; --p, v /= n_) r.v[p] = v % n_;
    return true;
  }
  uint64_t total() const override { return total_; }

 private:
  const FpUnitSpec& s_;
  uint64_t nops_, n_;
  int k_;
  uint64_t total_, i_ = 0;
};

}  // namespace

std::unique_ptr<VectorSource> fp_special_source(const FpUnitSpec& s, const Format& f, uint64_t seed) {
  if (s.dot3) return std::make_unique<SpecialDot3>(f, seed);
  if (s.ternary()) return std::make_unique<SpecialTernary>(s, f);
  return std::make_unique<SpecialBinary>(s, f);
}

std::unique_ptr<VectorSource> fp_random_source(const FpUnitSpec& s, const Format& f, uint64_t seed, uint64_t n) {
  synth::UnitConfig c;
  c.fmt = f;
  return registry_random_source(*s.unit, c, seed, n);
}

uint64_t fp_exhaustive_count(const FpUnitSpec& s, const Format& f) {
  return s.ops.size() << (s.operands * f.width());
}

std::unique_ptr<VectorSource> fp_exhaustive_source(const FpUnitSpec& s, const Format& f) {
  const int max_w = s.unary() ? 24 : s.ternary() ? 8 : s.dot3 ? 4 : 12;
  if (f.width() > max_w)
    throw std::invalid_argument(f.name() + " is too wide for an exhaustive run of " + s.unit->name + " (at most " +
                                std::to_string(max_w) + " bits)");
  return std::make_unique<ExhaustiveTuples>(s, f);
}

}  // namespace ru::tb
