// rayunits trax: the TRaX-style processor model running the renderer's ray tracer.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include <memory>
#include <set>

#include "cli_util.hpp"
#include "render_common.hpp"
#include "rayunits/rtl/cache.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/trax/cosim.hpp"
#include "rayunits/trax/trax.hpp"

namespace ru::cli {
namespace {

int run_trax_cmd(int argc, char** argv) {
  CLI::App app{"Simulate a TRaX-style chip (thread processors, shared pipelined units, caches, DRAM) running the "
               "renderer's ray tracer; writes image.png, summary.json, summary.md"};
  SceneArgs sa;
  sa.add(app);
  std::string config_path, format, tri, noise, traversal, size = "32x32", out, profile_path;
  bool quiet = false, cosim = false, cosim_build = false, cosim_fp = false;
  std::set<std::string> profile_units;
  int64_t cosim_inject = -1;
  app.add_option("--config", config_path, "TOML configuration (model/data/trax/default.toml documents every key)");
  app.add_option("--from-profile", profile_path,
                 "JSON of `rayunits profile --json`: its recommended format, triangle algorithm, BVH and unit set "
                 "(--format / --tri given too override it)");
  app.add_option("--format", format, "number format: float | eXmY[-ftz] (overrides chip.format)");
  app.add_option("--tri", tri, "ray-triangle unit: robust | mt (overrides chip.tri)");
  app.add_option("--noise", noise,
                 "noise unit: fixed-trunc (ru_noise_trunc) | fixed (ru_noise, the baseline) | float (no unit) "
                 "(overrides chip.noise)");
  app.add_option("--traversal", traversal, "stack | stackless (overrides chip.traversal)");
  app.add_option("--size", size, "image size WxH (or N)");
  app.add_option("--out", out, "output directory")->required();
  app.add_flag("--quiet", quiet, "no progress lines");
  app.add_flag("--cosim", cosim,
               "co-simulate the box, triangle and noise units with their Verilated RTL (tb_trax_cosim next to "
               "this binary, or $RU_TRAX_COSIM): every result compared bit for bit");
  app.add_flag("--cosim-build", cosim_build,
               "--cosim against a companion with exactly this chip's box, triangle and noise configurations (format, "
               "Stages), built or reused from the rtl build cache ($RU_RTL_CACHE, docs/SWEEPS.md)");
  app.add_flag("--cosim-fp", cosim_fp,
               "with --cosim (implied): co-simulate the FP units too (fp_add, fp_mul, fp_div, fp_sqrt, fp_cmp, and fp_fma with chip.fma: every "
               "FP operation of the kernel compared with their Verilated RTL)");
  app.add_option("--cosim-inject", cosim_inject,
                 "test only: flip bit 0 of the golden result of the N-th co-simulated operation (must be caught)");
  std::string cosim_inject_op;
  app.add_option("--cosim-inject-op", cosim_inject_op,
                 "test only: with --cosim-inject, count only operations of this class (an operation with an operand "
                 "record: box, tri, noise, fadd, ...)");
  if (!parse_args(app, argc, argv)) return 0;

  trax::Config cfg;
  try {
    cfg = config_path.empty() ? trax::default_config() : trax::load_config(config_path);
    if (!profile_path.empty()) {
      std::ifstream pf(profile_path);
      if (!pf) throw UsageError("--from-profile: cannot open '" + profile_path + "'");
      nlohmann::json pj;
      try {
        pj = nlohmann::json::parse(pf);
        const auto& rf = pj.at("recommended_format");
        if (rf.is_null())
          throw UsageError("--from-profile " + profile_path + ": the profile recommends no format (none met its target)");
        cfg.format = rf.get<std::string>();
        cfg.tri = pj.at("tri").get<std::string>();
        cfg.bvh = pj.at("bvh").get<std::string>();
        for (const auto& u : pj.at("units")) profile_units.insert(u.get<std::string>());
      } catch (const nlohmann::json::exception& e) {
        throw UsageError("--from-profile " + profile_path + ": not a `rayunits profile --json` file (" + e.what() + ")");
      }
      if (cfg.tri != "robust" && cfg.tri != "mt")
        throw UsageError("--from-profile " + profile_path + ": unknown tri '" + cfg.tri + "'");
      if (!quiet)
        std::fprintf(stderr, "trax: from profile %s: format %s, tri %s, bvh %s, %zu units\n", profile_path.c_str(),
                     cfg.format.c_str(), cfg.tri.c_str(), cfg.bvh.c_str(), profile_units.size());
    }
    if (!format.empty()) cfg.format = format;
    if (!tri.empty()) {
      if (tri != "robust" && tri != "mt") throw UsageError("unknown --tri '" + tri + "' (accepted: robust, mt)");
      cfg.tri = tri;
    }
    if (!noise.empty()) {
      if (noise != "fixed-trunc" && noise != "fixed" && noise != "float")
        throw UsageError("unknown --noise '" + noise + "' (accepted: fixed-trunc, fixed, float)");
      cfg.noise = noise;
    }
    if (!traversal.empty()) {
      if (traversal != "stack" && traversal != "stackless")
        throw UsageError("unknown --traversal '" + traversal + "' (accepted: stack, stackless)");
      cfg.traversal = traversal;
    }
    if (cfg.format != "float") ru::num::Format::parse(cfg.format).validate();  // FormatError: one line
    cfg.validate(config_path.empty() ? "built-in defaults" : config_path);
  } catch (const trax::ConfigError& e) {
    throw UsageError(e.what());
  }
  int w = 0, h = 0;
  parse_size(size, &w, &h);
  const scene::Scene s = sa.load();
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) throw UsageError("cannot create output directory '" + out + "': " + ec.message());

