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

// Drives a Scoreboard from a VectorSource: traffic, random and forced resets, re-issue of what
// a reset dropped, the drain at the end, progress lines.
class Runner {
 public:
  Runner(Dut& dut, UnitAdapter& ad, VectorSource& src, const RunOptions& o)
      : dut_(dut),
        src_(src),
        o_(o),
        traffic_(mix_seed(o.seed, o.test + "#traffic"), o.traffic, o.stages, o.reset_every),
        sb_(dut, ad, o) {}

  static double thread_cpu() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }

  RunStats go() {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu();
    auto last_progress = t0;
    bool tracing = !o_.trace_path.empty();
    if (tracing && !dut_.trace_open(o_.trace_path)) {
      std::cerr << "[" << o_.test << "] note: FST tracing unavailable (model built without "
                << "TRACE_FST or Dut made without trace)\n";
      tracing = false;
    }
    sb_.set_tracing(tracing);
    RunStats& st = sb_.stats();
    std::deque<Record>& replay = sb_.dropped();
    // Initial reset: 2..4 cycles (X-initialized registers must be cleared by it).
    int initial_reset = 2 + static_cast<int>(sb_.junk().below(3));
    uint64_t drain = 0, quiet = 0;  // cycles since the last input; of them with nothing in flight
    uint64_t refused = 0;           // inputs refused in a row (in_ready_o = 0)
    bool exhausted = false;
    size_t next_forced = 0;
    std::vector<uint64_t> forced = o_.reset_at;
    std::sort(forced.begin(), forced.end());

    for (uint64_t t = 0;; ++t) {
      st.cycles = t + 1;
      Action a;
      const bool initial_reset_active = initial_reset > 0;
      if (initial_reset > 0) {
        --initial_reset;
        a = kReset;
      } else if (next_forced < forced.size() && forced[next_forced] == t) {
        ++next_forced;
        a = kReset;
      } else if (exhausted) {
        a = replay.empty() ? kIdle : kValid;  // re-issue what a forced reset dropped
      } else {
        a = traffic_.next();
      }
      if (a == kReset) {
        sb_.reset(t, initial_reset_active);
      } else {
        Record in;
        const bool issued = a == kValid && fetch(in);
        if (issued) drain = quiet = 0;
        if (!issued && a == kValid) exhausted = replay.empty();  // fetch() failed: nothing left
        sb_.cycle(t, issued ? &in : nullptr);
        if (issued && !sb_.accepted()) {  // refused (in_ready_o = 0): offer it again
          replay.push_front(in);
          if (++refused > sb_.drain_limit() + 1) {  // a unit that never takes another input
            sb_.stalled(t, refused);
            break;
          }
        } else if (issued) {
          refused = 0;
        }
      }
      if (st.errors.size() >= static_cast<size_t>(o_.max_errors)) {
        st.aborted = true;
        break;
      }
      if (t >= o_.stop_after_cycle) break;
      if (exhausted && replay.empty()) {
        // a handshake unit: until every result is out (bounded), then Stages + 1 quiet cycles
        if (sb_.handshake() && sb_.busy()) {
          if (++drain > sb_.drain_limit() + 1) break;
          quiet = 0;
        } else if (++quiet > static_cast<uint64_t>(sb_.latency()) + 1) {
          break;
        }
      }
      if (o_.progress && (t & 0xffff) == 0) {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_progress > std::chrono::seconds(5)) {
          last_progress = now;
          std::cerr << "[" << o_.test << "] cycle " << t << ", " << st.issued << " issued";
          if (src_.total()) std::cerr << " of " << src_.total();
          std::cerr << ", " << st.errors.size() << " errors\n";
        }
      }
    }
    if (o_.check && !st.aborted && o_.stop_after_cycle == ~0ull) sb_.finish(st.cycles);
    if (tracing) dut_.trace_close();
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    st.cpu_seconds = thread_cpu() - c0;
    if (o_.check && !st.aborted && st.checked + st.dropped != st.issued && o_.stop_after_cycle == ~0ull) {
      // Cannot happen unless the harness itself is broken: every issued item is either checked
      // or dropped by a reset (and replayed).
      throw std::logic_error("ru::tb::run: bookkeeping error (issued != checked + dropped)");
    }
    return st;
  }

 private:
  bool fetch(Record& r) {
    std::deque<Record>& replay = sb_.dropped();
    if (!replay.empty()) {
      r = replay.front();
      replay.pop_front();
      return true;
    }
    return src_.next(r);
  }

  Dut& dut_;
  VectorSource& src_;
  const RunOptions& o_;
  TrafficGen traffic_;
  Scoreboard sb_;
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// Scoreboard

