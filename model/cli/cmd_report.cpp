// rayunits report: the main job. Runs the report sections and writes a report directory.
#include <cstdio>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/num/format.hpp"
#include "rayunits/report/accuracy.hpp"
#include "rayunits/report/report.hpp"

namespace ru::cli {
namespace {

// "5..11" or "7" -> [lo, hi]
void parse_range(const std::string& text, const char* what, int min, int max, int& lo, int& hi) {
  std::string a = text, b = text;
  auto p = text.find("..");
  if (p != std::string::npos) {
    a = text.substr(0, p);
    b = text.substr(p + 2);
  }
  auto to_int = [&](const std::string& s, int& out) {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 4) return false;
    out = std::stoi(s);
    return true;
  };
  if (!to_int(a, lo) || !to_int(b, hi) || lo > hi || lo < min || hi > max)
    throw UsageError(std::string("bad ") + what + " range '" + text + "'; expected LO..HI or N with " +
                     std::to_string(min) + " <= LO <= HI <= " + std::to_string(max));
}

int run_report(int argc, char** argv) {
  CLI::App app{
      "Run the main job: measure the reduced-precision units and write a report directory "
      "(index.md, meta.json, CSV, PNG plots). Needs python3 with matplotlib for the plots. "
      "The report is written to a temporary directory next to --out and moved into place when "
      "complete; an existing --out is replaced only if an earlier report run wrote it.",
      "rayunits report"};
  ru::report::Options o;
  std::string out = "report", exp_range = "5..11", frac_range = "8..24";
  std::vector<std::string> params;
  bool list = false;
  app.add_option("--out", out, "report directory (default: report, under the current directory)");
  app.add_option("--seed", o.seed, "workload seed (default 1)");
  app.add_option("--threads", o.threads, "worker threads (default: all cores)");
  app.add_option("--exp", exp_range, "exponent widths E as LO..HI (default 5..11; 2..11)");
  app.add_option("--frac", frac_range, "fraction widths M as LO..HI (default 8..24; 1..52)");
  app.add_option("--samples", o.samples,
                 "operand sets per operation (default " + std::to_string(ru::report::kAccuracyDefaultSamples) + ")");
  app.add_option("--sections", o.sections, "comma-separated section ids (default: all)")->delimiter(',');
  app.add_option("--param", params, "section parameter KEY=VALUE (e.g. accuracy.emin=-33), repeatable");
  app.add_flag("--list-sections", list, "list the report sections and exit");
  app.add_flag("--quiet", o.quiet, "no progress on stderr");
  bool no_plots = false;
  app.add_flag("--no-plots", no_plots, "skip the PNG plots (Markdown and CSV only; no python needed)");
  app.add_flag("--live-synth", o.live_synth,
               "synthesize every cell-flow row of the synthesis and noise sections now (default: read the checked-in "
               "rows of sweeps/results/default and synth/results/cell whose rtl_hash matches the current RTL)");
  app.add_option("--checked-in", o.checked_in,
                 "checked-in results to read instead (a results.jsonl / *.jsonl file or a directory), repeatable; "
                 "replaces the defaults");
  if (!parse_args(app, argc, argv)) return 0;

  if (list) {
    for (const auto& s : ru::report::sections())
      std::printf("%-12s %s%s\n", s.id, s.title, s.default_on ? "" : " (not run by default)");
    return 0;
  }
  parse_range(exp_range, "--exp", ru::num::Format::kMinExp, ru::num::Format::kMaxExp, o.exp_lo, o.exp_hi);
  parse_range(frac_range, "--frac", ru::num::Format::kMinFrac, ru::num::Format::kMaxFrac, o.frac_lo, o.frac_hi);
  if (app.count("--samples") && o.samples < 1) throw UsageError("--samples must be >= 1");
  if (o.samples > 100000000) throw UsageError("--samples must be <= 100000000");
  if (app.count("--threads") && (o.threads < 1 || o.threads > 1024)) throw UsageError("--threads must be 1..1024");
  if (out.empty()) throw UsageError("--out must not be empty");
  for (const auto& p : params) {
    auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError("bad --param '" + p + "'; expected KEY=VALUE");
    o.params[p.substr(0, eq)] = p.substr(eq + 1);
  }
  o.out_dir = out;
  o.plots = !no_plots;
  o.command = command_line("rayunits report", argc, argv);

  ru::report::Summary s = ru::report::run_report(o);
  std::fprintf(stderr, "report: done in %.1f s\n", s.seconds);
  std::printf("report written to %s/index.md\n", s.dir.string().c_str());
  return 0;
}

}  // namespace

RU_COMMAND("report", "run the main job and write a report (Markdown, CSV, plots)", run_report);

}  // namespace ru::cli
