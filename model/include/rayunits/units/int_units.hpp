// Golden models of the thread processors' integer units (issue 16): the integer ALU
// (rtl/ru_int_alu.sv) and the branch unit (rtl/ru_branch.sv). Values are w-bit two's complement
// words held in the low bits of a uint64_t (the other bits zero). Checked against native integer
// arithmetic (tests/units/test_int_units.cpp) and cycle by cycle against the RTL (tb_int_alu,
// tb_branch).
#pragma once
#include <cstdint>

namespace ru::units {

enum class IntOp : uint8_t { Add = 0, Sub, And, Or, Xor, Sll, Srl, Sra, Slt, Sltu, Min, Max, Mov };
constexpr int kIntOps = 13;  // op codes 12..15 are all mov

inline uint64_t int_mask(int w) { return w >= 64 ? ~0ull : (1ull << w) - 1; }
// The w-bit word x as a signed number.
inline int64_t int_signed(uint64_t x, int w) {
  x &= int_mask(w);
  return w < 64 && (x >> (w - 1) & 1) ? static_cast<int64_t>(x | ~int_mask(w)) : static_cast<int64_t>(x);
}
// Bits of the shift amount the units read: clog2(w) (at least 1).
inline int int_shift_bits(int w) {
  int s = 0;
  while ((1 << s) < w) ++s;
  return s < 1 ? 1 : s;
}

// op: 0..15 (12..15 mov). Shifts take s = b mod 2^int_shift_bits(w); s >= w shifts everything out.
inline uint64_t int_alu(int w, unsigned op, uint64_t a, uint64_t b) {
  const uint64_t m = int_mask(w);
  a &= m;
  b &= m;
  const unsigned s = static_cast<unsigned>(b & ((1ull << int_shift_bits(w)) - 1));
  const int64_t sa = int_signed(a, w), sb = int_signed(b, w);
  switch (op) {
    case 0: return (a + b) & m;
    case 1: return (a - b) & m;
    case 2: return a & b;
    case 3: return a | b;
    case 4: return a ^ b;
    case 5: return s >= static_cast<unsigned>(w) ? 0 : (a << s) & m;
    case 6: return s >= static_cast<unsigned>(w) ? 0 : a >> s;
    case 7: return s >= static_cast<unsigned>(w) ? (sa < 0 ? m : 0) : static_cast<uint64_t>(sa >> s) & m;
    case 8: return sa < sb ? 1 : 0;
    case 9: return a < b ? 1 : 0;
    case 10: return sa < sb ? a : b;
    case 11: return sa < sb ? b : a;
    default: return a;
  }
}

struct BranchResult {
  bool taken = false;
  uint64_t next = 0;  // pc_w bits
};
// op 0 beq, 1 bne, 2 blt, 3 bge, 4 bltu, 5 bgeu, 6/7 always. next = taken ? pc + off : pc + 1.
inline BranchResult branch(int w, int pc_w, unsigned op, uint64_t a, uint64_t b, uint64_t pc, uint64_t off) {
  const uint64_t m = int_mask(w), pm = int_mask(pc_w);
  a &= m;
  b &= m;
  const int64_t sa = int_signed(a, w), sb = int_signed(b, w);
  bool t = true;
  switch (op & 7) {
    case 0: t = a == b; break;
    case 1: t = a != b; break;
    case 2: t = sa < sb; break;
    case 3: t = sa >= sb; break;
    case 4: t = a < b; break;
    case 5: t = a >= b; break;
    default: t = true; break;
  }
  return {t, ((t ? pc + off : pc + 1) & pm)};
}

}  // namespace ru::units
