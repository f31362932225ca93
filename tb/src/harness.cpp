// rayunits tb: the generic cycle-by-cycle scoreboard (see harness.hpp and tb/README.md).
#include "rayunits/tb/harness.hpp"

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include <time.h>

namespace ru::tb {

std::string hex(uint64_t v, int bits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "0x%0*" PRIx64, (bits + 3) / 4, v);
  return buf;
}

// ---------------------------------------------------------------------------------------------
// UnitAdapter defaults

std::string UnitAdapter::decimal(const FieldInfo& f, uint64_t v) const {
  if (f.kind == FieldKind::Enum && v < f.enum_names.size()) return f.enum_names[v];
  return std::to_string(v);
}

void UnitAdapter::parse_inputs(const std::vector<std::string>&, Record&) const {
  throw std::runtime_error(describe() + ": this unit does not read vector files");
}

void UnitAdapter::parse_outputs(const std::vector<std::string>&, Record&, uint32_t&) const {
  throw std::runtime_error(describe() + ": this unit does not read vector files");
}

// ---------------------------------------------------------------------------------------------
// Traffic: which cycles carry a valid input, and when reset is asserted.

namespace {

enum Action : uint8_t { kIdle, kValid, kReset };

class TrafficGen {
 public:
  TrafficGen(uint64_t seed, Traffic mode, int stages, uint32_t reset_every)
      : rng_(seed), mode_(mode), stages_(stages), reset_every_(reset_every) {}

  Action next() {
    if (reset_left_ > 0) {
      --reset_left_;
      return kReset;
    }
    if (mode_ == Traffic::BackToBack) return kValid;
    if (reset_every_ && rng_.below(reset_every_) == 0) {
      reset_left_ = static_cast<int>(rng_.below(3));  // 1..3 reset cycles
      return kReset;
    }
    while (left_ == 0) new_segment();
    --left_;
    switch (seg_) {
      case kBurst:
      case kLongRun: return kValid;
      case kGap: return kIdle;
      case kHalf: return rng_.below(2) ? kValid : kIdle;
      case kSparse: return rng_.below(8) == 0 ? kValid : kIdle;
    }
    return kIdle;
  }

 private:
  enum Segment : uint8_t { kBurst, kGap, kHalf, kLongRun, kSparse };
  void new_segment() {
    const uint64_t r = rng_.below(100);
    if (r < 30) {
      seg_ = kBurst, left_ = 1 + rng_.below(32);
    } else if (r < 55) {
      seg_ = kGap, left_ = 1 + rng_.below(2 * static_cast<uint64_t>(stages_) + 3);
    } else if (r < 75) {
      seg_ = kHalf, left_ = 16 + rng_.below(240);
    } else if (r < 85) {
      seg_ = kLongRun, left_ = 200 + rng_.below(2800);
    } else {
      seg_ = kSparse, left_ = 16 + rng_.below(112);
    }
  }
  Rng rng_;
  Traffic mode_;
  int stages_;
  uint32_t reset_every_;
  int reset_left_ = 0;
  Segment seg_ = kGap;
  uint64_t left_ = 0;
};

struct Slot {
  bool valid = false;
  int64_t item = -1;
  uint64_t cycle = 0;
  Record in;
  Record exp;
};

class Runner {
 public:
  Runner(Dut& dut, UnitAdapter& ad, VectorSource& src, const RunOptions& o)
      : dut_(dut),
        ad_(ad),
        src_(src),
        o_(o),
        ins_(ad.inputs()),
        outs_(ad.outputs()),
        latency_(o.stages + o.inject.latency_delta),
        traffic_(mix_seed(o.seed, o.test + "#traffic"), o.traffic, o.stages, o.reset_every),
        junk_(mix_seed(o.seed, o.test + "#junk")) {
    if (latency_ < 0) throw std::invalid_argument("ru::tb::run: negative expected latency");
    if (ins_.size() > kMaxFields || outs_.size() > kMaxFields)
      throw std::invalid_argument("ru::tb::run: more than kMaxFields fields in a record");
    const PortMap& pm = dut.ports();
    clk_ = pm.get("clk_i");
    rst_ = pm.get("rst_ni");
    in_valid_ = pm.get("in_valid_i");
    out_valid_ = pm.get("out_valid_o");
    ad_.bind(pm);
    ring_.resize(static_cast<size_t>(latency_) + 1);
  }

  static double thread_cpu() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }

