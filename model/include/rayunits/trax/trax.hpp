// rayunits trax: runs the renderer's ray tracer (render/tracer.hpp) as the kernel of a TRaX-style
// processor model and reports image, cycles, utilisation, stalls, caches, bandwidth and area.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rayunits/render/render.hpp"
#include "rayunits/scene/scene.hpp"
#include "rayunits/trax/config.hpp"
#include "rayunits/trax/sim.hpp"

namespace ru::trax {

struct AreaItem {
  std::string name;
  double count = 0;  // instances on the chip
  double each = 0;   // um2 per instance
  bool estimate = false;  // not a cell-flow measurement (memories, NAND2-eq estimates, composed units)
  double total() const { return count * each; }
};
struct Area {
  std::vector<AreaItem> items;
  double total = 0, units = 0, memories = 0;  // um2
  double estimated = 0;                       // um2 of items with estimate = true
};
// Functional units with at least one issued operation x count x TMs, plus register files,
// local stores, L1s (data and tags) and the L2 (docs/TRAX.md "Area model"), in um2. Memories come
// from the memory model (memory_cell_um2): labelled estimates.
Area area_estimate(const Config& c, const SimStats& st, const std::vector<AreaSource>* sources = nullptr);
// um2 of one bit cell with rw read/write, r read and w write ports (docs/TRAX.md "Memories"):
// CACTI's cell, sqrt(A / aspect) F wide and aspect times that high, grown by 2 x wire_pitch_f F per
// port beyond the first in each direction: h = b_h + 2p(w + rw - 1 + r), w = b_w + 2p(rw - 1 + r + w).
double memory_cell_um2(const Config& c, int rw, int r, int w);
// Bits of a cache's data and tag arrays (a valid bit and address_bits - index - offset per line).
double cache_bits(const Config& c, const CacheCfg& k);

// Memory access energy (docs/TRAX.md "Memory access energy"; an estimate with Horowitz's 45 nm
// constants, [energy] of the configuration): per structure the accesses the run made and the pJ
// of one. Register files: every source read and destination written (per file, at the file's
// width; the file is one thread's); local store: stack loads and stores (8 B); L1: scene loads
// (one value: the format's width, or the word with scene_storage = "word"); L2: L1 misses (a line
// each); DRAM: bytes read and written x dram_pj_per_bit x 8. Functional units are not included.
struct EnergyItem {
  std::string name;
  uint64_t accesses = 0;
  double pj_each = 0;
  double total() const { return double(accesses) * pj_each; }
};
struct Energy {
  std::vector<EnergyItem> items;
  double total_pj = 0;
};
// pJ of one access of `bits` bits to an SRAM array of `bytes` bytes (the [energy] law).
double sram_access_pj(const Config& c, double bytes, double bits);
Energy energy_estimate(const Config& c, const SimStats& st);

struct TraxResult {
  Config cfg;  // resolved (resolve_config): "rtl" latencies and "synth" areas filled in
  std::vector<AreaSource> area_sources;
  render::Image image;
  SimStats sim;
  uint64_t primary_rays = 0, shadow_rays = 0, bounce_rays = 0, software_noise_evals = 0, box_tests = 0, tri_tests = 0, noise_evals = 0;
  uint64_t texture_evals = 0, shading_samples = 0;  // TEXTURE requests; procedural material samples
  uint64_t node_visits = 0;   // nodes whose children / triangles were examined
  uint64_t up_steps = 0;      // stackless: moves to a parent
  uint32_t max_stack = 0;     // stack: deepest stack (entries of 8 bytes in the local store)
  size_t bvh_nodes = 0;
  int bvh_depth = 0;
  uint64_t value_bits = 0, node_bytes = 0, tri_bytes = 0;  // scene data in memory (chip.scene_storage)
  Area area;
  Energy energy;    // memory access energy of the run (estimate)
  ChipClock clock;  // cfg.clock_mhz and where it came from (STA of the slowest used unit, or configured)
  uint64_t rays() const { return primary_rays + shadow_rays + bounce_rays; }
  double seconds() const { return double(sim.cycles) / (cfg.clock_mhz * 1e6); }
  double rays_per_second() const { return sim.cycles ? double(rays()) / seconds() : 0.0; }
};

// The render options the kernel uses for a configuration (what `rayunits render` must be given
// to produce the same image: format, tri, box, bvh, leaf, noise; shadows on).
render::RenderOptions render_options(const Config& c, int width, int height);

// What the chip runs (studies; the default is the renderer's image).
struct RunOptions {
  // render: the renderer's shading (image equal to `rayunits render`); primary: primary rays
  // only (closest hit); shadow: primary + a hard-shadow ray to the light (any hit) per hit;
  // diffuse: primary + one diffuse bounce per hit (closest hit, a per-pixel pseudo-random
  // direction in the hemisphere of the facing normal: incoherent). Non-render images show the
  // primary hit mask.
  std::string workload = "render";
  // The noise function computed on the TPs in software (docs/TRAX.md: an instruction sequence
  // of the same algorithm, values from the hardware model) instead of the NOISE unit.
  bool software_noise = false;
  bool progress = false;
  IssueObserver* observer = nullptr;
};
TraxResult run_trax(const scene::Scene& s, const Config& c, int width, int height, const RunOptions& ro);

// Throws ConfigError / ru::num::FormatError / std::invalid_argument on bad input. observer:
// sees every BOX / TRI / NOISE issue (the RTL co-simulation, trax/cosim.hpp).
TraxResult run_trax(const scene::Scene& s, const Config& c, int width, int height, bool progress = false,
                    IssueObserver* observer = nullptr);

// summary.json / summary.md contents.
std::string summary_json(const TraxResult& r, const std::string& scene_name, const std::string& command);
std::string summary_md(const TraxResult& r, const std::string& scene_name, const std::string& command);
// The last stdout line: "cycles=C rays=R rays_per_s=X (at F MHz) area=A".
std::string summary_line(const TraxResult& r);

}  // namespace ru::trax
