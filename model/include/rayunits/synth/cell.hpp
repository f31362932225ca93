// rayunits: the standard-cell flow (`rayunits synth --flow osu018`): Yosys maps a unit onto a real
// cell library (dfflibmap + timing-driven `abc -liberty -D`), OpenSTA times the netlist. Method,
// constraints and their reasons: synth/README.md, "The cell-library flow".
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "rayunits/synth/units.hpp"

namespace ru::synth {

// Flow names `synth --flow` accepts: "generic" and the cell libraries.
const std::vector<std::string>& flow_names();
std::string flow_names_list();  // "generic, osu018, osu035, osu050"
bool is_cell_flow(const std::string& flow);
// Throws SynthError "unknown flow 'x' (flows: ...)".
void check_flow_name(const std::string& flow);

// A liberty file as the flow needs it: cell areas and which cells are sequential, read from the
// liberty itself (the `area` attribute and `ff`/`latch` groups of each `cell`).
struct CellLibrary {
  std::string name;     // osu018
  std::string liberty;  // path of the .lib
  std::string verilog;  // the library's cell models (.v), empty if absent
  std::string lef;      // .lef, empty if absent
  std::string area_unit = "um2";
  std::map<std::string, double> area;  // cell -> area (liberty units)
  std::set<std::string> flops, latches;
  std::string flop_cell = "DFFPOSX1";  // the plain rising-edge flip-flop (STA harness)
  std::string inv_cell = "INVX1";      // the FO4 inverter
};

// The library's directory: $RU_CELL_LIB_DIR/<name> if set, else /usr/share/qflow/tech/<name>
// (Debian qflow-tech-<name>). Throws SynthError naming the missing file and the package.
const CellLibrary& cell_library(const std::string& name);
// Parses a liberty file (tests use small hand-written ones).
CellLibrary parse_liberty(const std::string& name, const std::string& liberty_path);

// OpenSTA. Throws SynthError if `sta` is missing (names the Debian package opensta).
std::string sta_program(const std::string& sta);
std::string sta_version(const std::string& sta);

// The FO4 delay of the library: an inverter (inv_cell) driving four copies of itself, its input
// driven by an FO4 stage too; the mean of the rise and fall delays, from OpenSTA. Cached.
double measure_fo4_ps(const CellLibrary& lib, const std::string& sta, int timeout_s = 120);

// One STA run of a netlist that contains the unit inside the register harness (sta_harness).
struct StaPath {
  std::string start, end;  // instance names in the netlist (u_dut/... inside the unit)
  int segment = 0;         // pipeline segment of the path, 1..stages+1 (0: unknown)
  int segments = 0;        // stages + 1
  double clk_to_q_ps = 0;  // of the start register
  double logic_ps = 0;     // arrival at the end register minus clk_to_q: the unit's logic
  double setup_ps = 0;     // of the end register
  int cells = 0;           // cells on the path
};

struct StaResult {
  double period_ps = 0;  // the constraint
  double slack_ps = 0;   // worst setup slack
  double tns_ps = 0;
  StaPath path;
  // With scan_levels: register level -> the shortest period the registers of that level meet
  // (period - their worst slack). Level 0: the harness input registers; level k: the stage
  // ending there (the unit's stage k of stages + 1; run_synth checks the levels are 1..stages+1).
  std::map<int, double> level_ps;
  std::string report;  // the report_checks text (also in the work directory)
};

// Runs OpenSTA on `netlist` (top `top`, harness instance u_dut) at `period_ps`. `stages` is the
// unit's latency (for the segment numbering). Logs go to dir/<stem>.*.
// scan_levels: also time every register end point and group them by level (StaResult::stage_ps;
// one path search per end point: slower on large units).
StaResult run_sta(const CellLibrary& lib, const std::string& sta, const std::string& netlist,
                  const std::string& top, double period_ps, int stages, const std::string& dir,
                  const std::string& stem, int timeout_s, bool scan_levels = false);
// The Tcl script run_sta runs (written to dir/<stem>.tcl).
std::string sta_script(const CellLibrary& lib, const std::string& netlist, const std::string& top,
                       double period_ps, bool scan_levels = false);

// The register harness of STA: module `ru_sta_harness` with the unit's ports; every input goes
// through a flip-flop (lib.flop_cell after dfflibmap) into the unit and every output into one, so
// every path of the unit is register to register with a real clock-to-Q, load and setup time.
std::string sta_harness_verilog(const std::string& unit_top, const std::vector<Port>& ports);

// Area of a mapped module from its cell counts: total, sequential (flops and latches) and the
// rest. Throws SynthError for a cell the library does not have.
struct CellArea {
  double total = 0, seq = 0, comb = 0;
  long cells = 0, seq_cells = 0;
};
CellArea cell_area(const CellLibrary& lib, const std::map<std::string, long>& cells);

}  // namespace ru::synth
