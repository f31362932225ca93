// TRaX model: area estimate and the summary (JSON, Markdown, last stdout line).
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rayunits/trax/trax.hpp"

namespace ru::trax {

double memory_cell_um2(const Config& c, int rw, int r, int w) {
  const double bw = std::sqrt(c.sram_cell_f2 / c.sram_cell_aspect), bh = c.sram_cell_aspect * bw;  // F
  const double p = c.wire_pitch_f;
  const double h = bh + 2 * p * (w + rw - 1 + r), wd = bw + 2 * p * (rw - 1 + r + w);
  return h * wd * c.feature_um * c.feature_um;
}

double cache_bits(const Config& c, const CacheCfg& k) {
  const double lines = double(k.size) / k.line, sets = lines / k.ways;
  const double tag = c.address_bits - std::log2(sets) - std::log2(double(k.line));
  return lines * (8.0 * k.line + tag + 1);
}

Area area_estimate(const Config& c, const SimStats& st, const std::vector<AreaSource>* sources) {
  if (!(c.nand2_um2 > 0)) throw ConfigError("area_estimate: the configuration is not resolved (resolve_config)");
  Area a;
  for (int u = 0; u < kUnits; ++u) {
    if (!st.unit_ops[u]) continue;  // not used by the scene's kernel: not instantiated
    const UnitCfg& k = c.units[u];
    const bool measured = sources && static_cast<size_t>(u) < sources->size() && (*sources)[u].how == "measured";
    const std::string how = sources && static_cast<size_t>(u) < sources->size() ? (*sources)[u].how : "";
    a.items.push_back({std::string("unit ") + unit_name(static_cast<Unit>(u)) + (measured || how.empty() ? "" : " (" + how + ")"),
                       double(c.tms) * k.count, k.area, !measured});
    a.units += a.items.back().total();
  }
  auto n = [](double v, const char* f = "%g") {
    char b[32];
    std::snprintf(b, sizeof b, f, v);
    return std::string(b);
  };
  const double sram = memory_cell_um2(c, 1, 0, 0) / c.array_efficiency;
  const double rf = memory_cell_um2(c, 0, c.regfile_read_ports, c.regfile_write_ports) / c.array_efficiency;
  const std::string est = " um2/bit at efficiency " + n(c.array_efficiency) + "; memory model, estimate)";
  const std::string ports = std::to_string(c.regfile_read_ports) + "R" + std::to_string(c.regfile_write_ports) + "W ";
  const int fbits = c.value_bits();
  const std::vector<AreaItem> mem = {
      {"FP register files (" + std::to_string(c.fp_registers_per_thread) + " x " + std::to_string(fbits) +
           " bits per thread; " + ports + n(rf, "%.3g") + est,
       double(c.threads()), double(c.fp_registers_per_thread) * fbits * rf, true},
      {"integer register files (" + std::to_string(c.int_registers_per_thread) + " x 32 bits per thread; " + ports +
           n(rf, "%.3g") + est,
       double(c.threads()), double(c.int_registers_per_thread) * 32 * rf, true},
      {"local stores (" + std::to_string(c.local_store_bytes) + " B per thread; " + n(sram, "%.3g") + est,
       double(c.threads()), c.local_store_bytes * 8.0 * sram, true},
      {"L1 data caches (" + std::to_string(c.l1.size) + " B + tags; " + n(sram, "%.3g") + est, double(c.tms),
       cache_bits(c, c.l1) * sram, true},
      {"L2 cache (" + std::to_string(c.l2.size) + " B + tags; " + n(sram, "%.3g") + est, 1.0,
       cache_bits(c, c.l2) * sram, true},
  };
  for (const auto& m : mem) {
    a.items.push_back(m);
    a.memories += m.total();
  }
  a.total = a.units + a.memories;
  for (const auto& it : a.items)
    if (it.estimate) a.estimated += it.total();
  return a;
}

double sram_access_pj(const Config& c, double bytes, double bits) {
  return c.sram_pj_64b_8kib * std::pow(bytes / 8192.0, c.sram_capacity_exponent) * bits / 64.0;
}

Energy energy_estimate(const Config& c, const SimStats& st) {
  Energy e;
  const double fbits = c.value_bits();
  const double load_bits = c.scene_storage == "word" ? 8.0 * c.value_bytes() : fbits;
  const uint64_t local = st.op_count[static_cast<int>(Op::LoadLocal)] + st.op_count[static_cast<int>(Op::StoreLocal)];
  e.items = {
      {"FP register file accesses (" + std::to_string(c.fp_registers_per_thread) + " x " + std::to_string(int(fbits)) + " bits)",
       st.rf_reads_fp + st.rf_writes_fp, sram_access_pj(c, c.fp_registers_per_thread * fbits / 8, fbits)},
      {"integer register file accesses (" + std::to_string(c.int_registers_per_thread) + " x 32 bits)",
       st.rf_reads_int + st.rf_writes_int, sram_access_pj(c, c.int_registers_per_thread * 4.0, 32)},
      {"local store accesses (" + std::to_string(c.local_store_bytes) + " B, 64 bits)", local,
       sram_access_pj(c, c.local_store_bytes, 64)},
      {"L1 accesses (" + std::to_string(c.l1.size) + " B, " + std::to_string(int(load_bits)) + " bits)", st.l1.accesses,
       sram_access_pj(c, double(c.l1.size), load_bits)},
      {"L2 accesses (" + std::to_string(c.l2.size) + " B, " + std::to_string(8 * c.l1.line) + "-bit line fills)",
       st.l2.accesses, sram_access_pj(c, double(c.l2.size), 8.0 * c.l1.line)},
      {"DRAM bytes (read + write)", st.dram_read_bytes + st.dram_write_bytes, 8 * c.dram_pj_per_bit},
  };
  for (const auto& it : e.items) e.total_pj += it.total();
  return e;
}

namespace {
std::string num(double v, const char* fmt = "%.6g") {
  char b[64];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}
double dram_gbps(const TraxResult& r) {
  const double s = r.seconds();
  return s > 0 ? double(r.sim.dram_read_bytes + r.sim.dram_write_bytes) / s / 1e9 : 0.0;
}
double tp_cycles(const TraxResult& r) { return double(r.sim.cycles) * r.cfg.threads(); }
}  // namespace

std::string summary_line(const TraxResult& r) {
  std::ostringstream o;
  o << "cycles=" << r.sim.cycles << " rays=" << r.rays() << " rays_per_s=" << num(r.rays_per_second(), "%.4g")
    << " (at " << num(r.cfg.clock_mhz, "%g") << " MHz) area=" << num(r.area.total / 1e6, "%.4g") << "mm2";
  return o.str();
}

std::string summary_json(const TraxResult& r, const std::string& scene_name, const std::string& command) {
  const SimStats& s = r.sim;
  const Config& c = r.cfg;
  using J = nlohmann::ordered_json;  // fields in the documented order
  J o;
  o["command"] = command;
  o["scene"] = scene_name;
  o["width"] = r.image.width;
  o["height"] = r.image.height;
  o["format"] = c.format;
  o["tri"] = c.tri;
  o["box"] = c.box;
  o["noise"] = c.noise;
  o["traversal"] = c.traversal;
  o["bvh"] = c.bvh;
  o["tms"] = c.tms;
  o["tps_per_tm"] = c.tps_per_tm;
  o["clock_mhz"] = c.clock_mhz;
  o["clock_source"] = r.clock.how;
  o["cycles"] = s.cycles;
  o["rays"] = r.rays();
  o["primary_rays"] = r.primary_rays;
  o["shadow_rays"] = r.shadow_rays;
  o["rays_per_s"] = r.rays_per_second();
  o["frames_per_s"] = r.seconds() > 0 ? 1.0 / r.seconds() : 0.0;
  o["instructions"] = s.instructions;
  o["issue_rate"] = s.issue_rate(c);
  o["box_tests"] = r.box_tests;
  o["tri_tests"] = r.tri_tests;
  o["noise_evals"] = r.noise_evals;
  o["node_visits"] = r.node_visits;
  o["up_steps"] = r.up_steps;
  o["max_stack_entries"] = r.max_stack;
  o["max_live_registers"] = s.max_live_registers;
  o["max_live_fp_registers"] = s.max_live_fp_registers;
  o["max_live_int_registers"] = s.max_live_int_registers;
  o["scene_storage"] = c.scene_storage;
  o["value_bits"] = r.value_bits;
  o["node_bytes"] = r.node_bytes;
  o["tri_bytes"] = r.tri_bytes;
  o["bvh_nodes"] = r.bvh_nodes;
  o["bvh_depth"] = r.bvh_depth;
  J ops = J::object();
  for (int i = 0; i < kOps; ++i) ops[op_name(static_cast<Op>(i))] = s.op_count[i];
  o["ops"] = ops;
  J units = J::object();
  for (int u = 0; u < kUnits; ++u) {
    if (!s.unit_ops[u]) continue;
    const UnitCfg& k = c.units[u];
    units[unit_name(static_cast<Unit>(u))] = {{"ops", s.unit_ops[u]},
                                              {"utilisation", s.utilisation(c, static_cast<Unit>(u))},
                                              {"latency", k.latency},
                                              {"count", k.count},
                                              {"width", k.width},
                                              {"area_um2", k.area},
                                              {"fmax_mhz", k.fmax_mhz}};
  }
  o["units"] = units;
  o["stalls"] = {{"dependency", s.stall_dependency}, {"memory", s.stall_memory},
                 {"bank_conflicts", s.bank_conflicts}, {"contention", s.stall_contention},
                 {"idle", s.idle}, {"tp_cycles", tp_cycles(r)}};
  auto cache = [](const auto& m) {
    return J{{"accesses", m.accesses}, {"hits", m.hits}, {"pending_hits", m.pending_hits},
             {"misses", m.misses}, {"hit_rate", m.hit_rate()}};
  };
  o["l1"] = cache(s.l1);
  o["l2"] = cache(s.l2);
  o["dram"] = {{"read_bytes", s.dram_read_bytes}, {"write_bytes", s.dram_write_bytes}, {"gb_per_s", dram_gbps(r)}};
  J items = J::array();
  for (const auto& it : r.area.items)
    items.push_back({{"name", it.name}, {"count", it.count}, {"each", it.each}, {"total", it.total()},
                     {"estimate", it.estimate}});
  o["area_um2"] = {{"total", r.area.total}, {"units", r.area.units}, {"memories", r.area.memories},
                   {"estimated", r.area.estimated}, {"nand2_um2", c.nand2_um2}, {"items", items}};
  o["rays_per_s_per_mm2"] = r.area.total > 0 ? r.rays_per_second() / (r.area.total / 1e6) : 0.0;
  J eitems = J::array();
  for (const auto& it : r.energy.items)
    eitems.push_back({{"name", it.name}, {"accesses", it.accesses}, {"pj_each", it.pj_each}, {"total_pj", it.total()}});
  o["memory_energy_pj"] = {{"total", r.energy.total_pj},
                           {"per_ray", r.rays() ? r.energy.total_pj / double(r.rays()) : 0.0},
                           {"estimate", "Horowitz ISSCC 2014 constants at 45 nm ([energy], docs/TRAX.md \"Memory access energy\")"},
                           {"items", eitems}};
  o["host_seconds"] = s.host_seconds;
  o["host_instructions_per_s"] = s.host_seconds > 0 ? double(s.instructions) / s.host_seconds : 0.0;
  return o.dump(2) + "\n";
}

std::string summary_md(const TraxResult& r, const std::string& scene_name, const std::string& command) {
  const SimStats& s = r.sim;
  const Config& c = r.cfg;
  const double tpc = tp_cycles(r);
  std::ostringstream o;
  o << "# TRaX model: " << scene_name << " " << r.image.width << "x" << r.image.height << "\n\n`" << command
    << "`\n\n"
    << "| | |\n|---|---|\n"
    << "| chip | " << c.tms << " TMs x " << c.tps_per_tm << " TPs at " << num(c.clock_mhz, "%.4g") << " MHz |\n"
    << "| clock | " << r.clock.how << " |\n"
    << "| format / tri / box / noise | " << c.format << " / " << c.tri << " / " << c.box << " / " << c.noise << " |\n"
    << "| traversal | " << c.traversal << " (BVH " << c.bvh << ", " << r.bvh_nodes << " nodes, depth " << r.bvh_depth
    << ") |\n"
    << "| cycles | " << s.cycles << " |\n"
    << "| rays (primary + shadow) | " << r.rays() << " (" << r.primary_rays << " + " << r.shadow_rays << ") |\n"
    << "| rays/s | " << num(r.rays_per_second(), "%.4g") << " (" << num(r.seconds() > 0 ? 1 / r.seconds() : 0, "%.4g")
    << " frames/s) |\n"
    << "| instructions | " << s.instructions << " (issue rate " << num(s.issue_rate(c), "%.3f") << " per TP per cycle) |\n"
    << "| box / tri tests, noise | " << r.box_tests << " / " << r.tri_tests << ", " << r.noise_evals << " |\n"
    << "| node visits | " << r.node_visits << " (" << num(r.rays() ? double(r.node_visits) / r.rays() : 0, "%.2f")
    << " per ray; stackless up-steps " << r.up_steps << ") |\n"
    << "| registers per thread (max live) | " << s.max_live_fp_registers << " FP + " << s.max_live_int_registers
    << " integer, " << s.max_live_registers << " together (configured " << c.fp_registers_per_thread << " FP x "
    << c.value_bits() << " bits + " << c.int_registers_per_thread << " integer x 32 bits) |\n"
    << "| scene data | " << c.scene_storage << ": " << r.value_bits << "-bit values, " << r.node_bytes
    << " B per BVH node, " << r.tri_bytes << " B per triangle |\n"
    << "| local store per thread | " << 8 * r.max_stack << " B used (stack entries " << r.max_stack << " x 8 B; configured "
    << c.local_store_bytes << " B) |\n"
    << "| L1 hit rate | " << num(100 * s.l1.hit_rate(), "%.2f") << " % (" << s.l1.accesses << " accesses, "
    << s.l1.pending_hits << " hits on lines in flight) |\n"
    << "| L2 hit rate | " << num(100 * s.l2.hit_rate(), "%.2f") << " % (" << s.l2.accesses << " accesses) |\n"
    << "| DRAM | " << s.dram_read_bytes << " B read, " << s.dram_write_bytes << " B written, "
    << num(dram_gbps(r), "%.3f") << " GB/s |\n"
    << "| area | " << num(r.area.total / 1e6, "%.4g") << " mm2 (units " << num(r.area.units / 1e6, "%.4g")
    << ", memories " << num(r.area.memories / 1e6, "%.4g") << " [estimate]; " << num(r.area.estimated / 1e6, "%.4g")
    << " mm2 of it estimated, the rest osu018 cell area before placement) |\n"
    << "| rays/s per mm2 | " << num(r.area.total > 0 ? r.rays_per_second() / (r.area.total / 1e6) : 0, "%.4g") << " |\n"
    << "| host | " << num(s.host_seconds, "%.2f") << " s, "
    << num(s.host_seconds > 0 ? s.instructions / s.host_seconds / 1e6 : 0, "%.2f") << " M thread-instructions/s |\n\n";
  o << "## Stalls (TP-cycles, of " << num(tpc, "%.0f") << ")\n\n| cause | TP-cycles | share |\n|---|---:|---:|\n";
  auto row = [&](const char* n, uint64_t v) { o << "| " << n << " | " << v << " | " << num(tpc ? 100.0 * v / tpc : 0, "%.1f") << " % |\n"; };
  row("issued", s.instructions);
  row("dependency (FU result)", s.stall_dependency);
  row("memory (load / local store / atomic result, L1 bank conflict)", s.stall_memory);
  row("unit contention", s.stall_contention);
  row("idle (halted)", s.idle);
  o << "\n## Functional units (per TM)\n\n| unit | latency | count | width | ops | utilisation | area each (um2) | "
       "STA Fmax (MHz) |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (int u = 0; u < kUnits; ++u) {
    const UnitCfg& k = c.units[u];
    if (!s.unit_ops[u]) {
      o << "| " << unit_name(static_cast<Unit>(u)) << " | not used by this scene: not instantiated | | | | | | |\n";
      continue;
    }
    o << "| " << unit_name(static_cast<Unit>(u)) << " | " << k.latency << " | " << k.count << " | " << k.width << " | "
      << s.unit_ops[u] << " | " << num(100 * s.utilisation(c, static_cast<Unit>(u)), "%.1f") << " % | "
      << num(k.area, "%.0f") << " | " << (k.fmax_mhz > 0 ? num(k.fmax_mhz, "%.1f") : std::string("not timed")) << " |\n";
  }
  o << "\n## Area model (um2; units: osu018 cell area before placement, NAND2X1 = " << num(c.nand2_um2, "%g")
    << " um2; memories: CACTI's " << num(c.sram_cell_f2, "%g") << " F^2 SRAM cell at F = " << num(c.feature_um, "%g")
    << " um, grown per port, / array efficiency " << num(c.array_efficiency, "%g") << ", docs/TRAX.md \"Memories\")\n\n| item | count | each | total | |\n|---|---:|---:|---:|---|\n";
  for (const auto& it : r.area.items)
    o << "| " << it.name << " | " << num(it.count, "%g") << " | " << num(it.each, "%.0f") << " | "
      << num(it.total(), "%.0f") << " | " << (it.estimate ? "estimate" : "measured") << " |\n";
  o << "| **total** | | | **" << num(r.area.total, "%.0f") << "** | " << num(r.area.estimated, "%.0f")
    << " estimated |\n";
  if (!r.area_sources.empty()) {
    o << "\nUnit areas (docs/TRAX.md \"Area model\"; rows of model/data/trax/areas.json):\n\n";
    for (const auto& a : r.area_sources)
      if (a.how != "configured")
        o << "- " << a.unit << ": " << a.how
          << (a.fmax_mhz > 0 ? ", Fmax " + num(a.fmax_mhz, "%.1f") + " MHz (" + a.fmax_how + ")" : std::string(", not timed"))
          << (a.detail.empty() ? "" : " -- `" + a.detail + "`") << "\n";
  }
  o << "\n## Memory access energy (estimate: Horowitz's 45 nm constants, " << num(c.sram_pj_64b_8kib, "%g")
    << " pJ per 64 bits at 8 KiB x (C / 8 KiB)^" << num(c.sram_capacity_exponent, "%g") << ", DRAM "
    << num(c.dram_pj_per_bit, "%g") << " pJ/bit; docs/TRAX.md \"Memory access energy\")\n\n"
    << "| structure | accesses | pJ each | total (uJ) | share |\n|---|---:|---:|---:|---:|\n";
  for (const auto& it : r.energy.items)
    o << "| " << it.name << " | " << it.accesses << " | " << num(it.pj_each, "%.3g") << " | " << num(it.total() / 1e6, "%.4g")
      << " | " << num(r.energy.total_pj > 0 ? 100 * it.total() / r.energy.total_pj : 0, "%.1f") << " % |\n";
  o << "| **total** | | | **" << num(r.energy.total_pj / 1e6, "%.4g") << "** (" << num(r.rays() ? r.energy.total_pj / r.rays() : 0, "%.4g")
    << " pJ per ray) | |\n";
  o << "\n## Instruction mix\n\n| op | count |\n|---|---:|\n";
  for (int i = 0; i < kOps; ++i)
    if (s.op_count[i]) o << "| " << op_name(static_cast<Op>(i)) << " | " << s.op_count[i] << " |\n";
  return o.str();
}

}  // namespace ru::trax
