// rayunits study tri-outputs: error of t, beta, gamma against exact rationals and wrong hit
// decisions, per format, of Fig. 3.6 taken literally (3 divisions), the cheaper robust variants
// (1 reciprocal + 3 multiplications; deferred division: interval test by t*V products) and
// Moller-Trumbore (issue 14 §3; units/study_outputs.hpp, units/ray_tri_cheap.hpp).
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/units/study.hpp"
#include "rayunits/units/study_outputs.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/units/trace.hpp"

namespace ru::cli {
namespace {

using namespace ru::units;

int run_study_tri_outputs(int argc, char** argv) {
  CLI::App app{
      "Error of the outputs t, beta, gamma of the ray-triangle units against exact rationals (average "
      "relative error over the pairs the exact test hits, Tables 3.2-3.4 style) and their wrong hit decisions "
      "against the exact test, per format: Fig. 3.6 taken literally (3 divisions), the cheaper robust variants "
      "recip (1 reciprocal + 3 multiplications) and deferred (interval test t_min*V < Va < t_max*V, no "
      "division; its outputs are Fig. 3.6's divisions done once for the closest hit), and Moller-Trumbore.",
      "rayunits study tri-outputs"};
  std::string trace_file, csv = "study_tri_outputs.csv", exp_text = "7:8", frac_text = "8:25";
  size_t synthetic = 0, limit = 0;
  uint64_t seed = 1;
  int max_width = 32, threads = 2, table_exp = 0;
  bool quiet = false;
  app.add_option("--trace", trace_file, "binary trace (docs/UNITS.md); its tri records are used");
  app.add_option("--synthetic", synthetic, "use N synthetic ray-triangle pairs; default 2048 when no --trace");
  app.add_option("--seed", seed, "seed of the synthetic trace")->capture_default_str();
  app.add_option("--limit", limit, "use only the first N records");
  app.add_option("--exp", exp_text, "exponent bits LO:HI")->capture_default_str();
  app.add_option("--frac", frac_text, "fraction bits LO:HI")->capture_default_str();
  app.add_option("--max-width", max_width, "skip formats wider than this")->capture_default_str();
  app.add_option("--threads", threads, "worker threads")->capture_default_str()->check(CLI::Range(1, 64));
  app.add_option("--csv", csv, "output CSV (one row per format)")->capture_default_str();
  app.add_option("--table-exp", table_exp, "exponent width of the printed table (default: the largest <= 8 in --exp)");
  app.add_flag("--quiet", quiet, "no progress on stderr");
  if (!parse_args(app, argc, argv)) return 0;
  if (!trace_file.empty() && synthetic) throw UsageError("give either --trace or --synthetic, not both");
  int elo, ehi, mlo, mhi;
  parse_range(exp_text, "--exp", elo, ehi);
  parse_range(frac_text, "--frac", mlo, mhi);
  OutStudyOptions opt;
  opt.formats = format_grid(elo, ehi, mlo, mhi, max_width, true);
  opt.threads = threads;
  if (table_exp == 0) table_exp = std::max(elo, std::min(8, ehi));
  if (table_exp < elo || table_exp > ehi) throw UsageError("--table-exp must be inside --exp");

  std::vector<TriRecord> recs;
  std::string source;
  if (!trace_file.empty()) {
    recs = read_trace(trace_file).tris;
    if (recs.empty()) throw UsageError("trace " + trace_file + " holds no ray-triangle records");
    source = "trace " + trace_file;
  } else {
    if (!synthetic) synthetic = 2048;
    SynthTriOptions so;
    so.seed = seed;
    so.triangles = (synthetic + so.rays_per_packet - 1) / so.rays_per_packet;
    recs = synth_tri(so);
    recs.resize(synthetic);
    source = "synthetic trace (" + std::to_string(synthetic) + " pairs, seed " + std::to_string(seed) + ")";
  }
  if (limit && recs.size() > limit) recs.resize(limit);
  const std::string command = command_line("rayunits study tri-outputs", argc, argv);
  std::FILE* f = std::fopen(csv.c_str(), "w");
  if (!f) throw UsageError("cannot write " + csv);

  const auto t0 = std::chrono::steady_clock::now();
  if (!quiet)
    opt.progress = [&](size_t done, size_t total, const OutCell& c) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(stderr, "[study tri-outputs] %zu/%zu formats (%s)  %.1f s\n", done, total, c.fmt.name().c_str(), s);
    };
  const OutStudy st = study_tri_outputs(recs, opt);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::fprintf(f, "# %s\n# %s\n", command.c_str(), source.c_str());
  std::fprintf(f, "exponent_bits,significand_bits,records,exact_hits");
  const char* out_names[3] = {"t", "beta", "gamma"};
  for (int u : {0, 1, 3})
    for (int k = 0; k < 3; ++k)
      std::fprintf(f, ",%s_%s_avg_rel_error", out_names[k], out_unit_name(static_cast<OutUnit>(u)));
  for (int u = 0; u < kOutUnits; ++u)
    std::fprintf(f, ",%s_false_hit,%s_false_miss", out_unit_name(static_cast<OutUnit>(u)),
                 out_unit_name(static_cast<OutUnit>(u)));
  std::fprintf(f, ",nan_outputs,deferred_outputs_differ\n");
  for (const OutCell& c : st.cells) {
    std::fprintf(f, "%d,%d,%zu,%zu", c.fmt.exp_bits, c.fmt.frac_bits, st.records, st.exact_hits);
    uint64_t nan = 0;
    for (int u : {0, 1, 3})
      for (int k = 0; k < 3; ++k) {
        std::fprintf(f, ",%.6g", c.err[u][k].avg());
        nan += c.err[u][k].nan;
      }
    for (int u = 0; u < kOutUnits; ++u)
      std::fprintf(f, ",%llu,%llu", static_cast<unsigned long long>(c.false_hit[u]),
                   static_cast<unsigned long long>(c.false_miss[u]));
    std::fprintf(f, ",%llu,%llu\n", static_cast<unsigned long long>(nan),
                 static_cast<unsigned long long>(c.deferred_outputs_differ));
  }
  std::fclose(f);

