// rayunits tb: the generic cycle-by-cycle scoreboard.
//
// One harness for every RTL unit of the project. A unit plugs in through a thin UnitAdapter
// (its input and output records, how to drive/read its data ports, and its golden-model
// function); stimulus comes from a VectorSource. The harness owns the interface convention
// shared by all units: clk_i, rst_ni (active low), in_valid_i, out_valid_o, latency = Stages.
//
// Cycle t (see tb/README.md for the full contract):
//   1. drive rst_ni, in_valid_i and the data inputs (random junk when in_valid_i = 0);
//      if the input is valid, compute the model's answer now and put it in slot t of the queue;
//   2. clk_i = 0, eval: combinational outputs settle;
//   3. unless rst_ni = 0 in this cycle: out_valid_o must equal "an input was issued in cycle
//      t - Stages (and no reset since)"; if so, every output bit must equal the model's answer.
//      When nothing was issued Stages cycles earlier, out_valid_o must be 0 and the data
//      outputs are don't-care (not compared);
//   4. clk_i = 1, eval: rising edge.
// Reset (mid-stream, random, 1-3 cycles): every in-flight input is dropped from the queue (and
// re-issued later, so every vector is still checked); inputs presented while rst_ni = 0 (the
// harness drives in_valid_i randomly then) must be dropped by the DUT. Outputs are not
// compared in reset cycles; from the first cycle after reset on, a result that the queue does
// not expect (a stale one) is an error.
//
// Units with a handshake (the DUT has in_ready_o; synth::UnitSpec::handshake, ru_ray_tri_exact):
// an input is accepted in a cycle with in_valid_i && in_ready_o (a refused input is offered again
// later; while in_ready_o = 0 the harness still drives in_valid_i = 1 with it, which the DUT must
// ignore), and results leave in input order after a variable latency of at least Stages cycles.
// The queue is then a FIFO: each out_valid_o takes the oldest accepted input, whose expected
// outputs must match; out_valid_o with nothing accepted, or sooner than Stages cycles after the
// oldest input's acceptance, is UnexpectedValid; an oldest input older than opt.max_latency
// without a result is MissingValid. With a timing reference (opt.timing: the unit's cycle rules,
// e.g. tb/exact's replay of ru_ray_tri_exact's order buffer and side path), in_ready_o and
// out_valid_o are also compared with it in every cycle, so every result's cycle is checked
// exactly (Mismatch::Ready for in_ready_o).
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rayunits/tb/dut.hpp"
#include "rayunits/tb/port.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::tb {

// Small deterministic PRNG (xoshiro256**, seeded by splitmix64; rayunits/util/rng.hpp) used by
// the harness and sources. Its streams are pinned by tests/util/test_rng.cpp (RngPin.*).
class Rng : public util::Xoshiro256ss {
 public:
  using util::Xoshiro256ss::Xoshiro256ss;
  uint64_t below(uint64_t n) { return util::bounded_lemire(*this, n); }  // uniform in [0, n), n > 0
  bool chance(uint32_t num, uint32_t den) { return below(den) < num; }
};
using util::mix_seed;  // derive independent stream seeds: mix_seed(seed, salt)

constexpr int kMaxFields = 24;  // per input or output record; each field is at most 64 bits

struct Record {
  uint64_t v[kMaxFields];
};

enum class FieldKind : uint8_t { Hex, Float, Flags, Enum };

struct FieldInfo {
  std::string name;  // "a_i", "a0", "op_i", "y_o", ...
  int bits = 1;      // 1..64
  FieldKind kind = FieldKind::Hex;
  std::vector<std::string> enum_names;  // FieldKind::Enum: name of each value
  uint64_t mask() const { return bits >= 64 ? ~0ull : ((1ull << bits) - 1); }
};

// The per-unit part. Records hold one uint64_t per field, in the order of inputs()/outputs().
class UnitAdapter {
 public:
  virtual ~UnitAdapter() = default;
  virtual std::string describe() const = 0;  // e.g. "fp_mul e8m23 rne Stages=3"
  virtual const std::vector<FieldInfo>& inputs() const = 0;
  virtual const std::vector<FieldInfo>& outputs() const = 0;
  virtual void bind(const PortMap& ports) = 0;  // look up the data ports once
  virtual void drive(const Record& in) = 0;     // write the data input ports
  virtual void read(Record& out) = 0;           // read the data output ports
  virtual void model(const Record& in, Record& out) = 0;  // the golden model's answer
  // Human-readable value ("1.5", "-inf", "qNaN", "ix", "le"); hex is printed by the harness.
  virtual std::string decimal(const FieldInfo& f, uint64_t v) const;
  // Vector files (tb/README.md): parse "<op> <operands...>" and "<outputs...>" (after "->").
  // out_mask gets bit i set for every output field i that the file specifies ("?" = unchecked).
  virtual void parse_inputs(const std::vector<std::string>& tokens, Record& in) const;
  virtual void parse_outputs(const std::vector<std::string>& tokens, Record& out,
                             uint32_t& out_mask) const;
};

