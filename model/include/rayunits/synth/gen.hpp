// rayunits: generation of self-contained, synthesis-ready unit directories (`rayunits gen`).
#pragma once

#include <nlohmann/json.hpp>
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
};

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