  std::printf("rayunits study tri-outputs: %s\n", command.c_str());
  std::printf("source: %s; %zu records used, %zu skipped (non-finite); exact hits %zu; %zu formats, %.1f s on %d threads\n",
              source.c_str(), st.records, st.skipped, st.exact_hits, opt.formats.size(), secs, threads);
  std::printf("\nAverage relative error over the exact hits at e%d (Fig. 3.6 = 3 divisions, recip = 1/V and 3 mul, "
              "MT = Moller-Trumbore; deferred's outputs are Fig. 3.6's)\n", table_exp);
  std::printf("%4s | %10s %10s %10s | %10s %10s %10s | %10s %10s %10s\n", "M", "t fig3.6", "t recip", "t MT",
              "b fig3.6", "b recip", "b MT", "g fig3.6", "g recip", "g MT");
  for (const OutCell& c : st.cells) {
    if (c.fmt.exp_bits != table_exp) continue;
    std::printf("%4d |", c.fmt.frac_bits);
    for (int k = 0; k < 3; ++k) {
      for (int u : {0, 1, 3}) std::printf(" %10.3g", c.err[u][k].avg());
      std::printf(k < 2 ? " |" : "\n");
    }
  }
  std::printf("\nWrong hit decisions vs the exact test at e%d (false hits / false misses, of %zu pairs)\n", table_exp,
              st.records);
  std::printf("%4s | %13s %13s %13s %13s\n", "M", "fig3.6", "recip", "deferred", "MT");
  for (const OutCell& c : st.cells) {
    if (c.fmt.exp_bits != table_exp) continue;
    std::printf("%4d |", c.fmt.frac_bits);
    for (int u = 0; u < kOutUnits; ++u) {
      const std::string s = std::to_string(c.false_hit[u]) + "/" + std::to_string(c.false_miss[u]);
      std::printf(" %13s", s.c_str());
    }
    std::printf("\n");
  }
  uint64_t differ = 0;
  for (const OutCell& c : st.cells) differ += c.deferred_outputs_differ;
  std::printf("\ndeferred outputs differing from Fig. 3.6's (must be 0): %llu\nwrote %s\n",
              static_cast<unsigned long long>(differ), csv.c_str());
  return 0;
}

}  // namespace

RU_COMMAND("study tri-outputs", "error of t, beta, gamma and wrong decisions: Fig. 3.6, recip, deferred, MT",
           run_study_tri_outputs);

}  // namespace ru::cli
