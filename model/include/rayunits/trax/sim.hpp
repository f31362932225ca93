// rayunits trax: the cycle-by-cycle timing model (SystemC kernel), replaying the instruction
// streams recorded by kernels (thread.hpp).
//
// Timing rules (docs/TRAX.md "Timing model" is the contract the hand-computed tests follow):
//   * cycle 0 is the first clock edge. Every TP is single issue and in order: in each cycle it
//     issues at most its next instruction, and only when every source register is ready
//     (ready cycle <= now) and a slot is free on the resource the instruction needs.
//   * an instruction issued in cycle c with latency L makes its result ready in cycle c + L
//     (a dependent instruction may issue in cycle c + L).
//   * functional units: per TM and unit class, count x width issue slots per cycle; all fully
//     pipelined. TPs of a TM are served in rotating priority order: in cycle c the TP with
//     index c mod tps_per_tm goes first; TMs are visited in rotating order c mod tms (this
//     order also arbitrates the chip-wide atomic unit and the L2 banks), so runs are
//     deterministic.
//   * Atomic: one chip-wide increment per cycle, latency [atomic].latency. Each TP starts with
//     an Atomic; the returned number is its next work item (its stream follows), or, when all
//     items are handed out, the TP halts.
//   * Load: L1 bank (addr / line) mod banks must be free this cycle (one access per bank per
//     cycle), else the TP stalls (memory). L1 hit: ready at c + l1.latency (or when the line's
//     fill arrives, for a line still in flight). L1 miss: L2 request at t1 = c + l1.latency;
//     L2 bank b accepts one request per cycle: start = max(t1, free_b); hit: ready at
//     start + l2.latency; miss: DRAM request at t2 = start + l2.latency: begin =
//     max(t2, dram_free), dram_free = begin + line/bytes_per_cycle, ready = begin +
//     dram.latency + line/bytes_per_cycle. Lines are allocated at request time (LRU).
//   * LoadLocal/StoreLocal: per-TP local store, latency [local_store].latency, never contended.
//   * Store (frame buffer): issues in one cycle, bypasses the caches, occupies the DRAM channel
//     for bytes/bytes_per_cycle cycles (no result, never stalls the TP).
//   * total cycles = the latest result-ready time of any instruction (the last Atomic included).
//   * stall causes, per TP and cycle without an issue (halted TPs are idle, not stalled):
//     memory (a source produced by Load/LoadLocal/Atomic not ready, or an L1 bank conflict),
//     dependency (a source produced by a functional unit not ready), contention (sources
//     ready, no free unit slot).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rayunits/trax/config.hpp"
#include "rayunits/trax/thread.hpp"

namespace ru::trax {

// The work of a run: `items` work items; generate() records item i's stream (after the
// leading Atomic, which the timing model issues itself) into th.
class WorkSource {
 public:
  virtual ~WorkSource() = default;
  virtual uint64_t items() const = 0;
  virtual void generate(uint64_t item, Thread& th) = 0;
};

struct CacheStats {
  uint64_t accesses = 0, hits = 0, pending_hits = 0, misses = 0;
  double hit_rate() const { return accesses ? double(hits + pending_hits) / double(accesses) : 0.0; }
};

struct SimStats {
  uint64_t cycles = 0;
  uint64_t items = 0;
  uint64_t instructions = 0;  // issued, Atomics included
  std::array<uint64_t, kOps> op_count{};
  std::array<uint64_t, kUnits> unit_ops{};  // issued on each unit class (all TMs)
  uint64_t stall_dependency = 0, stall_memory = 0, stall_contention = 0, idle = 0;  // TP-cycles
  uint64_t bank_conflicts = 0;  // part of stall_memory
  CacheStats l1, l2;
  uint64_t dram_read_bytes = 0, dram_write_bytes = 0;
  // register file accesses of the issued instructions (sources read, destinations written), by
  // file (Stream::fp: the format's FP file, else the 32-bit integer file)
  uint64_t rf_reads_fp = 0, rf_reads_int = 0, rf_writes_fp = 0, rf_writes_int = 0;
  uint32_t max_live_registers = 0;  // over all streams
  uint32_t max_live_fp_registers = 0, max_live_int_registers = 0;  // per register file (Stream::fp)
  uint64_t max_stream_length = 0;
  bool stopped = false;     // an IssueObserver stopped the run (co-simulation mismatch)
  uint64_t observed = 0;    // unit operations passed to the IssueObserver
  double host_seconds = 0;  // wall clock of the simulation (functional execution included)
  // Derived
  double issue_rate(const Config& c) const {  // instructions per TP per cycle
    return cycles ? double(instructions) / (double(cycles) * c.threads()) : 0.0;
  }
  double utilisation(const Config& c, Unit u) const {
    const UnitCfg& k = c.unit(u);
    return cycles ? double(unit_ops[static_cast<int>(u)]) / (double(cycles) * c.tms * k.count * k.width) : 0.0;
  }
};

// One issued BOX / TRI / NOISE operation, as seen by an IssueObserver (RTL co-simulation).
struct UnitIssue {
  uint64_t cycle = 0;  // issue cycle
  int tm = 0, tp = 0;  // thread multiprocessor, thread processor within it
  int slot = 0;        // issue slot of the unit class in this TM and cycle: 0 .. count x width - 1
                       // (unit slot / width, lane slot % width; one RTL instance per slot)
  uint64_t item = 0;   // work item (pixel number)
  uint64_t index = 0;  // instruction index within the item's stream
  Op op = Op::Box;
  const uint64_t* data = nullptr;  // unit_inputs(op) inputs, then unit_outputs(op) golden outputs
};

// Sees every unit operation in issue order (cycle order; within a cycle in the model's
// arbitration order). Used by the RTL co-simulation (model/src/trax/cosim.cpp).
class IssueObserver {
 public:
  virtual ~IssueObserver() = default;
  virtual void issue(const UnitIssue& u) = 0;
  // Checked once per cycle: true ends the run (SimStats::stopped).
  virtual bool failed() const { return false; }
  // true: the FP units' operations (fp_add, fp_mul, fp_div, fp_sqrt, fp_cmp) are passed too
  // (--cosim-fp); each must carry its operand record (thread.hpp), else issue() sees data = null.
  virtual bool fp_units() const { return false; }
};

// Runs the timing model on a fresh SystemC simulation context (deterministic; may be called
// any number of times in one process). progress: a line on stderr every ~2 s. With an
// observer, kernels record operands of unit instructions (Thread::keep_operands) and every
// BOX / TRI / NOISE issue is passed to it.
SimStats simulate(const Config& cfg, WorkSource& work, bool progress = false, IssueObserver* observer = nullptr);

// A WorkSource for micro-kernels and tests: item i's stream is recorded by f(i, th).
class FunctionWork : public WorkSource {
 public:
  FunctionWork(uint64_t n, std::function<void(uint64_t, Thread&)> f) : n_(n), f_(std::move(f)) {}
  uint64_t items() const override { return n_; }
  void generate(uint64_t item, Thread& th) override { f_(item, th); }

 private:
  uint64_t n_;
  std::function<void(uint64_t, Thread&)> f_;
};

}  // namespace ru::trax
