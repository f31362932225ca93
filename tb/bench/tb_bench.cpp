// rayunits tb_bench: simulated operations per second of the Verilated scoreboard harness
// (issue 3 section 6), and what the golden-model check costs per operation.
//
//   tb_bench [--vectors=N] [--runs=R] [--seed=S] [--only=<config substring>] [--wall]
//
// For every configuration linked in (tb/CMakeLists.txt: fp_mul and fp_add e8m23, built with
// RU_TB_OPT_FAST, no tracing) and the same pre-generated random operands (OperandGen):
//   sim only      harness drives the Verilated model back to back, no model, no compare
//   checked       the same plus the golden model and the compare of every output bit
//   model only    the golden-model calls alone (no simulation)
//   mixed         checked, with the test suite's traffic (bubbles, bursts, resets)
// Each figure is the median of R runs on one core, measured in the thread's CPU time (so a
// loaded machine does not distort it; --wall for wall-clock time); the per-op check cost is
// 1/checked - 1/sim_only.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include <time.h>

#include "rayunits/tb/fp.hpp"
#include "rayunits/tb/testing.hpp"

using namespace ru::tb;

namespace {

double thread_cpu() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

bool arg_u64(const std::string& a, const char* key, uint64_t& out) {
  const std::string k = std::string("--") + key + "=";
  if (a.rfind(k, 0) != 0) return false;
  char* end = nullptr;
  out = std::strtoull(a.c_str() + k.size(), &end, 10);
  if (*end || a.size() == k.size()) {
    std::cerr << "tb_bench: error: " << a << ": expected a non-negative integer\n";
    std::exit(2);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  uint64_t n = 1000000, runs = 5, seed = 1;
  std::string only;
  bool wall = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--wall") {
      wall = true;
      continue;
    }
    if (arg_u64(a, "vectors", n) || arg_u64(a, "runs", runs) || arg_u64(a, "seed", seed)) continue;
    if (a.rfind("--only=", 0) == 0) {
      only = a.substr(7);
      continue;
    }
    std::cerr << "tb_bench: error: unknown argument '" << a
              << "' (accepted: --vectors=N --runs=R --seed=S --only=SUBSTRING --wall)\n";
    return 2;
  }
  if (n == 0 || runs == 0) {
    std::cerr << "tb_bench: error: --vectors and --runs must be at least 1\n";
    return 2;
  }
  if (registered_configs().empty()) {
    std::cerr << "tb_bench: error: no Verilated configuration was linked in (RTL missing at configure time?)\n";
    return 2;
  }
  std::printf("tb_bench: %llu vectors per run, median of %llu runs, seed %llu, one core, %s time\n",
              static_cast<unsigned long long>(n), static_cast<unsigned long long>(runs),
              static_cast<unsigned long long>(seed), wall ? "wall-clock" : "thread CPU");
  std::printf("%-22s %12s %12s %12s %12s %14s %12s\n", "configuration", "sim only", "checked", "model only",
              "check ns/op", "mixed checked", "mixed cyc/s");
  std::printf("%-22s %12s %12s %12s %12s %14s %12s\n", "", "[Mops/s]", "[Mops/s]", "[Mops/s]", "", "[Mops/s]",
              "[Mcyc/s]");
  for (const ConfigDesc& cfg : registered_configs()) {
    if (!only.empty() && cfg.full_name().find(only) == std::string::npos) continue;
    const FpUnitSpec* spec = fp_unit_spec(cfg.unit);
    if (!spec) continue;
    const ru::num::Format f = fp_format(cfg);
    const int stages = static_cast<int>(cfg.param("Stages", 0));
    std::vector<Record> recs(n);
    {
      auto src = fp_random_source(*spec, f, seed, n);
      for (auto& r : recs) src->next(r);
    }
    std::vector<double> sim, chk, mdl, mix, mixc;
    for (uint64_t r = 0; r < runs; ++r) {
      std::cerr << "tb_bench: " << cfg.full_name() << " run " << r + 1 << "/" << runs << "\n";
      for (int mode = 0; mode < 3; ++mode) {
        RunOptions o;
        o.test = "bench." + cfg.full_name();
        o.seed = seed;
        o.stages = stages;
        o.traffic = mode == 2 ? Traffic::Mixed : Traffic::BackToBack;
        o.reset_every = mode == 2 ? 3000 : 0;
        o.check = mode != 0;
        DutOptions d;
        d.seed = seed;
        auto dut = cfg.make(d);
        FpAdapter ad(*spec, f, stages);
        ArraySource src(&recs);
        const RunStats st = run(*dut, ad, src, o);
        if (!st.ok()) {
          std::cerr << "tb_bench: error: " << cfg.full_name() << ": the RTL disagrees with the model\n";
          return 1;
        }
        const double sec = wall ? st.seconds : st.cpu_seconds;
        if (mode == 0) sim.push_back(st.issued / sec);
        if (mode == 1) chk.push_back(st.checked / sec);
        if (mode == 2) mix.push_back(st.checked / sec), mixc.push_back(st.cycles / sec);
      }
      FpAdapter ad(*spec, f, stages);
      Record out;
      uint64_t sink = 0;
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = thread_cpu();
      for (const Record& rec : recs) {
        ad.model(rec, out);
        sink += out.v[0];
      }
      const double s = wall ? std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()
                            : thread_cpu() - c0;
      mdl.push_back(n / s);
      if (sink == 42) std::cerr << "";  // keep the loop
    }
    const double ms = median(sim), mc = median(chk), mm = median(mdl);
    std::printf("%-22s %12.2f %12.2f %12.2f %12.1f %14.2f %12.2f\n", cfg.full_name().c_str(), ms / 1e6, mc / 1e6,
                mm / 1e6, (1.0 / mc - 1.0 / ms) * 1e9, median(mix) / 1e6, median(mixc) / 1e6);
  }
  return 0;
}
