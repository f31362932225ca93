// The TRaX timing model: a SystemC clock drives one clocked process that steps every thread
// multiprocessor once per cycle (rules in rayunits/trax/sim.hpp and docs/TRAX.md).
#include "rayunits/trax/sim.hpp"

#include <systemc>

#include <algorithm>
#include <chrono>
#include <memory>
#include <cmath>
#include <cstdio>
#include <unordered_map>

#include "rayunits/noise/texture.hpp"
#include "rayunits/synth/units.hpp"

namespace ru::trax {

const char* op_name(Op op) {
  static const char* const n[kOps] = {"fadd", "fmul", "fdiv", "fsqrt", "fcmp", "ffma", "conv", "int", "branch", "box",
                                      "tri",  "noise", "texture", "load", "ldlocal", "stlocal", "store", "atomic"};
  return n[static_cast<int>(op)];
}

uint32_t Thread::load_cached(uint64_t addr) {
  auto it = load_cache_.find(addr);
  if (it != load_cache_.end()) return it->second;
  const uint32_t r = mark_fp(load(addr));  // a scene value of the format
  load_cache_.emplace(addr, r);
  return r;
}

void Thread::finish() {
  // Live range of a register: from its definition to its last use (a value never used is live
  // in its defining instruction only). max_live = the most ranges covering one instruction.
  Stream& s = *s_;
  const uint32_t n = s.nregs;
  live_end_.assign(n, 0);
  std::vector<uint32_t>& end = live_end_;
  for (uint32_t i = 0; i < s.code.size(); ++i) {
    const Instr& in = s.code[i];
    for (uint32_t k = 0; k < in.nsrc; ++k) end[s.srcs[in.src + k]] = i;
    if (in.dst && end[in.dst] < i) end[in.dst] = i;
  }
  // delta[k][i]: +1 at definition, -1 after the last use, per register file k (0 integer, 1 FP;
  // register 1, the item, is an integer live from 0).
  auto is_fp = [&](uint32_t r) { return r < s.fp.size() && s.fp[r]; };
  std::vector<int32_t> delta[2];
  for (auto& d : delta) d.assign(s.code.size() + 1, 0);
  if (!s.code.empty()) {
    delta[0][0] += 1;
    delta[0][end[1] + 1] -= 1;
  }
  for (uint32_t i = 0; i < s.code.size(); ++i) {
    const Instr& in = s.code[i];
    if (!in.dst) continue;
    auto& d = delta[is_fp(in.dst) ? 1 : 0];
    d[i] += 1;
    d[end[in.dst] + 1] -= 1;
  }
  int32_t live[2] = {0, 0}, best[3] = {0, 0, 0};
  for (size_t i = 0; i < s.code.size(); ++i) {
    for (int k = 0; k < 2; ++k) {
      live[k] += delta[k][i];
      best[k] = std::max(best[k], live[k]);
    }
    best[2] = std::max(best[2], live[0] + live[1]);
  }
  s.max_live_int = static_cast<uint32_t>(best[0]);
  s.max_live_fp = static_cast<uint32_t>(best[1]);
  s.max_live = static_cast<uint32_t>(best[2]);
}

namespace {

struct Cache {
  struct Line {
    uint64_t tag = ~0ull;  // line address
    uint64_t ready = 0;    // cycle the data is there
    uint64_t lru = 0;
  };
  CacheCfg cfg;
  uint64_t sets = 1;
  std::vector<Line> lines;
  uint64_t tick = 0;
  explicit Cache(const CacheCfg& c) : cfg(c) {
    sets = c.size / (static_cast<uint64_t>(c.line) * c.ways);
    lines.resize(sets * c.ways);
  }
  // The way holding line address la, or nullptr.
  Line* find(uint64_t la) {
    Line* set = &lines[(la & (sets - 1)) * cfg.ways];
    for (int w = 0; w < cfg.ways; ++w)
      if (set[w].tag == la) {
        set[w].lru = ++tick;
        return &set[w];
      }
    return nullptr;
  }
  Line* alloc(uint64_t la, uint64_t ready) {
    Line* set = &lines[(la & (sets - 1)) * cfg.ways];
    Line* victim = &set[0];
    for (int w = 1; w < cfg.ways; ++w)
      if (set[w].lru < victim->lru) victim = &set[w];
    victim->tag = la;
    victim->ready = ready;
    victim->lru = ++tick;
    return victim;
  }
};

struct TP {
  Stream s;
  size_t pc = 0;
  uint64_t item = 0;
  bool active = false, halted = false;
  std::vector<uint64_t> ready;
  std::vector<uint8_t> from_mem;
};

struct TM {
  std::vector<TP> tps;
  Cache l1;
  std::array<int, kUnits> used{};
  std::vector<uint8_t> bank_used;
  std::vector<uint64_t> texture_free;  // per texture unit: the first cycle it accepts a request
  TM(int n, const CacheCfg& c, int textures) : tps(n), l1(c), bank_used(c.banks, 0), texture_free(textures, 0) {}
};

class Machine {
 public:
  Machine(const Config& c, WorkSource& w, IssueObserver* obs)
      : cfg_(c), work_(w), obs_(obs), l2_(c.l2), l2_free_(c.l2.banks, 0) {
    th_.set_keep_operands(obs != nullptr);
    tms_.reserve(c.tms);
    for (int i = 0; i < c.tms; ++i) tms_.emplace_back(c.tps_per_tm, c.l1, c.unit(Unit::Texture).count);
    for (int u = 0; u < kUnits; ++u) cap_[u] = c.units[u].count * c.units[u].width;
    texture_root_ = static_cast<int>(  // ru_texture's RootStages (the registry default)
        synth::param_value(synth::find_unit("texture"), synth::UnitConfig{}, "RootStages"));
    items_ = w.items();
    st.items = items_;
    running_ = c.threads();
  }