Scoreboard::Scoreboard(Dut& dut, UnitAdapter& ad, const RunOptions& o)
    : dut_(dut),
      ad_(ad),
      o_(o),
      ins_(ad.inputs()),
      outs_(ad.outputs()),
      latency_(o.stages + o.inject.latency_delta),
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
  handshake_ = pm.has("in_ready_o");
  if (handshake_) {
    in_ready_ = pm.get("in_ready_o");
    if (o.timing && o.check) timing_ = o.timing(o);
  }
}

uint64_t Scoreboard::drain_limit() const {
  if (!handshake_) return static_cast<uint64_t>(latency_);
  return o_.max_latency > 0 ? static_cast<uint64_t>(o_.max_latency) : 1000000;
}

void Scoreboard::stalled(uint64_t t, uint64_t n) {
  report(t, Slot{}, Mismatch::Ready, 0, nullptr,
         "in_ready_o = 0 in each of the last " + std::to_string(n) + " cycles that offered an input");
  st_.aborted = true;
}

void Scoreboard::finish(uint64_t t) {
  // Results that never came (a handshake unit stuck past the drain): each is a missing result,
  // up to max_errors reports (then the run counts as stopped early).
  while (!fifo_.empty()) {
    if (st_.errors.size() >= static_cast<size_t>(o_.max_errors)) {
      st_.aborted = true;
      return;
    }
    const Slot s = fifo_.front();
    fifo_.pop_front();
    --in_flight_;
    ++st_.checked;
    report(t, s, Mismatch::MissingValid, 0, nullptr,
           "the run ended " + std::to_string(t - s.cycle) + " cycles after this input was accepted, without its result");
  }
}

void Scoreboard::advance_to(uint64_t t) {
  if (t < next_) throw std::logic_error("ru::tb::Scoreboard: cycle " + std::to_string(t) + " after cycle " +
                                        std::to_string(next_ - 1));
  if (t > next_ && in_flight_ > 0)
    throw std::logic_error("ru::tb::Scoreboard: cycles skipped while results are in flight");
  next_ = t + 1;
}

void Scoreboard::drive_junk() {
  Record j;
  for (size_t i = 0; i < ins_.size(); ++i) j.v[i] = junk_.next() & ins_[i].mask();
  ad_.drive(j);
}

void Scoreboard::edge(uint64_t t) {
  clk_.set(0);
  dut_.eval();
  if (tracing_ && t >= o_.trace_from) dut_.trace_dump(10 * t);
}

void Scoreboard::reset(uint64_t t, bool initial) {
  advance_to(t);
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
      --in_flight_;
    }
  }
  for (const Slot& s : fifo_) {
    replay_.push_back(s.in);
    ++st_.dropped;
    --in_flight_;
  }
  fifo_.clear();
  if (timing_) timing_->reset();
  accepted_ = false;
  edge(t);
  clk_.set(1);
  dut_.eval();
  if (tracing_ && t >= o_.trace_from) dut_.trace_dump(10 * t + 5);
}

// The expectation of the input issued (accepted) in cycle t: its outputs from exp or the model.
void Scoreboard::expect(Slot& s, uint64_t t, const Record& in, const Record* exp) {
  s.valid = true;
  ++in_flight_;
  s.item = static_cast<int64_t>(st_.issued);
  s.cycle = t;
  s.in = in;
  if (exp)
    s.exp = *exp;
  else
    ad_.model(s.in, s.exp);
  if (s.item == o_.inject.flip_item) s.exp.v[o_.inject.flip_field] ^= 1ull << o_.inject.flip_bit;
}

