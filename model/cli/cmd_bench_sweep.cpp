// `rayunits bench sweep` (issue 17 §5): the sweep engine's own speed, measured side by side in
// one run — throughput of CPU-bound jobs with 1 and 2 local workers (the speedup ratio), and the
// engine's overhead per job on trivial jobs (sweep wall time minus the jobs' own wall times).
// Jobs are `study box` runs (kind "study", one seed per job), each sweep in a fresh directory.
// Then the Verilator build cache of `rtl` jobs: one grid of scoreboard runs swept twice, each time
// in a fresh sweep directory, against one fresh cache: the hit rate of the first sweep and of the
// repeated one, and the wall time of a job that builds against one that hits.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "rayunits/sweep/sweep.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/interrupt.hpp"
#include "rayunits/util/process.hpp"

namespace ru::cli {
namespace {

namespace fs = std::filesystem;

struct SweepTime {
  double wall = 0;      // the whole run_jobs call
  double job_wall = 0;  // the sum of the jobs' own wall_s (results.jsonl)
  std::size_t jobs = 0;
};

SweepTime time_sweep(const std::string& grid, int workers, const fs::path& dir) {
  const sweep::Expansion ex = sweep::expand_grid(grid, "bench-sweep.toml");
  sweep::RunOptions ro;
  ro.dir = dir.string();
  ro.jobs = workers;
  ro.exe = util::self_exe();
  ro.heartbeat_s = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const sweep::RunSummary s = sweep::run_jobs(ex.jobs, ro);
  SweepTime t;
  t.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (s.interrupted) throw UsageError("interrupted");
  if (s.failed) throw UsageError("a benchmark job failed (logs in " + dir.string() + "/logs)");
  for (const auto& r : sweep::read_results(dir.string())) t.job_wall += r.value("wall_s", 0.0);
  t.jobs = ex.jobs.size();
  return t;
}

struct CacheFigures {
  std::size_t jobs = 0, hits_first = 0, hits_repeat = 0;
  double miss_job_s = 0, hit_job_s = 0;  // medians of the jobs' wall_s
};

// `rtl` jobs of fp_add at e4m3, Stages 0..n-1 (few vectors: the build is what is measured).
CacheFigures time_rtl_cache(int configs, const fs::path& dir) {
  std::string stages;
  for (int i = 0; i < configs; ++i) stages += (i ? ", " : "") + std::to_string(i);
  const std::string g = "kind = \"rtl\"\nunit = \"fp_add\"\nformat = \"e4m3\"\nvectors = 200\nstages = [" + stages + "]\n";
  ::setenv("RU_RTL_CACHE", (dir / "cache").c_str(), 1);  // the jobs' cache: fresh
  CacheFigures f;
  std::vector<double> miss, hit;
  for (int pass = 0; pass < 2; ++pass) {
    const fs::path d = dir / (pass ? "repeat" : "first");
    time_sweep(g, 1, d);
    for (const auto& r : sweep::read_results(d.string())) {
      const bool h = r.at("result").at(0).value("cache_hit", false);
      (pass ? f.hits_repeat : f.hits_first) += h;
      (h ? hit : miss).push_back(r.value("wall_s", 0.0));
      f.jobs += pass == 0;
    }
  }
  ::unsetenv("RU_RTL_CACHE");
  f.miss_job_s = miss.empty() ? 0 : median(miss);
  f.hit_job_s = hit.empty() ? 0 : median(hit);
  return f;
}

std::string grid(int jobs, long pairs) {
  std::string seeds;
  for (int i = 1; i <= jobs; ++i) seeds += (i > 1 ? ", " : "") + std::to_string(i);
  return "kind = \"study\"\nstudy = \"box\"\nformat = \"e5m10\"\nsynthetic = " + std::to_string(pairs) +
         "\nadversarial = 0\nthreads = 1\nseed = [" + seeds + "]\n";
}

int run_bench_sweep(int argc, char** argv) {
  CLI::App app{"Sweep engine speed: CPU-bound jobs with 1 and 2 workers (speedup), engine overhead per trivial "
               "job; medians of --repeats runs, each sweep in a fresh temporary directory"};
  int cpu_jobs = 8, trivial_jobs = 40, repeats = 3, rtl_configs = 4;
  long pairs = 300000;
  std::string json;
  app.add_option("--cpu-jobs", cpu_jobs, "CPU-bound jobs per sweep")->check(CLI::Range(2, 1000));
  app.add_option("--pairs", pairs, "ray-box pairs per CPU-bound job (300000: about 3 s here)")
      ->check(CLI::Range(1L, 100000000L));
  app.add_option("--trivial-jobs", trivial_jobs, "trivial jobs (one pair each) for the overhead")
      ->check(CLI::Range(1, 100000));
  app.add_option("--repeats", repeats, "runs of each measurement (median reported)")->check(CLI::Range(1, 100));
  app.add_option("--rtl-configs", rtl_configs,
                 "rtl jobs (fp_add e4m3 Stages 0..N-1) swept twice against a fresh build cache (0: skip)")
      ->check(CLI::Range(0, 6));
  app.add_option("--json", json, "also write the figures as JSON here");
  if (!parse_args(app, argc, argv)) return 0;
  util::install_interrupt_handler();
  synth::TempDir tmp("ru-bench-sweep");
  std::vector<double> t1, t2, speedup, over_ms, per_job_ms;
  int run = 0;
  for (int r = 0; r < repeats; ++r) {
    const SweepTime a = time_sweep(grid(cpu_jobs, pairs), 1, fs::path(tmp.path()) / ("c1_" + std::to_string(run)));
    const SweepTime b = time_sweep(grid(cpu_jobs, pairs), 2, fs::path(tmp.path()) / ("c2_" + std::to_string(run)));
    const SweepTime c = time_sweep(grid(trivial_jobs, 1), 1, fs::path(tmp.path()) / ("t_" + std::to_string(run)));
    ++run;
    t1.push_back(a.wall);
    t2.push_back(b.wall);
    speedup.push_back(a.wall / b.wall);
    over_ms.push_back(1000 * (c.wall - c.job_wall) / static_cast<double>(c.jobs));
    per_job_ms.push_back(1000 * c.wall / static_cast<double>(c.jobs));
    std::fprintf(stderr, "[bench sweep] run %d/%d: %d CPU-bound jobs 1 worker %.2f s, 2 workers %.2f s (x%.2f); "
                 "%d trivial jobs %.1f ms/job, engine overhead %.1f ms/job\n",
                 r + 1, repeats, cpu_jobs, a.wall, b.wall, a.wall / b.wall, trivial_jobs, per_job_ms.back(),
                 over_ms.back());
  }
  std::printf("CPU-bound (%d x study box %ld pairs): 1 worker median %.2f s, 2 workers median %.2f s, "
              "speedup median x%.2f (ideal x2.00; %d runs)\n",
              cpu_jobs, pairs, median(t1), median(t2), median(speedup), repeats);
  std::printf("trivial (%d x study box 1 pair): median %.1f ms/job wall, engine overhead median %.1f ms/job "
              "(wall minus the jobs' own wall time)\n",
              trivial_jobs, median(per_job_ms), median(over_ms));
  CacheFigures cf;
  if (rtl_configs > 0) {
    std::fprintf(stderr, "[bench sweep] Verilator build cache: %d rtl jobs, swept twice\n", rtl_configs);
    cf = time_rtl_cache(rtl_configs, fs::path(tmp.path()) / "rtl");
    std::printf("Verilator build cache (%zu rtl jobs, fp_add e4m3 Stages 0..%d, a fresh cache): hit rate %zu/%zu "
                "on the first sweep, %zu/%zu on the repeated sweep; job wall time median %.2f s building, "
                "%.2f s on a hit\n",
                cf.jobs, rtl_configs - 1, cf.hits_first, cf.jobs, cf.hits_repeat, cf.jobs, cf.miss_job_s,
                cf.hit_job_s);
  }
  if (!json.empty()) {
    nlohmann::ordered_json j = {{"cpu_jobs", cpu_jobs},           {"pairs", pairs},
                                {"trivial_jobs", trivial_jobs},   {"repeats", repeats},
                                {"one_worker_s", median(t1)},     {"two_workers_s", median(t2)},
                                {"speedup", median(speedup)},     {"ms_per_trivial_job", median(per_job_ms)},
                                {"overhead_ms_per_job", median(over_ms)},
                                {"rtl_jobs", cf.jobs},            {"rtl_hits_first", cf.hits_first},
                                {"rtl_hits_repeat", cf.hits_repeat}, {"rtl_miss_job_s", cf.miss_job_s},
                                {"rtl_hit_job_s", cf.hit_job_s}};
    synth::write_file_atomic(json, j.dump(1) + "\n");
  }
  return 0;
}

}  // namespace

RU_COMMAND("bench sweep",
           "sweep engine speed: 1 vs 2 workers on CPU-bound jobs, overhead per trivial job, Verilator cache hit rate",
           run_bench_sweep);

}  // namespace ru::cli
