// rayunits trax: the instruction set of the thread processors and the thread API a kernel is
// written against.
//
// Representation (docs/TRAX.md): a thread processor (TP) runs one work item (a pixel) at a time.
// When the timing model hands a TP its next item (the atomic increment), the kernel is executed
// functionally for that item in ordinary C++ and every operation it performs is appended to an
// instruction stream: op class, one destination register, source registers, byte address for
// memory operations. Registers are virtual and single-assignment (a fresh number per result;
// register 1 holds the work item number delivered by the atomic increment; 0 = none / an
// immediate). The SystemC timing model (sim.hpp) then replays the stream in order, cycle by
// cycle. Values never depend on timing (scene data is read-only, the frame buffer write-only),
// so executing ahead of the timing is exact.
//
// TVal is the kernel's floating-point value: a value of the configured format (ru::num::Soft,
// bit-accurate) plus the register holding it, or the scene-memory address it lives at (a value
// of the scene data, loaded on first use by a LOAD). Its operators record one instruction each
// and compute through the format model, so the renderer's shading code (render/tracer.hpp),
// instantiated with TVal, is the kernel: no second copy of the shading.
#pragma once
#include <cstdint>
#include <initializer_list>
#include <unordered_map>
#include <vector>

#include "rayunits/num/fp.hpp"
#include "rayunits/render/arith.hpp"
#include "rayunits/trax/config.hpp"

