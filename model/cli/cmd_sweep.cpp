// `rayunits sweep`: a TOML grid of synth / study / render jobs, expanded, run on N local worker
// processes, resumable (docs/SWEEPS.md; the engine is rayunits/sweep/sweep.hpp).
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/sweep/sweep.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/interrupt.hpp"
#include "rayunits/util/process.hpp"
#include "render_common.hpp"
#include "synth_options.hpp"

namespace ru::cli {
namespace {

namespace fs = std::filesystem;

std::string sweep_help() {
  return "usage: rayunits sweep GRID.toml --out DIR [--jobs N] [--timeout S] [--force] [--dry-run]\n\n"
         "Expands the grid (TOML: `kind` and option keys; an array is an axis, a scalar a fixed value;\n"
         "docs/SWEEPS.md) to DIR/jobs.jsonl and runs every job as a `rayunits` child process (no shell)\n"
         "on N workers: one log per job in DIR/logs/, each finished job one line of DIR/results.jsonl\n"
         "(hash, parameters, status, wall time, the job's typed result) and DIR/results.csv. A job\n"
         "whose hash already has an ok row is skipped. Exit status 0: every job ok; 1: some failed or\n"
         "timed out; 2: bad grid or options (nothing written); 130: interrupted.\n\n"
         "  --out DIR      sweep directory (created; rerunning resumes it)\n"
         "  --jobs N, -j N worker processes (default 1)\n"
         "  --timeout S    kill a job after S seconds and record it as timed out\n"
         "  --force        rerun jobs that have an ok result\n"
         "  --dry-run      print the jobs (JSON Lines) and what would run; write nothing\n\n"
         "kinds and keys:\n" +
         sweep::kinds_help();
}

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("rayunits") : p.string();
}

// Each job's argv, parsed and checked by the command it runs (as far as that command can be
// checked without running it).
void check_job_argv(const sweep::Job& j) {
  if (j.kind != "synth" && j.kind != "render") return;
  std::vector<std::string> args(j.argv.begin() + 1, j.argv.end());  // the command name is argv[0]
  std::vector<char*> av;
  for (auto& a : args) av.push_back(a.data());
  av.push_back(nullptr);
  const int ac = static_cast<int>(args.size());
  if (j.kind == "synth") {
    SynthCommand sc;
    parse_synth_command(ac, av.data(), sc);
  } else {
    RenderCommand rc;
    parse_render_command(ac, av.data(), rc);
  }
}

int run_sweep_cmd(int argc, char** argv) {
  CLI::App app{"", "rayunits sweep"};
  app.formatter_fn([](const CLI::App*, std::string, CLI::AppFormatMode) { return sweep_help(); });
  std::string grid, out;
  int jobs = 1;
  double timeout = 0;
  bool force = false, dry = false;
  app.add_option("grid", grid, "the grid file")->required();
  app.add_option("--out", out, "sweep directory")->required();
  app.add_option("--jobs,-j", jobs, "worker processes")->check(CLI::Range(1, 1024));
  app.add_option("--timeout", timeout, "kill a job after S seconds")->check(CLI::PositiveNumber);
  app.add_flag("--force", force, "rerun jobs with an ok result");
  app.add_flag("--dry-run", dry, "print the jobs, run nothing");
  if (!parse_args(app, argc, argv)) return 0;

  if (!fs::is_regular_file(grid)) throw UsageError("cannot read grid file '" + grid + "'");
  const std::string text = synth::read_file(grid);
  sweep::ExpandOptions eo;
  eo.check_job = check_job_argv;
  const sweep::Expansion ex = sweep::expand_grid(text, grid, eo);  // GridError: one line, exit 2
  for (const auto& s : ex.skipped) std::fprintf(stderr, "[sweep] skipped %s\n", s.c_str());
  if (dry) {
    std::fputs(sweep::jobs_jsonl(ex.jobs).c_str(), stdout);
    std::size_t done = 0;
    for (const auto& r : sweep::read_results(out))
      for (const auto& j : ex.jobs) done += r.value("hash", "") == j.hash && r.value("status", "") == "ok";
    std::fprintf(stderr, "[sweep] %zu jobs, %zu with an ok result in %s; %zu would run\n", ex.jobs.size(), done,
                 out.c_str(), force ? ex.jobs.size() : ex.jobs.size() - done);
    return 0;
  }
  util::install_interrupt_handler();
  sweep::RunOptions ro;
  ro.dir = out;
  ro.jobs = jobs;
  ro.timeout_s = timeout;
  ro.force = force;
  ro.exe = self_exe();
  ro.grid_text = text;
  ro.progress = [](const std::string& s) {
    std::fprintf(stderr, "%s\n", s.c_str());
    std::fflush(stderr);
  };
  const sweep::RunSummary s = sweep::run_jobs(ex.jobs, ro);
  std::fprintf(stderr, "[sweep] %zu jobs: %zu ok, %zu failed, %zu skipped (ok earlier)%s; %s/results.csv\n", s.total,
               s.ok, s.failed, s.skipped,
               s.interrupted ? (", interrupted: " + std::to_string(s.not_run) + " not run").c_str() : "",
               out.c_str());
  if (s.interrupted) return 130;
  return s.failed ? 1 : 0;
}

}  // namespace

RU_COMMAND("sweep", "run a TOML grid of synth/study/render jobs on N local workers, resumable (docs/SWEEPS.md)",
           run_sweep_cmd);

}  // namespace ru::cli
