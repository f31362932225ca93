// rayunits tb: type-erased access to one port of a Verilated model.
//
// Verilator stores a port of width w as uint8_t (w <= 8), uint16_t (<= 16), uint32_t (<= 32),
// uint64_t (<= 64) or VlWide<N> (an array of N 32-bit words, w > 64). A Port remembers the
// storage pointer and the declared width, so the generic harness and the per-unit adapters
// can drive and read any port without knowing the generated model class.
//
// Inputs must be "clean" for Verilator (no bits above the declared width): set() masks.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

namespace ru::tb {

class Port {
 public:
  Port() = default;
  Port(uint8_t* p, int bits) : p_(p), bits_(bits), kind_(k8) { check(8); }
  Port(uint16_t* p, int bits) : p_(p), bits_(bits), kind_(k16) { check(16); }
  Port(uint32_t* p, int bits) : p_(p), bits_(bits), kind_(bits > 32 ? kWide : k32) {}
  Port(uint64_t* p, int bits) : p_(p), bits_(bits), kind_(k64) { check(64); }

  bool valid() const { return p_ != nullptr; }
  int bits() const { return bits_; }
  int words64() const { return (bits_ + 63) / 64; }
  uint64_t mask() const { return bits_ >= 64 ? ~0ull : ((1ull << bits_) - 1); }

  // Ports of at most 64 bits.
  void set(uint64_t v) {
    v &= mask();
    switch (kind_) {
      case k8: *static_cast<uint8_t*>(p_) = static_cast<uint8_t>(v); break;
      case k16: *static_cast<uint16_t*>(p_) = static_cast<uint16_t>(v); break;
      case k32: *static_cast<uint32_t*>(p_) = static_cast<uint32_t>(v); break;
      case k64: *static_cast<uint64_t*>(p_) = v; break;
      case kWide: set_words(&v, 1); break;
    }
  }
  uint64_t get() const {
    switch (kind_) {
      case k8: return *static_cast<const uint8_t*>(p_) & mask();
      case k16: return *static_cast<const uint16_t*>(p_) & mask();
      case k32: return *static_cast<const uint32_t*>(p_) & mask();
      case k64: return *static_cast<const uint64_t*>(p_) & mask();
      case kWide: {
        const uint32_t* w = static_cast<const uint32_t*>(p_);
        return (static_cast<uint64_t>(w[1]) << 32) | w[0];
      }
    }
    return 0;
  }
  // Any width: little-endian 64-bit words (words64() of them). Bits above the width are dropped.
  void set_words(const uint64_t* w, int nwords) {
    if (kind_ != kWide) {
      set(nwords > 0 ? w[0] : 0);
      return;
    }
    uint32_t* d = static_cast<uint32_t*>(p_);
    const int n32 = (bits_ + 31) / 32;
    for (int i = 0; i < n32; ++i) {
      const int wi = i / 2;
      const uint64_t src = wi < nwords ? w[wi] : 0;
      d[i] = static_cast<uint32_t>((i & 1) ? (src >> 32) : src);
    }
    if (bits_ % 32) d[n32 - 1] &= (1u << (bits_ % 32)) - 1;
  }
  void get_words(uint64_t* w) const {
    if (kind_ != kWide) {
      w[0] = get();
      return;
    }
    const uint32_t* d = static_cast<const uint32_t*>(p_);
    const int n32 = (bits_ + 31) / 32;
    for (int i = 0; i < words64(); ++i) w[i] = 0;
    for (int i = 0; i < n32; ++i) w[i / 2] |= static_cast<uint64_t>(d[i]) << ((i & 1) * 32);
  }

 private:
  enum Kind : uint8_t { k8, k16, k32, k64, kWide };
  void check(int storage_bits) const {
    if (bits_ < 1 || bits_ > storage_bits)
      throw std::logic_error("ru::tb::Port: width " + std::to_string(bits_) +
                             " does not fit its Verilator storage");
  }
  void* p_ = nullptr;
  int bits_ = 0;
  Kind kind_ = k8;
};

// Ports of one Verilated model by their RTL names ("a_i", "y_o", ...).
class PortMap {
 public:
  void add(const std::string& name, Port p) { ports_[name] = p; }
  bool has(const std::string& name) const { return ports_.count(name) != 0; }
  Port get(const std::string& name) const {
    auto it = ports_.find(name);
    if (it == ports_.end()) throw std::runtime_error("ru::tb: the DUT has no port '" + name + "'");
    return it->second;
  }
  const std::map<std::string, Port>& all() const { return ports_; }

 private:
  std::map<std::string, Port> ports_;
};

}  // namespace ru::tb