// The DUT's outputs against slot s's expectation (out_valid_o is 1).
void Scoreboard::compare(uint64_t t, const Slot& s) {
  ad_.read(act_);
  uint32_t diff = 0;
  for (size_t i = 0; i < outs_.size(); ++i) {
    if (((act_.v[i] ^ s.exp.v[i]) & outs_[i].mask()) != 0) diff |= 1u << i;
  }
  if (diff) report(t, s, Mismatch::Data, diff, &act_);
}

bool Scoreboard::cycle(uint64_t t, const Record* in, const Record* exp) {
  advance_to(t);
  const size_t errors = st_.errors.size();
  if (handshake_) {
    rst_.set(1);
    if (in) {
      in_valid_.set(1);
      ad_.drive(*in);
    } else {
      in_valid_.set(0);
      drive_junk();
    }
    edge(t);
    const bool ready = in_ready_.get() != 0;
    accepted_ = in && ready;
    if (accepted_) {
      if (o_.check) {
        fifo_.emplace_back();
        expect(fifo_.back(), t, *in, exp);
      }
      ++st_.issued;
    }
    if (o_.check) check_handshake(t, ready, accepted_ ? in : nullptr);
    clk_.set(1);
    dut_.eval();
    if (tracing_ && t >= o_.trace_from) dut_.trace_dump(10 * t + 5);
    return st_.errors.size() == errors;
  }
  accepted_ = in != nullptr;
  Slot& s = ring_[t % ring_.size()];
  if (s.valid) throw std::logic_error("ru::tb::Scoreboard: a result slot was not retired");
  rst_.set(1);
  if (in) {
    in_valid_.set(1);
    ad_.drive(*in);
    if (o_.check) expect(s, t, *in, exp);
    ++st_.issued;
  } else {
    in_valid_.set(0);
    drive_junk();
  }
  edge(t);
  if (o_.check) check(t);
  clk_.set(1);
  dut_.eval();
  if (tracing_ && t >= o_.trace_from) dut_.trace_dump(10 * t + 5);
  return st_.errors.size() == errors;
}

void Scoreboard::check(uint64_t t) {
  Slot& s = ring_[(t + 1) % ring_.size()];  // the slot of cycle t - latency
  const bool dv = out_valid_.get() != 0;
  if (!s.valid) {
    if (dv) report(t, s, Mismatch::UnexpectedValid, 0, nullptr);
    return;
  }
  s.valid = false;
  --in_flight_;
  ++st_.checked;  // its result was due now (and is right or reported)
  if (!dv) {
    report(t, s, Mismatch::MissingValid, 0, nullptr);
    return;
  }
  compare(t, s);
}

void Scoreboard::check_handshake(uint64_t t, bool ready, const Record* accepted) {
  const bool dv = out_valid_.get() != 0;
  const Slot none{};
  bool reported = false;
  if (timing_) {
    const bool want_ready = timing_->ready();
    const bool want_out = timing_->step(t, accepted);
    if (dv && !want_out) {
      report(t, none, Mismatch::UnexpectedValid, 0, nullptr, "out_valid_o = 1, but the timing reference has no result in this cycle");
      reported = true;
    } else if (!dv && want_out) {
      report(t, fifo_.empty() ? none : fifo_.front(), Mismatch::MissingValid, 0, nullptr,
             "out_valid_o = 0, but the timing reference has the result of this input leave now");
      reported = true;
    }
    if (ready != want_ready && !reported)  // one report per cycle (max_errors counts cycles)
      report(t, none, Mismatch::Ready, 0, nullptr,
             "in_ready_o = " + std::to_string(ready ? 1 : 0) + ", the timing reference expects " +
                 std::to_string(want_ready ? 1 : 0));
  }
  if (!dv) {
    if (!fifo_.empty() && o_.max_latency > 0 && t - fifo_.front().cycle > static_cast<uint64_t>(o_.max_latency)) {
      const Slot s = fifo_.front();
      fifo_.pop_front();
      --in_flight_;
      ++st_.checked;
      report(t, s, Mismatch::MissingValid, 0, nullptr,
             "no result " + std::to_string(t - s.cycle) + " cycles after acceptance (the bound is " +
                 std::to_string(o_.max_latency) + ")");
    }
    return;
  }
  if (fifo_.empty()) {
    if (!reported) report(t, none, Mismatch::UnexpectedValid, 0, nullptr, "out_valid_o = 1, but no accepted input is waiting");
    return;
  }
  const Slot s = fifo_.front();
  fifo_.pop_front();
  --in_flight_;
  ++st_.checked;
  if (t - s.cycle < static_cast<uint64_t>(latency_)) {
    if (!reported)
      report(t, s, Mismatch::UnexpectedValid, 0, nullptr,
             "out_valid_o = 1 " + std::to_string(t - s.cycle) + " cycles after the oldest waiting input was accepted, " +
                 "sooner than the latency " + std::to_string(latency_));
    return;
  }
  compare(t, s);
}