  RunStats go() {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu();
    auto last_progress = t0;
    tracing_ = !o_.trace_path.empty();
    if (tracing_ && !dut_.trace_open(o_.trace_path)) {
      std::cerr << "[" << o_.test << "] note: FST tracing unavailable (model built without "
                << "TRACE_FST or Dut made without trace)\n";
      tracing_ = false;
    }
    // Initial reset: 2..4 cycles (X-initialized registers must be cleared by it).
    int initial_reset = 2 + static_cast<int>(junk_.below(3));
    uint64_t drain = 0;
    bool exhausted = false;
    size_t next_forced = 0;
    std::vector<uint64_t> forced = o_.reset_at;
    std::sort(forced.begin(), forced.end());

    for (uint64_t t = 0;; ++t) {
      st_.cycles = t + 1;
      Action a;
      const bool initial_reset_active = initial_reset > 0;
      if (initial_reset > 0) {
        --initial_reset;
        a = kReset;
      } else if (next_forced < forced.size() && forced[next_forced] == t) {
        ++next_forced;
        a = kReset;
      } else if (exhausted) {
        a = replay_.empty() ? kIdle : kValid;  // re-issue what a forced reset dropped
      } else {
        a = traffic_.next();
      }
      Slot& s = ring_[t % ring_.size()];
      s.valid = false;
      if (a == kReset) {
        reset_cycle(t, initial_reset_active);
      } else {
        rst_.set(1);
        bool issued = false;
        if (a == kValid && fetch(s.in)) {
          in_valid_.set(1);
          ad_.drive(s.in);
          if (o_.check) {
            s.valid = true;
            s.item = static_cast<int64_t>(st_.issued);
            s.cycle = t;
            ad_.model(s.in, s.exp);
            if (s.item == o_.inject.flip_item) s.exp.v[o_.inject.flip_field] ^= 1ull << o_.inject.flip_bit;
          }
          ++st_.issued;
          issued = true;
          drain = 0;
        }
        if (!issued) {
          in_valid_.set(0);
          drive_junk();
          if (a == kValid) exhausted = replay_.empty();  // fetch() failed: nothing left
        }
      }
      clk_.set(0);
      dut_.eval();
      if (o_.check && a != kReset) check(t);
      if (tracing_ && t >= o_.trace_from) dut_.trace_dump(10 * t);
      clk_.set(1);
      dut_.eval();
      if (tracing_ && t >= o_.trace_from) dut_.trace_dump(10 * t + 5);

      if (st_.errors.size() >= static_cast<size_t>(o_.max_errors)) {
        st_.aborted = true;
        break;
      }
      if (t >= o_.stop_after_cycle) break;
      if (exhausted && replay_.empty()) {
        if (++drain > static_cast<uint64_t>(latency_) + 1) break;
      }
      if (o_.progress && (t & 0xffff) == 0) {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_progress > std::chrono::seconds(5)) {
          last_progress = now;
          std::cerr << "[" << o_.test << "] cycle " << t << ", " << st_.issued << " issued";
          if (src_.total()) std::cerr << " of " << src_.total();
          std::cerr << ", " << st_.errors.size() << " errors\n";
        }
      }
    }
    if (tracing_) dut_.trace_close();
    st_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    st_.cpu_seconds = thread_cpu() - c0;
    if (o_.check && !st_.aborted && st_.checked + st_.dropped != st_.issued && o_.stop_after_cycle == ~0ull) {
      // Cannot happen unless the harness itself is broken: every issued item is either checked
      // or dropped by a reset (and replayed).
      throw std::logic_error("ru::tb::run: bookkeeping error (issued != checked + dropped)");
    }
    return st_;
  }

 private:
  bool fetch(Record& r) {
    if (!replay_.empty()) {
      r = replay_.front();
      replay_.pop_front();
      return true;
    }
    return src_.next(r);
  }

  void drive_junk() {
    Record j;
    for (size_t i = 0; i < ins_.size(); ++i) j.v[i] = junk_.next() & ins_[i].mask();
    ad_.drive(j);
  }

  void reset_cycle(uint64_t t, bool initial) {
    ++st_.resets;
    if (!initial) last_reset_ = t;
    rst_.set(o_.inject.skip_reset && !initial ? 1 : 0);
    // Inputs presented while rst_ni = 0 must be dropped by the DUT: present one every cycle.
    in_valid_.set(1);
    drive_junk();
    for (Slot& s : ring_) {
      if (s.valid) {
        replay_.push_back(s.in);
        ++st_.dropped;
        s.valid = false;
      }
    }
  }

  void check(uint64_t t) {
    const Slot& s = ring_[(t + 1) % ring_.size()];  // the slot of cycle t - latency
    const bool dv = out_valid_.get() != 0;
    if (!s.valid) {
      if (dv) report(t, s, Mismatch::UnexpectedValid, 0, nullptr);
      return;
    }
    ++st_.checked;  // its result was due now (and is right or reported)
    if (!dv) {
      report(t, s, Mismatch::MissingValid, 0, nullptr);
      return;
    }
    ad_.read(act_);
    uint32_t diff = 0;
    for (size_t i = 0; i < outs_.size(); ++i) {
      if (((act_.v[i] ^ s.exp.v[i]) & outs_[i].mask()) != 0) diff |= 1u << i;
    }
    if (diff) report(t, s, Mismatch::Data, diff, &act_);
  }

  std::string field_line(const FieldInfo& f, uint64_t v) const {
    return hex(v & f.mask(), f.bits) + " (" + ad_.decimal(f, v & f.mask()) + ")";
  }

  void report(uint64_t t, const Slot& s, Mismatch::Kind kind, uint32_t diff, const Record* act) {
    std::ostringstream os;
    os << "[" << o_.test << "] MISMATCH at cycle " << t << " (trace time " << 10 * t
       << "): seed=" << o_.seed << ", " << ad_.describe();
    if (!o_.format.empty() && ad_.describe().find(o_.format) == std::string::npos) os << ", format " << o_.format;
    os << ", Stages=" << o_.stages << "\n";
    if (kind == Mismatch::UnexpectedValid) {
      os << "  out_valid_o = 1, but no input was issued in cycle "
         << (t >= static_cast<uint64_t>(latency_) ? std::to_string(t - latency_) : std::string("< 0"))
         << " (" << latency_ << " cycles earlier"
         << (latency_ != o_.stages ? ", the expected latency" : "") << ")";
      if (last_reset_ != ~0ull) os << "; last reset in cycle " << last_reset_ << " (stale result?)";
      os << "\n  output (don't-care data shown):";
      Record a;
      ad_.read(a);
      for (size_t i = 0; i < outs_.size(); ++i) os << " " << outs_[i].name << "=" << field_line(outs_[i], a.v[i]);
      os << "\n";
    } else {
      os << "  input #" << s.item << " issued in cycle " << s.cycle << ":\n";
      for (size_t i = 0; i < ins_.size(); ++i)
        os << "    " << ins_[i].name << " = " << field_line(ins_[i], s.in.v[i]) << "\n";
      if (kind == Mismatch::MissingValid) {
        os << "  out_valid_o = 0, but the result of that input is due now; expected:";
        for (size_t i = 0; i < outs_.size(); ++i) os << " " << outs_[i].name << "=" << field_line(outs_[i], s.exp.v[i]);
        os << "\n";
      } else {
        for (size_t i = 0; i < outs_.size(); ++i) {
          os << "    " << outs_[i].name << ": expected " << field_line(outs_[i], s.exp.v[i]) << ", actual "
             << field_line(outs_[i], act->v[i]);
          if (diff & (1u << i)) os << "   <-- differs (xor " << hex((s.exp.v[i] ^ act->v[i]) & outs_[i].mask(), outs_[i].bits) << ")";
          os << "\n";
        }
      }
    }
    if (!o_.rerun_hint.empty()) os << "  rerun: " << o_.rerun_hint << "\n";
    Mismatch m;
    m.kind = kind;
    m.cycle = t;
    m.item = kind == Mismatch::UnexpectedValid ? -1 : s.item;
    m.field_mask = diff;
    m.report = os.str();
    if (!o_.quiet) std::cerr << m.report << std::flush;
    st_.errors.push_back(std::move(m));
  }

  Dut& dut_;
  UnitAdapter& ad_;
  VectorSource& src_;
  const RunOptions& o_;
  const std::vector<FieldInfo>& ins_;
  const std::vector<FieldInfo>& outs_;
  int latency_;
  TrafficGen traffic_;
  Rng junk_;
  Port clk_, rst_, in_valid_, out_valid_;
  std::vector<Slot> ring_;
  std::deque<Record> replay_;
  Record act_;
  RunStats st_;
  bool tracing_ = false;
  uint64_t last_reset_ = ~0ull;
};

}  // namespace

RunStats run(Dut& dut, UnitAdapter& adapter, VectorSource& src, const RunOptions& opt) {
  Runner r(dut, adapter, src, opt);
  return r.go();
}

}  // namespace ru::tb
