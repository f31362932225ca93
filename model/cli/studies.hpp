// The studies behind `study tri`, `study box` and `study watertight` as functions: the command
// parses its options into the Args struct and calls run_*; `rayunits report` (report_studies.cpp)
// fills the same struct and calls the same function, then builds its tables from the typed
// result. The printout (what the command prints on stdout) goes to `out`, warnings and progress
// to `err`; the files (CSV, PNG) are written as the command writes them. Errors are thrown
// (UsageError for bad arguments, as the command reports them).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "rayunits/units/study.hpp"
#include "rayunits/units/watertight.hpp"

namespace ru::cli {

// ---- study tri ------------------------------------------------------------------------------
struct TriStudyArgs {
  std::string trace_file, write_trace_file, out_dir = "study_tri", exp_text = "6:11", frac_text = "8:25",
                                            ref_dir = std::string(RU_SOURCE_DIR) + "/../shared/reference";
  size_t synthetic = 0, limit = 0;
  uint64_t seed = 1;
  double scale = 1.0, spread = 0.0;
  int max_width = 32, threads = 2, rank_exp = 0;
  bool ftz = false, no_plot = false, no_decisions = false, quiet = false;
};
struct TriStudyRun {
  units::TriStudy study;
  std::string source;  // "synthetic trace (...)" or "trace FILE"
};
// `command` is the command line the printout and the CSVs record.
TriStudyRun run_tri_study(const TriStudyArgs& a, const std::string& command, std::FILE* out, std::FILE* err);

// ---- study box ------------------------------------------------------------------------------
struct BoxStudyArgs {
  std::string trace_file, write_trace_file, csv = "study_box.csv", exp_text = "7", frac_text = "7:23", formats;
  size_t synthetic = 0, limit = 0, adversarial = 0;
  uint64_t seed = 1;
  double scale = 1.0;
  int threads = 2, max_width = 32;
  bool ftz = false, quiet = false;
};
struct BoxStudyRun {
  std::vector<units::BoxCell> cells;
  std::string source;
  size_t records = 0;
};
BoxStudyRun run_box_study(const BoxStudyArgs& a, const std::string& command, std::FILE* out, std::FILE* err);

// ---- study watertight -------------------------------------------------------------------------
struct WatertightArgs {
  std::string scene, mesh_file, format = "e8m23", tri = "robust", csv;
  size_t rays = 10000, near_vertex = 0;
  double scale = 1.0;
  uint64_t seed = 1;
  int threads = 2;
  bool tie_break = false, quiet = false;
};
struct WatertightRun {
  std::string mesh_name, format;  // format as printed (Format::name())
  units::WatertightResult result;
};
WatertightRun run_watertight_study(const WatertightArgs& a, std::FILE* out, std::FILE* err);

}  // namespace ru::cli
