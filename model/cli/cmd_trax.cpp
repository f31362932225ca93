// rayunits trax: the TRaX-style processor model running the renderer's ray tracer.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli_util.hpp"
#include "render_common.hpp"
#include "rayunits/trax/trax.hpp"

namespace ru::cli {
namespace {

int run_trax_cmd(int argc, char** argv) {
  CLI::App app{"Simulate a TRaX-style chip (thread processors, shared pipelined units, caches, DRAM) running the "
               "renderer's ray tracer; writes image.png, summary.json, summary.md"};
  SceneArgs sa;
  sa.add(app);
  std::string config_path, format, tri, traversal, size = "32x32", out;
  bool quiet = false;
  app.add_option("--config", config_path, "TOML configuration (model/data/trax/default.toml documents every key)");
  app.add_option("--format", format, "number format: float | eXmY[-ftz] (overrides chip.format)");
  app.add_option("--tri", tri, "ray-triangle unit: robust | mt (overrides chip.tri)");
  app.add_option("--traversal", traversal, "stack | stackless (overrides chip.traversal)");
  app.add_option("--size", size, "image size WxH (or N)");
  app.add_option("--out", out, "output directory")->required();
  app.add_flag("--quiet", quiet, "no progress lines");
  if (!parse_args(app, argc, argv)) return 0;

  trax::Config cfg;
  try {
    cfg = config_path.empty() ? trax::default_config() : trax::load_config(config_path);
    if (!format.empty()) cfg.format = format;
    if (!tri.empty()) {
      if (tri != "robust" && tri != "mt") throw UsageError("unknown --tri '" + tri + "' (accepted: robust, mt)");
      cfg.tri = tri;
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
  if (!quiet)
    std::fprintf(stderr, "trax: %s %dx%d, %d TMs x %d TPs, %s, %s traversal\n", s.name.c_str(), w, h, cfg.tms,
                 cfg.tps_per_tm, cfg.format.c_str(), cfg.traversal.c_str());
  const trax::TraxResult r = trax::run_trax(s, cfg, w, h, !quiet);
  render::write_png(out + "/image.png", r.image);
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream f(out + "/" + name, std::ios::binary);
    f << text;
    if (!f) throw UsageError("cannot write '" + out + "/" + name + "'");
  };
  write("summary.json", trax::summary_json(r, s.name, command));
  write("summary.md", trax::summary_md(r, s.name, command));
  write("config.toml", trax::to_toml(cfg));
  std::printf("wrote %s/image.png, summary.json, summary.md, config.toml\n", out.c_str());
  std::printf("instructions %llu (issue rate %.3f), L1 hit %.2f %%, L2 hit %.2f %%, simulated in %.2f s (%.2f M instr/s)\n",
              (unsigned long long)r.sim.instructions, r.sim.issue_rate(cfg), 100 * r.sim.l1.hit_rate(),
              100 * r.sim.l2.hit_rate(), r.sim.host_seconds,
              r.sim.host_seconds > 0 ? r.sim.instructions / r.sim.host_seconds / 1e6 : 0.0);
  std::printf("%s\n", trax::summary_line(r).c_str());
  return 0;
}

}  // namespace

RU_COMMAND("trax", "simulate a TRaX-style ray-tracing chip on a scene (cycles, rays/s, utilisation, area)",
           run_trax_cmd);

}  // namespace ru::cli
