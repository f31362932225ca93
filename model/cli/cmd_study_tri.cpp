// rayunits study tri: dissertation Tables 3.2-3.4 (lowest average relative error of V, Va,
// V0..2 per exponent/fraction width against exact rationals), the formula search over all
// equivalent scalar triple products, sign errors of V0..2 and wrong hit decisions of the two
// ray-triangle units (units/study.hpp).
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "studies.hpp"
#include "rayunits/units/study.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/units/trace.hpp"
#include "rayunits/util/process.hpp"

namespace ru::cli {
namespace {

using namespace ru::units;
using ru::num::Format;

// Dissertation table: (M, E) -> value, from shared/reference/table_3_*.csv.
using RefTable = std::map<std::pair<int, int>, double>;

RefTable load_reference(const std::string& path) {
  RefTable t;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 's') continue;
    int m, e;
    double v;
    if (std::sscanf(line.c_str(), "%d,%d,%lf", &m, &e, &v) == 3) t[{m, e}] = v;
  }
  return t;
}

struct Ranked {
  std::vector<int> order;  // classes best first
  std::vector<int> rank;   // rank[class], 1 = best (ties share the rank)
};

// Classes with NaN results rank after all classes without; then by average relative error.
Ranked rank_classes(const std::vector<VolStat>& st) {
  Ranked r;
  const int n = static_cast<int>(st.size());
  auto key = [&](int c) { return std::make_pair(st[c].nan > 0, st[c].avg()); };
  for (int c = 0; c < n; ++c) r.order.push_back(c);
  std::stable_sort(r.order.begin(), r.order.end(), [&](int a, int b) { return key(a) < key(b); });
  r.rank.assign(n, 0);
  for (int c = 0; c < n; ++c) {
    int better = 0;
    for (int o = 0; o < n; ++o) better += key(o) < key(c);
    r.rank[c] = better + 1;
  }
  return r;
}

std::string sci(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.7f", v);
  if (v != 0 && (v < 1e-4 || v >= 1e4)) std::snprintf(b, sizeof b, "%.3e", v);
  return b;
}

void ensure_dir(const std::string& d) {
  if (d.empty()) return;
  struct stat st;
  if (stat(d.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode)) throw UsageError("--out " + d + " exists and is not a directory");
    return;
  }
  if (mkdir(d.c_str(), 0777) != 0) throw UsageError("cannot create directory " + d);
}

int run_study_tri(int argc, char** argv) {
  CLI::App app{
      "Exact-arithmetic error study of the signed volumes (dissertation §3.7-3.9): for every format of the "
      "grid, the lowest average relative error of V, Va and V0..2 over all equivalent scalar triple products "
      "(Tables 3.2-3.4), the formula ranking (36 / 384 / 36 formulations, ranked per class of formulations "
      "that differ only in edge directions), sign errors of V0..2 and wrong hit decisions of ray_tri_robust "
      "and ray_tri_mt. Writes CSVs and a heat map; prints the tables.",
      "rayunits study tri"};
  TriStudyArgs a;
  app.add_option("--trace", a.trace_file, "binary trace (docs/UNITS.md); its tri records are used");
  app.add_option("--synthetic", a.synthetic,
                 "use N synthetic ray-triangle pairs (random triangles about the origin, ~25 % hits); default "
                 "2048 when no --trace");
  app.add_option("--seed", a.seed, "seed of the synthetic trace")->capture_default_str();
  app.add_option("--scale", a.scale, "scale of the synthetic scene")->capture_default_str();
  app.add_option("--scale-spread", a.spread,
                 "synthetic: scale each packet by a random 2^u, u in [-S, S] (values over many binades)")
      ->capture_default_str();
  app.add_option("--write-trace", a.write_trace_file, "also write the synthetic trace to this file");
  app.add_option("--limit", a.limit, "use only the first N records");
  app.add_option("--exp", a.exp_text, "exponent bits LO:HI")->capture_default_str();
  app.add_option("--frac", a.frac_text, "fraction (significand) bits LO:HI")->capture_default_str();
  app.add_option("--max-width", a.max_width, "skip formats wider than this (the dissertation stopped at 32)")
      ->capture_default_str();
  app.add_flag("--ftz", a.ftz, "flush-to-zero formats (default: subnormals)");
  app.add_option("--threads", a.threads, "worker threads")->capture_default_str()->check(CLI::Range(1, 64));
  app.add_option("--out", a.out_dir, "output directory for the CSVs and the PNG")->capture_default_str();
  app.add_option("--rank-exp", a.rank_exp, "exponent width of the printed formula ranking (default: 8, or the "
                                         "largest in the grid)");
  app.add_option("--reference", a.ref_dir, "directory of the dissertation's tables (CSV)")->capture_default_str();
  app.add_flag("--no-plot", a.no_plot, "do not run scripts/plot_study_tri.py");
  app.add_flag("--no-decisions", a.no_decisions, "skip the ray_tri_robust / ray_tri_mt decision counts");
  app.add_flag("--quiet", a.quiet, "no progress on stderr");
  if (!parse_args(app, argc, argv)) return 0;
  run_tri_study(a, command_line("rayunits study tri", argc, argv), stdout, stderr);
  return 0;
}

}  // namespace

