// TRaX model studies (issue 7 section 5); see rayunits/trax/studies.hpp.
#include "rayunits/trax/studies.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "rayunits/render/render.hpp"
#include "rayunits/trax/trax.hpp"
#include "rayunits/util/csv.hpp"

namespace ru::trax {

const std::vector<std::string> kStudyKinds = {"formats", "rays", "traversal", "noise", "units", "texture"};
const std::vector<std::string> kDefaultFormats = {"e5m8",  "e5m10", "e5m11", "e6m12", "e6m14",
                                                  "e7m16", "e8m19", "e8m23"};

namespace {

std::string f(double v, const char* fmt = "%.4g") {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char b[64];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}
std::string i(uint64_t v) { return std::to_string(v); }

void say(const StudyOptions& o, const std::string& m) {
  if (o.log) o.log(m);
}

RunOptions quiet_run() {
  RunOptions r;
  return r;
}

// rays/s per mm2 (um2 / 1e6)
double per_area(const TraxResult& r) { return r.area.total > 0 ? r.rays_per_second() / (r.area.total / 1e6) : 0; }
std::string mm2(double um2) { return f(um2 / 1e6, "%.4g"); }

std::string source_of(const TraxResult& r, const std::string& unit) {
  for (const auto& a : r.area_sources)
    if (a.unit == unit) return a.how;
  return "";
}

StudyTable formats(const scene::Scene& s, const StudyOptions& o) {
  StudyTable t;
  t.kind = "formats";
  t.title = "Whole-chip speed/accuracy trade (scene " + s.name + ", " + std::to_string(o.width) + "x" +
            std::to_string(o.height) + ")";
  t.cols = {"format", "bits", "cycles", "clock_mhz", "clock_unit", "rays", "rays_per_s", "area_mm2",
            "unit_area_mm2", "estimated_mm2", "rays_per_s_per_mm2", "rays_per_s_per_unit_mm2", "error_pixels", "error_pct", "psnr_db",
            "tolerated", "box_latency", "tri_latency", "box_area_source", "tri_area_source", "clock_source",
            "memory_mm2", "value_bits", "node_bytes", "tri_bytes", "l1_hit_pct", "l2_hit_pct", "dram_bytes_per_ray",
            "cycles_word", "dram_bytes_per_ray_word", "memory_pj_per_ray", "memory_pj_per_ray_word"};
  Config rc = o.base;
  render::RenderOptions ro = render_options(rc, o.width, o.height);
  ro.format = "double";
  ro.fma = false;  // the plain double render, whatever chip.fma
  ro.threads = 2;
  say(o, "reference render in double");
  const render::Image ref = render::render(s, ro);
  const auto& list = o.formats.empty() ? kDefaultFormats : o.formats;
  struct Point {
    std::string format;
    int bits;
    bool ok;
    double clock, cycles, cycles_word, units, memories, per_area;
  };
  std::vector<Point> pts;
  for (const std::string& fm : list) {
    Config c = o.base;
    c.format = fm;
    say(o, "format " + fm);
    const TraxResult r = run_trax(s, c, o.width, o.height, quiet_run());
    Config cw = c;  // the same chip with the scene in 32-bit words (the layout before issue 16)
    cw.scene_storage = "word";
    const TraxResult w = c.scene_storage == "word" ? r : run_trax(s, cw, o.width, o.height, quiet_run());
    auto dram_per_ray = [](const TraxResult& x) {
      return f(double(x.sim.dram_read_bytes + x.sim.dram_write_bytes) / double(std::max<uint64_t>(1, x.rays())), "%.1f");
    };
    auto pj_per_ray = [](const TraxResult& x) {
      return f(x.energy.total_pj / double(std::max<uint64_t>(1, x.rays())), "%.4g");
    };
    const render::ImageDiff d = render::compare(r.image, ref);
    const double pct = d.pixels ? 100.0 * double(d.errors) / double(d.pixels) : 0;
    const bool ok = pct <= 0.1 && d.psnr >= 40.0;
    const num::Format F = num::Format::parse(fm == "float" ? "e8m23" : fm);
    t.rows.push_back({fm, i(F.width()), i(r.sim.cycles), f(r.cfg.clock_mhz, "%.1f"), r.clock.unit, i(r.rays()),
                      f(r.rays_per_second()), mm2(r.area.total), mm2(r.area.units), mm2(r.area.estimated),
                      f(per_area(r)), f(r.area.units > 0 ? r.rays_per_second() / (r.area.units / 1e6) : 0), i(d.errors), f(pct, "%.3f"), f(d.psnr, "%.2f"), ok ? "yes" : "no",
                      i(r.cfg.unit(Unit::Box).latency), i(r.cfg.unit(Unit::Tri).latency), source_of(r, "ray_box"),
                      source_of(r, r.cfg.tri == "mt" ? "ray_tri_mt" : "ray_tri_robust"), r.clock.how,
                      mm2(r.area.memories), i(r.value_bits), i(r.node_bytes), i(r.tri_bytes),
                      f(100 * r.sim.l1.hit_rate(), "%.2f"), f(100 * r.sim.l2.hit_rate(), "%.2f"), dram_per_ray(r),
                      i(w.sim.cycles), dram_per_ray(w), pj_per_ray(r), pj_per_ray(w)});
    pts.push_back({fm, F.width(), ok, r.cfg.clock_mhz, double(r.sim.cycles), double(w.sim.cycles), r.area.units,
                   r.area.memories, per_area(r)});
  }
  // Where the smallest tolerated format's gain over the widest comes from: rays/s per mm2 =
  // clock x (1 / cycles) x (1 / area), so the gain is the product of the three ratios; the cycle
  // ratio splits into the packed scene data's part (against the word layout) and the rest, the
  // area ratio into units and memories in proportion to the mm2 each saves. Shares: of the log.
  std::string gain;
  const Point* small = nullptr;
  const Point* wide = nullptr;
  for (const Point& p : pts) {
    if (p.ok && (!small || p.bits < small->bits)) small = &p;
    if (!wide || p.bits > wide->bits) wide = &p;
  }
  if (small && wide && small != wide && small->per_area > 0 && wide->per_area > 0) {
    const double total = small->per_area / wide->per_area, clock = small->clock / wide->clock,
                 cycles = wide->cycles / small->cycles,
                 layout = cycles / (wide->cycles_word / small->cycles_word),
                 area = (wide->units + wide->memories) / (small->units + small->memories);
    const double du = wide->units - small->units, dm = wide->memories - small->memories;
    const double lt = std::log(total);
    auto pct = [&](double x) { return f(100 * x / lt, "%.0f") + " %"; };
    const double la = std::log(area), lu = du + dm != 0 ? la * du / (du + dm) : 0, lm = la - lu;
    gain = " Gain of " + small->format + " (the smallest tolerated) over " + wide->format + ": " + f(total, "%.2f") +
           "x rays/s per mm2 = clock " + f(clock, "%.2f") + "x * cycles " + f(cycles, "%.2f") + "x (packed scene data " +
           f(layout, "%.2f") + "x, the rest " + f(cycles / layout, "%.2f") + "x) * area " + f(area, "%.2f") +
           "x (units " + f(-du / 1e6, "%+.1f") + " mm2, memories " + f(-dm / 1e6, "%+.1f") +
           " mm2). Shares of the log of the gain: clock " + pct(std::log(clock)) + ", packed scene data (bandwidth) " +
           pct(std::log(layout)) + ", other cycles " + pct(std::log(cycles / layout)) + ", units' area " + pct(lu) +
           ", memories' area " + pct(lm) + ".";
  }
  t.note = "Every FP operation, the box/triangle units and the noise unit compute in the format; the image error is "
           "against the same renderer in double (pixels with a channel more than 10 % off; PSNR, peak 1). "
           "\"tolerated\": <= 0.1 % error pixels and PSNR >= 40 dB (the target of `rayunits profile`). Area (mm2): "
           "units (osu018 cell area before placement from model/data/trax/areas.json: measured rows, box/tri "
           "composed from the FP rows where not measured) plus register files, local stores and caches "
           "(memory_mm2: the memory model of docs/TRAX.md, CACTI's SRAM cell grown per port over an assumed array "
           "efficiency, an estimate; FP registers at the format's width; estimated_mm2 = every estimated item; "
           "rays_per_s_per_unit_mm2 counts the functional units only); scene data stored in the format "
           "(value_bits per value, node_bytes per BVH node, tri_bytes per triangle; cache hit rates and DRAM bytes "
           "per ray of that layout), cycles_word and dram_bytes_per_ray_word: the same chip with every scene value "
           "in a 32-bit word (chip.scene_storage = \"word\", the layout before issue 16); memory_pj_per_ray "
           "(_word): memory access energy per ray, register files to DRAM (an estimate with Horowitz's 45 nm "
           "constants, docs/TRAX.md \"Memory access energy\"); "
           "rays/s at the chip clock = the STA Fmax of the slowest used unit at its Stages (clock_unit; "
           "clock_source says whether it is measured or estimated), docs/TRAX.md." + gain;
  return t;
}

StudyTable rays(const scene::Scene& s, const StudyOptions& o) {
  StudyTable t;
  t.kind = "rays";
  t.title = "Coherent vs incoherent rays (scene " + s.name + ")";
  t.cols = {"workload", "rays", "primary", "secondary", "cycles", "rays_per_s", "cycles_per_ray",
            "box_tests_per_ray", "l1_hit_pct", "l2_hit_pct", "issue_rate", "secondary_rays_per_s"};
  uint64_t primary_cycles = 0;
  for (const std::string w : {"primary", "shadow", "diffuse"}) {
    RunOptions ro;
    ro.workload = w;
    say(o, "workload " + w);
    const TraxResult r = run_trax(s, o.base, o.width, o.height, ro);
    if (w == "primary") primary_cycles = r.sim.cycles;
    const uint64_t sec = r.shadow_rays + r.bounce_rays;
    const double extra = double(r.sim.cycles) - double(primary_cycles);
    const double sec_rate = (sec && extra > 0) ? double(sec) / (extra / (r.cfg.clock_mhz * 1e6)) : 0;
    t.rows.push_back({w, i(r.rays()), i(r.primary_rays), i(sec), i(r.sim.cycles), f(r.rays_per_second()),
                      f(double(r.sim.cycles) * r.cfg.threads() / std::max<uint64_t>(1, r.rays()), "%.1f"),
                      f(double(r.box_tests) / std::max<uint64_t>(1, r.rays()), "%.2f"),
                      f(100 * r.sim.l1.hit_rate(), "%.2f"), f(100 * r.sim.l2.hit_rate(), "%.2f"),
                      f(r.sim.issue_rate(r.cfg), "%.3f"), w == "primary" ? "" : f(sec_rate)});
  }
  t.note = "primary: one primary ray per pixel (closest hit, no shading); shadow: + a hard-shadow ray to the point "
           "light per hit (any hit); diffuse: + one diffuse bounce per hit in a per-pixel pseudo-random direction "
           "(closest hit; incoherent). cycles_per_ray = TP-cycles per ray; secondary_rays_per_s = the secondary "
           "rays over the cycles they add to the primary-only run.";
  return t;
}

StudyTable traversal(const scene::Scene& s, const StudyOptions& o) {
  StudyTable t;
  t.kind = "traversal";
  t.title = "Stack vs stackless traversal (scene " + s.name + ")";
  t.cols = {"traversal", "cycles", "rays_per_s", "instructions", "box_tests", "node_visits", "up_steps",
            "local_store_used_bytes", "local_store_bytes", "max_live_registers", "area_mm2", "rays_per_s_per_mm2"};
  for (const std::string tv : {"stack", "stackless"}) {
    Config c = o.base;
    c.traversal = tv;
    if (tv == "stackless") c.local_store_bytes = 0;  // no stack: no local store
    say(o, "traversal " + tv);
    const TraxResult r = run_trax(s, c, o.width, o.height, quiet_run());
    t.rows.push_back({tv, i(r.sim.cycles), f(r.rays_per_second()), i(r.sim.instructions), i(r.box_tests),
                      i(r.node_visits), i(r.up_steps), i(8ull * r.max_stack), i(c.local_store_bytes),
                      i(r.sim.max_live_registers), mm2(r.area.total), f(per_area(r))});
  }
  t.note = "The same triangles are tested in the same order by both (images equal); stackless re-tests the far "
           "sibling's box and loads parent links instead of keeping a stack, and is charged no local store "
           "(stack: the configured local store per thread).";
  return t;
}

StudyTable noise(const scene::Scene& s, const StudyOptions& o) {
  StudyTable t;
  t.kind = "noise";
  t.title = "Hardware noise unit vs noise in software on the TPs (scene " + s.name + ")";
  t.cols = {"noise", "cycles", "rays_per_s", "instructions", "noise_evals", "instructions_per_noise",
            "clock_mhz", "area_mm2", "noise_unit_area_mm2", "rays_per_s_per_mm2"};
  uint64_t hw_instr = 0;
  for (const bool sw : {false, true}) {
    RunOptions ro;
    ro.software_noise = sw;
    say(o, sw ? "software noise" : "hardware noise");
    const TraxResult r = run_trax(s, o.base, o.width, o.height, ro);
    if (!sw) hw_instr = r.sim.instructions;
    const uint64_t evals = sw ? r.software_noise_evals : r.noise_evals;
    double unit_area = 0;
    for (const auto& a : r.area.items)
      if (a.name.rfind("unit noise", 0) == 0) unit_area = a.total();
    t.rows.push_back({sw ? "software (TPs)" : "hardware unit", i(r.sim.cycles), f(r.rays_per_second()),
                      i(r.sim.instructions), i(evals),
                      sw && evals ? f(double(r.sim.instructions - hw_instr) / double(evals) + 1, "%.1f") : "1",
                      f(r.cfg.clock_mhz, "%.1f"), mm2(r.area.total), mm2(unit_area), f(per_area(r))});
  }
  t.note = "Software: the unit's algorithm as TP instructions in the chip's format (per evaluation ~200 "
           "instructions incl. 30 table loads; docs/TRAX.md), timing only (values from the hardware model); the "
           "noise unit is then not instantiated nor charged. Kensler (sec. 4) suggests up to 50 % faster shading "
           "with the unit for noise-heavy scenes.";
  return t;
}

// Issue 15 §2: the texture unit, the noise unit with the octave sums on the TPs, and everything in
// software, on the same scene (normally the noise-heavy "noisy"); each chip charged for the units it
// uses. The noise share is of TP instructions (the software run's instructions beyond the
// hardware-noise run's, plus its NOISE instructions), not of time.
StudyTable texture(const scene::Scene& s, const StudyOptions& o) {
  StudyTable t;
  t.kind = "texture";
  t.title = "Texture unit vs noise unit + TP sums vs software noise (scene " + s.name + ")";
  t.cols = {"variant", "cycles", "rays_per_s", "instructions", "shading_samples", "noise_evals",
            "noise_per_sample", "texture_requests", "noise_instr_share_pct", "clock_mhz", "area_mm2",
            "texture_or_noise_unit_mm2", "rays_per_s_per_mm2", "speedup_vs_software"};
  struct V {
    const char* name;
    std::string texture;
    bool sw;
  };
  std::vector<TraxResult> rs;
  const V vs[] = {{"texture unit", "unit", false}, {"noise unit + TP sums", "shader", false}, {"software (TPs)", "shader", true}};
  for (const V& v : vs) {
    Config c = o.base;
    c.texture = v.texture;
    RunOptions ro;
    ro.software_noise = v.sw;
    say(o, v.name);
    rs.push_back(run_trax(s, c, o.width, o.height, ro));
  }
  const TraxResult &hw = rs[1], &sw = rs[2];
  const double share = sw.sim.instructions > 0 && sw.sim.instructions >= hw.sim.instructions
                           ? 100.0 * double(sw.sim.instructions - hw.sim.instructions + sw.software_noise_evals) /
                                 double(sw.sim.instructions)
                           : 0;
  for (size_t k = 0; k < rs.size(); ++k) {
    const TraxResult& r = rs[k];
    double unit_area = 0;
    for (const auto& a : r.area.items)
      if (a.name.rfind("unit noise", 0) == 0 || a.name.rfind("unit texture", 0) == 0) unit_area += a.total();
    const uint64_t evals = k == 2 ? r.software_noise_evals : r.noise_evals;
    t.rows.push_back({vs[k].name, i(r.sim.cycles), f(r.rays_per_second()), i(r.sim.instructions), i(r.shading_samples),
                      i(evals), r.shading_samples ? f(double(evals) / double(r.shading_samples), "%.2f") : "0",
                      i(r.texture_evals), k == 2 ? f(share, "%.1f") : "", f(r.cfg.clock_mhz, "%.1f"), mm2(r.area.total),
                      mm2(unit_area), f(per_area(r)),
                      f(sw.rays_per_second() > 0 ? r.rays_per_second() / sw.rays_per_second() : 0, "%.3f")});
  }
  t.note = "Texture unit: one TEXTURE instruction per procedural material sample on ru_texture (Units 4 noise units, "
           "a request of n octaves occupies it ceil(n/4) cycles); noise unit + TP sums: the renderer's shader, one "
           "NOISE instruction per octave and the sums/transfer functions as FP instructions; software: the noise "
           "function as TP instructions too (docs/TRAX.md). noise_instr_share_pct: the software run's share of TP "
           "instructions spent on noise (an instruction count, not a time). Images: the texture unit's differ from "
           "the shader's (fixed-point sums; docs/NOISE.md). Kensler (sec. 4) suggests up to 50 % faster for "
           "noise-heavy scenes.";
  return t;
}

StudyTable units(const scene::Scene& s, const StudyOptions& o) {
  StudyTable t;
  t.kind = "units";
  t.title = "FP adder/multiplier count sweep (scene " + s.name + ")";
  t.cols = {"fp_units_per_tm", "threads_per_fp_unit", "cycles", "rays_per_s", "area_mm2", "rays_per_s_per_mm2",
            "fp_add_util_pct", "fp_mul_util_pct", "contention_stall_pct"};
  for (int n = 1; n <= o.base.tps_per_tm; n *= 2) {
    Config c = o.base;
    c.unit(Unit::FpAdd).count = n;
    c.unit(Unit::FpMul).count = n;
    say(o, "fp units per TM " + std::to_string(n));
    const TraxResult r = run_trax(s, c, o.width, o.height, quiet_run());
    const double tpc = double(r.sim.cycles) * c.threads();
    t.rows.push_back({i(n), f(double(c.tps_per_tm) / n, "%g"), i(r.sim.cycles), f(r.rays_per_second()),
                      mm2(r.area.total), f(per_area(r)), f(100 * r.sim.utilisation(r.cfg, Unit::FpAdd), "%.1f"),
                      f(100 * r.sim.utilisation(r.cfg, Unit::FpMul), "%.1f"),
                      f(tpc > 0 ? 100.0 * r.sim.stall_contention / tpc : 0, "%.2f")});
  }
  t.note = "fp_add and fp_mul count per TM varied together (simtrax 65 nm: one of each per 8 threads); every other "
           "unit as configured.";
  return t;
}

using util::csv_cell;

}  // namespace

std::string StudyTable::csv() const {
  std::ostringstream o;
  for (size_t k = 0; k < cols.size(); ++k) o << (k ? "," : "") << cols[k];
  o << "\n";
  for (const auto& r : rows) {
    for (size_t k = 0; k < r.size(); ++k) o << (k ? "," : "") << csv_cell(r[k]);
    o << "\n";
  }
  return o.str();
}

std::string StudyTable::markdown() const {
  std::ostringstream o;
  o << "|";
  for (const auto& c : cols) o << " " << c << " |";
  o << "\n|";
  for (size_t k = 0; k < cols.size(); ++k) o << (k ? "---:|" : "---|");
  o << "\n";
  for (const auto& r : rows) {
    o << "|";
    for (const auto& v : r) o << " " << v << " |";
    o << "\n";
  }
  return o.str();
}

StudyTable run_study(const std::string& kind, const scene::Scene& s, const StudyOptions& o) {
  if (kind == "formats") return formats(s, o);
  if (kind == "rays") return rays(s, o);
  if (kind == "traversal") return traversal(s, o);
  if (kind == "noise") return noise(s, o);
  if (kind == "units") return units(s, o);
  if (kind == "texture") return texture(s, o);
  throw std::invalid_argument("unknown study '" + kind + "' (accepted: formats, rays, traversal, noise, units, texture)");
}

}  // namespace ru::trax