class VectorSource {
 public:
  virtual ~VectorSource() = default;
  virtual bool next(Record& in) = 0;            // false when exhausted
  virtual uint64_t total() const { return 0; }  // number of vectors if known (progress lines)
};

// A fixed list of records (vector files, the benchmark's pre-generated stream).
class ArraySource final : public VectorSource {
 public:
  explicit ArraySource(std::vector<Record> v) : own_(std::move(v)), v_(&own_) {}
  // Borrows `v` (must outlive the source).
  explicit ArraySource(const std::vector<Record>* v) : v_(v) {}
  bool next(Record& in) override {
    if (i_ >= v_->size()) return false;
    in = (*v_)[i_++];
    return true;
  }
  uint64_t total() const override { return v_->size(); }

 private:
  std::vector<Record> own_;
  const std::vector<Record>* v_;
  size_t i_ = 0;
};

enum class Traffic : uint8_t {
  Mixed,       // bursts, bubbles, random 50% and sparse stretches, long back-to-back runs
  BackToBack,  // a valid input every cycle (benchmark; pipelines stay full)
};

// Planted errors that prove the harness fails (tests/inject tests in tb/src/selftest.cpp).
struct Injection {
  int64_t flip_item = -1;  // flip one bit of the expected output of the item issued as #flip_item
  int flip_field = 0, flip_bit = 0;
  int latency_delta = 0;    // expect results Stages + latency_delta cycles after issue
  bool skip_reset = false;  // at resets: drop the expectations but leave rst_ni high (a DUT
                            // whose reset does not clear its pipeline: stale results follow)
};

// The cycle timing of a unit with a handshake, as a reference (RunOptions::timing).
class HandshakeTiming {
 public:
  virtual ~HandshakeTiming() = default;
  // in_ready_o the DUT must show in the coming cycle.
  virtual bool ready() const = 0;
  // Cycle t: `accepted` is the input the DUT accepted in it (nullptr: none). Returns whether a
  // result leaves in cycle t (out_valid_o), the oldest inside.
  virtual bool step(uint64_t t, const Record* accepted) = 0;
  virtual void reset() = 0;  // rst_ni = 0: everything inside is dropped
};

struct RunOptions {
  std::string test = "tb";  // name used in messages
  uint64_t seed = 1;
  int stages = 0;  // the DUT's latency
  Traffic traffic = Traffic::Mixed;
  uint32_t reset_every = 3000;          // mean cycles between random resets (0: none mid-stream)
  std::vector<uint64_t> reset_at;       // additional resets forced at these cycles
  int max_errors = 5;                   // stop after this many mismatches
  bool check = true;                    // false: drive only, no model, no compare (benchmark)
  std::string trace_path;               // non-empty: write an FST (Dut made with trace = true)
  uint64_t trace_from = 0;              // first cycle written to the trace
  uint64_t stop_after_cycle = ~0ull;    // end the run after this cycle (trace re-runs)
  bool progress = false;                // progress lines on stderr every few seconds
  bool quiet = false;                   // do not print mismatch reports (traced re-runs)
  std::string format;                   // printed in mismatch reports ("e8m23 rne")
  std::string rerun_hint;               // printed in mismatch reports (how to reproduce)
  // Extra report lines for the item with this issue index (where it came from: the TRaX
  // co-simulation names the cycle, TM, TP and instruction that issued it).
  std::function<std::string(int64_t item)> item_context;
  // Cycle numbers in reports are the scoreboard's cycle - report_cycle_base (the co-simulation
  // resets each instance before TRaX cycle 0 and numbers its cycles TRaX cycle + 3).
  uint64_t report_cycle_base = 0;
  Injection inject;
  // Units with a handshake (see the top of this file): the longest a result may take (0: no
  // bound), and a factory of the timing reference (empty: order and bounds only). The factory
  // gets these options (inject.latency_delta shifts the reference's latency: a planted error).
  int max_latency = 0;
  std::function<std::unique_ptr<HandshakeTiming>(const RunOptions&)> timing;
};

struct Mismatch {
  enum Kind : uint8_t { Data, MissingValid, UnexpectedValid, Ready };
  Kind kind = Data;
  uint64_t cycle = 0;        // cycle whose outputs were wrong
  int64_t item = -1;         // issue index of the expected item (-1: none expected)
  uint32_t field_mask = 0;   // Data: output fields that differ
  std::string report;        // the full multi-line report that was printed
};

