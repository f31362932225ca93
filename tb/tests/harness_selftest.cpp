// rayunits tb: tests of the scoreboard harness itself, without Verilator.
//
// SoftPipe is a software DUT with the project's interface (clk_i, rst_ni, in_valid_i, a_i, b_i,
// out_valid_o, y_o, flags_o) that computes ru::num::mul with a configurable latency, and that
// can carry real DUT-side bugs: a reset that does not clear the pipeline, one extra pipeline
// stage, one flipped result bit, one dropped valid bit. The harness must accept the correct
// DUT (with an asynchronous or a synchronous reset) and report every bug.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <deque>
#include <fstream>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/tb/fp.hpp"
#include "rayunits/tb/harness.hpp"
#include "rayunits/tb/testing.hpp"
#include "rayunits/tb/vector_file.hpp"

namespace ru::tb {
namespace {

using ru::num::Format;

enum class Bug { None, NoReset, ExtraStage, FlipBit, DropValid, SyncReset };

class SoftPipe final : public Dut {
 public:
  SoftPipe(const Format& f, int stages, Bug bug, uint64_t bug_item = 0)
      : f_(f), bug_(bug), bug_item_(bug_item), depth_(stages + (bug == Bug::ExtraStage ? 1 : 0)),
        valid_(depth_, false), y_(depth_, 0), fl_(depth_, 0) {
    pm_.add("clk_i", Port(&clk_, 1));
    pm_.add("rst_ni", Port(&rst_, 1));
    pm_.add("in_valid_i", Port(&in_valid_, 1));
    pm_.add("a_i", Port(&a_, f.width()));
    pm_.add("b_i", Port(&b_, f.width()));
    pm_.add("out_valid_o", Port(&out_valid_, 1));
    pm_.add("y_o", Port(&y_out_, f.width()));
    pm_.add("flags_o", Port(&flags_out_, 5));
    for (size_t i = 0; i < valid_.size(); ++i) valid_[i] = (i * 7 + 3) % 2;  // "X" at power-up
  }
  void eval() override {
    // Bug::NoReset: the power-up reset works, later ones do not clear the pipeline.
    if (!rst_) had_reset_ = true;
    if (rst_ && had_reset_) released_ = true;
    reset_active_ = !rst_ && !(bug_ == Bug::NoReset && released_);
    if (reset_active_ && bug_ != Bug::SyncReset) std::fill(valid_.begin(), valid_.end(), false);
    if (clk_ && !last_clk_) edge();
    last_clk_ = clk_;
    const ru::num::Result r = ru::num::mul(f_, a_, b_);
    if (depth_ == 0) {
      out_valid_ = in_valid_;
      y_out_ = r.bits;
      flags_out_ = r.flags;
    } else {
      out_valid_ = valid_.back();
      y_out_ = y_.back();
      flags_out_ = fl_.back();
    }
  }
  const PortMap& ports() const override { return pm_; }
  bool trace_open(const std::string&) override { return false; }
  void trace_dump(uint64_t) override {}
  void trace_close() override {}

