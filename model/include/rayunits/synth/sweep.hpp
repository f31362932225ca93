// rayunits: synthesis sweeps (`rayunits synth-sweep`): a grid of (unit, format, stages) points run
// by the sweep engine (rayunits/sweep/sweep.hpp) as `rayunits synth` jobs, collected as CSV + JSON
// and plotted (area vs fraction bits, Fmax vs stages) by synth/plot_sweep.py.
#pragma once

#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rayunits/synth/flow.hpp"

namespace ru::synth {

struct SweepOptions {
  std::vector<std::string> units = {"fp_add", "fp_mul", "fp_div"};
  std::vector<std::string> formats = {"e5m10", "e6m12", "e7m16", "e8m23"};
  // Stage counts; "max" = the unit's maximum for the format. Counts above a unit's maximum are
  // skipped for that unit (listed in the output's "skipped").
  std::vector<std::string> stages = {"0", "1", "2", "3", "4", "max"};
  std::string round = "rne";
  int jobs = 2;
  std::string out_dir;
  // Reuse the points of an earlier run in DIR/sweep (the sweep engine's results with the same
  // content hash: parameters, flow options, RTL sources, Yosys and rayunits versions).
  bool resume = false;
  bool plot = true;
  std::string python;   // empty: /usr/bin/python3 if present, else python3 on PATH
  std::string command;  // recorded in the output
  FlowOptions flow;
  std::string exe;      // the rayunits binary the points run (empty: this process's executable)
};

struct SweepPoint {
  const UnitSpec* unit;
  UnitConfig cfg;
};

// Expands the grid (validating every unit and format); points beyond a unit's stage range go to
// `skipped` as "fp_add e5m10 s9: <reason>".
std::vector<SweepPoint> sweep_points(const SweepOptions& o, std::vector<std::string>* skipped);

// One row of a sweep as typed values (what synth_sweep.csv holds for the columns the report shows).
struct SweepRow {
  std::string unit, format;  // format "" for units without one
  int stages = 0;
  std::string error;         // non-empty: the point failed; the other fields are unset
  double area_nand2 = std::nan(""), fmax_est_mhz = std::nan("");
  long reg_bits = 0;
  int depth = 0;
  bool ice40_run = false, ice40_fits = false;
  long ice40_luts = 0;
  double ice40_fmax_mhz = std::nan("");  // NaN without place and route
};
SweepRow sweep_row(const nlohmann::json& row);  // from a row of synth_sweep.json

struct SweepResult {
  int failed = 0;              // points with an error row
  std::vector<SweepRow> rows;  // in grid order (the order of synth_sweep.csv)
};

// run_sweep, also returning the rows (the report's synthesis tables are built from them).
SweepResult run_sweep_rows(const SweepOptions& o, const std::function<void(const std::string&)>& progress);

// The sweep engine's grid (TOML) of these options: kind "synth", axes unit/format/stages, the flow
// options as keys.
std::string sweep_grid(const SweepOptions& o);

// Runs the sweep, writing into o.out_dir: synth_sweep.csv, synth_sweep.json (meta + rows),
// sweep/ (the engine's directory: jobs.jsonl, results.jsonl, a log per point; --resume reuses
// its ok rows) and synth_sweep.png.
// Progress lines go to `progress` (stderr in the CLI). Returns the number of failed points.
int run_sweep(const SweepOptions& o, const std::function<void(const std::string&)>& progress);

// CSV header + one line per row (rows as produced by to_json, plus "error" rows).
std::string sweep_csv(const nlohmann::json& rows);

}  // namespace ru::synth
