// rayunits study box: false misses and false hits of the plain and the conservative ray-box
// test against the exact slab test, per (exponent, fraction) width (units/study.hpp).
#include <chrono>
#include <cstdio>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "studies.hpp"
#include "rayunits/units/study.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::cli {
namespace {

using namespace ru::units;

double ppm(uint64_t n, uint64_t d) { return d ? 1e6 * static_cast<double>(n) / static_cast<double>(d) : 0; }

int run_study_box(int argc, char** argv) {
  CLI::App app{
      "False misses / false hits of the ray-box unit (plain: round to nearest; conservative: directed "
      "rounding) against the exact slab test on the same format-rounded inputs, per exponent/fraction "
      "width; then against the ray direction d itself (the unit given inv = RNE(1/d) in the format, as the "
      "renderer does), with the d-conservative mode (reciprocal bounds). Counts are per million ray-box "
      "pairs. Also writes a CSV.",
      "rayunits study box"};
  BoxStudyArgs a;
  app.add_option("--trace", a.trace_file, "binary trace (docs/UNITS.md); its box records are used");
  app.add_option("--synthetic", a.synthetic, "use N synthetic ray-box pairs (default 20000 when no --trace)");
  app.add_option("--seed", a.seed, "seed of the synthetic trace")->capture_default_str();
  app.add_option("--scale", a.scale, "scale of the synthetic scene")->capture_default_str();
  app.add_option("--write-trace", a.write_trace_file, "also write the synthetic trace to this file");
  app.add_option("--limit", a.limit, "use only the first N records");
  app.add_option("--exp", a.exp_text, "exponent bits LO:HI")->capture_default_str();
  app.add_option("--frac", a.frac_text, "fraction bits LO:HI")->capture_default_str();
  app.add_option("--max-width", a.max_width, "skip formats wider than this")->capture_default_str();
  app.add_flag("--ftz", a.ftz, "flush-to-zero formats");
  app.add_option("--threads", a.threads, "worker threads")->capture_default_str()->check(CLI::Range(1, 64));
  app.add_option("--csv", a.csv, "CSV output file")->capture_default_str();
  app.add_flag("--quiet", a.quiet, "no progress on stderr");
  if (!parse_args(app, argc, argv)) return 0;
  run_box_study(a, command_line("rayunits study box", argc, argv), stdout, stderr);
  return 0;
}

}  // namespace

