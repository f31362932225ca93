// rayunits tb: Dut implementation for a Verilated model class M (included by generated glue only;
// it needs the Verilator headers and the model's VM_TRACE_FST setting).
#pragma once

#include <memory>
#include <string>

#include "rayunits/tb/dut.hpp"
#include "verilated.h"
#if VM_TRACE_FST
#include "verilated_fst_c.h"
#endif

namespace ru::tb {

template <class M>
class VerilatedDut final : public Dut {
 public:
  using Binder = void (*)(M&, PortMap&);
  VerilatedDut(const DutOptions& o, Binder bind) : ctx_(new VerilatedContext) {
    ctx_->randReset(2);  // with --x-initial unique: random initial values, seeded below
    ctx_->randSeed(static_cast<int>(o.seed % 2147483647u) + 1);
    ctx_->traceEverOn(o.trace);
    trace_ok_ = o.trace;
    model_.reset(new M(ctx_.get(), "dut"));
    bind(*model_, ports_);
  }
  ~VerilatedDut() override {
    trace_close();
    model_->final();
  }
  void eval() override { model_->eval(); }
  const PortMap& ports() const override { return ports_; }
  bool trace_open(const std::string& path) override {
#if VM_TRACE_FST
    if (!trace_ok_) return false;
    trace_close();
    fst_.reset(new VerilatedFstC);
    model_->trace(fst_.get(), 99);
    fst_->open(path.c_str());
    return fst_->isOpen();
#else
    (void)path;
    return false;
#endif
  }
  void trace_dump(uint64_t time) override {
#if VM_TRACE_FST
    if (fst_) fst_->dump(time);
#else
    (void)time;
#endif
  }
  void trace_close() override {
#if VM_TRACE_FST
    if (fst_) {
      fst_->close();
      fst_.reset();
    }
#endif
  }

 private:
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<M> model_;
  PortMap ports_;
  bool trace_ok_ = false;
#if VM_TRACE_FST
  std::unique_ptr<VerilatedFstC> fst_;
#endif
};

}  // namespace ru::tb
