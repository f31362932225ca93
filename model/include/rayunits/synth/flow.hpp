// rayunits: the open synthesis flow (Yosys 0.23, nextpnr-ice40). See synth/README.md for the
// method, the NAND2-equivalent weights and the delay model.
#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rayunits/synth/cell.hpp"
#include "rayunits/synth/units.hpp"

namespace ru::synth {

struct FlowOptions {
  // "generic" (Yosys gates: NAND2-eq, fo4-v1 estimate, plus the FPGA flows below) or a cell
  // library (osu018, osu035, osu050: liberty mapping and OpenSTA; the FPGA flows do not run).
  std::string flow = "generic";
  // Target clock periods of the cell flow in ps (abc -D and the STA clock), one result each;
  // empty: one run mapped without a delay target and timed at kUntargetedPeriodPs.
  std::vector<double> clocks_ps;
  std::string sta = "sta";      // OpenSTA
  std::string netlist_out;      // cell flow: copy the mapped unit (first clock) here; empty: no
  // Register placement (units with a SegW parameter, UnitSpec::seg_weights_param): "depth" (the
  // RTL's own depth estimates) or "delay" (a cell flow first maps the unit with every cut
  // registered and times each stage; those delays become the SegW weights of the placement).
  std::string placement = "depth";
  // Cell flow: OpenSTA also reports the period every pipeline stage needs (CellRun::stage_ps).
  bool stage_periods = false;
  std::string yosys = "yosys";  // name on PATH or a path
  std::string nextpnr = "nextpnr-ice40";
  std::string rtl_dir;                // empty: default_rtl_dir()
  bool ice40 = true;                  // synth_ice40 LUT counts
  bool xilinx = true;                 // synth_xilinx LUT/DSP counts
  bool pnr = false;                   // nextpnr-ice40 place & route for Fmax (slow)
  // Yosys resource sharing (`share`, part of `synth`). Off for units whose UnitSpec says so:
  // on the ray-triangle units its SAT search runs for hours (synth/README.md).
  bool share = true;
  std::string ice40_device = "hx8k";  // hx8k or up5k
  int timeout_s = 0;                  // per tool run, 0 = none
  bool keep_temp = false;             // keep the temp directory (path in the result)
  std::string temp_parent;            // where temp dirs go; empty: $TMPDIR or /tmp
};

// The delay model (synth/README.md): every logic level of Yosys's generic gate library costs
// kLevelFo4 FO4 delays, a pipeline register adds kFlopFo4 (clock-to-Q + setup + margin), and one
// FO4 is kFo4Ps picoseconds (a generic 65 nm-class process). Fmax = 1 / (depth*level + flop).
struct DelayModel {
  static constexpr double kFo4Ps = 25.0;
  static constexpr double kLevelFo4 = 1.5;
  static constexpr double kFlopFo4 = 4.0;
  static constexpr const char* kName = "fo4-v1";
  static double stage_ps(int depth) { return (depth * kLevelFo4 + kFlopFo4) * kFo4Ps; }
  static double fmax_mhz(int depth) { return 1e6 / stage_ps(depth); }
};

// NAND2-equivalent weight of a Yosys internal gate cell ($_NAND_, $_DFF_PN0_, ...).
// Throws SynthError for a cell type without a documented weight (e.g. a latch).
double nand2_weight(const std::string& cell_type);
bool is_flop_cell(const std::string& cell_type);

struct GenericResult {
  std::map<std::string, long> cells;  // by Yosys cell type
  long cells_total = 0;
  double area_nand2 = 0;
  long transistors = 0;              // `stat -tech cmos`
  bool transistors_complete = true;  // false: Yosys printed "N+" (some cell types not counted)
  long transistors_uncounted = 0;    // cells Yosys 0.23 has no count for: flops with reset/enable
  long reg_bits = 0;
  int depth = 0;  // `ltp -noff`: gate levels of the worst stage
  double stage_ps = 0;
  double fmax_mhz = 0;
};

struct Ice40Result {
  bool run = false;
  std::string device;
  long luts = 0, carries = 0, ffs = 0, dsps = 0, brams = 0;
  long device_luts = 0;
  bool fits = false;
  std::string reason;  // why it does not fit / why pnr failed
  bool pnr_run = false;
  bool pnr_ok = false;
  double fmax_mhz = 0;  // nextpnr, register-to-register through the harness
  long lcs = 0;         // ICESTORM_LC used by the harnessed design
};

struct XilinxResult {
  bool run = false;
  long luts = 0, ffs = 0, dsps = 0, carry4 = 0, muxf = 0, srls = 0, lutram = 0, bram = 0;
  long lcs = 0;  // `stat -tech xilinx` estimate
};

// One mapping of the cell flow at one target clock.
struct CellRun {
  double target_ps = 0;  // 0: mapped without a delay target
  std::map<std::string, long> cells;  // of the unit module (harness registers excluded)
  CellArea area;
  StaResult sta;
  double achieved_ps = 0;  // period - slack: the shortest clock period this netlist meets
  std::string netlist;     // the mapped unit module (in the work directory)
  double fmax_mhz = 0;
  double yosys_s = 0, sta_s = 0;
  // With FlowOptions::stage_periods (set by run_synth): the period each of the stages + 1
  // pipeline stages needs, in order (from StaResult::level_ps).
  std::vector<double> stage_ps;
};

// The STA clock of a mapping without a target: any period gives the same achieved period
// (period - slack) as long as the same path is worst; this one is long enough to be met.
constexpr double kUntargetedPeriodPs = 100000;

struct CellResult {
  bool run = false;
  std::string library, liberty, sta_version;
  double fo4_ps = 0;  // measure_fo4_ps
  double premap_s = 0;  // Yosys synth + dfflibmap, shared by all clocks
  std::vector<CellRun> runs;  // one per target clock, in the order given
};

struct SynthResult {
  std::string unit, top;
  UnitConfig cfg;
  std::string flow = "generic";
  GenericResult generic;  // generic flow only
  CellResult cell;        // cell flows only
  Ice40Result ice40;
  XilinxResult xilinx;
  std::string yosys_version;
  bool share = true;                           // `synth` ran with resource sharing (else -noshare)
  std::string rtl_hash;                        // sources_hash() of what was synthesized (set by run_synth)
  double seconds = 0;                          // wall time of run_flow
  std::map<std::string, double> step_seconds;  // generic, ice40, ice40_harness, nextpnr, xilinx
  std::string temp_dir;                        // only when kept
  // Register placement: "depth" or "delay" (FlowOptions::placement). With "delay" at
  // 0 < Stages < maximum: the characterization (every cut registered, same flow and first
  // clock): the logic delay of each segment (stage period minus clock-to-Q and setup) and the
  // SegW weights made of them (UnitConfig::seg_weights).
  std::string placement = "depth";
  std::vector<double> segment_delays_ps;
  std::vector<int> seg_weights;
};

// Synthesizes the wrapper of (unit, config): checks the request, writes the wrapper into a
// temp dir, runs the flows selected in `o`. Throws SynthError/FormatError with one line.
SynthResult run_synth(const UnitSpec& u, const UnitConfig& c, const FlowOptions& o);

// Runs the flows on explicit sources (used by run_synth, by `gen` on the generated directory
// and by tests). `ports` drive the FPGA harness. work_dir must exist; logs are written there.
SynthResult run_flow(const std::vector<std::string>& sources, const std::string& top,
                     const std::vector<Port>& ports, const std::string& work_dir, const FlowOptions& o);

// Labels a run_flow result as (unit, config): unit name, configuration, RTL hash of its sources and
// the number of pipeline segments of every cell-flow critical path (Stages + 1). run_synth and
// `gen` both call it, so a datasheet and a synth row say the same.
void label_result(SynthResult& r, const UnitSpec& u, const UnitConfig& c, const Sources& src);

// The Yosys script of the generic gate-level flow (what `gen` writes as synth.ys when given
// bare file names). With measure=true it also writes stat.json / cmos.txt / ltp.txt.
std::string generic_script(const std::vector<std::string>& sources, const std::string& top, bool measure,
                           bool share = true);

std::string yosys_version(const std::string& yosys);  // "Yosys 0.23 (git sha1 ...)"; throws if missing

// The Yosys scripts of the cell flow: the mapping up to flip-flops (writes premap.il), and the
// combinational mapping at one target clock (`abc -liberty -D`; target_ps 0: no -D) that writes
// <stem>.v, <stem>.json (stat -json) and <stem>.txt (stat -liberty).
std::string cell_premap_script(const CellLibrary& lib, const std::vector<std::string>& sources,
                               const std::string& unit_top, bool share);
// reading the ABC script <stem>.abc, which is cell_abc_script(target_ps).
// <stem>_unit.v is the unit module alone.
std::string cell_map_script(const CellLibrary& lib, const std::string& stem, const std::string& unit_top);
std::string cell_abc_script(double target_ps);

// JSON rows: the synthesis row schema (synth/README.md, "Row schema"): one object per (unit,
// configuration, flow, target clock). to_json is the first (the generic flow has one).
std::vector<nlohmann::json> to_json_rows(const SynthResult& r);
nlohmann::json to_json(const SynthResult& r);
std::string format_table(const SynthResult& r);

}  // namespace ru::synth