TriStudyRun run_tri_study(const TriStudyArgs& args, const std::string& command, std::FILE* out, std::FILE* err) {
  const std::string &trace_file = args.trace_file, &write_trace_file = args.write_trace_file,
                    &out_dir = args.out_dir, &exp_text = args.exp_text, &frac_text = args.frac_text,
                    &ref_dir = args.ref_dir;
  size_t synthetic = args.synthetic;
  const size_t limit = args.limit;
  const uint64_t seed = args.seed;
  const double scale = args.scale, spread = args.spread;
  const int max_width = args.max_width, threads = args.threads;
  int rank_exp = args.rank_exp;
  const bool ftz = args.ftz, no_plot = args.no_plot, no_decisions = args.no_decisions, quiet = args.quiet;
  if (!trace_file.empty() && synthetic) throw UsageError("give either --trace or --synthetic, not both");

  int elo, ehi, mlo, mhi;
  parse_range(exp_text, "--exp", elo, ehi);
  parse_range(frac_text, "--frac", mlo, mhi);
  TriStudyOptions opt;
  opt.formats = format_grid(elo, ehi, mlo, mhi, max_width, !ftz);
  opt.threads = threads;
  opt.decisions = !no_decisions;
  if (rank_exp == 0) rank_exp = (elo <= 8 && 8 <= ehi) ? 8 : ehi;
  if (rank_exp < elo || rank_exp > ehi) throw UsageError("--rank-exp must be inside --exp");

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
    so.scale = scale;
    so.log2_spread = spread;
    so.rays_per_packet = 16;
    so.triangles = (synthetic + so.rays_per_packet - 1) / so.rays_per_packet;
    recs = synth_tri(so);
    recs.resize(synthetic);
    source = "synthetic trace (" + std::to_string(synthetic) + " pairs, seed " + std::to_string(seed) +
             ", scale " + decimal(scale) +
             (spread > 0 ? ", scale spread 2^+-" + decimal(spread) : std::string()) + ")";
    if (!write_trace_file.empty()) {
      Trace t;
      t.tris = recs;
      write_trace(write_trace_file, t);
    }
  }
  if (limit && recs.size() > limit) recs.resize(limit);

  const auto t0 = std::chrono::steady_clock::now();
  if (!quiet)
    opt.progress = [&](size_t done, size_t total, const TriCell& c) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(err, "[study tri] %zu/%zu formats  (%s %.1f s)  %.1f s\n", done, total,
                   c.fmt.name().c_str(), c.seconds, s);
    };
  const TriStudy st = study_tri(recs, opt);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::fprintf(out, "rayunits study tri: %s\n", command.c_str());
  std::fprintf(out, "source: %s; %zu records used, %zu skipped (non-finite); exact hits %zu (%.1f %%)\n", source.c_str(),
              st.records, st.skipped, st.exact_hits,
              st.records ? 100.0 * static_cast<double>(st.exact_hits) / static_cast<double>(st.records) : 0.0);
  std::fprintf(out, "formats: %zu (exp %d..%d, frac %d..%d, width <= %d%s); %.1f s on %d threads\n", opt.formats.size(), elo,
              ehi, mlo, mhi, max_width, ftz ? ", flush-to-zero" : "", secs, threads);
  std::fprintf(out, "exactly zero (left out of that volume's average): V %llu, Va %llu, V0..2 %llu\n",
              static_cast<unsigned long long>(st.exact_zero[0]), static_cast<unsigned long long>(st.exact_zero[1]),
              static_cast<unsigned long long>(st.exact_zero[2] + st.exact_zero[3] + st.exact_zero[4]));

  std::map<std::pair<int, int>, const TriCell*> cell;  // (M, E)
  for (const TriCell& c : st.cells) cell[{c.fmt.frac_bits, c.fmt.exp_bits}] = &c;

  const char* ref_files[3] = {"table_3_2_determinant_V.csv", "table_3_3_distance_Va.csv",
                              "table_3_4_barycentrics_V012.csv"};
  RefTable ref[3];
  bool have_ref = true;
  for (int k = 0; k < 3; ++k) {
    ref[k] = load_reference(ref_dir + "/" + ref_files[k]);
    have_ref = have_ref && !ref[k].empty();
  }
  const char* titles[3] = {"Table 3.2: determinant V", "Table 3.3: distance Va", "Table 3.4: barycentrics V0..2"};
  const KnownFormula known[3] = {KnownFormula::Eq33, KnownFormula::Eq34, KnownFormula::Eq35};

  ensure_dir(out_dir);
  const std::string tables_csv = out_dir + "/study_tri_tables.csv";
  const std::string formulas_csv = out_dir + "/study_tri_formulas.csv";
  const std::string signs_csv = out_dir + "/study_tri_signs.csv";
  std::FILE* ft = std::fopen(tables_csv.c_str(), "w");
  std::FILE* ff = std::fopen(formulas_csv.c_str(), "w");
  std::FILE* fs = std::fopen(signs_csv.c_str(), "w");
  if (!ft || !ff || !fs) throw UsageError("cannot write the CSVs in " + out_dir);
  std::fprintf(ft, "# %s\n# %s\n", command.c_str(), source.c_str());
  std::fprintf(ft,
               "significand_bits,exponent_bits,volume,avg_rel_error,dissertation_avg_rel_error,best_formula,"
               "worst_over_best,known_formula,known_rank,known_avg_rel_error,inf_results,nan_results\n");
  std::fprintf(ff, "exponent_bits,significand_bits,volume,class,formula,members,rank,avg_rel_error,n,nan_results,"
                   "inf_results,exact_zero,sign_errors\n");
  std::fprintf(fs, "exponent_bits,significand_bits,volumes,sign_err_eq35,sign_err_eq36,sign_err_fig36,"
                   "sign_err_best,sign_err_worst,robust_false_hit,robust_false_miss,mt_false_hit,mt_false_miss,"
                   "overflow_ops,underflow_ops,invalid_ops,soft_ops\n");

  const int c35 = known_formula_class(KnownFormula::Eq35), c36 = known_formula_class(KnownFormula::Eq36);
  for (const TriCell& c : st.cells) {
    const int E = c.fmt.exp_bits, M = c.fmt.frac_bits;
    for (int k = 0; k < 3; ++k) {
      const VolKind kind = static_cast<VolKind>(k);
      const Ranked r = rank_classes(c.cls[k]);
      const auto& reps = stp_class_reps(kind);
      const int best = r.order.front(), worst = r.order.back();
      const VolStat& b = c.cls[k][best];
      const int kc = known_formula_class(known[k]);
      const auto it = ref[k].find({M, E});
      std::fprintf(ft, "%d,%d,%s,%.9g,%s,\"%s\",%.6g,%s,%d,%.9g,%llu,%llu\n", M, E, vol_kind_name(kind), b.avg(),
                   it == ref[k].end() ? "" : sci(it->second).c_str(), reps[best].text(kind).c_str(),
                   b.avg() > 0 ? c.cls[k][worst].avg() / b.avg() : 0.0, known_formula_name(known[k]), r.rank[kc],
                   c.cls[k][kc].avg(), static_cast<unsigned long long>(b.inf),
                   static_cast<unsigned long long>(b.nan));
      for (int cl = 0; cl < static_cast<int>(reps.size()); ++cl) {
        const VolStat& v = c.cls[k][cl];
        std::fprintf(ff, "%d,%d,%s,%d,\"%s\",%d,%d,%.9g,%llu,%llu,%llu,%llu,%llu\n", E, M, vol_kind_name(kind), cl,
                     reps[cl].text(kind).c_str(), kind == VolKind::Va ? 8 : 4, r.rank[cl], v.avg(),
                     static_cast<unsigned long long>(v.n), static_cast<unsigned long long>(v.nan),
                     static_cast<unsigned long long>(v.inf), static_cast<unsigned long long>(v.exact_zero),
                     static_cast<unsigned long long>(v.sign_err));
      }
    }
    const Ranked r = rank_classes(c.cls[2]);
    std::fprintf(fs, "%d,%d,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu\n", E, M,
                 static_cast<unsigned long long>(3 * st.records),
                 static_cast<unsigned long long>(c.cls[2][c35].sign_err),
                 static_cast<unsigned long long>(c.cls[2][c36].sign_err),
                 static_cast<unsigned long long>(c.fig36.sign_err),
                 static_cast<unsigned long long>(c.cls[2][r.order.front()].sign_err),
                 static_cast<unsigned long long>(c.cls[2][r.order.back()].sign_err),
                 static_cast<unsigned long long>(c.robust_false_hit),
                 static_cast<unsigned long long>(c.robust_false_miss), static_cast<unsigned long long>(c.mt_false_hit),
                 static_cast<unsigned long long>(c.mt_false_miss), static_cast<unsigned long long>(c.flags.overflow),
                 static_cast<unsigned long long>(c.flags.underflow), static_cast<unsigned long long>(c.flags.invalid),
                 static_cast<unsigned long long>(c.flags.ops));
  }
  std::fclose(ft);
  std::fclose(ff);
  std::fclose(fs);

  // ---- printed tables (shape of Tables 3.2-3.4: rows = significand bits, columns = exponent bits)
  for (int k = 0; k < 3; ++k) {
    std::fprintf(out, "\n%s: lowest average relative error over all formulations (this run%s)\n", titles[k],
                have_ref ? "; [dissertation] in brackets" : "");
    std::fprintf(out, "%4s", "M\\E");
    for (int e = elo; e <= ehi; ++e) std::fprintf(out, " %*d", have_ref ? 23 : 11, e);
    std::fprintf(out, "\n");
    for (int m = mlo; m <= mhi; ++m) {
      std::fprintf(out, "%4d", m);
      for (int e = elo; e <= ehi; ++e) {
        auto it = cell.find({m, e});
        std::string s;
        if (it != cell.end()) s = sci(it->second->cls[k][rank_classes(it->second->cls[k]).order.front()].avg());
        if (have_ref) {
          auto rf = ref[k].find({m, e});
          s += rf == ref[k].end() ? std::string(12, ' ') : " [" + sci(rf->second) + "]";
        }
        std::fprintf(out, " %*s", have_ref ? 23 : 11, s.c_str());
      }
      std::fprintf(out, "\n");
    }
  }

  // ---- formula search at rank_exp
  std::fprintf(out, "\nFormula search at %d exponent bits: rank of the dissertation's formulas among the classes "
              "(V: 9, Va: 48, V0..2: 9; 1 = best) and worst/best error ratio\n", rank_exp);
  std::fprintf(out, "%4s %8s %10s %8s %10s %8s %8s %10s %9s\n", "M", "Eq3.3", "V w/b", "Eq3.4", "Va w/b", "Eq3.5",
              "Eq3.6", "V012 w/b", "MT V,Va");
  const int cmv = known_formula_class(KnownFormula::MtV), cmva = known_formula_class(KnownFormula::MtVa);
  for (int m = mlo; m <= mhi; ++m) {
    auto it = cell.find({m, rank_exp});
    if (it == cell.end()) continue;
    const TriCell& c = *it->second;
    Ranked r[3];
    double wb[3];
    for (int k = 0; k < 3; ++k) {
      r[k] = rank_classes(c.cls[k]);
      const double b = c.cls[k][r[k].order.front()].avg();
      wb[k] = b > 0 ? c.cls[k][r[k].order.back()].avg() / b : 0;
    }
    std::fprintf(out, "%4d %8d %10.1f %8d %10.1f %8d %8d %10.1f %4d,%-4d\n", m, r[0].rank[known_formula_class(KnownFormula::Eq33)],
                wb[0], r[1].rank[known_formula_class(KnownFormula::Eq34)], wb[1], r[2].rank[c35], r[2].rank[c36], wb[2],
                r[0].rank[cmv], r[1].rank[cmva]);
  }
  {
    const int mid = std::min(mhi, std::max(mlo, 16));
    auto it = cell.find({mid, rank_exp});
    if (it != cell.end()) {
      for (int k = 0; k < 3; ++k) {
        const VolKind kind = static_cast<VolKind>(k);
        const Ranked r = rank_classes(it->second->cls[k]);
        std::fprintf(out, "\nRanking of the %s formulations at e%dm%d (one line per class; equivalent members differ only in "
                    "edge directions):\n", vol_kind_name(kind), rank_exp, mid);
        const int show = static_cast<int>(r.order.size());
        for (int i = 0; i < show; ++i) {
          const int cl = r.order[i];
          if (kind == VolKind::Va && i >= 6 && i < show - 3) {
            if (i == 6) std::fprintf(out, "  ... (%d more)\n", show - 9);
            continue;
          }
          std::string tag;
          for (KnownFormula kf : {KnownFormula::Eq33, KnownFormula::Eq34, KnownFormula::Eq35, KnownFormula::Eq36,
                                  KnownFormula::MtV, KnownFormula::MtVa})
            if (known_formula_kind(kf) == kind && known_formula_class(kf) == cl) tag += std::string("  <- ") + known_formula_name(kf);
          std::fprintf(out, "  %2d. %-44s %s%s\n", r.rank[cl], stp_class_reps(kind)[cl].text(kind).c_str(),
                      sci(it->second->cls[k][cl].avg()).c_str(), tag.c_str());
        }
      }
    }
  }

  // ---- sign errors and decisions at rank_exp
  std::fprintf(out, "\nSign errors of V0..2 at %d exponent bits (out of %zu volumes; dissertation §3.9 at e7m24: 2 and 4 "
              "for Eq. 3.5/3.6, 237 for the worst formula)\n", rank_exp, 3 * st.records);
  std::fprintf(out, "%4s %8s %8s %8s %8s %8s | %s\n", "M", "Eq3.5", "Eq3.6", "Fig3.6", "best", "worst",
              opt.decisions ? "wrong hit decisions vs exact: robust FH/FM, MT FH/FM" : "");
  for (int m = mlo; m <= mhi; ++m) {
    auto it = cell.find({m, rank_exp});
    if (it == cell.end()) continue;
    const TriCell& c = *it->second;
    const Ranked r = rank_classes(c.cls[2]);
    std::fprintf(out, "%4d %8llu %8llu %8llu %8llu %8llu |", m, static_cast<unsigned long long>(c.cls[2][c35].sign_err),
                static_cast<unsigned long long>(c.cls[2][c36].sign_err),
                static_cast<unsigned long long>(c.fig36.sign_err),
                static_cast<unsigned long long>(c.cls[2][r.order.front()].sign_err),
                static_cast<unsigned long long>(c.cls[2][r.order.back()].sign_err));
    if (opt.decisions)
      std::fprintf(out, " %6llu/%-6llu %6llu/%-6llu", static_cast<unsigned long long>(c.robust_false_hit),
                  static_cast<unsigned long long>(c.robust_false_miss), static_cast<unsigned long long>(c.mt_false_hit),
                  static_cast<unsigned long long>(c.mt_false_miss));
    std::fprintf(out, "\n");
  }

  std::fprintf(out, "\nwrote %s, %s, %s\n", tables_csv.c_str(), formulas_csv.c_str(), signs_csv.c_str());
  if (!no_plot) {
    const std::string png = out_dir + "/study_tri.png";
    // Debian's python3 has python3-matplotlib; a pyenv python3 earlier in PATH may not.
    const std::string py = access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
    const std::string cmd = py + " '" + std::string(RU_SOURCE_DIR) + "/scripts/plot_study_tri.py' '" + tables_csv +
                            "' '" + png + "'";
    if (util::run_foreground({py, std::string(RU_SOURCE_DIR) + "/scripts/plot_study_tri.py", tables_csv, png}) == 0)
      std::fprintf(out, "wrote %s\n", png.c_str());
    else
      std::fprintf(err, "rayunits study tri: warning: the heat map was not drawn (%s failed; python3-matplotlib "
                           "missing?)\n", cmd.c_str());
  }
  return {st, source};
}


RU_COMMAND("study tri", "error study of the signed volumes vs exact rationals (Tables 3.2-3.4)", run_study_tri);

}  // namespace ru::cli