namespace ru::trax {

enum class Op : uint8_t {
  FAdd = 0, FMul, FDiv, FSqrt, FCmp, FFma, Conv, Int, Branch,  // functional units (Unit of the same order)
  Box, Tri, Noise, Texture,
  Load,        // scene data through L1/L2/DRAM (dst = value)
  LoadLocal,   // per-thread local store (traversal stack)
  StoreLocal,  // per-thread local store
  Store,       // frame buffer: bypasses the caches (DRAM bandwidth only), no result
  Atomic,      // chip-wide atomic increment (work distribution)
  kCount
};
constexpr int kOps = static_cast<int>(Op::kCount);
const char* op_name(Op op);
// The functional unit of an op, or Unit::kCount for memory / atomic ops.
inline Unit op_unit(Op op) {
  switch (op) {
    case Op::FAdd: return Unit::FpAdd;
    case Op::FMul: return Unit::FpMul;
    case Op::FDiv: return Unit::FpDiv;
    case Op::FSqrt: return Unit::FpSqrt;
    case Op::FCmp: return Unit::FpCmp;
    case Op::FFma: return Unit::FpFma;
    case Op::Conv: return Unit::Conv;
    case Op::Int: return Unit::Int;
    case Op::Branch: return Unit::Branch;
    case Op::Box: return Unit::Box;
    case Op::Tri: return Unit::Tri;
    case Op::Noise: return Unit::Noise;
    case Op::Texture: return Unit::Texture;
    default: return Unit::kCount;
  }
}

struct Instr {
  Op op;
  uint8_t nsrc;
  uint32_t dst;   // 0: no result
  uint32_t src;   // index of the first source in Stream::srcs
  uint64_t addr;  // byte address (Load, Store, LoadLocal, StoreLocal); Box/Tri/Noise with
                  // operand recording on: offset of its operands in Stream::data
  uint8_t aux = 0;  // Texture: the request's octave count (its occupancy and latency)
  uint8_t rec = 0;  // an operand record is attached (Thread::attach; addr is its offset)
};

// Operand records of the unit instructions (kept only when Thread::keep_operands(): the RTL
// co-simulation). Bit patterns, inputs then the golden model's outputs:
//   Box   14 in: o.xyz, inv.xyz, lo.xyz, hi.xyz, t_min, t_max;  3 out: hit, t_enter, t_exit
//   Tri   17 in: a.xyz, d.xyz, p0.xyz, p1.xyz, p2.xyz, t_min, t_max;
//          5 out: hit, why (units::TriMiss), t, beta, gamma
//   Noise  3 in: the noise unit's input words x, y, z (FixedNoise::quantize, two's complement
//          masked to IntBits + FracBits); 1 out: value (masked to OutW bits)
//   Texture 5 in: the texture unit's words x, y, z (FixedTexture::quantize), mode, octaves;
//          1 out: value (masked to OutF + 2 bits)
// and of the FP units (co-simulated with --cosim-fp; issue 16), the format's bit patterns:
//   FAdd  a, b, op (0 add, 1 sub) -> y      FMul a, b -> y      FDiv a, b -> y      FSqrt a -> y
//   FCmp  a, b, op (0 lt, 1 le, 2 eq, 3 min, 4 max) -> y (lt/le/eq: 0 or 1, the predicate the
//         branch reads; a > b is lt(b, a), a != b is eq(a, b) with the branch inverted)
//   FFma  a, b, c, op (0 a*b+c, 1 a*b-c) -> y
constexpr int kBoxIn = 14, kBoxOut = 3, kTriIn = 17, kTriOut = 5, kNoiseIn = 3, kNoiseOut = 1, kTextureIn = 5,
              kTextureOut = 1;
inline bool fp_unit_op(Op op) {
  return op == Op::FAdd || op == Op::FMul || op == Op::FDiv || op == Op::FSqrt || op == Op::FCmp || op == Op::FFma;
}
inline int unit_inputs(Op op) {
  switch (op) {
    case Op::Box: return kBoxIn;
    case Op::Tri: return kTriIn;
    case Op::Noise: return kNoiseIn;
    case Op::Texture: return kTextureIn;
    case Op::FFma: return 4;
    case Op::FAdd: case Op::FCmp: return 3;
    case Op::FMul: case Op::FDiv: return 2;
    case Op::FSqrt: return 1;
    default: return 0;
  }
}
inline int unit_outputs(Op op) {
  return op == Op::Box ? kBoxOut : op == Op::Tri ? kTriOut : op == Op::Noise ? kNoiseOut : op == Op::Texture ? kTextureOut
         : fp_unit_op(op) ? 1 : 0;
}
// The same layout by RTL data port (unit registry names, model/include/rayunits/synth/units.hpp):
// each entry covers `n` consecutive words, the port's elements low first. The co-simulation maps
// words to the registry's fields with it (and checks the counts against the registry); outputs
// of the RTL that are not listed (the triangle units' vol_o) come from the registry's model.
struct UnitWords {
  const char* port;
  int n;
};
inline const std::vector<UnitWords>& unit_words(Op op) {
  static const std::vector<UnitWords> box = {{"org_i", 3}, {"rdir_i", 3}, {"bmin_i", 3}, {"bmax_i", 3},
                                             {"tmin_i", 1}, {"tmax_i", 1}, {"hit_o", 1}, {"t_enter_o", 1},
                                             {"t_exit_o", 1}};
  static const std::vector<UnitWords> tri = {{"a_i", 3},    {"d_i", 3},    {"p0_i", 3},   {"p1_i", 3},
                                             {"p2_i", 3},   {"tmin_i", 1}, {"tmax_i", 1}, {"hit_o", 1},
                                             {"why_o", 1},  {"t_o", 1},    {"beta_o", 1}, {"gamma_o", 1}};
  static const std::vector<UnitWords> noise = {{"x_i", 1}, {"y_i", 1}, {"z_i", 1}, {"value_o", 1}};
  static const std::vector<UnitWords> texture = {{"x_i", 1}, {"y_i", 1}, {"z_i", 1}, {"mode_i", 1}, {"oct_i", 1}, {"value_o", 1}};
  static const std::vector<UnitWords> fp_op = {{"a_i", 1}, {"b_i", 1}, {"op_i", 1}, {"y_o", 1}};  // fp_add, fp_cmp
  static const std::vector<UnitWords> fp_ab = {{"a_i", 1}, {"b_i", 1}, {"y_o", 1}};               // fp_mul, fp_div
  static const std::vector<UnitWords> fp_a = {{"a_i", 1}, {"y_o", 1}};                            // fp_sqrt
  static const std::vector<UnitWords> fp_abc = {{"a_i", 1}, {"b_i", 1}, {"c_i", 1}, {"op_i", 1}, {"y_o", 1}};  // fp_fma
  static const std::vector<UnitWords> none;
  switch (op) {
    case Op::Box: return box;
    case Op::Tri: return tri;
    case Op::Noise: return noise;
    case Op::Texture: return texture;
    case Op::FAdd: case Op::FCmp: return fp_op;
    case Op::FMul: case Op::FDiv: return fp_ab;
    case Op::FSqrt: return fp_a;
    case Op::FFma: return fp_abc;
    default: return none;
  }
}

struct Stream {
  std::vector<Instr> code;
  std::vector<uint32_t> srcs;
  std::vector<uint64_t> data;  // operand records (see kBoxIn), only with keep_operands
  uint32_t nregs = 2;     // registers used: 0 (none), 1 (work item), 2..nregs-1
  uint32_t max_live = 0;  // most registers live at once (a lower bound on the register file)
  // Registers holding a value of the format (Thread::mark_fp): the FP register file, whose width
  // is the format's; the others (indices, addresses, predicates, the item) are 32-bit integers.
  std::vector<uint8_t> fp;
  uint32_t max_live_fp = 0, max_live_int = 0;  // the same count per register file
  void clear() {
    code.clear();
    srcs.clear();
    data.clear();
    fp.clear();
    nregs = 2;
    max_live = max_live_fp = max_live_int = 0;
  }
};

// Records one work item's instruction stream. Kernels emit through the current Thread
// (Thread::current(), set by Scope) or directly.
class Thread {
 public:
  static constexpr uint32_t kItemReg = 1;

