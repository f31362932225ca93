// rayunits trax --cosim: the RTL co-simulation link between the timing model and the companion
// executable tb_trax_cosim (tb/trax/), which holds the Verilated RTL of the box, triangle and
// noise units (docs/TRAX.md "RTL co-simulation").
//
// The timing model runs as usual; a Client (an IssueObserver) streams every issued BOX / TRI /
// NOISE operation through a pipe to the companion: issue cycle, TM, TP, unit slot, work item,
// instruction index, operand bit patterns and the golden model's outputs. The companion drives
// the operation into the RTL instance of that (TM, unit, slot) in its issue cycle, takes the
// result at out_valid_o (which must come exactly `latency` cycles later) and compares every
// output bit with the golden outputs; the first difference ends both processes with a report
// naming cycle, TM, TP, instruction and operands.
//
// Protocol (host byte order; both ends are built from this header):
//   client -> companion (its stdin): one text line, header_line(cfg), then Records, each
//     followed by rec.nwords 64-bit words (inputs, then golden outputs: thread.hpp kBoxIn...);
//     a Record with op == kEndOp (cycle = the run's last cycle) ends the stream.
//   companion -> client (its stdout): "OK <what>\n" or "ERROR <one line>\n" after the header;
//     at the end "DONE <counts>\n" or, at the first mismatch, "MISMATCH ...\n" + report lines
//     (then it exits with status 1 without reading further).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rayunits/synth/units.hpp"
#include <sys/types.h>
#include <vector>

#include "rayunits/trax/config.hpp"
#include "rayunits/trax/sim.hpp"
#include "rayunits/util/process.hpp"

namespace ru::trax::cosim {

constexpr const char* kProtocol = "rayunits-trax-cosim 1";
constexpr uint8_t kEndOp = 0xff;

struct Record {
  uint64_t cycle;
  uint64_t item;
  uint64_t index;
  uint16_t tm, tp, slot;
  uint8_t op;  // Op::Box, Op::Tri, Op::Noise or kEndOp
  uint8_t nwords;
};
static_assert(sizeof(Record) == 32, "cosim::Record layout");

// The FP units of --cosim-fp: header key and registry unit name, chip unit class, operation; in
// the order companion_units appends them.
struct FpUnit {
  const char* name;
  Unit unit;
  uint8_t op;  // trax::Op (thread.hpp)
};
const std::vector<FpUnit>& fp_units();
// The ones a chip has: fp_fma only with chip.fma (the kernel issues FFMA only then).
std::vector<FpUnit> chip_fp_units(const Config& c);

// "rayunits-trax-cosim 1 format=e8m23 tms=4 box=plain:L:S tri=robust:L:S noise=fixed-trunc:L:S"
// (L = latency, S = issue slots per TM = count x width; cfg must be resolved: resolve_config);
// with fp (--cosim-fp) also " fp_add=fp:L:S fp_mul=fp:L:S fp_div=fp:L:S fp_sqrt=fp:L:S fp_cmp=fp:L:S"
// and, with chip.fma, " fp_fma=fp:L:S".
std::string header_line(const Config& cfg, bool fp = false);

// The RTL configurations the companion must have for this resolved chip: ray_box (OptConservative
// by chip.box), ray_tri_robust or ray_tri_mt (no tie-break, eps test or volume outputs) and
// noise_trunc or noise by chip.noise (trax::noise_unit; the widths of noise::default_config, the
// model the chip runs), each in the chip's format at its latency as Stages — what
// tb/trax/cosim_main.cpp looks for when it reads header_line(). `rayunits trax --cosim-build`
// builds exactly these (rtl::ensure_cosim).
// With fp, then fp_add, fp_mul, fp_div, fp_sqrt, fp_cmp (and fp_fma with chip.fma) in the chip's
// format at their latencies (chip_fp_units).
std::vector<std::pair<const synth::UnitSpec*, synth::UnitConfig>> companion_units(const Config& cfg, bool fp = false);

// The companion next to this rayunits binary: $RU_TRAX_COSIM if set, else
// <build>/tb/trax/tb_trax_cosim for <build>/model/cli/rayunits (from /proc/self/exe).
std::string default_executable();

struct Outcome {
  bool ok = false;
  uint64_t compared = 0;
  std::string summary;  // "DONE ..." line (ok) or the mismatch report (multi-line)
};

class Client : public IssueObserver {
 public:
  // inject >= 0: planted error for the tests: the golden result of the inject-th co-simulated
  // operation (0-based) is sent with bit 0 flipped (box t_enter, tri t, noise value).
  // fp: co-simulate the FP units too (--cosim-fp). inject_op (an Op, or -1 for any): count only
  // the operations of that class (the inject-th FFMA, say).
  Client(std::string exe, int64_t inject = -1, bool fp = false, int inject_op = -1)
      : exe_(std::move(exe)), inject_(inject), inject_op_(inject_op), fp_(fp) {}
  ~Client() override;
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Starts the companion and sends the configuration. Throws std::runtime_error with one line
  // (companion missing, or it has no RTL build for this configuration).
  void start(const Config& resolved_cfg);
  void issue(const UnitIssue& u) override;
  bool failed() const override { return failed_; }
  bool fp_units() const override { return fp_; }
  // Ends the stream (last_cycle: the run's total cycles) and collects the companion's verdict.
  Outcome finish(uint64_t last_cycle);
  const std::string& started_line() const { return ok_line_; }

 private:
  void put(const void* p, size_t n);
  void flush();
  std::string exe_;
  int64_t inject_ = -1;
  int inject_op_ = -1;
  bool fp_ = false;
  uint64_t sent_ = 0;  // operations counted for inject_ (of class inject_op_ if set)
  std::unique_ptr<util::Child> child_;  // the companion (util/process.hpp)
  int to_ = -1, from_ = -1;              // its stdin / stdout pipes (owned by child_)
  bool failed_ = false;
  std::vector<char> buf_;
  std::string ok_line_;
};

}  // namespace ru::trax::cosim