struct RunStats {
  uint64_t cycles = 0, issued = 0, checked = 0, dropped = 0, resets = 0;
  double seconds = 0;      // wall clock
  double cpu_seconds = 0;  // CPU time of the calling thread (robust on a loaded machine)
  std::vector<Mismatch> errors;
  bool aborted = false;  // stopped at max_errors
  bool ok() const { return errors.empty(); }
};

// Runs the stream from `src` through `dut` until the source is exhausted (plus a drain of
// Stages+1 idle cycles) or max_errors mismatches. Prints mismatch reports on stderr.
// Built on the Scoreboard below.
RunStats run(Dut& dut, UnitAdapter& adapter, VectorSource& src, const RunOptions& opt);

// The scoreboard one cycle at a time (the cycle contract above), for a caller that decides in
// every cycle whether to reset, what to issue and, optionally, what the expected outputs are:
// run() drives it from a VectorSource and its traffic generator, the TRaX co-simulation
// (tb/trax/cosim_main.cpp) from the timing model's operation stream. Cycles are numbered by the
// caller and strictly increase; cycles may be skipped only while nothing is in flight (the
// pipeline's valid bits are all zero then, so no result can be lost or invented in them).
class Scoreboard {
 public:
  // Binds clk_i, rst_ni, in_valid_i, out_valid_o and the adapter's ports. Latency = opt.stages +
  // opt.inject.latency_delta. `opt` must outlive the scoreboard.
  Scoreboard(Dut& dut, UnitAdapter& adapter, const RunOptions& opt);

  // Cycle t with rst_ni = 0 (or held high with opt.inject.skip_reset unless `initial`): an input
  // is presented with in_valid_i = 1 (the DUT must drop it), outputs are not compared, and the
  // items in flight are dropped (their inputs appended to dropped()).
  void reset(uint64_t t, bool initial);
  // Cycle t with rst_ni = 1: issues *in (nullptr: in_valid_i = 0 and junk on the data inputs)
  // whose expected outputs are *exp (nullptr: the adapter's golden model), compares out_valid_o
  // and the outputs due in cycle t, then gives the rising edge. Returns false if the cycle
  // added a mismatch (stats().errors; printed on stderr unless opt.quiet).
  // Units with a handshake: *in is issued only if in_ready_o is high (accepted()).
  bool cycle(uint64_t t, const Record* in, const Record* exp = nullptr);

  bool busy() const { return in_flight_ > 0; }  // results still due
  bool handshake() const { return handshake_; }  // the DUT has in_ready_o
  bool accepted() const { return accepted_; }    // the last cycle() issued its input
  // Cycles a drain may take: the latency, or for a handshake unit opt.max_latency (or 10^6).
  uint64_t drain_limit() const;
  // End of a run: results of a handshake unit still missing are reported (MissingValid).
  void finish(uint64_t t);
  // run() gives up on a handshake unit that refused n inputs in a row (more than drain_limit()).
  void stalled(uint64_t t, uint64_t n);
  int latency() const { return latency_; }
  std::deque<Record>& dropped() { return replay_; }  // inputs dropped by resets, to re-issue
  RunStats& stats() { return st_; }
  Rng& junk() { return junk_; }          // the junk stream (run() also draws its reset lengths)
  void set_tracing(bool on) { tracing_ = on; }  // dump every cycle >= opt.trace_from

 private:
  struct Slot {
    bool valid = false;
    int64_t item = -1;
    uint64_t cycle = 0;
    Record in;
    Record exp;
  };
  void advance_to(uint64_t t);
  void drive_junk();
  void expect(Slot& s, uint64_t t, const Record& in, const Record* exp);
  void compare(uint64_t t, const Slot& s);
  void check(uint64_t t);
  void check_handshake(uint64_t t, bool ready, const Record* accepted);
  void edge(uint64_t t);
  std::string field_line(const FieldInfo& f, uint64_t v) const;
  void report(uint64_t t, const Slot& s, Mismatch::Kind kind, uint32_t diff, const Record* act,
              const std::string& why = "");

  Dut& dut_;
  UnitAdapter& ad_;
  const RunOptions& o_;
  const std::vector<FieldInfo>& ins_;
  const std::vector<FieldInfo>& outs_;
  int latency_;
  Rng junk_;
  Port clk_, rst_, in_valid_, out_valid_;
  std::vector<Slot> ring_;
  // handshake units: the accepted inputs in order, the optional timing reference
  bool handshake_ = false, accepted_ = false;
  Port in_ready_;
  std::deque<Slot> fifo_;
  std::unique_ptr<HandshakeTiming> timing_;
  std::deque<Record> replay_;
  Record act_;
  RunStats st_;
  uint64_t next_ = 0;  // the first cycle not yet simulated
  int in_flight_ = 0;
  bool tracing_ = false;
  uint64_t last_reset_ = ~0ull;
};


std::string hex(uint64_t v, int bits);  // "0x0003f800" with the field's digit count

}  // namespace ru::tb
