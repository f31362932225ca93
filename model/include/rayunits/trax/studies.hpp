// rayunits trax studies (issue 7 section 5), each one table (CSV + Markdown) and one plot:
//   formats     the whole-chip speed/accuracy trade: per format rays/s, area, rays/s per area,
//               image error vs a double render (pixels over 10 %, PSNR) -- the headline plot
//   rays        coherent vs incoherent rays: primary only, + hard shadow, + one diffuse bounce
//   traversal   stack vs stackless (bit trail) traversal
//   noise       hardware noise unit vs noise computed in software on the TPs
//   units       functional-unit count sweep (threads per FP adder/multiplier)
// Command: `rayunits study trax --kind K` (model/cli/cmd_study_trax.cpp); report section
// "trax" (model/cli/report_trax.cpp).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "rayunits/scene/scene.hpp"
#include "rayunits/trax/config.hpp"

namespace ru::trax {

struct StudyTable {
  std::string kind, title, note;
  std::vector<std::string> cols;
  std::vector<std::vector<std::string>> rows;
  std::string csv() const;
  std::string markdown() const;
};

struct StudyOptions {
  std::string scene = "default";
  int width = 32, height = 32;
  Config base = default_config();  // or --config
  std::vector<std::string> formats;  // formats study; empty: kDefaultFormats
  bool progress = false;
  std::function<void(const std::string&)> log;  // progress lines (may be empty)
};

extern const std::vector<std::string> kStudyKinds;      // formats, rays, traversal, noise, units
extern const std::vector<std::string> kDefaultFormats;  // e5m8 ... e8m23

// Runs one study on scene `s` (throws on bad input).
StudyTable run_study(const std::string& kind, const scene::Scene& s, const StudyOptions& o);

}  // namespace ru::trax
