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
  return "usage: rayunits sweep GRID.toml --out DIR [--jobs N] [--timeout S] [--force] [--dry-run]\n"
         "       rayunits sweep GRID.toml --emit-slurm DIR [--partition P] [--time T] [--mem M] [--cpus C]\n"
         "                                [--max-parallel K] [--timeout S]\n"
         "       rayunits sweep --run-job DIR/jobs.jsonl:INDEX [--timeout S] [--force]\n"
         "       rayunits sweep --collect DIR\n\n"
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
         "On a Slurm cluster (docs/SWEEPS.md, \"On a cluster\"):\n"
         "  --emit-slurm DIR    write DIR/jobs.jsonl and DIR/sweep.sbatch (an array, one task per job;\n"
         "                      each task runs --run-job and writes DIR/results/<index>.json); run nothing\n"
         "  --partition P, --time T, --mem M, --cpus C   the script's #SBATCH options (Slurm's syntax)\n"
         "  --max-parallel K    at most K tasks at once (--array=0-(N-1)%K)\n"
         "  --run-job FILE:INDEX  run job INDEX of the job list FILE (an array task); its row goes to\n"
         "                      results/INDEX.json beside FILE; exit 0 ok, 1 failed, 130 cancelled\n"
         "  --collect DIR       merge DIR/results/*.json into DIR/results.jsonl and results.csv, report\n"
         "                      missing and failed tasks and write DIR/rerun.sbatch for exactly those;\n"
         "                      exit 0 when every job is ok, 1 otherwise\n\n"
         "kinds and keys:\n" +
         sweep::kinds_help();
}

std::string self_exe() {
  const std::string p = util::self_exe();
  return p.empty() ? std::string("rayunits") : p;
}

// Each job's argv, parsed and checked by the command it runs (as far as that command can be
// checked without running it).
void check_job_argv(const sweep::Job& j) {
  if (j.kind != "synth" && j.kind != "render" && j.kind != "rtl") return;
  std::vector<std::string> args(j.argv.begin() + 1, j.argv.end());  // the command name is argv[0]
  std::vector<char*> av;
  for (auto& a : args) av.push_back(a.data());
  av.push_back(nullptr);
  const int ac = static_cast<int>(args.size());
  if (j.kind == "synth") {
    SynthCommand sc;
    parse_synth_command(ac, av.data(), sc);
  } else if (j.kind == "rtl") {
    RtlCommand rc;
    parse_rtl_command(ac, av.data(), rc);
  } else {
    RenderCommand rc;
    parse_render_command(ac, av.data(), rc);
  }
}

int run_task_cmd(const std::string& ref, double timeout, bool force) {
  const auto [file, index] = sweep::parse_job_ref(ref);
  util::install_interrupt_handler();  // scancel: SIGTERM stops the job; nothing is written
  sweep::RunOptions ro;
  ro.exe = self_exe();
  ro.timeout_s = timeout;
  ro.force = force;
  const sweep::TaskOutcome t = sweep::run_task(file, index, ro);
  const std::string st = t.row.value("status", "");
  const std::string where = sweep::task_result_path(fs::absolute(file).parent_path().string(), index);
  if (t.skipped)
    std::fprintf(stderr, "[sweep] job %zu (%s): ok earlier (%s; --force reruns it)\n", index,
                 t.row.value("label", "").c_str(), where.c_str());
  else if (!t.written)
    std::fprintf(stderr, "[sweep] job %zu: %s; no result written\n", index, st.c_str());
  else
    std::fprintf(stderr, "[sweep] job %zu (%s): %s%s; %s\n", index, t.row.value("label", "").c_str(), st.c_str(),
                 t.row.value("error", "").empty() ? "" : (" (" + t.row.value("error", "") + ")").c_str(),
                 where.c_str());
  if (!t.written && !t.skipped) return 130;
  return st == "ok" ? 0 : 1;
}

int collect_cmd(const std::string& dir) {
  if (!fs::is_regular_file(fs::path(dir) / "jobs.jsonl"))
    throw UsageError("--collect '" + dir + "': no jobs.jsonl there (made by --emit-slurm)");
  const sweep::CollectSummary s = sweep::collect(dir);
  for (const auto& p : s.problems) std::fprintf(stderr, "[sweep] %s\n", p.c_str());
  std::fprintf(stderr, "[sweep] collect %s: %zu jobs: %zu ok, %zu failed, %zu missing; %s/results.jsonl, results.csv\n",
               dir.c_str(), s.total, s.ok, s.failed.size(), s.missing.size(), dir.c_str());
  if (!s.rerun.empty()) {
    std::vector<std::size_t> again = s.failed;
    again.insert(again.end(), s.missing.begin(), s.missing.end());
    std::fprintf(stderr, "[sweep] rerun them: sbatch %s   (--array=%s)\n", util::shell_quote(s.rerun).c_str(),
                 sweep::array_spec(again, 0).c_str());
  }
  return s.failed.empty() && s.missing.empty() ? 0 : 1;
}

