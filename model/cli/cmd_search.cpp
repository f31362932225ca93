// rayunits search tri: NSGA-II over ray-triangle formulations on area x error x watertightness
// (issue 18 §2, docs/DATAPATH.md "The search").
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <optional>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/dp/emit.hpp"
#include "rayunits/dp/search.hpp"
#include "rayunits/synth/args.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/util/parallel.hpp"
#include "rayunits/util/process.hpp"

namespace ru::cli {
namespace {

namespace fs = std::filesystem;

std::string fmt_g(double v, int prec = 4) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", prec, v);
  return b;
}

// Mixed-precision searches add the wide format's operation counts and the conversions (columns
// after `fma`); the files of other searches are what they were.
std::string csv_header(bool mixed = false) {
  return std::string("genome,area_um2,units_um2,reg_um2,latency,add,mul,div,cmp,fma,") +
         (mixed ? "add_w,mul_w,div_w,cmp_w,fma_w,cvt_up,cvt_down," : "") +
         "mean_rel,max_rel,mean_rel_t,mean_rel_beta,mean_rel_gamma,nan,false_hits,false_misses,leaks,double_hits,misses,"
         "extras,role";
}

// Operations of kind k in a design's cost breakdown (0 when it has none).
std::string op_count(const dp::Fitness& f, const char* k) {
  const auto it = f.cost.ops.find(k);
  return std::to_string(it == f.cost.ops.end() ? 0 : it->second);
}

std::string csv_row(const dp::TriGenome& g, const dp::Fitness& f, const std::string& role, bool mixed = false) {
  auto op = [&](const char* k) { return op_count(f, k); };
  std::string w;
  if (mixed)
    for (const char* k : {"add_w", "mul_w", "div_w", "cmp_w", "fma_w", "cvt_up", "cvt_down"}) w += op(k) + ",";
  return dp::genome_name(g) + "," + fmt_g(f.cost.area_um2, 8) + "," + fmt_g(f.cost.units_um2, 8) + "," +
         fmt_g(f.cost.reg_um2, 8) + "," + std::to_string(f.cost.latency) + "," + op("add") + "," + op("mul") + "," +
         op("div") + "," + op("cmp") + "," + op("fma") + "," + w + fmt_g(f.mean_rel, 6) + "," + fmt_g(f.max_rel, 6) + "," +
         fmt_g(f.mean_tbg[0], 6) + "," + fmt_g(f.mean_tbg[1], 6) + "," + fmt_g(f.mean_tbg[2], 6) + "," +
         std::to_string(f.nan) + "," + std::to_string(f.false_hits) + "," + std::to_string(f.false_misses) + "," +
         std::to_string(f.leaks) + "," + std::to_string(f.double_hits) + "," + std::to_string(f.misses()) + "," +
         std::to_string(f.extras()) + "," + role;
}

// A design a search reports: its registry stem (dp_<stem>), graph and the origin line of its module.
struct Reported {
  std::string stem, name;
  dp::Graph graph;
};

// Writes every reported design as a run-time registry unit (DIR/designs/<stem>.dp; DIR/rtl: a copy
// of the project's RTL and the emitted modules) and, with verify, checks each cycle by cycle with
// `rayunits rtl dp_<stem> --stages max` (its build cache) against its graph at the format. Returns
// "pass", "FAIL (log)" or "not verified" per design.
std::vector<std::string> emit_and_verify(const fs::path& out, const num::Format& fmt, const std::vector<Reported>& ds,
                                         bool verify, const std::function<void(const std::string&)>& say) {
  const fs::path dd = out / "designs", rd = out / "rtl", vd = out / "verify";
  for (const auto& d : {dd, rd, vd}) fs::create_directories(d);
  for (const auto& e : fs::directory_iterator(synth::default_rtl_dir()))
    if (e.path().extension() == ".sv" || e.path().extension() == ".svh")
      synth::write_file_atomic((rd / e.path().filename()).string(), synth::read_file(e.path().string()));
  std::vector<std::string> status(ds.size(), "not verified");
  for (const auto& d : ds) {
    const std::string module = "ru_dp_" + d.stem;
    synth::write_file_atomic((dd / (d.stem + ".dp")).string(), d.graph.print());
    synth::write_file_atomic((rd / (module + ".sv")).string(), dp::emit_sv(d.graph, module, "genome " + d.name));
    synth::write_file_atomic((rd / (module + ".f")).string(), dp::emit_filelist(module, d.graph));
  }
  if (!verify) return status;
  ::setenv("RU_DP_DESIGNS", fs::absolute(dd).c_str(), 1);  // for the children (rtl, its tb)
  for (size_t i = 0; i < ds.size(); ++i) {
    const std::string& st = ds[i].stem;
    const std::string json = (vd / (st + ".json")).string(), log = (vd / (st + ".log")).string();
    say("verifying " + ds[i].name + " (" + std::to_string(i + 1) + "/" + std::to_string(ds.size()) + "): rayunits rtl dp_" +
        st + " --format " + fmt.name() + " --stages max (log " + log + ")");
    std::vector<std::string> argv = {util::self_exe(), "rtl",      "dp_" + st, "--format", fmt.name(),
                                     "--round",        num::round_name(fmt.round), "--stages", "max", "--rtl",
                                     fs::absolute(rd).string(), "--vectors", "20000", "--json", json};
    util::ProcessOptions po;
    po.out = util::Redirect::file(log);
    po.err_to_out = true;
    const util::ProcessResult p = util::run_process(argv, po);
    if (p.interrupted) throw UsageError("interrupted");
    status[i] = p.status() == 0 ? "pass" : "FAIL (" + log + ")";
    say("  " + status[i]);
  }
  return status;
}

std::string stem_of(const std::string& name) {
  std::string st = name;
  std::replace(st.begin(), st.end(), '-', '_');
  return st;
}

// The cost model of a search: rows of `rows` (and DIR/cell_rows.jsonl, characterizing what is
// missing unless no_characterize); an output directory this call made is removed again on error.
dp::CostModel search_cost_model(const std::vector<std::string>& rows, const std::string& library, const num::Format& fmt,
                                double period_ps, const std::string& out, bool no_characterize, bool fma,
                                const std::function<void(const std::string&)>& say,
                                const std::optional<num::Format>& wide = std::nullopt) {
  const synth::CellLibrary& lib = synth::cell_library(library);
  const bool made_out = !fs::exists(out);
  if (!no_characterize) fs::create_directories(out);
  try {
    const dp::CostModel cm = dp::CostModel::build(
        rows, lib, fmt, period_ps, no_characterize ? "" : (fs::path(out) / "cell_rows.jsonl").string(), say, fma, wide);
    for (const auto& [u, ch] : cm.units())
      say("cost model: " + u + " " + (u.find("@") != std::string::npos ? std::string() : fmt.name() + " ") + "Stages " + std::to_string(ch.stages) + ", " +
          fmt_g(ch.area_um2, 7) + " um2, " + fmt_g(ch.period_ps, 5) + " ps (" + ch.point + ")");
    return cm;
  } catch (...) {
    std::error_code ec;
    if (made_out && fs::is_empty(out, ec)) fs::remove(out, ec);  // nothing half-made left behind
    throw;
  }
}

struct BoxArgs {
  std::string format = "e7m16", clock = "250MHz", out, trace, library = "osu018";
  std::vector<std::string> rows;
  size_t records = 20000, adversarial = 4000;
  unsigned long long seed = 1;
  int threads = 1;
  bool quiet = false, no_characterize = false, no_verify = false;
  double epsilon = 0.05;
};

std::string box_csv_header() {
  return "design,area_um2,units_um2,reg_um2,latency,period_ps,add,mul,fma,cmp,mean_rel,max_rel,mean_rel_enter,"
         "mean_rel_exit,max_rel_enter,max_rel_exit,nan,false_misses,false_hits,role";
}

std::string box_csv_row(const std::string& name, const dp::Fitness& f, const std::string& role) {
  auto op = [&](const char* k) { return op_count(f, k); };
  return name + "," + fmt_g(f.cost.area_um2, 8) + "," + fmt_g(f.cost.units_um2, 8) + "," + fmt_g(f.cost.reg_um2, 8) +
         "," + std::to_string(f.cost.latency) + "," + fmt_g(f.cost.period_ps, 6) + "," + op("add") + "," + op("mul") +
         "," + op("fma") + "," + op("cmp") + "," + fmt_g(f.mean_rel, 6) + "," + fmt_g(f.max_rel, 6) + "," +
         fmt_g(f.mean_tbg[0], 6) + "," + fmt_g(f.mean_tbg[1], 6) + "," + fmt_g(f.max_tbg[0], 6) + "," +
         fmt_g(f.max_tbg[1], 6) + "," + std::to_string(f.nan) + "," + std::to_string(f.false_misses) + "," +
         std::to_string(f.false_hits) + "," + role;
}

// rayunits search box: every ray-box formulation (16: exhaustive, fewer than one NSGA-II
// population) evaluated on the trace's ray-box records, the Pareto front of area, mean and max
// error of t_enter / t_exit, false misses, false hits and the clock period, the epsilon-box front
// emitted and verified cycle by cycle.
int run_box(const BoxArgs& a, int argc, char** argv) {
  if (!(a.epsilon > 0) || !std::isfinite(a.epsilon)) throw UsageError("--epsilon must be a positive number");
  const num::Format fmt = num::Format::parse(a.format);
  const double period_ps = synth::parse_clock_ps("--clock", a.clock);
  if (a.records < 1) throw UsageError("--records must be at least 1");
  auto say = [&](const std::string& s) {
    if (!a.quiet) std::fprintf(stderr, "[search box] %s\n", s.c_str());
  };
  std::vector<units::BoxRecord> recs;
  if (!a.trace.empty()) {
    recs = units::read_trace(a.trace).boxes;
    if (recs.empty()) throw UsageError("trace " + a.trace + " holds no ray-box records");
    if (recs.size() > a.records) {  // evenly spaced records of the whole trace
      std::vector<units::BoxRecord> sub;
      for (size_t i = 0; i < a.records; ++i) sub.push_back(recs[i * recs.size() / a.records]);
      recs.swap(sub);
    }
  } else {
    units::SynthBoxOptions so;
    so.seed = a.seed;
    so.boxes = (a.records + so.rays_per_packet - 1) / so.rays_per_packet;
    recs = units::synth_box(so);
    if (recs.size() > a.records) recs.resize(a.records);
  }
  // adversarial rays (box corners, edges, faces: units::AdversarialBoxGen), where rounding decides
  // a hit; a captured trace rarely has them
  units::AdversarialBoxGen adv(fmt, a.seed);
  for (size_t i = 0; i < a.adversarial; ++i) recs.push_back(adv.next());
  std::vector<std::string> rows = a.rows;
  if (rows.empty()) rows = {(fs::path(synth::default_rtl_dir()).parent_path() / "synth" / "results" / "cell").string()};
  const dp::CostModel cm = search_cost_model(rows, a.library, fmt, period_ps, a.out, a.no_characterize, true, say);
  const auto t0 = std::chrono::steady_clock::now();
  const dp::BoxWorkload w = dp::make_box_workload(recs, fmt);
  say("workload: " + std::to_string(w.in.size()) + " ray-box records, " + std::to_string(a.adversarial) +
      " of them adversarial (" + std::to_string(w.skipped) +
      " skipped: an origin or box coordinate overflows " + fmt.name() + ")");
  const auto genomes = dp::all_box_genomes();
  std::vector<dp::Candidate> all(genomes.size());
  util::parallel_for(genomes.size(), a.threads, [&](size_t i) {
    all[i].name = dp::box_genome_name(genomes[i]);
    all[i].key = all[i].name;
    all[i].fit = dp::evaluate_box_fitness(dp::box_graph(genomes[i]), w, cm);
  });
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto front = dp::pareto_front(all, true);
  const auto reported = dp::epsilon_front(front, a.epsilon, true);
  std::vector<Reported> ds;
  for (const auto& c : reported) ds.push_back({stem_of(c.name), c.name, dp::box_graph(dp::parse_box_genome_name(c.name))});
  fs::create_directories(a.out);
  const std::vector<std::string> status = emit_and_verify(a.out, fmt, ds, !a.no_verify, say);

  const std::string plain = dp::box_genome_name(dp::box_plain_genome()),
                    cons = dp::box_genome_name(dp::box_conservative_genome());
  auto role_of = [&](const std::string& n) {
    return n == plain ? std::string("hand: ru_ray_box") : n == cons ? std::string("hand: ru_ray_box conservative") : std::string();
  };
  nlohmann::json fr = nlohmann::json::array(), alj = nlohmann::json::array();
  std::string csv = box_csv_header() + ",rtl\n", csv_all = box_csv_header() + "\n";
  for (size_t i = 0; i < reported.size(); ++i) {
    fr.push_back({{"design", reported[i].name}, {"unit", "dp_" + ds[i].stem}, {"fitness", to_json(reported[i].fit)},
                  {"rtl", status[i]}});
    csv += box_csv_row(reported[i].name, reported[i].fit, "front") + "," + status[i] + "\n";
  }
  std::set<std::string> on_front;
  for (const auto& c : front) on_front.insert(c.name);
  for (const auto& c : all) {
    const std::string role = role_of(c.name);
    alj.push_back({{"design", c.name}, {"pareto", on_front.count(c.name) > 0}, {"role", role}, {"fitness", to_json(c.fit)}});
    csv_all += box_csv_row(c.name, c.fit, on_front.count(c.name) ? "pareto" : "dominated") + "\n";
    if (!role.empty()) csv += box_csv_row(c.name, c.fit, "reference:" + role.substr(6)) + ",\n";
  }
  const nlohmann::json doc = {
      {"command", command_line("rayunits search", argc, argv)},
      {"context", {{"kind", "box"}, {"format", fmt.name()}, {"round", num::round_name(fmt.round)}, {"period_ps", period_ps},
                   {"workload", w.hash}, {"records", w.in.size()}, {"adversarial", a.adversarial}, {"skipped", w.skipped},
                   {"trace", a.trace.empty() ? std::string("synthetic") : fs::path(a.trace).filename().string()},
                   {"cost_model", cm.to_json()}}},
      {"objectives", {"area_um2 (cost model estimate)", "mean_rel", "max_rel", "false_misses", "false_hits", "period_ps (cost model)"}},
      {"epsilon", a.epsilon},
      {"front", fr},
      {"all", alj}};
  synth::write_file_atomic((fs::path(a.out) / "front.json").string(), doc.dump(1) + "\n");
  synth::write_file_atomic((fs::path(a.out) / "front.csv").string(), csv);
  synth::write_file_atomic((fs::path(a.out) / "all.csv").string(), csv_all);
  std::printf("search box %s at %s ps: %zu designs evaluated (%.1f s), Pareto front %zu, reported (epsilon %g) %zu\n",
              fmt.name().c_str(), fmt_g(period_ps, 6).c_str(), all.size(), secs, front.size(), a.epsilon, reported.size());
  std::printf("%-14s %12s %4s %8s %10s %10s %8s %8s  %s\n", "design", "area_um2", "lat", "period", "mean_rel", "max_rel",
              "f_miss", "f_hit", "rtl / role");
  auto line = [&](const dp::Candidate& c, const std::string& tail) {
    std::printf("%-14s %12.0f %4d %8.0f %10.3g %10.3g %8llu %8llu  %s\n", c.name.c_str(), c.fit.cost.area_um2,
                c.fit.cost.latency, c.fit.cost.period_ps, c.fit.mean_rel, c.fit.max_rel,
                static_cast<unsigned long long>(c.fit.false_misses), static_cast<unsigned long long>(c.fit.false_hits),
                tail.c_str());
  };
  for (size_t i = 0; i < reported.size(); ++i) line(reported[i], status[i]);
  std::printf("hand designs:\n");
  for (const auto& c : all)
    if (!role_of(c.name).empty()) line(c, role_of(c.name));
  std::printf("area: cost-model estimate (FP-unit cell rows + liberty registers); wrote %s/front.json, front.csv, all.csv, "
              "designs/, rtl/, verify/\n", a.out.c_str());
  for (const auto& st : status)
    if (!a.no_verify && st != "pass") {
      std::fprintf(stderr, "rayunits search: a reported design failed its cycle-by-cycle verification\n");
      return 1;
    }
  return 0;
}

int run_search_cmd(int argc, char** argv) {
  CLI::App app{"Searches datapath formulations (docs/DATAPATH.md \"The search\"). tri: NSGA-II over ray-triangle "
               "formulations on area at the clock (a cost model built from the cell-library flow's FP-unit rows, "
               "an estimate), mean and max relative error of t, beta, gamma against exact rationals, misses "
               "(watertightness leaks on a closed mesh + false misses) and extras (double hits + false hits), with "
               "--fused also the clock period; resumable: run the same command again to continue, a larger --budget "
               "extends a finished run; writes DIR/front.json, front.csv, evaluations.jsonl, state.json, "
               "cell_rows.jsonl, designs/<genome>.dp. box: all 16 ray-box formulations on area, error of t_enter / "
               "t_exit against the exact slab test, false misses, false hits and the clock period; writes "
               "DIR/front.json, front.csv, all.csv, designs/. Both emit the reported designs and verify them cycle by "
               "cycle (DIR/rtl, DIR/verify).",
               "rayunits search"};
  app.require_subcommand(1);
  auto* tri = app.add_subcommand("tri", "ray-triangle formulations (NSGA-II)");
  auto* box = app.add_subcommand("box", "ray-box formulations (all 16: conservative rounding placement, fma form, "
                                        "min/max tree), on the trace's ray-box records");
  BoxArgs ba;
  ba.threads = static_cast<int>(util::hardware_threads());
  box->add_option("--format", ba.format, "number format eXmY[-ftz] (default e7m16)");
  box->add_option("--clock", ba.clock, "target clock (250MHz, 4ns, 4000ps; default 250MHz)");
  box->add_option("--out", ba.out, "output directory (created)")->required();
  box->add_option("--trace", ba.trace, "binary trace with ray-box records (rayunits render --trace-out)");
  box->add_option("--records", ba.records, "records used: N evenly spaced records of the trace, or N synthetic (default 20000)");
  box->add_option("--adversarial", ba.adversarial,
                  "adversarial rays added to the records: grazing box corners, edges and faces (default 4000)");
  box->add_option("--seed", ba.seed, "seed of the synthetic and adversarial records (default 1)");
  box->add_option("--rows", ba.rows,
                  "directory or .jsonl file of cell-flow rows; repeat for several (default <source>/synth/results/cell)")
      ->check(CLI::ExistingPath);
  box->add_option("--library", ba.library, "cell library of the rows (default osu018)");
  box->add_option("--threads", ba.threads, "evaluation threads (default: all cores)");
  box->add_flag("--no-characterize", ba.no_characterize, "use only existing rows (default: characterize missing units)");
  box->add_option("--epsilon", ba.epsilon, "epsilon-box size of the reported front (default 0.05: 5 %)");
  box->add_flag("--no-verify", ba.no_verify, "skip the cycle-by-cycle verification of the reported designs");
  box->add_flag("--quiet", ba.quiet, "no progress lines");
  std::string format = "e7m16", clock = "250MHz", out, start = "fig36", trace, mesh_name = "icosphere",
              library = "osu018";
  long budget = 480;
  std::vector<std::string> rows;
  int population = 24, threads = static_cast<int>(util::hardware_threads());
  unsigned long long seed = 1;
  size_t records = 2048, mesh_rays = 400;
  bool quiet = false, no_characterize = false, no_verify = false, fused = false;
  std::string mixed;
  double epsilon = 0.05;
  tri->add_option("--format", format, "number format eXmY[-ftz] (default e7m16)");
  tri->add_option("--clock", clock, "target clock (250MHz, 4ns, 4000ps; default 250MHz)");
  tri->add_option("--budget", budget, "evaluations: population x (generations + 1) (default 480)");
  tri->add_option("--out", out, "output directory (created; an unfinished search there is resumed)")->required();
  tri->add_option("--population", population, "NSGA-II population, a multiple of 4, >= 8 (default 24)");
  tri->add_option("--seed", seed, "seed (default 1): same seed, same front");
  tri->add_option("--start", start,
                  "start formulation: fig36, fig36_tie, fig36_recip, mt, worst or a genome name (default fig36)");
  tri->add_option("--trace", trace, "binary trace of ray-triangle records (rayunits render --trace-out)");
  tri->add_option("--records", records, "records used: N evenly spaced records of the trace, or N synthetic (default 2048)");
  tri->add_option("--mesh", mesh_name,
                  std::string("closed mesh for the watertightness counts: a .off/.obj file or ") +
                      units::builtin_mesh_names() + " (default icosphere)");
  tri->add_option("--mesh-rays", mesh_rays, "edge + vertex rays (and half as many near-vertex rays) (default 400)");
  tri->add_option("--rows", rows,
                  "directory or .jsonl file of cell-flow rows; repeat for several (default <source>/synth/results/cell)")
      ->check(CLI::ExistingPath);
  tri->add_option("--library", library, "cell library of the rows (default osu018)");
  tri->add_option("--threads", threads, "evaluation threads (default: all cores)");
  tri->add_flag("--no-characterize", no_characterize,
                "use only existing rows (default: FP units without a current row meeting the clock are synthesized "
                "in the cell flow now, rows appended to DIR/cell_rows.jsonl)");
  tri->add_option("--epsilon", epsilon, "epsilon-box size of the reported front (default 0.05: 5 %)");
  tri->add_flag("--no-verify", no_verify,
                "skip the cycle-by-cycle verification of the reported designs (they are then marked "
                "'not verified')");
  tri->add_flag("--fused", fused,
                "also move over fused multiply-adds (gene u: dot products, then cross products as ru_fp_fma; "
                "characterizes fp_fma at the clock)");
  tri->add_option("--mixed", mixed,
                  "also move over mixed precision (gene w: dot products, also cross products, or all of it in this "
                  "wider format eXmY, converted by ru_fp_cvt; characterizes its units and fp_cvt at the clock)");
  tri->add_flag("--quiet", quiet, "no progress lines");
  if (!parse_args(app, argc, argv)) return 0;
  if (box->parsed()) return run_box(ba, argc, argv);

  const bool verify = !no_verify;
  if (!(epsilon > 0) || !std::isfinite(epsilon)) throw UsageError("--epsilon must be a positive number");
  const num::Format fmt = num::Format::parse(format);
  const double period_ps = synth::parse_clock_ps("--clock", clock);
  if (budget < population) throw UsageError("--budget must be at least --population (" + std::to_string(population) + ")");
  if (records < 1) throw UsageError("--records must be at least 1");
  if (rows.empty()) rows = {(fs::path(synth::default_rtl_dir()).parent_path() / "synth" / "results" / "cell").string()};
  const dp::TriGenome start_genome = [&] {
    try {
      return dp::start_genome(start);
    } catch (const dp::IrError& e) {
      throw UsageError(std::string("--start: ") + e.what());
    }
  }();
  if (start_genome.fuse != 0 && !fused)
    throw UsageError("--start " + start + " has fused operations (gene u): add --fused");
  std::optional<num::Format> wide;
  if (!mixed.empty()) {
    wide = num::Format::parse(mixed);
    wide->subnormals = fmt.subnormals;
    wide->round = fmt.round;
    if (wide->exp_bits < fmt.exp_bits || wide->frac_bits < fmt.frac_bits ||
        (wide->exp_bits == fmt.exp_bits && wide->frac_bits == fmt.frac_bits))
      throw UsageError("--mixed " + mixed + ": the wide format must be wider than " + fmt.name() +
                       " (no fewer exponent and fraction bits, more of one)");
  }
  if (start_genome.wide != 0 && !wide)
    throw UsageError("--start " + start + " has mixed precision (gene w): add --mixed FORMAT");
  auto say = [&](const std::string& s) {
    if (!quiet) std::fprintf(stderr, "[search tri] %s\n", s.c_str());
  };

  std::vector<units::TriRecord> recs;
  if (!trace.empty()) {
    recs = units::read_trace(trace).tris;
    if (recs.empty()) throw UsageError("trace " + trace + " holds no ray-triangle records");
    if (recs.size() > records) {  // evenly spaced records of the whole trace
      std::vector<units::TriRecord> sub;
      for (size_t i = 0; i < records; ++i) sub.push_back(recs[i * recs.size() / records]);
      recs.swap(sub);
    }
  } else {
    units::SynthTriOptions so;
    so.seed = seed;
    so.rays_per_packet = 8;
    so.triangles = (records + so.rays_per_packet - 1) / so.rays_per_packet;
    recs = units::synth_tri(so);
    if (recs.size() > records) recs.resize(records);
  }
  units::Mesh mesh = fs::is_regular_file(mesh_name) ? units::load_mesh(mesh_name) : units::builtin_mesh(mesh_name);
  if (population < 8 || population % 4 != 0)
    throw UsageError("--population must be a multiple of 4 and at least 8, got " + std::to_string(population));
  const dp::CostModel cm = search_cost_model(rows, library, fmt, period_ps, out, no_characterize, fused, say, wide);

  const auto t0 = std::chrono::steady_clock::now();
  const dp::Workload w = dp::make_workload(recs, fmt, std::move(mesh), mesh_rays, seed);
  say("workload: " + std::to_string(w.in.size()) + " records (" + std::to_string(w.skipped) +
      " skipped: an input overflows " + fmt.name() + "), mesh " + w.mesh.name + " with " +
      std::to_string(mesh_rays + mesh_rays / 2) + " rays");

  const nlohmann::json context = {{"kind", "tri"},
                                  {"objectives", "area mean_rel max_rel misses extras"},
                                  {"format", fmt.name()},
                                  {"round", num::round_name(fmt.round)},
                                  {"period_ps", period_ps},
                                  {"workload", w.hash},
                                  {"records", w.in.size()},
                                  {"trace", trace.empty() ? std::string("synthetic") : fs::path(trace).filename().string()},
                                  {"mesh", w.mesh.name},
                                  {"mesh_rays", mesh_rays},
                                  {"cost_model", cm.to_json()}};
  dp::SearchOptions so;
  so.out_dir = out;
  so.start = start_genome;
  so.start_name = start;
  so.fused = fused;
  if (wide) so.wide_de = wide->exp_bits - fmt.exp_bits, so.wide_dm = wide->frac_bits - fmt.frac_bits;
  so.start.wide_de = so.wide_de, so.start.wide_dm = so.wide_dm;
  so.population = population;
  so.generations = static_cast<int>(std::max(0L, (budget + population - 1) / population - 1));
  so.seed = seed;
  so.threads = threads;
  so.progress = say;
  dp::SearchResult res;
  try {
    res = dp::run_search(so, w, cm, context);
  } catch (const dp::IrError& e) {
    throw UsageError(e.what());
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // The hand designs under the same workload and cost model, beside the front.
  struct Ref {
    const char* name;
    dp::TriGenome g;
  };
  std::vector<Ref> refs = {{"fig36", dp::start_genome("fig36")},
                           {"fig36_tie", dp::start_genome("fig36_tie")},
                           {"fig36_recip", dp::start_genome("fig36_recip")},
                           {"mt", dp::mt_genome()}};
  std::vector<dp::Fitness> ref_fit(refs.size());
  util::parallel_for(refs.size(), threads,
                     [&](size_t i) { ref_fit[i] = dp::evaluate_fitness(dp::tri_graph(refs[i].g), w, cm); });

  // The reported front: the epsilon-box front of the search's front.
  const bool with_period = fused || wide.has_value();
  const std::vector<dp::Candidate> reported = dp::epsilon_front(res.front, epsilon, with_period);
  std::vector<Reported> ds;
  for (const auto& c : reported)
    ds.push_back({stem_of(dp::genome_name(c.genome)), dp::genome_name(c.genome), dp::tri_graph(c.genome)});
  const std::vector<std::string> status = emit_and_verify(out, fmt, ds, verify, say);

  nlohmann::json front = nlohmann::json::array(), all = nlohmann::json::array(), refj = nlohmann::json::array();
  const bool mx = wide.has_value();
  std::string csv = csv_header(mx) + ",rtl\n", csv_all = csv_header(mx) + "\n";
  for (size_t i = 0; i < reported.size(); ++i) {
    const auto& c = reported[i];
    front.push_back({{"genome", dp::genome_name(c.genome)}, {"unit", "dp_" + ds[i].stem},
                     {"genes", dp::genes_record(c.genome)}, {"key", c.key}, {"fitness", to_json(c.fit)},
                     {"rtl", status[i]}});
    csv += csv_row(c.genome, c.fit, "front", mx) + "," + status[i] + "\n";
  }
  for (const auto& c : res.front) {
    all.push_back({{"genome", dp::genome_name(c.genome)}, {"key", c.key}, {"fitness", to_json(c.fit)}});
    csv_all += csv_row(c.genome, c.fit, "pareto", mx) + "\n";
  }
  for (size_t i = 0; i < refs.size(); ++i) {
    refj.push_back({{"name", refs[i].name}, {"genome", dp::genome_name(refs[i].g)}, {"fitness", to_json(ref_fit[i])}});
    csv += csv_row(refs[i].g, ref_fit[i], std::string("reference:") + refs[i].name, mx) + ",\n";
  }
  const nlohmann::json doc = {{"command", command_line("rayunits search", argc, argv)},
                              {"context", context},
                              {"start", dp::genome_name(start_genome)},
                              {"population", population},
                              {"generations", so.generations},
                              {"seed", seed},
                              {"objectives", with_period ? nlohmann::json{"area_um2 (cost model estimate)", "mean_rel", "max_rel", "misses", "extras", "period_ps (cost model)"}
                                     : nlohmann::json{"area_um2 (cost model estimate)", "mean_rel", "max_rel", "misses", "extras"}},
                              {"epsilon", epsilon},
                              {"front", front},
                              {"pareto_all", all},
                              {"references", refj},
                              {"evaluations_this_run", res.evaluations}};
  synth::write_file_atomic((fs::path(out) / "front.json").string(), doc.dump(1) + "\n");
  synth::write_file_atomic((fs::path(out) / "front.csv").string(), csv);
  synth::write_file_atomic((fs::path(out) / "pareto_all.csv").string(), csv_all);

  std::printf("search tri %s at %s ps: %d generations of %d, %zu new evaluations (%.1f s); Pareto front %zu "
              "designs, reported (epsilon %g) %zu\n",
              fmt.name().c_str(), fmt_g(period_ps, 6).c_str(), so.generations, population, res.evaluations, secs,
              res.front.size(), epsilon, reported.size());
  std::printf("%-40s %12s %4s %10s %10s %6s %6s %6s %7s  %s\n", "design", "area_um2", "lat", "mean_rel", "max_rel",
              "f_miss", "leaks", "f_hit", "double", "rtl");
  auto line = [&](const std::string& n, const dp::Fitness& f, const std::string& rtl) {
    std::printf("%-40s %12.0f %4d %10.3g %10.3g %6llu %6llu %6llu %7llu  %s\n", n.c_str(), f.cost.area_um2,
                f.cost.latency, f.mean_rel, f.max_rel, static_cast<unsigned long long>(f.false_misses),
                static_cast<unsigned long long>(f.leaks), static_cast<unsigned long long>(f.false_hits),
                static_cast<unsigned long long>(f.double_hits), rtl.c_str());
  };
  for (size_t i = 0; i < reported.size(); ++i) line(dp::genome_name(reported[i].genome), reported[i].fit, status[i]);
  std::printf("references:\n");
  for (size_t i = 0; i < refs.size(); ++i)
    line(std::string(refs[i].name) + " " + dp::genome_name(refs[i].g), ref_fit[i], "");
  std::printf("area: cost-model estimate (FP-unit cell rows + liberty registers); wrote %s/front.json, front.csv, "
              "pareto_all.csv, designs/, rtl/, verify/\n",
              out.c_str());
  for (const auto& st : status)
    if (verify && st != "pass") {
      std::fprintf(stderr, "rayunits search: a reported design failed its cycle-by-cycle verification\n");
      return 1;
    }
  return 0;
}

}  // namespace

RU_COMMAND("search", "search ray-triangle (NSGA-II) and ray-box formulations on area x error", run_search_cmd);

}  // namespace ru::cli