  int texture_root_ = 0;
  bool done() const { return running_ == 0; }
  bool stopped() const { return obs_ && obs_->failed(); }
  uint64_t next_item() const { return next_item_; }

  void cycle(uint64_t now) {
    atomic_used_ = false;
    const int n = cfg_.tms;
    for (int k = 0; k < n; ++k) step((now + k) % n, now);
  }

  SimStats st;

 private:
  uint64_t load(TM& tm, uint64_t addr, uint64_t now) {
    const uint64_t la1 = addr / cfg_.l1.line;
    ++st.l1.accesses;
    if (Cache::Line* l = tm.l1.find(la1)) {
      if (l->ready <= now + cfg_.l1.latency) {
        ++st.l1.hits;
        return now + cfg_.l1.latency;
      }
      ++st.l1.pending_hits;
      return l->ready;
    }
    ++st.l1.misses;
    const uint64_t t1 = now + cfg_.l1.latency;
    const uint64_t la2 = addr / cfg_.l2.line;
    uint64_t& bank_free = l2_free_[la2 % cfg_.l2.banks];
    const uint64_t start = std::max(t1, bank_free);
    bank_free = start + 1;
    ++st.l2.accesses;
    uint64_t ready;
    if (Cache::Line* l = l2_.find(la2)) {
      if (l->ready <= start + cfg_.l2.latency) {
        ++st.l2.hits;
        ready = start + cfg_.l2.latency;
      } else {
        ++st.l2.pending_hits;
        ready = l->ready;
      }
    } else {
      ++st.l2.misses;
      const uint64_t t2 = start + cfg_.l2.latency;
      const double transfer = double(cfg_.l2.line) / cfg_.dram_bytes_per_cycle;
      const double begin = std::max(double(t2), dram_free_);
      dram_free_ = begin + transfer;
      ready = static_cast<uint64_t>(std::ceil(begin + transfer)) + cfg_.dram_latency;
      st.dram_read_bytes += cfg_.l2.line;
      l2_.alloc(la2, ready);
    }
    tm.l1.alloc(la1, ready);
    return ready;
  }