  std::string command = "rayunits trax";
  for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
  if (cosim_build || cosim_fp) cosim = true;
  if (cosim_inject >= 0 && !cosim) throw UsageError("--cosim-inject needs --cosim");
  int inject_op = -1;
  if (!cosim_inject_op.empty()) {
    if (cosim_inject < 0) throw UsageError("--cosim-inject-op needs --cosim-inject");
    // the co-simulated operations: those with an operand record (trax::unit_inputs), the texture
    // unit excepted (not co-simulated in a chip run)
    std::string accepted;
    for (int i = 0; i < trax::kOps; ++i) {
      const auto op = static_cast<trax::Op>(i);
      if (trax::unit_inputs(op) == 0 || op == trax::Op::Texture) continue;
      accepted += (accepted.empty() ? "" : ", ") + std::string(trax::op_name(op));
      if (cosim_inject_op == trax::op_name(op)) inject_op = i;
    }
    if (inject_op < 0)
      throw UsageError("--cosim-inject-op: unknown operation '" + cosim_inject_op + "' (accepted: " + accepted + ")");
  }
  std::unique_ptr<trax::cosim::Client> client;
  if (cosim) {
    trax::Config rc;
    try {
      rc = trax::resolve_config(cfg);
    } catch (const trax::ConfigError& e) {
      throw UsageError(e.what());
    }
    std::string companion = trax::cosim::default_executable();
    if (cosim_build) {
      rtl::CosimRequest req;
      req.units = trax::cosim::companion_units(rc, cosim_fp);
      if (!quiet) req.progress = [](const std::string& l) { std::fprintf(stderr, "%s\n", l.c_str()); };
      synth::install_interrupt_handler();
      companion = rtl::ensure_cosim(req).exe;
    }
    client = std::make_unique<trax::cosim::Client>(companion, cosim_inject, cosim_fp, inject_op);
    try {
      client->start(rc);
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
    if (!quiet) std::fprintf(stderr, "trax: co-simulating %s\n", client->started_line().c_str());
  }
  if (!quiet)
    std::fprintf(stderr, "trax: %s %dx%d, %d TMs x %d TPs, %s, %s traversal\n", s.name.c_str(), w, h, cfg.tms,
                 cfg.tps_per_tm, cfg.format.c_str(), cfg.traversal.c_str());
  trax::TraxResult r;
  try {
    r = trax::run_trax(s, cfg, w, h, !quiet, client.get());
  } catch (const trax::ConfigError& e) {
    throw UsageError(e.what());
  }
  if (!profile_units.empty()) {
    // The profile's unit set is what the chip has: the kernel must not need any other unit.
    for (int u = 0; u < trax::kUnits; ++u) {
      if (!r.sim.unit_ops[u]) continue;
      const trax::Unit un = static_cast<trax::Unit>(u);
      std::string name = trax::unit_name(un);
      if (un == trax::Unit::Box) name = "ray_box";
      if (un == trax::Unit::Tri) name = r.cfg.tri == "mt" ? "ray_tri_mt" : "ray_tri_robust";
      if (un == trax::Unit::Conv || un == trax::Unit::Int || un == trax::Unit::Branch) continue;  // TP datapath
      if (!profile_units.count(name))
        throw UsageError("--from-profile " + profile_path + ": the kernel issued " + std::to_string(r.sim.unit_ops[u]) +
                         " operations on " + name + ", which the profile's unit set does not have");
    }
  }
  std::string cosim_line;
  if (client) {
    const trax::cosim::Outcome o = client->finish(r.sim.cycles);
    if (!o.ok) {
      std::fprintf(stderr, "rayunits trax: RTL co-simulation failed (run stopped at cycle %llu):\n%s\n",
                   (unsigned long long)r.sim.cycles, o.summary.c_str());
      return 1;
    }
    const size_t b = o.summary.find(" box=");
    cosim_line = "cosim: " + std::to_string(o.compared) + " unit results equal to the RTL bit for bit (" +
                 (b == std::string::npos ? o.summary : o.summary.substr(b + 1)) + ")";
  }
  render::write_png(out + "/image.png", r.image);
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream f(out + "/" + name, std::ios::binary);
    f << text;
    if (!f) throw UsageError("cannot write '" + out + "/" + name + "'");
  };
  write("summary.json", trax::summary_json(r, s.name, command));
  write("summary.md", trax::summary_md(r, s.name, command) + (cosim_line.empty() ? "" : "\n" + cosim_line + "\n"));
  write("config.toml", trax::to_toml(r.cfg));  // resolved: "rtl" latencies, "synth" areas filled in
  std::printf("wrote %s/image.png, summary.json, summary.md, config.toml\n", out.c_str());
  std::printf("instructions %llu (issue rate %.3f), L1 hit %.2f %%, L2 hit %.2f %%, simulated in %.2f s (%.2f M instr/s)\n",
              (unsigned long long)r.sim.instructions, r.sim.issue_rate(cfg), 100 * r.sim.l1.hit_rate(),
              100 * r.sim.l2.hit_rate(), r.sim.host_seconds,
              r.sim.host_seconds > 0 ? r.sim.instructions / r.sim.host_seconds / 1e6 : 0.0);
  if (!cosim_line.empty()) std::printf("%s\n", cosim_line.c_str());
  std::printf("%s\n", trax::summary_line(r).c_str());
  return 0;
}

}  // namespace

RU_COMMAND("trax", "simulate a TRaX-style ray-tracing chip on a scene (cycles, rays/s, utilisation, area)",
           run_trax_cmd);

}  // namespace ru::cli
