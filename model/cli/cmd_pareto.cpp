// `rayunits pareto`: non-dominated points of measured result rows (rayunits/pareto/pareto.hpp),
// the cheapest point meeting a target, and a scene profile's cheapest format.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli_util.hpp"
#include "rayunits/pareto/pareto.hpp"
#include "rayunits/report/report.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/process.hpp"

namespace ru::cli {
namespace {

namespace fs = std::filesystem;

int run_pareto(int argc, char** argv) {
  CLI::App app{
      "Pareto fronts of measured rows: per group (default: per unit) the points no other point beats on every "
      "axis (error, area, clock or throughput), the cheapest point meeting a target, and with --profile the "
      "cheapest format a scene tolerates. Inputs: `rayunits sweep` directories, .jsonl (synth --json rows), "
      ".json arrays, .csv tables (e.g. docs/trax/trax_formats.csv). Axis aliases: area (area_um2, area_mm2, "
      "area_nand2), fmax (fmax_mhz, rays_per_s, clock_mhz, fmax_est_mhz), error (error_pct, error_fraction, "
      "unit_roundoff = the format's rounding-error bound 2^-(M+1)). docs/PARETO.md."};
  std::vector<std::string> inputs, where, targets, unit_targets, by, label;
  std::string x = "error", y = "area", z = "fmax", out, profile, title, plot_axes = "1,2";
  bool two_d = false, all = false, no_plot = false;
  app.add_option("inputs", inputs, "sweep directories, .jsonl, .json or .csv files")->required();
  app.add_option("--x", x, "first axis FIELD[:min|max] (default error)");
  app.add_option("--y", y, "second axis, the cost of --target and --profile (default area)");
  app.add_option("--z", z, "third axis (default fmax); --2d leaves it out");
  app.add_flag("--2d", two_d, "a front on --x and --y only");
  app.add_option("--by", by, "group by these fields (comma-separated; default: unit when rows have one)")
      ->delimiter(',');
  app.add_option("--where", where, "keep rows with FIELD=VALUE (repeatable)");
  app.add_option("--label", label, "fields that name a point (comma-separated)")->delimiter(',');
  app.add_option("--target", targets, "FIELD>=V or FIELD<=V (repeatable): the cheapest point per group meeting all");
  app.add_option("--profile", profile,
                 "a `rayunits profile --json` file: the cheapest format whose measured image error meets the "
                 "profile's target, summed over the units the scene needs");
  app.add_option("--unit-target", unit_targets,
                 "with --profile: a per-unit row condition, e.g. fmax_mhz>=100 (repeatable)");
  app.add_flag("--all", all, "list dominated points too");
  app.add_option("--out", out, "write pareto.csv, pareto.md and pareto.png (plot) into DIR");
  app.add_option("--title", title, "plot title");
  app.add_flag("--no-plot", no_plot, "with --out: no pareto.png");
  app.add_option("--plot-axes", plot_axes, "I,J: the axes (1-based) on the plot's x and y; the other is colour")
      ->check([](const std::string& v) {
        return v == "1,2" || v == "2,1" || v == "1,3" || v == "3,1" || v == "2,3" || v == "3,2"
                   ? std::string()
                   : std::string("accepted: 1,2 2,1 1,3 3,1 2,3 3,2");
      });
  if (!parse_args(app, argc, argv)) return 0;

  pareto::Options o;
  try {
    o.axes.push_back(pareto::parse_axis(x));
    o.axes.push_back(pareto::parse_axis(y));
    if (!two_d) o.axes.push_back(pareto::parse_axis(z));
    if (two_d && plot_axes != "1,2" && plot_axes != "2,1") throw UsageError("--plot-axes " + plot_axes + ": --2d has axes 1 and 2 only");
    for (const auto& w : where) {
      const auto eq = w.find('=');
      if (eq == std::string::npos || eq == 0) throw UsageError("--where '" + w + "': accepted: FIELD=VALUE");
      o.where.push_back({w.substr(0, eq), w.substr(eq + 1)});
    }
    o.group_by = by;
    o.label = label;
    std::vector<pareto::Target> ts, uts;
    for (const auto& t : targets) ts.push_back(pareto::parse_target(t));
    for (const auto& t : unit_targets) uts.push_back(pareto::parse_target(t));
    if (!uts.empty() && profile.empty()) throw UsageError("--unit-target needs --profile");

    std::vector<pareto::Row> rows;
    for (const auto& in : pareto::expand_inputs(inputs)) {
      auto r = pareto::load_rows(in);
      rows.insert(rows.end(), std::make_move_iterator(r.begin()), std::make_move_iterator(r.end()));
    }
    if (rows.empty()) throw UsageError("no rows in the inputs (a sweep directory counts its ok jobs only)");
    const pareto::Result res = pareto::compute(rows, o);
    std::string md = "# Pareto fronts\n\n`" + command_line("rayunits pareto", argc, argv) + "`\n\n";
    md += pareto::front_markdown(res, rows, all);
    if (!ts.empty()) md += pareto::picks_markdown(res, rows, ts, pareto::cheapest(res, rows, ts, 1)) + "\n";
    if (!profile.empty()) {
      nlohmann::json pj;
      try {
        pj = nlohmann::json::parse(synth::read_file(profile));
      } catch (const nlohmann::json::exception& e) {
        throw UsageError("--profile " + profile + ": not JSON (" + e.what() + ")");
      }
      md += "### Cheapest format for the scene\n\n" +
            pareto::plan_markdown(pareto::plan_from_profile(pj, rows, o.axes[1], uts), rows) + "\n";
    }
    std::fputs(md.c_str(), stdout);
    if (!out.empty()) {
      fs::create_directories(out);
      const std::string csv = (fs::path(out) / "pareto.csv").string();
      synth::write_file_atomic(csv, pareto::points_csv(res, rows));
      synth::write_file_atomic((fs::path(out) / "pareto.md").string(), md);
      std::fprintf(stderr, "wrote %s and pareto.md\n", csv.c_str());
      if (!no_plot) {
        const std::string png = (fs::path(out) / "pareto.png").string();
        const std::string tmp = png + ".tmp.png";
        std::vector<std::string> cmd = {report::find_python(), (report::scripts_dir() / "plot_pareto.py").string(),
                                        csv, tmp};
        cmd.push_back("--axes=" + plot_axes);
        if (!title.empty()) cmd.push_back("--title=" + title);
        const int rc = util::run_foreground(cmd);
        if (rc != 0) {
          std::error_code ec;
          fs::remove(tmp, ec);
          throw UsageError("plot failed (scripts/plot_pareto.py exit status " + std::to_string(rc) +
                           "; its messages are above); pareto.csv and pareto.md are written (--no-plot skips the plot)");
        }
        fs::rename(tmp, png);
        std::fprintf(stderr, "wrote %s\n", png.c_str());
      }
    }
  } catch (const pareto::ParetoError& e) {
    throw UsageError(e.what());
  } catch (const report::ReportError& e) {
    throw UsageError(e.what());
  }
  return 0;
}

}  // namespace

RU_COMMAND("pareto", "Pareto fronts (error x area x clock) of result rows; cheapest point meeting a target",
           run_pareto);

}  // namespace ru::cli
