// rayunits: checked-in synthesis rows (issue 17 §4). The report reads measured cell-flow rows
// from the repository instead of synthesizing them again, when they are current:
//   - sweeps/results/default/results.jsonl (`rayunits sweep sweeps/default.toml`: one job per
//     line, its rows under "result", its command in "argv", the binary's commit in deps.tool),
//   - synth/results/cell/*.jsonl (synth/cell/run.py: one row per line with "command" and
//     "built_from").
// A row is used only for the same wrapper top (unit, format, Stages, extra parameters,
// rounding), flow, target clock, register placement and resource sharing, and only if its
// rtl_hash equals sources_hash() of the current RTL; otherwise the caller synthesizes live.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace ru::synth {

struct CheckedInRow {
  nlohmann::json row;    // the synthesis row (synth/README.md, "Row schema")
  std::string file;      // the file it was read from (as found under the given path)
  int line = 0;          // its line in that file (1-based)
  std::string command;   // the command recorded with it
  std::string commit;    // the commit / build recorded with it ("" if the file records none)
};

// What a lookup found: a current row, or why none is usable.
struct CheckedInLookup {
  const CheckedInRow* row = nullptr;  // set: a row with the current rtl_hash
  std::string why_not;                // row == nullptr: "no checked-in row" or "stale: ..."
};

class CheckedInRows {
 public:
  // Reads the paths: a file (.jsonl), or a directory: its results.jsonl when it has one (a sweep
  // directory), else every *.jsonl directly in it. A path that does not exist is skipped.
  // Throws SynthError with one line "FILE:LINE: ..." for a malformed line (not JSON, not an
  // object, a row without unit/top/flow/stages/rtl_hash of the right type, a cell row without
  // numeric area_um2/fmax_mhz/target_clock_ps).
  static CheckedInRows load(const std::vector<std::string>& paths);

  // The row of (top, flow, target clock in ps, placement, resource sharing) whose rtl_hash is
  // `rtl_hash`; the last such row in load order if several.
  CheckedInLookup find(const std::string& top, const std::string& flow, double target_clock_ps,
                       const std::string& placement, bool share, const std::string& rtl_hash) const;

  const std::vector<CheckedInRow>& rows() const { return rows_; }
  const std::vector<std::string>& files() const { return files_; }

 private:
  std::vector<CheckedInRow> rows_;
  std::vector<std::string> files_;  // every file read, in order
};

}  // namespace ru::synth