  void begin(Stream* s) {
    s_ = s;
    s_->clear();
    load_cache_.clear();
  }
  Stream& stream() { return *s_; }

  // Appends one instruction; returns its destination register (0 when !has_dst). Source
  // registers 0 (immediates) are dropped.
  uint32_t emit(Op op, const uint32_t* src, int n, bool has_dst = true, uint64_t addr = 0) {
    Instr in;
    in.op = op;
    in.src = static_cast<uint32_t>(s_->srcs.size());
    uint8_t k = 0;
    for (int i = 0; i < n; ++i)
      if (src[i]) {
        s_->srcs.push_back(src[i]);
        ++k;
      }
    in.nsrc = k;
    in.dst = has_dst ? s_->nregs++ : 0;
    in.addr = addr;
    s_->code.push_back(in);
    // FP arithmetic results are values of the format; other producers are marked where a
    // format value is known to come out (mark_fp: scene loads, BOX/TRI t, conversions to FP)
    if (op == Op::FAdd || op == Op::FMul || op == Op::FDiv || op == Op::FSqrt || op == Op::FFma || op == Op::Noise ||
        op == Op::Texture)
      mark_fp(in.dst);
    return in.dst;
  }
  uint32_t emit(Op op, std::initializer_list<uint32_t> src, bool has_dst = true, uint64_t addr = 0) {
    return emit(op, src.begin(), static_cast<int>(src.size()), has_dst, addr);
  }
  // Operand recording for the RTL co-simulation (set by the timing model when it has an
  // IssueObserver). With it on, the unit instruction just emitted gets its operand record.
  bool keep_operands() const { return keep_operands_; }
  void set_keep_operands(bool on) { keep_operands_ = on; }
  // Attaches n words to the last instruction (a Box/Tri/Noise): Instr::addr = their offset.
  void attach(const uint64_t* w, int n) {
    s_->code.back().addr = s_->data.size();
    s_->code.back().rec = 1;
    s_->data.insert(s_->data.end(), w, w + n);
  }
  // A load of scene data at `addr` (address computed from register addr_reg, 0 = constant).
  uint32_t load(uint64_t addr, uint32_t addr_reg = 0) { return emit(Op::Load, {addr_reg}, true, addr); }
  // A load of a scene value used by the shading code: the first use in an item loads it, later
  // uses read the same register (the compiler's load reuse; scene data is read-only).
  uint32_t load_cached(uint64_t addr);

  // Marks register r as holding a value of the format (the FP register file). Returns r.
  uint32_t mark_fp(uint32_t r) {
    if (r) {
      if (s_->fp.size() <= r) s_->fp.resize(r + 1, 0);
      s_->fp[r] = 1;
    }
    return r;
  }

  // Computes Stream::max_live (and per register file). Call once after the item's last instruction.
  void finish();

  // The thread whose stream TVal operations record into (nullptr: compute only).
  static Thread*& current() {
    static thread_local Thread* t = nullptr;
    return t;
  }
  class Scope {
   public:
    explicit Scope(Thread* t) : saved_(current()) { current() = t; }
    ~Scope() { current() = saved_; }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    Thread* saved_;
  };