  void step(uint64_t tm_index, uint64_t now) {
    TM& tm = tms_[tm_index];
    tm.used.fill(0);
    std::fill(tm.bank_used.begin(), tm.bank_used.end(), 0);
    const int n = cfg_.tps_per_tm;
    for (int k = 0; k < n; ++k) {
      const uint64_t tp_index = (now + k) % n;
      TP& p = tm.tps[tp_index];
      if (p.halted) {
        ++st.idle;
        continue;
      }
      if (!p.active) {  // next work item: the atomic increment
        if (atomic_used_) {
          ++st.stall_contention;
          continue;
        }
        atomic_used_ = true;
        ++st.instructions;
        ++st.op_count[static_cast<int>(Op::Atomic)];
        const uint64_t done_at = now + cfg_.atomic_latency;
        last_ = std::max(last_, done_at);
        if (next_item_ >= items_) {
          p.halted = true;
          --running_;
          continue;
        }
        const uint64_t item = next_item_++;
        p.item = item;
        th_.begin(&p.s);
        {
          Thread::Scope scope(&th_);
          work_.generate(item, th_);
        }
        th_.finish();
        st.max_live_registers = std::max(st.max_live_registers, p.s.max_live);
        st.max_live_fp_registers = std::max(st.max_live_fp_registers, p.s.max_live_fp);
        st.max_live_int_registers = std::max(st.max_live_int_registers, p.s.max_live_int);
        st.max_stream_length = std::max<uint64_t>(st.max_stream_length, p.s.code.size());
        p.ready.assign(p.s.nregs, 0);
        p.from_mem.assign(p.s.nregs, 0);
        p.ready[Thread::kItemReg] = done_at;
        p.from_mem[Thread::kItemReg] = 1;
        p.pc = 0;
        p.active = !p.s.code.empty();
        continue;
      }
      const Instr& in = p.s.code[p.pc];
      bool blocked = false, mem = false;
      for (uint32_t i = 0; i < in.nsrc; ++i) {
        const uint32_t r = p.s.srcs[in.src + i];
        if (p.ready[r] > now) {
          blocked = true;
          mem = mem || p.from_mem[r];
        }
      }
      if (blocked) {
        if (mem)
          ++st.stall_memory;
        else
          ++st.stall_dependency;
        continue;
      }
      const Unit u = op_unit(in.op);
      uint64_t ready;
      bool is_mem = false;
      if (u != Unit::kCount) {
        const int ui = static_cast<int>(u);
        // The texture unit: a request of n octaves occupies one of the TM's texture units for
        // K = ceil(n / width) cycles (width = its noise units) and is done K + latency cycles later.
        int tex = -1, tex_groups = 0;
        if (u == Unit::Texture) {
          for (size_t k = 0; k < tm.texture_free.size(); ++k)
            if (tm.texture_free[k] <= now) {
              tex = static_cast<int>(k);
              break;
            }
          if (tex < 0) {
            ++st.stall_contention;
            continue;
          }
          tex_groups = noise::texture_groups(std::max<int>(1, in.aux), cfg_.units[ui].width);
        } else if (tm.used[ui] >= cap_[ui]) {
          ++st.stall_contention;
          continue;
        }
        if (obs_ && (u == Unit::Box || u == Unit::Tri || u == Unit::Noise || u == Unit::Texture ||
                     (obs_->fp_units() && fp_unit_op(in.op)))) {
          UnitIssue e;
          e.cycle = now;
          e.tm = static_cast<int>(tm_index);
          e.tp = static_cast<int>(tp_index);
          e.slot = u == Unit::Texture ? tex : tm.used[ui];
          e.item = p.item;
          e.index = p.pc;
          e.op = in.op;
          e.data = in.rec ? p.s.data.data() + in.addr : nullptr;  // none: not recorded
          ++st.observed;
          obs_->issue(e);
        }
        ++tm.used[ui];
        ++st.unit_ops[ui];
        ready = now + cfg_.units[ui].latency;
        if (u == Unit::Texture) {
          tm.texture_free[tex] = now + tex_groups;
          ready += tex_groups + texture_root_;  // latency K + Stages + RootStages (rtl/ru_texture.sv)
        }
      } else {
        is_mem = true;
        switch (in.op) {
          case Op::Load: {
            uint8_t& b = tm.bank_used[(in.addr / (cfg_.l1.word_interleave ? 4 : cfg_.l1.line)) % cfg_.l1.banks];
            if (b) {
              ++st.stall_memory;
              ++st.bank_conflicts;
              continue;
            }
            b = 1;
            ready = load(tm, in.addr, now);
            break;
          }
          case Op::LoadLocal:
          case Op::StoreLocal:
            ready = now + cfg_.local_store_latency;
            break;
          case Op::Store: {
            const double bytes = cfg_.framebuffer_bytes_per_pixel;
            dram_free_ = std::max(double(now), dram_free_) + bytes / cfg_.dram_bytes_per_cycle;
            st.dram_write_bytes += cfg_.framebuffer_bytes_per_pixel;
            ready = now + 1;
            break;
          }
          default:  // Atomic inside a stream is not part of the ISA kernels may emit
            ready = now + cfg_.atomic_latency;
            break;
        }
      }
      if (in.dst) {
        p.ready[in.dst] = ready;
        p.from_mem[in.dst] = is_mem;
      }
      last_ = std::max(last_, ready);
      {
        const auto is_fp = [&](uint32_t r) { return r < p.s.fp.size() && p.s.fp[r]; };
        for (uint32_t k = 0; k < in.nsrc; ++k) ++(is_fp(p.s.srcs[in.src + k]) ? st.rf_reads_fp : st.rf_reads_int);
        if (in.dst) ++(is_fp(in.dst) ? st.rf_writes_fp : st.rf_writes_int);
      }
      ++st.instructions;
      ++st.op_count[static_cast<int>(in.op)];
      if (++p.pc == p.s.code.size()) p.active = false;
    }
  }