 private:
  void edge() {
    if (reset_active_) {  // synchronous reset (and the asynchronous one held over the edge)
      std::fill(valid_.begin(), valid_.end(), false);
      return;
    }
    if (depth_ == 0) return;
    for (int i = depth_ - 1; i > 0; --i) valid_[i] = valid_[i - 1], y_[i] = y_[i - 1], fl_[i] = fl_[i - 1];
    const ru::num::Result r = ru::num::mul(f_, a_, b_);
    bool v = in_valid_ != 0;
    uint64_t y = r.bits;
    if (v && !reset_active_) {
      if (count_ == bug_item_ && bug_ == Bug::FlipBit) y ^= 1ull << 3;
      if (count_ == bug_item_ && bug_ == Bug::DropValid) v = false;
      ++count_;
    }
    valid_[0] = v;
    y_[0] = y;
    fl_[0] = r.flags;
  }
  Format f_;
  Bug bug_;
  uint64_t bug_item_;
  int depth_;
  std::vector<bool> valid_;
  std::vector<uint64_t> y_;
  std::vector<uint8_t> fl_;
  uint8_t clk_ = 0, last_clk_ = 0, rst_ = 1, in_valid_ = 0, out_valid_ = 0, flags_out_ = 0;
  uint64_t a_ = 0, b_ = 0, y_out_ = 0;
  uint64_t count_ = 0;
  bool had_reset_ = false, released_ = false, reset_active_ = false;
  PortMap pm_;
};

// n random e5m10 fp_mul vectors through a software DUT; o: test name, traffic, reset rate, ...
RunStats run_mul(Dut& dut, int stages, uint64_t n, RunOptions o) {
  const Format f = Format::parse("e5m10");
  FpAdapter ad(*fp_unit_spec("fp_mul"), f, stages);
  auto src = fp_random_source(*fp_unit_spec("fp_mul"), f, 11, n);
  o.seed = 5;
  o.stages = stages;
  o.quiet = true;
  return run(dut, ad, *src, o);
}

RunStats run_soft(int stages, Bug bug, uint64_t n, uint32_t reset_every = 50, uint64_t bug_item = 0,
                  Traffic traffic = Traffic::Mixed) {
  SoftPipe dut(Format::parse("e5m10"), stages, bug, bug_item);
  RunOptions o;
  o.test = "soft";
  o.reset_every = reset_every;
  o.traffic = traffic;
  return run_mul(dut, stages, n, o);
}

TEST(TbHarness, CorrectDutPassesEveryLatencyAndResetStyle) {
  for (int s : {0, 1, 2, 5}) {
    for (Bug b : {Bug::None, Bug::SyncReset}) {
      const RunStats st = run_soft(s, b, 3000);
      EXPECT_TRUE(st.ok()) << "Stages " << s << ": " << (st.errors.empty() ? "" : st.errors[0].report);
      EXPECT_EQ(st.checked, 3000u);
      if (s > 0) {
        EXPECT_GT(st.dropped, 0u) << "resets never hit an in-flight result";
      }
      EXPECT_GT(st.resets, 20u);
    }
  }
}

TEST(TbHarness, ReportsStaleResultsOfADutWhoseResetKeepsItsPipeline) {
  for (int s : {1, 2, 5}) {
    const RunStats st = run_soft(s, Bug::NoReset, 3000);
    ASSERT_FALSE(st.ok()) << "Stages " << s;
    EXPECT_EQ(st.errors[0].kind, Mismatch::UnexpectedValid);
    EXPECT_NE(st.errors[0].report.find("last reset in cycle"), std::string::npos);
  }
}

TEST(TbHarness, ReportsAnExtraPipelineStage) {
  for (int s : {0, 1, 4}) {
    const RunStats st = run_soft(s, Bug::ExtraStage, 1000);
    ASSERT_FALSE(st.ok()) << "Stages " << s;
    EXPECT_EQ(st.errors[0].kind, Mismatch::MissingValid);
    EXPECT_TRUE(st.aborted);
  }
}

TEST(TbHarness, ReportsOneFlippedBitExactlyOnce) {
  const RunStats st = run_soft(3, Bug::FlipBit, 2000, 0, 1234);
  ASSERT_EQ(st.errors.size(), 1u);
  EXPECT_EQ(st.errors[0].kind, Mismatch::Data);
  EXPECT_EQ(st.errors[0].item, 1234);
  EXPECT_EQ(st.errors[0].field_mask, 1u);  // y_o only
  EXPECT_NE(st.errors[0].report.find("xor 0x0008"), std::string::npos) << st.errors[0].report;
}

TEST(TbHarness, ReportsOneDroppedValid) {
  const RunStats st = run_soft(2, Bug::DropValid, 2000, 0, 777, Traffic::BackToBack);
  ASSERT_EQ(st.errors.size(), 1u);
  EXPECT_EQ(st.errors[0].kind, Mismatch::MissingValid);
  EXPECT_EQ(st.errors[0].item, 777);
}

TEST(TbHarness, StopsAfterMaxErrorsAndReportsInputsExpectedActual) {
  Format f = Format::parse("e5m10");
  SoftPipe dut(f, 2, Bug::ExtraStage);
  FpAdapter ad(*fp_unit_spec("fp_mul"), f, 2);
  auto src = fp_random_source(*fp_unit_spec("fp_mul"), f, 3, 500);
  RunOptions o;
  o.stages = 2;
  o.max_errors = 3;
  o.quiet = true;
  o.seed = 99;
  const RunStats st = run(dut, ad, *src, o);
  ASSERT_EQ(st.errors.size(), 3u);
  EXPECT_TRUE(st.aborted);
  const std::string& r = st.errors[0].report;
  for (const char* s : {"seed=99", "fp_mul e5m10 rne", "Stages=2", "a_i = 0x", "b_i = 0x", "expected"})
    EXPECT_NE(r.find(s), std::string::npos) << s << " missing in:\n" << r;
}

// The step-wise scoreboard (the TRaX co-simulation's): caller-chosen cycles with gaps while
// nothing is in flight, caller-supplied expected outputs, context lines in the report, and the
// report cycle base.
TEST(TbScoreboard, StepWiseWithGapsSuppliedExpectationsAndContext) {
  Format f = Format::parse("e5m10");
  for (const bool plant : {false, true}) {
    SoftPipe dut(f, 3, Bug::None);
    FpAdapter ad(*fp_unit_spec("fp_mul"), f, 3);
    RunOptions o;
    o.test = "step";
    o.stages = 3;
    o.quiet = true;
    o.report_cycle_base = 100;
    o.item_context = [](int64_t item) { return "  from work item " + std::to_string(item) + "\n"; };
    Scoreboard sb(dut, ad, o);
    for (uint64_t c = 0; c < 3; ++c) sb.reset(c, true);
    auto src = fp_random_source(*fp_unit_spec("fp_mul"), f, 7, 40);
    uint64_t t = 100;  // a gap of 97 cycles: nothing is in flight
    Record in, exp;
    for (int i = 0; src->next(in); ++i) {
      ad.model(in, exp);
      if (plant && i == 17) exp.v[0] ^= 1;
      sb.cycle(t++, &in, &exp);
      if (i % 10 == 9) {  // drain, then skip ahead
        while (sb.busy()) sb.cycle(t++, nullptr);
        t += 50;
      }
    }
    while (sb.busy()) sb.cycle(t++, nullptr);
    EXPECT_EQ(sb.stats().checked, 40u);
    if (!plant) {
      EXPECT_TRUE(sb.stats().ok()) << sb.stats().errors[0].report;
      // skipping cycles with results in flight is a harness misuse, not a silent pass
      sb.cycle(t++, &in, &exp);
      EXPECT_THROW(sb.cycle(t + 5, nullptr), std::logic_error);
      continue;
    }
    ASSERT_EQ(sb.stats().errors.size(), 1u);
    const Mismatch& m = sb.stats().errors[0];
    EXPECT_EQ(m.kind, Mismatch::Data);
    EXPECT_EQ(m.item, 17);
    // item 17 is the 8th of the second group of 10, issued at 100 + 10 + 3 + 50 + 7 = 170
    EXPECT_NE(m.report.find("input #17 issued in cycle 70:"), std::string::npos) << m.report;
    EXPECT_NE(m.report.find("MISMATCH at cycle 73 "), std::string::npos) << m.report;
    EXPECT_NE(m.report.find("  from work item 17\n"), std::string::npos) << m.report;
  }
}

TEST(TbPort, WideAndNarrowPortsRoundTrip) {
  uint32_t words[6] = {};
  Port p(words, 190);
  const uint64_t in[3] = {0x0123456789abcdefull, 0xfedcba9876543210ull, ~0ull};
  p.set_words(in, 3);
  EXPECT_EQ(words[5], 0x3fffffffu);  // bits above 190 cleared
  uint64_t out[3];
  p.get_words(out);
  EXPECT_EQ(out[0], in[0]);
  EXPECT_EQ(out[1], in[1]);
  EXPECT_EQ(out[2], in[2] & ((1ull << 62) - 1));
  uint8_t b = 0;
  Port q(&b, 5);
  q.set(0xff);
  EXPECT_EQ(b, 0x1f);
  EXPECT_THROW(Port(&b, 9), std::logic_error);
}

std::string write_tmp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(TbVectorFile, ParsesOperandsOutputsAndDirectives) {
  Format f = Format::parse("e8m23");
  FpAdapter ad(*fp_unit_spec("fp_add"), f, 0);
  const std::string p = write_tmp("ok.txt",
                                  "# c\nformat e8m23\nround rne\n\nadd 1 2 -> 3 -\nsub 0x3f800000 1.5 # x\n"
                                  "add 1 2 -> ? ix\n");
  const VectorFile vf = read_vector_file(p, ad);
  EXPECT_EQ(vf.format, "e8m23");
  EXPECT_EQ(vf.round, "rne");
  ASSERT_EQ(vf.vectors.size(), 3u);
  // records in the registry's layout: a_i, b_i, op_i
  EXPECT_EQ(vf.vectors[0].in.v[0], 0x3f800000u);
  EXPECT_EQ(vf.vectors[0].out.v[0], 0x40400000u);
  EXPECT_EQ(vf.vectors[0].out_mask, 3u);
  EXPECT_EQ(vf.vectors[1].in.v[2], 1u);  // sub
  EXPECT_EQ(vf.vectors[1].in.v[1], 0x3fc00000u);
  EXPECT_EQ(vf.vectors[1].out_mask, 0u);
  EXPECT_EQ(vf.vectors[2].out_mask, 2u);
  EXPECT_EQ(vf.vectors[2].out.v[1], static_cast<uint64_t>(ru::num::kInvalid | ru::num::kInexact));
}

TEST(TbVectorFile, BadLinesGiveFileAndLine) {
  Format f = Format::parse("e8m23");
  FpAdapter ad(*fp_unit_spec("fp_mul"), f, 0);
  struct Case {
    const char* text;
    const char* msg;
  };
  for (const Case& c : {Case{"mul 1\n", ":1: mul takes 2 operands"}, Case{"\nadd 1 2\n", ":2: unknown op 'add'"},
                        Case{"mul 1 zz\n", ":1:"}, Case{"mul 1 2 -> 2\n", ":1: expected outputs"},
                        Case{"mul 1 2 -> 2 q\n", ":1: bad flags"}, Case{"mul 1 2\nformat e8m23\n", ":2: 'format' must come before"},
                        Case{"mul 0x1ffffffff 1\n", ":1:"}}) {
    const std::string p = write_tmp("bad.txt", c.text);
    try {
      read_vector_file(p, ad);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(c.msg), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "not one line: " << e.what();
    }
  }
  EXPECT_THROW(read_vector_file("/nonexistent/x.txt", ad), std::runtime_error);
}

// SoftQueue: a software DUT with a handshake (in_ready_o) and a variable latency, results in
// order -- the shape of ru_ray_tri_exact: ru::num::mul, Stages cycles, plus 5..36 more for one
// input in eight (a "side path"), at most Cap = 3 inside. Its bugs: it ignores in_ready_o (accepts
// when full), swaps two results, lets one result out a cycle early, or loses one.
enum class QBug { None, IgnoreReady, Reorder, Early, Lose, Stuck };

class SoftQueue final : public Dut {
 public:
  SoftQueue(const Format& f, int stages, QBug bug, uint64_t bug_item) : f_(f), stages_(stages), bug_(bug), bug_item_(bug_item) {
    pm_.add("clk_i", Port(&clk_, 1));
    pm_.add("rst_ni", Port(&rst_, 1));
    pm_.add("in_valid_i", Port(&in_valid_, 1));
    pm_.add("in_ready_o", Port(&in_ready_, 1));
    pm_.add("a_i", Port(&a_, f.width()));
    pm_.add("b_i", Port(&b_, f.width()));
    pm_.add("out_valid_o", Port(&out_valid_, 1));
    pm_.add("y_o", Port(&y_out_, f.width()));
    pm_.add("flags_o", Port(&flags_out_, 5));
  }
  void eval() override {
    if (!rst_) q_.clear();
    if (clk_ && !last_clk_) edge();
    last_clk_ = clk_;
    in_ready_ = q_.size() < kCap;
    out_valid_ = !q_.empty() && cyc_ >= q_.front().due && !stuck_;
    y_out_ = out_valid_ ? q_.front().y : 0;
    flags_out_ = out_valid_ ? q_.front().flags : 0;
  }
  const PortMap& ports() const override { return pm_; }
  bool trace_open(const std::string&) override { return false; }
  void trace_dump(uint64_t) override {}
  void trace_close() override {}