BoxStudyRun run_box_study(const BoxStudyArgs& args, const std::string& command, std::FILE* out, std::FILE* err) {
  std::string trace_file = args.trace_file, write_trace_file = args.write_trace_file, csv = args.csv;
  size_t synthetic = args.synthetic, limit = args.limit;
  const uint64_t seed = args.seed;
  const double scale = args.scale;
  const int threads = args.threads, max_width = args.max_width;
  const bool ftz = args.ftz, quiet = args.quiet;
  if (!trace_file.empty() && synthetic) throw UsageError("give either --trace or --synthetic, not both");
  int elo, ehi, mlo, mhi;
  parse_range(args.exp_text, "--exp", elo, ehi);
  parse_range(args.frac_text, "--frac", mlo, mhi);
  BoxStudyOptions opt;
  opt.formats = format_grid(elo, ehi, mlo, mhi, max_width, !ftz);
  opt.threads = threads;

  std::vector<BoxRecord> recs;
  std::string source;
  if (!trace_file.empty()) {
    recs = read_trace(trace_file).boxes;
    if (recs.empty()) throw UsageError("trace " + trace_file + " holds no ray-box records");
    source = "trace " + trace_file;
  } else {
    if (!synthetic) synthetic = 20000;
    SynthBoxOptions so;
    so.seed = seed;
    so.scale = scale;
    so.boxes = (synthetic + so.rays_per_packet - 1) / so.rays_per_packet;
    recs = synth_box(so);
    recs.resize(synthetic);
    source = "synthetic trace (" + std::to_string(synthetic) + " pairs, seed " + std::to_string(seed) + ", scale " +
             decimal(scale) + ")";
    if (!write_trace_file.empty()) {
      Trace t;
      t.boxes = recs;
      write_trace(write_trace_file, t);
    }
  }
  if (limit && recs.size() > limit) recs.resize(limit);
  const auto t0 = std::chrono::steady_clock::now();
  if (!quiet)
    opt.progress = [&](size_t done, size_t total, const BoxCell& c) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(err, "[study box] %zu/%zu formats  (%s)  %.1f s\n", done, total, c.fmt.name().c_str(), s);
    };
  std::vector<BoxCell> cells = study_box(recs, opt);

  std::fprintf(out, "rayunits study box: %s\n", command.c_str());
  std::fprintf(out, "source: %s; %zu records\n", source.c_str(), recs.size());
  std::fprintf(out, "per million pairs; FM = false miss (exact hit, unit missed), FH = false hit\n");
  std::fprintf(out, "%-10s %9s %8s %10s %10s %10s %10s %10s\n", "format", "pairs", "hit %", "plain FM", "plain FH",
              "cons FM", "cons FH", "overflows");
  std::FILE* f = std::fopen(csv.c_str(), "w");
  if (!f) throw UsageError("cannot write " + csv);
  std::fprintf(f, "# %s\n# %s\n", command.c_str(), source.c_str());
  std::fprintf(f, "format,exponent_bits,significand_bits,pairs,exact_hits,plain_false_miss,plain_false_hit,"
                  "cons_false_miss,cons_false_hit,overflow_ops,dir_pairs,dir_exact_hits,dir_plain_false_miss,"
                  "dir_plain_false_hit,dir_cons_false_miss,dir_cons_false_hit,dir_dcons_false_miss,"
                  "dir_dcons_false_hit\n");
  for (const BoxCell& c : cells) {
    std::fprintf(out, "%-10s %9llu %8.2f %10.1f %10.1f %10.1f %10.1f %10llu\n", c.fmt.name().c_str(),
                static_cast<unsigned long long>(c.records), 100.0 * static_cast<double>(c.exact_hits) / static_cast<double>(c.records ? c.records : 1),
                ppm(c.plain_false_miss, c.records), ppm(c.plain_false_hit, c.records), ppm(c.cons_false_miss, c.records),
                ppm(c.cons_false_hit, c.records), static_cast<unsigned long long>(c.flags.overflow));
    std::fprintf(f, "%s,%d,%d,%llu,%llu,%llu,%llu,%llu,%llu,%llu", c.fmt.name().c_str(), c.fmt.exp_bits,
                 c.fmt.frac_bits, static_cast<unsigned long long>(c.records),
                 static_cast<unsigned long long>(c.exact_hits), static_cast<unsigned long long>(c.plain_false_miss),
                 static_cast<unsigned long long>(c.plain_false_hit), static_cast<unsigned long long>(c.cons_false_miss),
                 static_cast<unsigned long long>(c.cons_false_hit), static_cast<unsigned long long>(c.flags.overflow));
    for (uint64_t v : {c.dir_records, c.dir_exact_hits, c.dir_plain_false_miss, c.dir_plain_false_hit,
                       c.dir_cons_false_miss, c.dir_cons_false_hit, c.dir_dcons_false_miss, c.dir_dcons_false_hit})
      std::fprintf(f, ",%llu", static_cast<unsigned long long>(v));
    std::fprintf(f, "\n");
  }
  // Against the direction d: what the renderer's pairs see (inv = RNE(1/d) in the format).
  std::fprintf(out, "\nagainst the ray direction d (the unit gets inv = RNE(1/d) in the format; exact slab test on d):\n");
  std::fprintf(out, "%-10s %9s %10s %10s %10s %10s %10s %10s\n", "format", "pairs", "plain FM", "plain FH", "cons FM",
               "cons FH", "d-cons FM", "d-cons FH");
  for (const BoxCell& c : cells)
    std::fprintf(out, "%-10s %9llu %10.1f %10.1f %10.1f %10.1f %10.1f %10.1f\n", c.fmt.name().c_str(),
                 static_cast<unsigned long long>(c.dir_records), ppm(c.dir_plain_false_miss, c.dir_records),
                 ppm(c.dir_plain_false_hit, c.dir_records), ppm(c.dir_cons_false_miss, c.dir_records),
                 ppm(c.dir_cons_false_hit, c.dir_records), ppm(c.dir_dcons_false_miss, c.dir_records),
                 ppm(c.dir_dcons_false_hit, c.dir_records));
  std::fclose(f);
  std::fprintf(out, "wrote %s\n", csv.c_str());
  return {cells, source, recs.size()};
}


RU_COMMAND("study box", "false misses / hits of the plain and conservative ray-box test", run_study_box);

}  // namespace ru::cli