std::string Scoreboard::field_line(const FieldInfo& f, uint64_t v) const {
  return hex(v & f.mask(), f.bits) + " (" + ad_.decimal(f, v & f.mask()) + ")";
}

void Scoreboard::report(uint64_t t, const Slot& s, Mismatch::Kind kind, uint32_t diff, const Record* act,
                        const std::string& why) {
  std::ostringstream os;
  const uint64_t b = o_.report_cycle_base;
  os << "[" << o_.test << "] MISMATCH at cycle " << t - b << " (trace time " << 10 * t << "): seed=" << o_.seed
     << ", " << ad_.describe();
  if (!o_.format.empty() && ad_.describe().find(o_.format) == std::string::npos) os << ", format " << o_.format;
  os << ", Stages=" << o_.stages << "\n";
  if (kind == Mismatch::Ready || (kind == Mismatch::UnexpectedValid && (!handshake_ || s.item < 0))) {
    if (why.empty()) {
      os << "  out_valid_o = 1, but no input was issued in cycle "
         << (t >= b + static_cast<uint64_t>(latency_) ? std::to_string(t - b - latency_) : std::string("< 0")) << " ("
         << latency_ << " cycles earlier" << (latency_ != o_.stages ? ", the expected latency" : "") << ")";
    } else {
      os << "  " << why;
    }
    if (last_reset_ != ~0ull) os << "; last reset in cycle " << last_reset_ - b << (kind == Mismatch::Ready ? "" : " (stale result?)");
    os << "\n  output (don't-care data shown):";
    Record a;
    ad_.read(a);
    for (size_t i = 0; i < outs_.size(); ++i) os << " " << outs_[i].name << "=" << field_line(outs_[i], a.v[i]);
    os << "\n";
  } else if (s.item < 0) {  // a handshake unit's timing reference expected a result, none is waiting
    os << "  " << why << "\n";
  } else {
    if (!why.empty()) os << "  " << why << "\n";
    os << "  input #" << s.item << " issued in cycle " << s.cycle - b << ":\n";
    if (o_.item_context) os << o_.item_context(s.item);
    for (size_t i = 0; i < ins_.size(); ++i)
      os << "    " << ins_[i].name << " = " << field_line(ins_[i], s.in.v[i]) << "\n";
    if (kind == Mismatch::MissingValid || kind == Mismatch::UnexpectedValid) {
      os << (kind == Mismatch::UnexpectedValid ? "  expected:" : "  out_valid_o = 0, but the result of that input is due now; expected:");
      for (size_t i = 0; i < outs_.size(); ++i) os << " " << outs_[i].name << "=" << field_line(outs_[i], s.exp.v[i]);
      os << "\n";
    } else {
      for (size_t i = 0; i < outs_.size(); ++i) {
        os << "    " << outs_[i].name << ": expected " << field_line(outs_[i], s.exp.v[i]) << ", actual "
           << field_line(outs_[i], act->v[i]);
        if (diff & (1u << i))
          os << "   <-- differs (xor " << hex((s.exp.v[i] ^ act->v[i]) & outs_[i].mask(), outs_[i].bits) << ")";
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

RunStats run(Dut& dut, UnitAdapter& adapter, VectorSource& src, const RunOptions& opt) {
  Runner r(dut, adapter, src, opt);
  return r.go();
}

}  // namespace ru::tb