 private:
  static constexpr size_t kCap = 3;
  struct Item {
    uint64_t y, due;
    uint8_t flags;
  };
  void edge() {
    const bool out = !q_.empty() && cyc_ >= q_.front().due && !stuck_;
    const bool acc = rst_ && in_valid_ && (q_.size() < kCap || bug_ == QBug::IgnoreReady);
    if (rst_ && out) q_.pop_front();
    if (acc) {
      const ru::num::Result r = ru::num::mul(f_, a_, b_);
      const uint64_t extra = (a_ & 7) == 0 ? 5 + (a_ >> 3) % 32 : 0;
      Item it{r.bits, cyc_ + static_cast<uint64_t>(stages_) + extra, r.flags};
      const bool bug_now = count_++ == bug_item_;
      if (bug_now && bug_ == QBug::Stuck) stuck_ = true;  // no result ever leaves again
      if (bug_now && bug_ == QBug::Early) it.due -= 1;
      if (bug_now && bug_ == QBug::Reorder && !q_.empty()) {
        q_.insert(q_.end() - 1, it);
      } else if (!(bug_now && bug_ == QBug::Lose)) {
        q_.push_back(it);
      }
      // in order: nothing leaves before the one ahead of it
      for (size_t i = 1; i < q_.size(); ++i) q_[i].due = std::max(q_[i].due, q_[i - 1].due + 1);
    }
    ++cyc_;
  }
  Format f_;
  int stages_;
  QBug bug_;
  uint64_t bug_item_;
  std::deque<Item> q_;
  uint64_t cyc_ = 0, count_ = 0;
  bool stuck_ = false;
  uint8_t clk_ = 0, last_clk_ = 0, rst_ = 1, in_valid_ = 0, in_ready_ = 0, out_valid_ = 0, flags_out_ = 0;
  uint64_t a_ = 0, b_ = 0, y_out_ = 0;
  PortMap pm_;
};

RunStats run_queue(int stages, QBug bug, uint64_t n, uint32_t reset_every, uint64_t bug_item = 300,
                   int max_latency = 200) {
  SoftQueue dut(Format::parse("e5m10"), stages, bug, bug_item);
  RunOptions o;
  o.test = "soft_queue";
  o.reset_every = reset_every;
  o.max_latency = max_latency;
  return run_mul(dut, stages, n, o);
}

// The scoreboard's handshake mode (results in order, latency >= Stages, at most max_latency):
// the correct queue passes, with refused inputs offered again and resets; each bug is reported.
TEST(TbHarness, HandshakeUnitInOrderWithVariableLatency) {
  for (int s : {1, 2, 4}) {
    for (uint32_t reset_every : {0u, 400u}) {
      const RunStats st = run_queue(s, QBug::None, 3000, reset_every);
      EXPECT_TRUE(st.ok()) << "Stages " << s << ": " << (st.errors.empty() ? "" : st.errors[0].report);
      EXPECT_EQ(st.checked, 3000u);
      if (reset_every) {
        EXPECT_GT(st.dropped, 0u) << "resets never hit a waiting result";
      }
    }
  }
  const RunStats ign = run_queue(2, QBug::IgnoreReady, 3000, 0);
  EXPECT_FALSE(ign.ok()) << "a DUT that accepts while in_ready_o = 0 went unnoticed";
  const RunStats reo = run_queue(2, QBug::Reorder, 3000, 0);
  ASSERT_FALSE(reo.ok()) << "swapped results went unnoticed";
  EXPECT_EQ(reo.errors[0].kind, Mismatch::Data);
  const RunStats early = run_queue(2, QBug::Early, 3000, 0, 0);  // the first input: nothing ahead of it
  ASSERT_FALSE(early.ok()) << "a result a cycle before the latency went unnoticed";
  EXPECT_EQ(early.errors[0].kind, Mismatch::UnexpectedValid);
  EXPECT_NE(early.errors[0].report.find("sooner than the latency 2"), std::string::npos) << early.errors[0].report;
  const RunStats lose = run_queue(2, QBug::Lose, 3000, 0);
  EXPECT_FALSE(lose.ok()) << "a lost result went unnoticed";
  // A unit that stops: with no latency bound the run still ends -- the inputs it never takes, or
  // (only three inputs, all taken) the results it never gives, are reported.
  const RunStats stop = run_queue(2, QBug::Stuck, 3000, 0, 10, 0);
  ASSERT_FALSE(stop.ok());
  EXPECT_EQ(stop.errors[0].kind, Mismatch::Ready);
  EXPECT_TRUE(stop.aborted);
  const RunStats stop3 = run_queue(2, QBug::Stuck, 3, 0, 0, 0);
  ASSERT_EQ(stop3.errors.size(), 3u);
  for (const Mismatch& m : stop3.errors) EXPECT_EQ(m.kind, Mismatch::MissingValid);
  EXPECT_NE(stop3.errors[0].report.find("without its result"), std::string::npos);
}

TEST(TbOptions, ParsesAndRejects) {
  {
    char a0[] = "tb", a1[] = "--seed=42", a2[] = "--gtest_filter=x", a3[] = "--vectors=7";
    char* argv[] = {a0, a1, a2, a3, nullptr};
    int argc = 4;
    ASSERT_TRUE(parse_options(argc, argv));
    EXPECT_EQ(argc, 2);
    EXPECT_EQ(std::string(argv[1]), "--gtest_filter=x");
    EXPECT_EQ(global_options().seed, 42u);
    EXPECT_EQ(global_options().vectors, 7);
  }
  for (const char* bad : {"--seed=abc", "--seed=-1", "--vectors=", "--max-errors=0", "--frobnicate", "--trace=3"}) {
    char a0[] = "tb";
    std::string s = bad;
    char* argv[] = {a0, s.data(), nullptr};
    int argc = 2;
    EXPECT_FALSE(parse_options(argc, argv)) << bad;
  }
  global_options() = GlobalOptions{};
}

}  // namespace
}  // namespace ru::tb