int run_sweep_cmd(int argc, char** argv) {
  CLI::App app{"", "rayunits sweep"};
  app.formatter_fn([](const CLI::App*, std::string, CLI::AppFormatMode) { return sweep_help(); });
  std::string grid, out, emit, run_job, collect_dir;
  int jobs = 1;
  double timeout = 0;
  bool force = false, dry = false;
  sweep::SlurmOptions so;
  app.add_option("grid", grid, "the grid file");
  app.add_option("--out", out, "sweep directory");
  app.add_option("--jobs,-j", jobs, "worker processes")->check(CLI::Range(1, 1024));
  app.add_option("--timeout", timeout, "kill a job after S seconds")->check(CLI::PositiveNumber);
  app.add_flag("--force", force, "rerun jobs with an ok result");
  app.add_flag("--dry-run", dry, "print the jobs, run nothing");
  auto* o_emit = app.add_option("--emit-slurm", emit, "write jobs.jsonl and sweep.sbatch");
  auto* o_run = app.add_option("--run-job", run_job, "run one job: FILE:INDEX");
  auto* o_col = app.add_option("--collect", collect_dir, "merge the array tasks' results");
  auto* o_part = app.add_option("--partition", so.partition, "Slurm partition");
  auto* o_time = app.add_option("--time", so.time, "Slurm time limit");
  auto* o_mem = app.add_option("--mem", so.mem, "Slurm memory");
  auto* o_cpus = app.add_option("--cpus", so.cpus, "Slurm CPUs per task")->check(CLI::Range(1, 100000));
  auto* o_par = app.add_option("--max-parallel", so.max_parallel, "tasks at once")->check(CLI::Range(1, 1000000));
  if (!parse_args(app, argc, argv)) return 0;

  const int modes = (o_emit->count() > 0) + (o_run->count() > 0) + (o_col->count() > 0) + !out.empty();
  if (modes != 1)
    throw UsageError("give exactly one of --out DIR, --emit-slurm DIR, --run-job FILE:INDEX, --collect DIR (see --help)");
  const bool slurm_opts = o_part->count() || o_time->count() || o_mem->count() || o_cpus->count() || o_par->count();
  if (slurm_opts && !o_emit->count())
    throw UsageError("--partition, --time, --mem, --cpus and --max-parallel go with --emit-slurm");
  if (o_run->count() || o_col->count()) {
    if (!grid.empty()) throw UsageError("--run-job and --collect take no grid file (they read DIR/jobs.jsonl)");
    if (o_col->count() && (dry || force || timeout > 0 || jobs != 1))
      throw UsageError("--collect takes no other option");
    if (o_run->count() && (dry || jobs != 1)) throw UsageError("--run-job takes --timeout and --force only");
    return o_run->count() ? run_task_cmd(run_job, timeout, force) : collect_cmd(collect_dir);
  }
  if (grid.empty()) throw UsageError("no grid file (see --help)");
  if (o_emit->count()) {
    if (dry || force || jobs != 1) throw UsageError("--emit-slurm runs nothing: no --dry-run, --force or --jobs");
    for (auto [opt, v] : {std::pair{o_part, &so.partition}, {o_time, &so.time}, {o_mem, &so.mem}})
      if (opt->count() && v->empty()) throw UsageError(opt->get_name() + " '': expected a value");
    so.exe = self_exe();
    so.timeout_s = timeout;
    try {
      sweep::check_slurm_options(so);  // before the grid: one line, nothing written
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  if (!fs::is_regular_file(grid)) throw UsageError("cannot read grid file '" + grid + "'");
  const std::string text = synth::read_file(grid);
  sweep::ExpandOptions eo;
  eo.check_job = check_job_argv;
  const sweep::Expansion ex = sweep::expand_grid(text, grid, eo);  // GridError: one line, exit 2
  for (const auto& s : ex.skipped) std::fprintf(stderr, "[sweep] skipped %s\n", s.c_str());
  if (!emit.empty()) {
    const std::string script = sweep::emit_slurm(ex.jobs, emit, so, text);
    const std::size_t n = ex.jobs.size();
    std::vector<std::size_t> all;
    for (const auto& j : ex.jobs) all.push_back(j.index);
    std::fprintf(stderr, "[sweep] %zu jobs: %s/jobs.jsonl and %s (--array=%s)\n", n, emit.c_str(), script.c_str(),
                 sweep::array_spec(all, so.max_parallel).c_str());
    if (n > 1001)
      std::fprintf(stderr, "[sweep] note: %zu tasks: Slurm's default MaxArraySize is 1001 (index 1000 at most); "
                           "check `scontrol show config | grep MaxArraySize`\n", n);
    std::fprintf(stderr, "[sweep] submit: sbatch %s; then: %s sweep --collect %s\n", util::shell_quote(script).c_str(),
                 util::shell_quote(so.exe).c_str(), util::shell_quote(emit).c_str());
    return 0;
  }
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
