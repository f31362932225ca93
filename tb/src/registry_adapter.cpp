// rayunits tb: the registry adapter (registry_adapter.hpp).
#include "rayunits/tb/registry_adapter.hpp"

#include <stdexcept>

#include "rayunits/num/format.hpp"
#include "rayunits/tb/fp.hpp"  // fp_text, fp_format_name

namespace ru::tb {

synth::UnitConfig unit_config(const ConfigDesc& cfg) {
  const synth::UnitSpec& u = synth::find_unit(cfg.unit);
  std::map<std::string, long long> p;
  for (const auto& [k, v] : cfg.params) p[k] = v;
  return synth::config_from_params(u, p);
}

namespace {

FieldKind field_kind(synth::FieldKind k) {
  switch (k) {
    case synth::FieldKind::Bits: return FieldKind::Hex;
    case synth::FieldKind::Float: return FieldKind::Float;
    case synth::FieldKind::Flags: return FieldKind::Flags;
    case synth::FieldKind::Enum: return FieldKind::Enum;
  }
  return FieldKind::Hex;
}

void pack(const uint64_t* x, int n, int bits, uint64_t* w, int nw) {
  for (int i = 0; i < nw; ++i) w[i] = 0;
  for (int i = 0; i < n; ++i) {
    const int pos = i * bits, wi = pos / 64, sh = pos % 64;
    w[wi] |= x[i] << sh;
    if (sh && sh + bits > 64) w[wi + 1] |= x[i] >> (64 - sh);
  }
}

void unpack(const uint64_t* w, int n, int bits, uint64_t* x) {
  const uint64_t m = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
  for (int i = 0; i < n; ++i) {
    const int pos = i * bits, wi = pos / 64, sh = pos % 64;
    uint64_t v = w[wi] >> sh;
    if (sh && sh + bits > 64) v |= w[wi + 1] << (64 - sh);
    x[i] = v & m;
  }
}

constexpr int kMaxWords = (kMaxFields * 64 + 63) / 64;

}  // namespace

RegistryAdapter::RegistryAdapter(const synth::UnitSpec& u, const synth::UnitConfig& rtl)
    : RegistryAdapter(u, rtl, rtl) {}

RegistryAdapter::RegistryAdapter(const synth::UnitSpec& u, const synth::UnitConfig& rtl,
                                 const synth::UnitConfig& model)
    : u_(u), rtl_(rtl), mcfg_(model) {
  if (!u_.golden) throw std::logic_error("unit " + u_.name + " has no golden model in the registry");
  golden_ = u_.golden(mcfg_);
  for (const synth::PortDir dir : {synth::PortDir::In, synth::PortDir::Out}) {
    std::vector<FieldInfo>& fields = dir == synth::PortDir::In ? ins_ : outs_;
    std::vector<Group>& groups = dir == synth::PortDir::In ? in_groups_ : out_groups_;
    for (const synth::Field& f : synth::fields_for(u_, rtl_, dir)) {
      if (f.elem == 0) groups.push_back({f.port, static_cast<int>(fields.size()), 0, f.bits, {}});
      ++groups.back().n;
      fields.push_back({f.name, f.bits, field_kind(f.kind), f.enum_names});
    }
    if (fields.size() > static_cast<size_t>(kMaxFields))
      throw std::logic_error(u_.name + ": more than kMaxFields fields in a record");
  }
}

std::string RegistryAdapter::describe() const {
  std::string s = u_.name;
  if (u_.uses_format) s += " " + fp_format_name(rtl_.fmt);
  for (const auto& p : u_.extra_params) {
    const long long v = synth::param_value(u_, rtl_, p.name);
    if (v != p.def) s += " " + p.name + "=" + std::to_string(v);
  }
  if (!note_.empty()) s += " " + note_;
  return s;
}

int RegistryAdapter::input_index(const std::string& field) const {
  for (size_t i = 0; i < ins_.size(); ++i)
    if (ins_[i].name == field) return static_cast<int>(i);
  return -1;
}
int RegistryAdapter::output_index(const std::string& field) const {
  for (size_t i = 0; i < outs_.size(); ++i)
    if (outs_[i].name == field) return static_cast<int>(i);
  return -1;
}

void RegistryAdapter::bind(const PortMap& pm) {
  for (std::vector<Group>* gs : {&in_groups_, &out_groups_})
    for (Group& g : *gs) {
      g.p = pm.get(g.port);
      if (g.p.bits() != g.n * g.bits)
        throw std::runtime_error(describe() + ": port " + g.port + " is " + std::to_string(g.p.bits()) +
                                 " bits in the RTL, the registry says " + std::to_string(g.n * g.bits));
    }
}

void RegistryAdapter::drive(const Record& in) {
  uint64_t w[kMaxWords];
  for (Group& g : in_groups_) {
    const int nw = (g.n * g.bits + 63) / 64;
    pack(&in.v[g.first], g.n, g.bits, w, nw);
    g.p.set_words(w, nw);
  }
}

void RegistryAdapter::read(Record& out) {
  uint64_t w[kMaxWords];
  for (Group& g : out_groups_) {
    g.p.get_words(w);
    unpack(w, g.n, g.bits, &out.v[g.first]);
  }
}

void RegistryAdapter::model(const Record& in, Record& out) {
  out = Record{};
  if (hook_) {
    Record x = in;
    hook_(x);
    golden_(x.v, out.v);
  } else {
    golden_(in.v, out.v);
  }
  for (size_t i = 0; i < outs_.size(); ++i) out.v[i] &= outs_[i].mask();
}

std::string RegistryAdapter::decimal(const FieldInfo& f, uint64_t v) const {
  switch (f.kind) {
    case FieldKind::Float: return fp_text(rtl_.fmt, v);
    case FieldKind::Flags: return ru::num::flags_letters(static_cast<uint8_t>(v));
    default: return UnitAdapter::decimal(f, v);
  }
}

namespace {
class RegistrySource final : public VectorSource {
 public:
  RegistrySource(synth::InputGen g, uint64_t n) : g_(std::move(g)), n_(n) {}
  bool next(Record& in) override {
    if (i_ >= n_) return false;
    ++i_;
    in = Record{};
    g_(in.v);
    return true;
  }
  uint64_t total() const override { return n_; }

 private:
  synth::InputGen g_;
  uint64_t n_, i_ = 0;
};
}  // namespace

std::unique_ptr<VectorSource> registry_random_source(const synth::UnitSpec& u, const synth::UnitConfig& c,
                                                     uint64_t seed, uint64_t n) {
  if (!u.random_inputs) throw std::logic_error("unit " + u.name + " has no random vector generator in the registry");
  return std::make_unique<RegistrySource>(u.random_inputs(c, seed), n);
}

}  // namespace ru::tb
