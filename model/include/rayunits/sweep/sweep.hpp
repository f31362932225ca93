// rayunits sweep engine (`rayunits sweep`, docs/SWEEPS.md): a TOML grid file expands to a job
// list (DIR/jobs.jsonl), a local runner executes the jobs as `rayunits` child processes (argv
// vectors through util::run_process, never a shell) on N workers, and every finished job becomes
// one whole line of DIR/results.jsonl (plus the regenerated DIR/results.csv), so an interrupted
// sweep leaves a consistent table and a rerun skips every job whose hash already has an ok row.
//
// A grid is a TOML table with a `kind` ("synth", "study" with `study = "box"|"tri"`, "render";
// `rtl` and `trax` are reserved) and keys named after the options of that command (`format`,
// `stages`, `generic_only`, ...): an array is an axis, a scalar a fixed value; the jobs are the
// product of the axes. A file holds one grid at the top level or several as [[grid]] tables.
// Every value is checked against the option it feeds (type, then the same parser/registry check
// the command uses) before anything is written; errors are one line naming the file, line and key.
#pragma once

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ru::sweep {

// A bad grid file: one line "GRID.toml:LINE: key 'format': ...". The CLI exits 2.
struct GridError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Job {
  std::size_t index = 0;    // position in the job list
  std::size_t grid = 0;     // which grid of the file ([[grid]] index; 0 for a top-level grid)
  std::string kind;         // "synth", "study box", "study tri", "render"
  nlohmann::json params;    // the job's parameters: key -> scalar (sorted keys; `param.X` for --param X=)
  nlohmann::json deps;      // what the hash covers besides params: {"tool": ..., "sources": ..., ...}
  std::string hash;         // 16 hex digits: util::fnv1a64_hex of kind + params + deps (canonical JSON)
  std::vector<std::string> argv;  // argv[0] "rayunits" (the runner substitutes its executable)
  std::string out_dir;      // relative to the sweep directory: out/<hash>
  std::string result;       // the file holding the job's typed result, relative to the sweep dir
  std::string label;        // "synth fp_add format=e5m10 stages=0" (progress lines)
};

struct ExpandOptions {
  std::string source_dir;   // the repository (default: the one rayunits was built from)
  // Identity of the rayunits code that runs the jobs (part of every hash). Empty: tool_id(source_dir).
  std::string tool;
  // Extra per-job check after the built-in ones (the CLI parses each argv as its command would);
  // throws std::exception with the message. May be empty.
  std::function<void(const Job&)> check_job;
};

struct Expansion {
  std::vector<Job> jobs;
  std::vector<std::string> skipped;  // "synth fp_add format=e5m10 stages=9: above the unit's maximum 7"
};

// "rayunits <version> model <git tree id of model/>[+<hash of its uncommitted diff>]" (without
// git: "rayunits <version> model unknown").
std::string tool_id(const std::string& source_dir);

// Parses and expands a grid. Throws GridError (one line) on any problem; `source` names the file
// in messages.
Expansion expand_grid(const std::string& toml_text, const std::string& source, const ExpandOptions& opt = {});
Expansion expand_grid_file(const std::string& path, const ExpandOptions& opt = {});

// The kinds a grid may name and their keys (docs, --help): "synth: unit format stages ...".
std::string kinds_help();

// One line of jobs.jsonl, and back (Slurm array tasks will read their job with job_from_json).
nlohmann::json job_json(const Job& j);
Job job_from_json(const nlohmann::json& j);
std::string jobs_jsonl(const std::vector<Job>& jobs);

struct RunOptions {
  std::string dir;          // the sweep directory (created)
  int jobs = 1;             // worker processes
  double timeout_s = 0;     // > 0: a job running longer is killed and recorded as timed out
  bool force = false;       // rerun jobs that have an ok result
  std::string exe;          // the rayunits executable (argv[0] of every job)
  std::string grid_text;    // copied to DIR/grid.toml ("" : not copied)
  std::function<void(const std::string&)> progress;  // one line at a time (stderr in the CLI)
  double heartbeat_s = 30;  // a status line when no job finished for that long (0: none)
  // results.csv is rewritten after a finished job at most this often (and at the end): it is
  // a view of results.jsonl, rebuilt from it at every start.
  double csv_period_s = 2;
};

struct RunSummary {
  std::size_t total = 0, skipped = 0, ok = 0, failed = 0, not_run = 0;
  bool interrupted = false;  // SIGINT/SIGTERM: the running jobs were stopped and not recorded
};

// Writes DIR/jobs.jsonl, runs every job without an ok row (all with force), appends each finished
// job's row to DIR/results.jsonl (one write + fsync per line) and rewrites DIR/results.csv (temp
// file + rename; see csv_period_s). Logs in DIR/logs/<hash>.log.
RunSummary run_jobs(const std::vector<Job>& jobs, const RunOptions& opt);

// Runs one job in DIR (its log in DIR/logs/<hash>.log, its files in DIR/out/<hash>/; opt.exe and
// opt.timeout_s apply) and returns its results.jsonl row without writing it: status "ok",
// "failed", "timeout" or "interrupted" (not recorded by run_jobs). A Slurm array task will run
// one job through this and write the row to a file of its own.
nlohmann::json run_one(const Job& job, const std::string& dir, const RunOptions& opt);

// The rows of DIR/results.jsonl, whole lines only (a torn last line is ignored), the last row
// per hash, in file order of their last appearance.
std::vector<nlohmann::json> read_results(const std::string& dir);

// The job list of a jobs.jsonl file (throws std::runtime_error naming the file and line).
std::vector<Job> read_jobs(const std::string& file);

// The rows of the directory's current grid: for each job of DIR/jobs.jsonl (in job order) its last
// row in results.jsonl, if any — what results.csv shows. results.jsonl itself keeps the rows of
// earlier grids and earlier sources too (other hashes). Without jobs.jsonl: read_results(dir).
std::vector<nlohmann::json> current_results(const std::string& dir);

// results.csv of these rows: hash, index, kind, status, wall_s, error, then every parameter, then
// every scalar field of the typed result (one CSV line per result row; a job with no result row
// gets one line).
std::string results_csv(const std::vector<nlohmann::json>& rows);

// ---- Slurm job arrays (issue 17 §2; model/src/sweep/slurm.cpp, docs/SWEEPS.md) ---------------
//
// `--emit-slurm DIR` writes DIR/jobs.jsonl and DIR/sweep.sbatch (an array of one task per job);
// each task runs `rayunits sweep --run-job DIR/jobs.jsonl:$SLURM_ARRAY_TASK_ID`, which runs that
// one job (run_one) and writes its row to DIR/results/<index>.json (temp file + rename: tasks
// never share a file). `--collect DIR` merges those rows into DIR/results.jsonl and results.csv
// (the local runner's row format and results_csv), and writes DIR/rerun.sbatch for exactly the
// missing and failed indices.

struct SlurmOptions {
  std::string exe;        // absolute path of the rayunits binary the tasks run
  std::string partition;  // --partition ("" : the cluster's default)
  std::string time;       // --time, Slurm's forms: M, M:S, H:M:S, D-H, D-H:M, D-H:M:S
  std::string mem;        // --mem: N[K|M|G|T]
  int cpus = 0;           // --cpus-per-task (0: not set)
  int max_parallel = 0;   // the %K of --array (0: no limit)
  double timeout_s = 0;   // passed to --run-job --timeout (0: none)
  std::string job_name = "rayunits-sweep";
};

// Throws std::invalid_argument with one line naming the option ("--time '1h': expected ...").
void check_slurm_options(const SlurmOptions& o);

// The --array= value for these indices: ranges ("0-3", "1,4-6"), then %K if max_parallel > 0.
std::string array_spec(std::vector<std::size_t> indices, int max_parallel);

// The text of an sbatch script for the sweep directory `dir` (absolute) and these job indices:
// #SBATCH lines, then `exec 'EXE' sweep --run-job 'DIR/jobs.jsonl':"$SLURM_ARRAY_TASK_ID"`
// (every path single-quoted with util::shell_quote).
std::string sbatch_script(const std::string& dir, const std::vector<std::size_t>& indices, const SlurmOptions& o);

// Checks the options, then writes DIR/jobs.jsonl, DIR/slurm.json (the options, for rerun.sbatch),
// DIR/grid.toml (if grid_text is not empty) and DIR/sweep.sbatch, each to a temporary file
// renamed into place, and creates DIR/results, DIR/logs and DIR/slurm (the tasks' output).
// Returns the path of sweep.sbatch.
std::string emit_slurm(const std::vector<Job>& jobs, const std::string& dir, const SlurmOptions& o,
                       const std::string& grid_text = "");

// "DIR/jobs.jsonl:3" -> the file and the index (the last ':'); throws std::invalid_argument.
std::pair<std::string, std::size_t> parse_job_ref(const std::string& ref);

// DIR/results/<index>.json for the sweep directory DIR.
std::string task_result_path(const std::string& dir, std::size_t index);

struct TaskOutcome {
  nlohmann::json row;     // the row written (or the ok row found, when skipped)
  bool skipped = false;   // an ok row of the same hash was there already (and not force)
  bool written = false;   // false: interrupted (nothing written; the task counts as missing)
};

// Runs job `index` of the job list `jobs_file` in its directory (run_one with opt.exe and
// opt.timeout_s) and writes the row to task_result_path atomically (plus "task": host and the
// SLURM_* ids, when set). An ok row of the same hash is kept unless opt.force.
TaskOutcome run_task(const std::string& jobs_file, std::size_t index, const RunOptions& opt);

struct CollectSummary {
  std::size_t total = 0, ok = 0;
  std::vector<std::size_t> failed, missing;  // job indices
  std::vector<std::string> problems;         // one line per failed / missing / unreadable task
  std::string rerun;                         // DIR/rerun.sbatch, "" when nothing is to rerun
};

// Reads DIR/jobs.jsonl and every DIR/results/<index>.json; a result that is unreadable, of
// another job (hash or index) or not an object with a status counts as failed. Rewrites
// DIR/results.jsonl (the task rows in index order, one line each) and DIR/results.csv
// (results_csv) atomically: the same input gives the same files. Writes DIR/rerun.sbatch for
// the missing and failed indices with the options of DIR/slurm.json (removes a stale one when
// there are none).
CollectSummary collect(const std::string& dir);

}  // namespace ru::sweep
