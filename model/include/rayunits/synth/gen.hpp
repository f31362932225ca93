// rayunits: generation of self-contained, synthesis-ready unit directories (`rayunits gen`).
#pragma once

#include <nlohmann/json.hpp>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/units.hpp"

namespace ru::synth {

struct GenOptions {
  std::string out_dir;
  bool force = false;    // replace a non-empty out_dir
  bool run_flow = true;  // synthesize for the datasheet's area/depth (false: --no-synth)
  FlowOptions flow;
  // A result of this very configuration and flow (e.g. the last probe of find_stages_for_clock):
  // the datasheet takes it instead of synthesizing again.
  std::optional<SynthResult> reuse;
  nlohmann::json clock_search;  // recorded in the datasheet when set (find_stages_for_clock)
};

// Clock-driven pipelining: the smallest Stages of (u, c) whose cell-flow STA meets `clock_ps`
// (o.flow must be a cell flow; c.stages is ignored). Probes the maximum useful Stages first --
// if that misses the clock, throws SynthError naming the most this unit reaches there -- then
// bisects min_stages..max, assuming that more stages never make a met clock fail (every probe is
// recorded, so the assumption can be checked in the datasheet).
struct ClockSearch {
  int stages = 0;
  SynthResult result;  // of the chosen Stages
  nlohmann::json probes = nlohmann::json::array();  // {stages, fmax_mhz, slack_ps, met, area_um2}
};
ClockSearch find_stages_for_clock(const UnitSpec& u, UnitConfig c, double clock_ps, const FlowOptions& o,
                                  const std::function<void(const std::string&)>& progress);

struct GenReport {
  std::string top;
  std::string dir;                 // absolute path of the written directory
  std::vector<std::string> files;  // names inside dir, sorted
  std::optional<SynthResult> synth;
};

// Writes the directory: <top>.sv (wrapper), copies of every source, files.f, synth.ys,
// datasheet.md, datasheet.json. Everything is first written into a temp dir next to out_dir and
// renamed into place at the end, so out_dir is either untouched or complete. Deterministic for
// a given configuration, sources and Yosys version (no timestamps).
GenReport generate(const UnitSpec& u, const UnitConfig& c, const GenOptions& o);

nlohmann::json datasheet_json(const UnitSpec& u, const UnitConfig& c, const std::vector<std::string>& files,
                              const std::optional<SynthResult>& synth);
std::string datasheet_markdown(const nlohmann::json& ds);

}  // namespace ru::synth