 public:
  uint64_t last() const { return last_; }

 private:
  const Config& cfg_;
  WorkSource& work_;
  IssueObserver* obs_ = nullptr;
  std::vector<TM> tms_;
  Cache l2_;
  std::vector<uint64_t> l2_free_;
  double dram_free_ = 0;
  std::array<int, kUnits> cap_{};
  bool atomic_used_ = false;
  uint64_t items_ = 0, next_item_ = 0, last_ = 0;
  int running_ = 0;
  Thread th_;
};

// The SystemC side: a clock and one clocked process stepping the machine.
struct Chip : sc_core::sc_module {
  sc_core::sc_clock clk;
  Machine& m;
  uint64_t now = 0;
  bool progress;
  std::chrono::steady_clock::time_point t0, last;
  SC_HAS_PROCESS(Chip);
  Chip(sc_core::sc_module_name nm, const sc_core::sc_time& period, Machine& mm, bool prog)
      : sc_core::sc_module(nm), clk("clk", period), m(mm), progress(prog) {
    SC_METHOD(tick);
    sensitive << clk.posedge_event();
    dont_initialize();
    t0 = last = std::chrono::steady_clock::now();
  }
  void tick() {
    m.cycle(now++);
    if (m.done() || m.stopped()) {
      sc_core::sc_stop();
      return;
    }
    if (progress && (now & 0xffff) == 0) {
      const auto t = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(t - last).count() >= 2.0) {
        last = t;
        std::fprintf(stderr, "trax: cycle %llu, %llu items started, %.1f s\n", (unsigned long long)now,
                     (unsigned long long)m.next_item(), std::chrono::duration<double>(t - t0).count());
      }
    }
  }
};

}  // namespace

SimStats simulate(const Config& cfg, WorkSource& work, bool progress, IssueObserver* observer) {
  cfg.validate();
  Config rc = cfg;  // "rtl" latencies resolved (areas do not matter here)
  for (Unit u : {Unit::Box, Unit::Tri, Unit::Noise, Unit::Texture})
    if (rc.unit(u).latency == kLatencyRtl) rc.unit(u).latency = rtl_latency(rc, u);
  const auto t0 = std::chrono::steady_clock::now();
  // A fresh simulation context per run (SystemC 2.3 cannot elaborate again after sc_start), owned
  // by this call: the module is destroyed while its context is current, then the context itself,
  // and the globals are reset so that nothing refers to freed memory (the next run, or any other
  // SystemC call, installs a context of its own).
  struct Context {
    sc_core::sc_simcontext* ctx = new sc_core::sc_simcontext();
    std::unique_ptr<sc_core::sc_module> top;
    Context() {
      sc_core::sc_curr_simcontext = ctx;
      sc_core::sc_default_global_context = ctx;
    }
    ~Context() {
      top.reset();
      delete ctx;
      sc_core::sc_curr_simcontext = nullptr;
      sc_core::sc_default_global_context = nullptr;
    }
  } context;
  sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
  Machine m(rc, work, observer);
  // SystemC's clock period; cycles do not depend on it (an unresolved "sta" clock: 1 ns)
  const double ps = std::max(2.0, std::round(1e6 / (rc.clock_mhz > 0 ? rc.clock_mhz : 1000.0)));
  context.top = std::make_unique<Chip>("trax", sc_core::sc_time(ps, sc_core::SC_PS), m, progress);
  sc_core::sc_start();
  SimStats st = m.st;
  st.stopped = m.stopped();
  st.cycles = m.last();
  st.host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return st;
}

}  // namespace ru::trax
