// rayunits study box: false misses and false hits of the plain and the conservative ray-box
// test against the exact slab test, per (exponent, fraction) width, and of the three modes against
// the ray direction d, on a trace or synthetic pairs plus adversarial pairs (units/study.hpp).
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

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
      "pairs. Records: a trace or synthetic pairs, plus --adversarial pairs per format. Also writes a CSV "
      "(one row per format and part: synthetic or trace, adversarial, all). Progress on stderr.",
      "rayunits study box"};
  BoxStudyArgs a;
  app.add_option("--trace", a.trace_file, "binary trace (docs/UNITS.md); its box records are used");
  app.add_option("--synthetic", a.synthetic, "use N synthetic ray-box pairs (default 20000 when no --trace)");
  app.add_option("--adversarial", a.adversarial,
                 "add N adversarial pairs per format, generated for that format (rays aimed exactly at box "
                 "corners, edges and faces, grazing rays with +-0 direction components, boxes of size 2^-4..2^4; "
                 "seed: --seed + 1); the d table and the CSV (column part) show them apart")
      ->check(CLI::Range(size_t(0), size_t(1) << 40));
  app.add_option("--seed", a.seed, "seed of the synthetic trace")->capture_default_str();
  app.add_option("--scale", a.scale, "scale of the synthetic scene")->capture_default_str();
  app.add_option("--write-trace", a.write_trace_file, "also write the synthetic trace to this file");
  app.add_option("--limit", a.limit, "use only the first N records");
  app.add_option("--exp", a.exp_text, "exponent bits LO:HI")->capture_default_str();
  app.add_option("--frac", a.frac_text, "fraction bits LO:HI")->capture_default_str();
  app.add_option("--max-width", a.max_width, "skip formats wider than this")->capture_default_str();
  app.add_option("--formats", a.formats,
                 "comma-separated formats (e.g. e5m10,e8m23,e11m52) instead of the --exp/--frac grid "
                 "(--max-width and --ftz do not apply)");
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
  if (args.formats.empty()) {
    opt.formats = format_grid(elo, ehi, mlo, mhi, max_width, !ftz);
  } else {
    std::stringstream list(args.formats);
    for (std::string name; std::getline(list, name, ',');) {
      try {
        opt.formats.push_back(ru::num::Format::parse(name));
      } catch (const ru::num::FormatError& e) {
        throw UsageError("--formats: " + std::string(e.what()));
      }
    }
    if (opt.formats.empty()) throw UsageError("--formats: no format given");
  }
  opt.threads = threads;
  opt.adversarial = args.adversarial;
  opt.adversarial_seed = seed + 1;

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
  std::string part = trace_file.empty() ? "synthetic" : "trace";
  if (opt.adversarial)
    source += " + " + std::to_string(opt.adversarial) + " adversarial pairs per format (seed " +
              std::to_string(opt.adversarial_seed) + ")";
  if (!quiet) {
    double last = 0;
    opt.pair_progress = [&, last](uint64_t done, uint64_t total) mutable {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (s - last < 10 && done < total) return;
      last = s;
      std::fprintf(err, "[study box] %llu/%llu pairs (%.0f %%)  %.1f s\n", static_cast<unsigned long long>(done),
                   static_cast<unsigned long long>(total), 100.0 * static_cast<double>(done) / static_cast<double>(total), s);
    };
  }
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
                  "dir_dcons_false_hit,part\n");
  // The parts of a cell: the given records, and with --adversarial the adversarial ones and all.
  auto parts = [&](const BoxCell& c) {
    std::vector<std::pair<std::string, BoxCounts>> v{{part, c.given()}};
    if (opt.adversarial) {
      v.emplace_back("adversarial", c.adversarial);
      v.emplace_back("all", c);
    }
    return v;
  };
  for (const BoxCell& c : cells) {
    std::fprintf(out, "%-10s %9llu %8.2f %10.1f %10.1f %10.1f %10.1f %10llu\n", c.fmt.name().c_str(),
                static_cast<unsigned long long>(c.records), 100.0 * static_cast<double>(c.exact_hits) / static_cast<double>(c.records ? c.records : 1),
                ppm(c.plain_false_miss, c.records), ppm(c.plain_false_hit, c.records), ppm(c.cons_false_miss, c.records),
                ppm(c.cons_false_hit, c.records), static_cast<unsigned long long>(c.flags.overflow));
    for (const auto& [name, p] : parts(c)) {
      std::fprintf(f, "%s,%d,%d", c.fmt.name().c_str(), c.fmt.exp_bits, c.fmt.frac_bits);
      for (uint64_t v : {p.records, p.exact_hits, p.plain_false_miss, p.plain_false_hit, p.cons_false_miss,
                         p.cons_false_hit})
        std::fprintf(f, ",%llu", static_cast<unsigned long long>(v));
      // Overflowing operations are counted per format (all parts together).
      std::fprintf(f, ",%s", name == "all" || !opt.adversarial ? std::to_string(c.flags.overflow).c_str() : "");
      for (uint64_t v : {p.dir_records, p.dir_exact_hits, p.dir_plain_false_miss, p.dir_plain_false_hit,
                         p.dir_cons_false_miss, p.dir_cons_false_hit, p.dir_dcons_false_miss, p.dir_dcons_false_hit})
        std::fprintf(f, ",%llu", static_cast<unsigned long long>(v));
      std::fprintf(f, ",%s\n", name.c_str());
    }
  }
  // Against the direction d: what the renderer's pairs see (inv = RNE(1/d) in the format).
  std::fprintf(out, "\nagainst the ray direction d (the unit gets inv = RNE(1/d) in the format; exact slab test on d):\n");
  std::fprintf(out, "%-10s %-11s %9s %10s %10s %10s %10s %10s %10s %8s\n", "format", "part", "pairs", "plain FM",
               "plain FH", "cons FM", "cons FH", "d-cons FM", "d-cons FH", "dc/c FH");
  for (const BoxCell& c : cells)
    for (const auto& [name, p] : parts(c)) {
      char ratio[32] = "-";
      if (p.dir_cons_false_hit)
        std::snprintf(ratio, sizeof ratio, "%.2f",
                      static_cast<double>(p.dir_dcons_false_hit) / static_cast<double>(p.dir_cons_false_hit));
      std::fprintf(out, "%-10s %-11s %9llu %10.1f %10.1f %10.1f %10.1f %10.1f %10.1f %8s\n", c.fmt.name().c_str(),
                   name.c_str(), static_cast<unsigned long long>(p.dir_records), ppm(p.dir_plain_false_miss, p.dir_records),
                   ppm(p.dir_plain_false_hit, p.dir_records), ppm(p.dir_cons_false_miss, p.dir_records),
                   ppm(p.dir_cons_false_hit, p.dir_records), ppm(p.dir_dcons_false_miss, p.dir_records),
                   ppm(p.dir_dcons_false_hit, p.dir_records), ratio);
    }
  std::fclose(f);
  std::fprintf(out, "wrote %s\n", csv.c_str());
  return {cells, source, recs.size()};
}


RU_COMMAND("study box", "false misses / hits of the plain and conservative ray-box test", run_study_box);

}  // namespace ru::cli