 private:
  Stream* s_ = nullptr;
  std::unordered_map<uint64_t, uint32_t> load_cache_;
  std::vector<uint32_t> live_end_;
  bool keep_operands_ = false;
};

// ------------------------------------------------------------------ TVal
struct TVal {
  num::Soft v;
  uint32_t reg = 0;   // register holding the value (0: none)
  uint64_t addr = 0;  // scene-memory address of the value (0: an immediate when reg == 0)
};

namespace detail {
inline uint32_t use(const TVal& a) {
  if (a.reg) return a.reg;
  if (a.addr) return Thread::current()->load_cached(a.addr);
  return 0;
}
// An FP unit's operand record (kBoxIn's list above): the operands, the op code if the unit has
// op_i, the result.
inline void fp_record(Thread& t, Op op, std::initializer_list<const TVal*> src, uint64_t code, uint64_t y) {
  uint64_t w[5];
  int n = 0;
  for (const TVal* p : src) w[n++] = p->v.bits;
  if (op == Op::FAdd || op == Op::FCmp || op == Op::FFma) w[n++] = code;
  w[n++] = y;
  t.attach(w, n);
}
// code: the unit's op_i (fp_add 1 = sub; fp_cmp 3 = min, 4 = max; fp_fma 1 = a*b-c).
inline TVal result(Op op, num::Soft v, std::initializer_list<const TVal*> src, uint64_t code = 0) {
  TVal r;
  r.v = v;
  if (Thread* t = Thread::current()) {
    uint32_t s[4];
    int n = 0;
    for (const TVal* p : src) s[n++] = use(*p);
    r.reg = t->mark_fp(t->emit(op, s, n));
    if (t->keep_operands() && fp_unit_op(op)) fp_record(*t, op, src, code, v.bits);
  }
  return r;
}
// A comparison branched on: FCmp (fp_cmp op `code` on (a, b), or (b, a) when swap) + branch; the
// unit's predicate is `value`, inverted when negate (a != b branches on eq's complement).
inline bool compare(bool value, const TVal& a, const TVal& b, uint64_t code, bool swap = false, bool negate = false) {
  if (Thread* t = Thread::current()) {
    const uint32_t p = t->emit(Op::FCmp, {use(a), use(b)});
    if (t->keep_operands()) fp_record(*t, Op::FCmp, {swap ? &b : &a, swap ? &a : &b}, code, (value != negate) ? 1 : 0);
    t->emit(Op::Branch, {p}, false);
  }
  return value;
}
}  // namespace detail

inline TVal operator+(const TVal& a, const TVal& b) { return detail::result(Op::FAdd, a.v + b.v, {&a, &b}); }
inline TVal operator-(const TVal& a, const TVal& b) { return detail::result(Op::FAdd, a.v - b.v, {&a, &b}, 1); }
inline TVal operator*(const TVal& a, const TVal& b) { return detail::result(Op::FMul, a.v * b.v, {&a, &b}); }
inline TVal operator/(const TVal& a, const TVal& b) { return detail::result(Op::FDiv, a.v / b.v, {&a, &b}); }
inline TVal operator-(const TVal& a) { return detail::result(Op::Int, -a.v, {&a}); }  // sign flip
// A comparison whose result is only branched on: compare + branch.
inline bool operator<(const TVal& a, const TVal& b) { return detail::compare(a.v < b.v, a, b, 0); }
inline bool operator<=(const TVal& a, const TVal& b) { return detail::compare(a.v <= b.v, a, b, 1); }
inline bool operator>(const TVal& a, const TVal& b) { return detail::compare(a.v > b.v, a, b, 0, true); }
inline bool operator>=(const TVal& a, const TVal& b) { return detail::compare(a.v >= b.v, a, b, 1, true); }
inline bool operator==(const TVal& a, const TVal& b) { return detail::compare(a.v == b.v, a, b, 2); }
inline bool operator!=(const TVal& a, const TVal& b) { return detail::compare(a.v != b.v, a, b, 2, false, true); }

// The arithmetic vocabulary of the golden models and the renderer (found by ADL).
inline uint64_t fp_bits(const TVal& x) { return x.v.bits; }
inline bool fp_isnan(const TVal& x) { return num::fp_isnan(x.v); }
inline double fp_to_double(const TVal& x) { return x.v.to_double(); }
inline TVal fp_canon(const TVal& x) { return x; }
inline TVal fp_abs(const TVal& x) { return detail::result(Op::Int, num::fp_abs(x.v), {&x}); }  // clear sign bit
inline TVal fp_min(const TVal& a, const TVal& b) { return detail::result(Op::FCmp, num::fp_min(a.v, b.v), {&a, &b}, 3); }
inline TVal fp_max(const TVal& a, const TVal& b) { return detail::result(Op::FCmp, num::fp_max(a.v, b.v), {&a, &b}, 4); }
inline TVal fp_fma(const TVal& a, const TVal& b, const TVal& c) {
  return detail::result(Op::FFma, render::fp_fma(a.v, b.v, c.v), {&a, &b, &c});
}
inline TVal fp_fms(const TVal& a, const TVal& b, const TVal& c) {
  return detail::result(Op::FFma, render::fp_fms(a.v, b.v, c.v), {&a, &b, &c}, 1);
}
inline TVal fp_sqrt(const TVal& x) { return detail::result(Op::FSqrt, render::fp_sqrt(x.v), {&x}); }
// floor = float->int (toward -inf) and int->float: two conversions, as render::fp_floor(Soft).
inline TVal fp_floor(const TVal& x) {
  const TVal i = detail::result(Op::Conv, x.v, {&x});
  return detail::result(Op::Conv, render::fp_floor(x.v), {&i});
}

}  // namespace ru::trax

namespace ru::num {
template <>
inline Format fp_format<ru::trax::TVal>() { return soft_format(); }
template <>
inline ru::trax::TVal fp_from_bits<ru::trax::TVal>(uint64_t b) {
  ru::trax::TVal t;
  t.v = Soft::from_bits(b);
  return t;
}
template <>
inline ru::trax::TVal fp_cast<ru::trax::TVal>(double x) {  // an immediate
  ru::trax::TVal t;
  t.v = Soft::from_double(x);
  return t;
}
}  // namespace ru::num
