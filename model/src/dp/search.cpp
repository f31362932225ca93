// rayunits dp: the search over ray-triangle formulations (see rayunits/dp/search.hpp).
#include "rayunits/dp/search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <pagmo/algorithms/nsga2.hpp>
#include <pagmo/bfe.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <set>
#include <sstream>

#include "rayunits/num/fp.hpp"
#include "rayunits/synth/checked_in.hpp"
#include "rayunits/synth/flow.hpp"
#include "rayunits/units/exact.hpp"
#include "rayunits/units/watertight.hpp"
#include "rayunits/util/hash.hpp"
#include "rayunits/util/parallel.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::dp {

namespace fs = std::filesystem;
using num::Format;
using num::Soft;

// ---- cost model ------------------------------------------------------------------------------

namespace {

// The registry unit that carries out a kind of graph operation (op_counts keys).
const std::map<std::string, std::string>& kind_units() {
  static const std::map<std::string, std::string> m = {
      {"add", "fp_add"}, {"mul", "fp_mul"}, {"div", "fp_div"}, {"cmp", "fp_cmp"}, {"fma", "fp_fma"}};
  return m;
}

double lib_area(const synth::CellLibrary& lib, const std::string& cell) {
  const auto it = lib.area.find(cell);
  if (it == lib.area.end())
    throw synth::SynthError("cost model: the library " + lib.name + " has no cell " + cell);
  return it->second;
}

}  // namespace

namespace {

struct Pick {
  bool found = false;
  UnitChoice best;
  double fastest = INFINITY;
  std::string fastest_point;
  UnitChoice fastest_row;  // the fastest current row (unit empty: none)
  size_t stale = 0;
  int max_stages = -1;  // the largest Stages among the current rows
};

// params: unit parameters a row must have (fp_cvt's source format), empty for the FP operators.
Pick pick_row(const std::vector<synth::CheckedInRow>& rows, const std::string& unit, const std::string& library,
              const Format& fmt, double period_ps, const std::string& hash,
              const std::map<std::string, long long>& params = {}) {
  Pick p;
  const std::string round = num::round_name(fmt.round);
  const std::string fname = Format{fmt.exp_bits, fmt.frac_bits, true, fmt.round}.name();
  for (const auto& r : rows) {
    const auto& j = r.row;
    if (j.value("unit", "") != unit || j.value("flow", "") != library) continue;
    if (!j.contains("format") || !j["format"].is_string() || j["format"].get<std::string>() != fname) continue;
    if (j.value("subnormals", true) != fmt.subnormals || j.value("round", "rne") != round) continue;
    bool same = true;
    for (const auto& [k, v] : params)
      same = same && j.contains("params") && j["params"].is_object() && j["params"].value(k, -1LL) == v;
    if (!same) continue;
    if (!j.contains("period_ps") || !j["period_ps"].is_number() || !j.contains("area_um2")) continue;
    if (j.value("rtl_hash", "") != hash) {
      ++p.stale;
      continue;
    }
    const double per = j["period_ps"].get<double>(), area = j["area_um2"].get<double>();
    p.max_stages = std::max(p.max_stages, j.value("stages", 0));
    std::string point = j.contains("point") && j["point"].is_string() ? j["point"].get<std::string>()
                                                                        : r.file + ":" + std::to_string(r.line);
    if (per < p.fastest) p.fastest = per, p.fastest_point = point, p.fastest_row = UnitChoice{unit, j.value("stages", 0), area, per, point};
    if (per > period_ps) continue;
    if (!p.found || area < p.best.area_um2) p.best = UnitChoice{unit, j.value("stages", 0), area, per, point}, p.found = true;
  }
  return p;
}

}  // namespace

CostModel CostModel::build(const std::vector<std::string>& row_paths, const synth::CellLibrary& lib,
                           const Format& fmt, double period_ps, const std::string& measure_file,
                           const std::function<void(const std::string&)>& progress, bool fma,
                           const std::optional<Format>& wide) {
  CostModel m;
  m.fmt_ = fmt;
  m.period_ps_ = period_ps;
  m.ff_um2 = lib_area(lib, lib.flop_cell);
  m.mux_um2 = lib_area(lib, "MUX2X1");
  m.gate_um2 = lib_area(lib, "AND2X2");
  std::vector<std::string> paths = row_paths;
  if (!measure_file.empty() && fs::exists(measure_file)) paths.push_back(measure_file);
  std::vector<synth::CheckedInRow> rows = synth::CheckedInRows::load(paths).rows();
  // One unit configuration per key: the smallest current row meeting the clock, characterized now
  // when there is none (and measure_file is given).
  auto choose = [&](const std::string& key, const std::string& unit, const Format& fmt,
                    const std::map<std::string, long long>& params) {
    const synth::UnitSpec& spec = synth::find_unit(unit);
    const std::string hash = synth::sources_hash(synth::resolve_sources(spec, synth::default_rtl_dir()));
    Pick p = pick_row(rows, unit, lib.name, fmt, period_ps, hash, params);
    synth::UnitConfig fc;
    fc.fmt = fmt;
    fc.params = params;
    std::string what = unit + " " + fmt.name();  // for messages and row points
    std::string stem = unit + "_" + fmt.name();
    if (params.count("InExpW")) {
      const std::string from = Format{static_cast<int>(params.at("InExpW")), static_cast<int>(params.at("InFracW")),
                                      fmt.subnormals, fmt.round}.name();
      what += " from " + from;
      stem += "_from_" + from;
    }
    // A current row at the unit's maximum useful Stages: it was characterized through its whole
    // range (by an earlier search) and none met the clock; not again.
    const bool exhausted = p.max_stages >= spec.max_stages(fc);
    if (!p.found && !measure_file.empty() && !exhausted) {
      // Characterize: Stages upward from an estimate until one meets the clock, then one more.
      synth::FlowOptions fo;
      fo.flow = lib.name;
      // ABC maps for its own delay model: besides the clock itself, two tighter targets, so that
      // a unit close to its limit gets the mapping that meets the STA clock if one does
      fo.clocks_ps = {period_ps, 0.85 * period_ps, 0.7 * period_ps};
      fo.ice40 = fo.xilinx = false;
      synth::UnitConfig c = fc;
      const int smax = spec.max_stages(c);
      int s = 0, met_at = -1;
      std::ofstream out(measure_file, std::ios::app);
      while (s <= smax && (met_at < 0 || s <= met_at + 1)) {
        c.stages = s;
        const synth::SynthResult r = synth::run_synth(spec, c, fo);
        for (nlohmann::json j : synth::to_json_rows(r)) {
          j["point"] = "search:" + stem + "_s" + std::to_string(s);
          j["command"] = "rayunits synth " + synth::config_args(spec, c) + " --flow " + lib.name + " --clock " +
                         std::to_string(static_cast<long>(period_ps)) + "ps";
          out << j.dump() << "\n";
          rows.push_back(synth::CheckedInRow{j, measure_file, 0, j["command"], ""});
        }
        out.flush();
        if (!out) throw synth::SynthError("cannot append to " + measure_file);
        double per = INFINITY, area = 0;
        for (const auto& run : r.cell.runs)
          if (run.achieved_ps < per) per = run.achieved_ps, area = run.area.total;
        if (progress)
          progress("characterized " + what + " Stages " + std::to_string(s) + ": fastest " +
                   std::to_string(static_cast<long>(per)) + " ps (" + std::to_string(static_cast<long>(area)) +
                   " um2) of " + std::to_string(r.cell.runs.size()) + " ABC targets");
        if (per <= period_ps && met_at < 0) met_at = s;
        // from Stages 0, jump to the estimate period0 / period_ps - 1 stages
        s = s == 0 && met_at < 0 ? std::max(1, static_cast<int>(std::ceil(per / period_ps)) - 1) : s + 1;
      }
      p = pick_row(rows, unit, lib.name, fmt, period_ps, hash, params);
    }
    if (!p.found && p.fastest_row.unit == unit) {
      // No configuration meets the clock: the fastest one, and the designs using it run slower
      if (progress)
        progress("cost model: no " + what + " configuration meets " + std::to_string(static_cast<long>(period_ps)) +
                 " ps; using the fastest, Stages " + std::to_string(p.fastest_row.stages) + " at " +
                 std::to_string(static_cast<long>(p.fastest)) + " ps (designs with it: clock <= " +
                 std::to_string(static_cast<long>(1e6 / p.fastest)) + " MHz)");
      p.best = p.fastest_row;
      p.found = true;
    }
    if (!p.found)
      throw synth::SynthError(
          "cost model: no current " + lib.name + " row of " + what + " (" + num::round_name(fmt.round) + ") meets " +
          std::to_string(static_cast<long>(period_ps)) + " ps" +
          (std::isfinite(p.fastest) ? " (the fastest is " + std::to_string(static_cast<long>(p.fastest)) + " ps, " +
                                          p.fastest_point + ")"
                                    : " (none at all)") +
          (p.stale ? "; " + std::to_string(p.stale) + " rows are stale (rtl_hash differs)" : "") +
          (measure_file.empty() ? "; let the search characterize the units (drop --no-characterize)" : ""));
    m.units_[key] = p.best;
  };
  for (const auto& [kind, unit] : kind_units())
    if (kind != "fma" || fma) choose(unit, unit, fmt, {});  // fp_fma only for searches with fused moves
  if (wide) {
    // Mixed precision: the operators in the wide format, and the conversions both ways (ru_fp_cvt
    // f2f, IntW 2 as the emitter instantiates it)
    m.wide_ = *wide;
    for (const auto& [kind, unit] : kind_units())
      if (kind != "fma" || fma) choose(unit + "@wide", unit, *wide, {});
    auto from = [](const Format& f) {
      return std::map<std::string, long long>{{"InExpW", f.exp_bits}, {"InFracW", f.frac_bits},
                                              {"InSubnormals", f.subnormals ? 1 : 0}, {"IntW", 2}};
    };
    choose("fp_cvt@up", "fp_cvt", *wide, from(fmt));
    choose("fp_cvt@down", "fp_cvt", fmt, from(*wide));
  }
  return m;
}

CostBreakdown CostModel::cost(const Graph& g) const {
  CostBreakdown c;
  c.ops = g.op_counts();
  const auto& ns = g.nodes();
  if (g.mixed() && !wide_)
    throw IrError("cost model: a mixed-precision graph needs a cost model with the wide format's rows");
  const int Wn = 1 + fmt_.exp_bits + fmt_.frac_bits, Ww = wide_ ? 1 + wide_->exp_bits + wide_->frac_bits : Wn;
  auto width = [&](int i) { return ns[i].wide ? Ww : Wn; };  // of node i's value (FP)
  std::vector<int> ready(ns.size(), 0), start(ns.size(), 0), hold(ns.size(), 0);
  for (size_t i = 0; i < ns.size(); ++i) {
    const Node& n = ns[i];
    int s = 0;
    for (const int o : {n.a, n.b, n.c})
      if (o >= 0) s = std::max(s, ready[o]);
    start[i] = s;
    std::string unit = op_unit(n.op);
    if (n.op == Op::Cvt) unit += n.wide ? "@up" : "@down";
    else if (n.wide && !unit.empty()) unit += "@wide";
    const int W = width(static_cast<int>(i));
    if (!unit.empty()) {
      const auto it = units_.find(unit);
      if (it == units_.end()) throw IrError("cost model: no " + unit + " in the model (" + op_name(n.op) + ")");
      ready[i] = s + it->second.stages + 1;
      c.units_um2 += it->second.area_um2;
      c.period_ps = std::max(c.period_ps, it->second.period_ps);
      c.reg_bits += op_is_bool(n.op) ? 1 : W;  // the output register
    } else {
      ready[i] = s;
      if (n.op == Op::Select) c.mux_um2 += W * mux_um2;
      else if (n.op == Op::IsNan || n.op == Op::IsInf) c.gate_um2 += (W - 2) * gate_um2;  // reduction trees
      else if (op_is_bool(n.op) && n.op != Op::BConst && n.op != Op::SignBit) c.gate_um2 += gate_um2;
    }
    for (const int o : {n.a, n.b, n.c})
      if (o >= 0) hold[o] = std::max(hold[o], s - ready[o]);
  }
  for (const auto& [name, n] : g.outputs()) c.latency = std::max(c.latency, ready[n]);
  for (const auto& [name, n] : g.outputs()) hold[n] = std::max(hold[n], c.latency - ready[n]);
  for (size_t i = 0; i < ns.size(); ++i)
    if (ns[i].op != Op::Const && ns[i].op != Op::BConst)
      c.reg_bits += static_cast<long>(hold[i]) * (op_is_bool(ns[i].op) ? 1 : width(static_cast<int>(i)));
  c.reg_um2 = static_cast<double>(c.reg_bits) * ff_um2;
  c.area_um2 = c.units_um2 + c.reg_um2 + c.mux_um2 + c.gate_um2;
  return c;
}

nlohmann::json CostModel::to_json() const {
  nlohmann::json u = nlohmann::json::object();
  for (const auto& [name, ch] : units_)
    u[name] = {{"stages", ch.stages}, {"area_um2", ch.area_um2}, {"period_ps", ch.period_ps}, {"point", ch.point}};
  nlohmann::json j = {{"format", fmt_.name()},      {"period_ps", period_ps_}, {"units", u},
                      {"ff_um2", ff_um2},           {"mux_um2", mux_um2},       {"gate_um2", gate_um2},
                      {"kind", "estimate: characterized FP-unit rows + registers, muxes and gates from the liberty"}};
  if (wide_) j["wide_format"] = wide_->name();  // only for mixed-precision searches
  return j;
}

// ---- workload and fitness --------------------------------------------------------------------

Workload make_workload(const std::vector<units::TriRecord>& recs, const Format& fmt, units::Mesh mesh,
                       size_t mesh_rays, uint64_t seed) {
  Workload w;
  w.fmt = fmt;
  w.mesh = std::move(mesh);
  w.mesh_rays = mesh_rays;
  w.seed = seed;
  const Format in_fmt{fmt.exp_bits, fmt.frac_bits, fmt.subnormals, num::Round::RNE};
  std::string h = fmt.name() + "|" + std::to_string(mesh_rays) + "|" + std::to_string(seed) + "|" + w.mesh.name + "|" +
                  std::to_string(w.mesh.verts.size()) + "|" + std::to_string(w.mesh.tris.size()) + "|";
  uint64_t hv = util::fnv1a64(h);
  for (const auto& v : w.mesh.verts) hv = util::fnv1a64(std::string_view(reinterpret_cast<const char*>(&v), sizeof v), hv);
  for (const auto& r : recs) {
    const std::vector<double> x = tri_inputs(r);
    std::array<double, 17> in{};
    bool finite = true;
    for (int k = 0; k < 17; ++k) {
      in[k] = num::to_double(in_fmt, num::from_double(in_fmt, x[k]).bits);
      if (k < 15 && !std::isfinite(in[k])) finite = false;
      if (k >= 15 && std::isnan(in[k])) finite = false;
    }
    if (!finite) {
      ++w.skipped;
      continue;
    }
    const auto V = [&](int k) { return units::Vec3d{in[k], in[k + 1], in[k + 2]}; };
    const units::ExactTriHit e = units::exact_tri(V(0), V(3), V(6), V(9), V(12), in[15], in[16]);
    w.in.push_back(in);
    w.exact_hit.push_back(e.hit);
    w.exact_tbg.push_back(e.hit ? std::array<mpq_class, 3>{e.t, e.beta, e.gamma} : std::array<mpq_class, 3>{});
    hv = util::fnv1a64(std::string_view(reinterpret_cast<const char*>(in.data()), sizeof in), hv);
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hv));
  w.hash = buf;
  return w;
}

std::vector<double> Fitness::objectives(bool with_period) const {
  std::vector<double> o = {cost.area_um2, mean_rel, max_rel, static_cast<double>(misses()), static_cast<double>(extras())};
  if (with_period) o.push_back(cost.period_ps);
  return o;
}

nlohmann::json to_json(const Fitness& f) {
  return {{"area_um2", f.cost.area_um2},
          {"units_um2", f.cost.units_um2},
          {"reg_um2", f.cost.reg_um2},
          {"mux_um2", f.cost.mux_um2},
          {"gate_um2", f.cost.gate_um2},
          {"reg_bits", f.cost.reg_bits},
          {"latency", f.cost.latency},
          {"period_ps", f.cost.period_ps},
          {"ops", f.cost.ops},
          {"mean_rel", f.mean_rel},
          {"max_rel", f.max_rel},
          {"mean_rel_tbg", f.mean_tbg},
          {"max_rel_tbg", f.max_tbg},
          {"nan", f.nan},
          {"false_hits", f.false_hits},
          {"false_misses", f.false_misses},
          {"leaks", f.leaks},
          {"double_hits", f.double_hits},
          {"misses", f.misses()},
          {"extras", f.extras()}};
}

Fitness fitness_from_json(const nlohmann::json& j) {
  Fitness f;
  f.cost.area_um2 = j.at("area_um2");
  f.cost.units_um2 = j.at("units_um2");
  f.cost.reg_um2 = j.at("reg_um2");
  f.cost.mux_um2 = j.at("mux_um2");
  f.cost.gate_um2 = j.at("gate_um2");
  f.cost.reg_bits = j.at("reg_bits");
  f.cost.latency = j.at("latency");
  f.cost.period_ps = j.at("period_ps");
  f.cost.ops = j.at("ops").get<std::map<std::string, int>>();
  f.mean_rel = j.at("mean_rel");
  f.max_rel = j.at("max_rel");
  f.mean_tbg = j.at("mean_rel_tbg");
  f.max_tbg = j.at("max_rel_tbg");
  f.nan = j.at("nan");
  f.false_hits = j.at("false_hits");
  f.false_misses = j.at("false_misses");
  f.leaks = j.at("leaks");
  f.double_hits = j.at("double_hits");
  return f;
}

namespace {

// Relative errors of up to three outputs against exact values (a NaN counts 1 and is counted in
// Fitness::nan; an infinity is clamped to the largest finite value), summed into the Fitness.
struct RelErrors {
  explicit RelErrors(double largest) : big(largest) {}
  double big;  // the format's largest finite value
  double sum[3] = {0, 0, 0};
  uint64_t cnt[3] = {0, 0, 0};
  mpq_class diff;
  void add(Fitness& f, int k, double y, const mpq_class& ex) {
    double rel;
    if (std::isnan(y)) {
      ++f.nan;
      rel = 1.0;
    } else {
      if (std::isinf(y)) y = std::copysign(big, y);
      diff = mpq_class(y) - ex;
      diff /= ex;
      rel = std::fabs(diff.get_d());
    }
    sum[k] += rel;
    ++cnt[k];
    f.max_tbg[k] = std::max(f.max_tbg[k], rel);
  }
  void finish(Fitness& f) const {
    for (int k = 0; k < 3; ++k) {
      f.mean_tbg[k] = cnt[k] ? sum[k] / static_cast<double>(cnt[k]) : 0.0;
      f.mean_rel = std::max(f.mean_rel, f.mean_tbg[k]);
      f.max_rel = std::max(f.max_rel, f.max_tbg[k]);
    }
  }
};

}  // namespace

Fitness evaluate_fitness(const Graph& g, const Workload& w, const CostModel& cm) {
  Fitness f;
  f.cost = cm.cost(g);
  num::SoftScope scope(w.fmt);
  const int hit_n = g.output_node("hit");
  const int out_n[3] = {g.output_node("t"), g.output_node("beta"), g.output_node("gamma")};
  RelErrors err(num::to_double(w.fmt, w.fmt.max_finite(false)));
  std::vector<Soft> x(17);
  for (size_t r = 0; r < w.in.size(); ++r) {
    for (int k = 0; k < 17; ++k) x[k] = Soft::from_double(w.in[r][k]);
    const auto v = evaluate<Soft>(g, x);
    const bool hit = v[hit_n].b;
    f.false_hits += hit && !w.exact_hit[r];
    f.false_misses += !hit && w.exact_hit[r];
    if (!w.exact_hit[r]) continue;
    for (int k = 0; k < 3; ++k) {
      const mpq_class& ex = w.exact_tbg[r][k];
      if (sgn(ex) == 0) continue;  // a ray through an edge: no relative error
      err.add(f, k, v[out_n[k]].v.to_double(), ex);
    }
  }
  err.finish(f);
  if (w.mesh_rays > 0) {
    units::WatertightOptions o;
    o.fmt = w.fmt;
    o.rays = w.mesh_rays;
    o.near_vertex_rays = w.mesh_rays / 2;
    o.seed = w.seed;
    o.threads = 1;
    o.unit = [&g, hit_n](const units::WatertightOptions::Vs& a, const units::WatertightOptions::Vs& d,
                         const units::WatertightOptions::Vs& p0, const units::WatertightOptions::Vs& p1,
                         const units::WatertightOptions::Vs& p2, Soft tmin, Soft tmax) {
      const std::vector<Soft> in = {a.x,  a.y,  a.z,  d.x,  d.y,  d.z,  p0.x, p0.y, p0.z,
                                    p1.x, p1.y, p1.z, p2.x, p2.y, p2.z, tmin, tmax};
      return evaluate<Soft>(g, in)[hit_n].b;
    };
    const units::WatertightCounts t = units::run_watertight(w.mesh, o).total();
    f.leaks = t.leaks;
    f.double_hits = t.double_hits;
  }
  return f;
}

// ---- the ray-box designs ---------------------------------------------------------------------

BoxWorkload make_box_workload(const std::vector<units::BoxRecord>& recs, const Format& fmt) {
  BoxWorkload w;
  w.fmt = fmt;
  const Format in_fmt{fmt.exp_bits, fmt.frac_bits, fmt.subnormals, num::Round::RNE};
  uint64_t hv = util::fnv1a64(fmt.name() + "|box|");
  for (const auto& r : recs) {
    const std::vector<double> x = box_inputs(r);
    std::array<double, 14> in{};
    bool ok = true;
    for (int k = 0; k < 14; ++k) {
      in[k] = num::to_double(in_fmt, num::from_double(in_fmt, x[k]).bits);
      if (std::isnan(in[k])) ok = false;
      const bool finite_needed = k < 3 || k >= 8;  // o, lo, hi (inv and t may be infinite)
      if (finite_needed && !std::isfinite(in[k])) ok = false;
    }
    if (!ok) {
      ++w.skipped;
      continue;
    }
    const auto V = [&](int k) { return units::Vec3d{in[k], in[k + 1], in[k + 2]}; };
    w.exact.push_back(units::exact_slab(V(0), V(3), V(8), V(11), in[6], in[7]));
    w.in.push_back(in);
    hv = util::fnv1a64(std::string_view(reinterpret_cast<const char*>(in.data()), sizeof in), hv);
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hv));
  w.hash = buf;
  return w;
}

Fitness evaluate_box_fitness(const Graph& g, const BoxWorkload& w, const CostModel& cm) {
  Fitness f;
  f.cost = cm.cost(g);
  num::SoftScope scope(w.fmt);
  const int hit_n = g.output_node("hit");
  const int out_n[2] = {g.output_node("t_enter"), g.output_node("t_exit")};
  RelErrors err(num::to_double(w.fmt, w.fmt.max_finite(false)));
  std::vector<Soft> x(14);
  for (size_t r = 0; r < w.in.size(); ++r) {
    for (int k = 0; k < 14; ++k) x[k] = Soft::from_double(w.in[r][k]);
    const auto v = evaluate<Soft>(g, x);
    const bool hit = v[hit_n].b, exact_hit = w.exact[r].hit;
    f.false_hits += hit && !exact_hit;
    f.false_misses += !hit && exact_hit;
    if (!exact_hit) continue;
    const units::XQ* ex[2] = {&w.exact[r].t_enter, &w.exact[r].t_exit};
    for (int k = 0; k < 2; ++k) {
      if (ex[k]->kind != units::XQ::Finite || sgn(ex[k]->q) == 0) continue;
      err.add(f, k, v[out_n[k]].v.to_double(), ex[k]->q);
    }
  }
  err.finish(f);
  return f;
}

// ---- the search ------------------------------------------------------------------------------

namespace {

// Positions of the non-dominated vectors (minimization: another vector is <= in every component
// and < in one); equal vectors do not dominate each other.
template <class V>
std::vector<size_t> non_dominated(const std::vector<V>& v) {
  std::vector<size_t> out;
  for (size_t i = 0; i < v.size(); ++i) {
    bool dominated = false;
    for (size_t j = 0; j < v.size() && !dominated; ++j) {
      bool le = true, lt = false;
      for (size_t k = 0; k < v[i].size(); ++k) le &= v[j][k] <= v[i][k], lt |= v[j][k] < v[i][k];
      dominated = le && lt;
    }
    if (!dominated) out.push_back(i);
  }
  return out;
}

std::string name_of(const Candidate& c) { return c.name.empty() ? genome_name(c.genome) : c.name; }

bool area_then_name(const Candidate& a, const Candidate& b) {
  if (a.fit.cost.area_um2 != b.fit.cost.area_um2) return a.fit.cost.area_um2 < b.fit.cost.area_um2;
  return name_of(a) < name_of(b);
}

}  // namespace

std::vector<Candidate> pareto_front(const std::vector<Candidate>& all, bool with_period) {
  std::vector<Candidate> u;
  std::set<std::string> seen;
  for (const auto& c : all)
    if (seen.insert(c.key).second) u.push_back(c);
  std::vector<std::vector<double>> obj;
  for (const auto& c : u) obj.push_back(c.fit.objectives(with_period));
  std::vector<Candidate> front;
  for (size_t i : non_dominated(obj)) front.push_back(u[i]);
  std::sort(front.begin(), front.end(), area_then_name);
  return front;
}

std::vector<Candidate> epsilon_front(const std::vector<Candidate>& front, double eps, bool with_period) {
  if (!(eps > 0)) throw IrError("epsilon must be > 0");
  using Box = std::vector<long>;
  auto box = [&](const Candidate& c) {
    const auto o = c.fit.objectives(with_period);
    Box b(o.size());
    for (size_t k = 0; k < o.size(); ++k) {
      const double v = k >= 3 ? 1.0 + o[k] : o[k];  // counts
      b[k] = v > 0 ? static_cast<long>(std::floor(std::log(v) / std::log1p(eps))) : std::numeric_limits<long>::min();
    }
    return b;
  };
  std::map<Box, Candidate> boxes;  // one design per box: the smallest area, then name
  for (const auto& c : front) {
    const Box b = box(c);
    auto it = boxes.find(b);
    if (it == boxes.end() || area_then_name(c, it->second)) boxes[b] = c;
  }
  std::vector<Box> keys;
  std::vector<Candidate> reps, out;
  for (const auto& [b, c] : boxes) keys.push_back(b), reps.push_back(c);
  for (size_t i : non_dominated(keys)) out.push_back(reps[i]);
  std::sort(out.begin(), out.end(), area_then_name);
  return out;
}

namespace {

// Evaluations, cached by content (graph text + workload + cost model), appended to
// evaluations.jsonl in the order the search asked for them.
struct Evaluator {
  const Workload* w = nullptr;
  const CostModel* cm = nullptr;
  std::string context_hash;
  int threads = 1;
  std::string log_path;
  std::map<std::string, Candidate> cache;
  std::vector<std::string> order;  // keys in evaluation order
  size_t evaluations = 0, hits = 0;
  int wide_de = 0, wide_dm = 0;  // the search's wide format (genomes with mixed precision)

  TriGenome with_wide(TriGenome g) const {
    g.wide_de = wide_de, g.wide_dm = wide_dm;
    return g;
  }

  std::string key_of(const Graph& g) const { return util::fnv1a64_hex(g.print() + "|" + context_hash); }

  void load(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
      ++n;
      if (line.empty()) continue;
      nlohmann::json j;
      try {
        j = nlohmann::json::parse(line);
        if (j.at("context") != context_hash) continue;  // another workload, cost model or schema
        Candidate c;
        c.genome = with_wide(parse_genome_name(j.at("genome")));
        c.key = j.at("key");
        c.fit = fitness_from_json(j.at("fitness"));
        if (!cache.count(c.key)) order.push_back(c.key);
        cache[c.key] = c;
      } catch (const std::exception& e) {
        throw IrError(path + ":" + std::to_string(n) + ": not an evaluation record (" + e.what() + ")");
      }
    }
  }

  std::vector<Candidate> run(const std::vector<TriGenome>& gs) {
    std::vector<Candidate> out(gs.size());
    std::vector<Graph> graphs;
    std::vector<size_t> todo;
    std::set<std::string> todo_keys;
    for (size_t i = 0; i < gs.size(); ++i) {
      out[i].genome = with_wide(canonical(gs[i]));
      graphs.push_back(tri_graph(out[i].genome));
      out[i].key = key_of(graphs.back());
      if (cache.count(out[i].key)) {
        ++hits;
      } else if (todo_keys.insert(out[i].key).second) {
        todo.push_back(i);
      }
    }
    std::vector<Fitness> fits(todo.size());
    util::parallel_for(todo.size(), threads,
                       [&](size_t k) { fits[k] = evaluate_fitness(graphs[todo[k]], *w, *cm); });
    std::ofstream log(log_path, std::ios::app);
    for (size_t k = 0; k < todo.size(); ++k) {
      Candidate c = out[todo[k]];
      c.fit = fits[k];
      cache[c.key] = c;
      order.push_back(c.key);
      ++evaluations;
      log << nlohmann::json{{"key", c.key},
                            {"genome", genome_name(c.genome)},
                            {"genes", genes_record(c.genome)},
                            {"context", context_hash},
                            {"fitness", to_json(c.fit)}}
                 .dump()
          << "\n";
    }
    if (!log) throw IrError("cannot append to " + log_path);
    for (auto& c : out) c.fit = cache.at(c.key).fit;
    return out;
  }
};

std::vector<double> objectives_of(const Fitness& f, bool with_period) { return f.objectives(with_period); }

// pagmo's problem: the genome as integers; fitness from the shared evaluator.
// The decision vector holds the genes moved over, `genes` (indices into to_vector(): the nine
// first, then the fuse gene with fused moves and the wide gene with mixed moves: a search without
// them is the one it was before those genes existed); the others are 0.
struct TriProblem {
  std::shared_ptr<Evaluator> ev;
  int n = kTriGenes;
  bool with_period = false;  // the clock period as a sixth objective (fused or mixed moves)
  std::vector<int> genes;
  pagmo::vector_double fitness(const pagmo::vector_double& x) const {
    return objectives_of(ev->run({decode(x)})[0].fit, with_period);
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    pagmo::vector_double lo(n, 0.0), hi(n);
    for (int i = 0; i < n; ++i) hi[i] = kTriGeneCount[genes[i]] - 1;
    return {lo, hi};
  }
  pagmo::vector_double::size_type get_nobj() const { return Fitness::kObjectives + (with_period ? 1 : 0); }
  pagmo::vector_double::size_type get_nix() const { return n; }
  std::string get_name() const { return "rayunits ray-triangle formulations"; }
  TriGenome decode(const pagmo::vector_double& x) const {
    std::vector<int> v(kTriGenes, 0);
    for (int i = 0; i < n; ++i) v[genes[i]] = static_cast<int>(std::lround(x[i]));
    return tri_genome(v);
  }
  pagmo::vector_double encode(const TriGenome& g) const {
    const auto v = to_vector(g);
    pagmo::vector_double x(n);
    for (int i = 0; i < n; ++i) x[i] = v[genes[i]];
    return x;
  }
};

// pagmo's batch evaluator: a generation's offspring evaluated together, in parallel, through the cache.
struct TriBatch {
  pagmo::vector_double operator()(const pagmo::problem& p, const pagmo::vector_double& dvs) const {
    const auto* tp = p.extract<TriProblem>();
    if (!tp) throw IrError("TriBatch: not a TriProblem");
    std::vector<TriGenome> gs;
    const size_t n = static_cast<size_t>(tp->n);
    for (size_t i = 0; i < dvs.size(); i += n)
      gs.push_back(tp->decode(pagmo::vector_double(dvs.begin() + i, dvs.begin() + i + n)));
    pagmo::vector_double f;
    for (const auto& c : tp->ev->run(gs)) {
      const auto o = objectives_of(c.fit, tp->with_period);
      f.insert(f.end(), o.begin(), o.end());
    }
    return f;
  }
  std::string get_name() const { return "rayunits cached parallel evaluator"; }
};

void write_atomic(const fs::path& p, const std::string& text) {
  const fs::path tmp = p.string() + ".tmp";
  {
    std::ofstream o(tmp);
    o << text;
    if (!o) throw IrError("cannot write " + tmp.string());
  }
  fs::rename(tmp, p);
}

// One mutation of a genome: each gene moved over redrawn with probability 1/3 (at least one changes).
TriGenome mutate(const TriGenome& g, const std::vector<int>& genes, util::Xoshiro256ss& rng) {
  std::vector<int> v = to_vector(g);
  const std::string before = genome_name(g);
  for (int tries = 0; tries < 64; ++tries) {
    for (const int i : genes)
      if (util::bounded_lemire(rng, 3) == 0) v[i] = static_cast<int>(util::bounded_lemire(rng, kTriGeneCount[i]));
    if (genome_name(tri_genome(v)) != before) break;
  }
  return tri_genome(v);
}

}  // namespace

SearchResult run_search(const SearchOptions& opt, const Workload& w, const CostModel& cm,
                        const nlohmann::json& context) {
  if (opt.population < 8 || opt.population % 4 != 0)
    throw IrError("--population must be a multiple of 4 and at least 8, got " + std::to_string(opt.population));
  if (opt.generations < 0) throw IrError("generations must be >= 0");
  const fs::path dir = opt.out_dir;
  fs::create_directories(dir);
  auto say = [&](const std::string& s) {
    if (opt.progress) opt.progress(s);
  };
  const std::string context_hash = util::fnv1a64_hex(context.dump());
  if (!opt.fused && opt.start.fuse != 0)
    throw IrError("the start " + genome_name(opt.start) + " has fused operations: search with fused moves (--fused)");
  const bool mixed = opt.wide_de > 0 || opt.wide_dm > 0;
  if (!mixed && opt.start.wide != 0)
    throw IrError("the start " + genome_name(opt.start) + " has mixed precision: search with mixed moves (--mixed FORMAT)");
  if (opt.wide_de < 0 || opt.wide_dm < 0)
    throw IrError("the wide format of mixed moves must not be narrower than the unit's");
  nlohmann::json settings = {{"context", context},
                             {"context_hash", context_hash},
                             {"start", genome_name(opt.start)},
                             {"population", opt.population},
                             {"seed", opt.seed}};
  if (opt.fused) settings["fused"] = true;  // absent without: the settings of searches before the gene
  if (mixed) settings["mixed"] = {opt.wide_de, opt.wide_dm};
  // state.json: the settings, the generation reached and its population.
  const fs::path state_path = dir / "state.json";
  auto ev = std::make_shared<Evaluator>();
  ev->w = &w;
  ev->cm = &cm;
  ev->context_hash = context_hash;
  ev->threads = opt.threads;
  ev->log_path = (dir / "evaluations.jsonl").string();
  ev->wide_de = opt.wide_de, ev->wide_dm = opt.wide_dm;
  if (fs::exists(ev->log_path)) ev->load(ev->log_path);

  // Genes moved over: nine, then the fuse gene with fused moves, the wide gene with mixed moves.
  const bool with_period = opt.fused || mixed;
  std::vector<int> genes;
  for (int i = 0; i < kTriGenesUnfused; ++i) genes.push_back(i);
  if (opt.fused) genes.push_back(kTriGenes - 2);  // fuse
  if (mixed) genes.push_back(kTriGenes - 1);      // wide
  TriProblem tp{ev, static_cast<int>(genes.size()), with_period, genes};
  pagmo::problem prob{tp};
  pagmo::population pop{prob, 0u, static_cast<unsigned>(opt.seed)};
  int gen = 0;
  SearchResult res;
  if (fs::exists(state_path)) {
    std::ifstream in(state_path);
    nlohmann::json st;
    try {
      st = nlohmann::json::parse(in);
    } catch (const std::exception& e) {
      throw IrError(state_path.string() + ": not a search state (" + e.what() + ")");
    }
    if (st.value("settings", nlohmann::json()) != settings)
      throw IrError(state_path.string() +
                    ": a search with other settings (format, clock, workload, start, population or seed) is in this "
                    "directory; use another --out or delete it");
    gen = st.at("generation");
    std::vector<TriGenome> gs;
    for (const auto& v : st.at("population")) gs.push_back(tri_genome(v.get<std::vector<int>>()));
    const auto cs = ev->run(gs);  // from the cache
    for (const auto& c : cs) pop.push_back(tp.encode(c.genome), objectives_of(c.fit, tp.with_period));
    say("resumed at generation " + std::to_string(gen) + " from " + state_path.string());
  } else {
    // Generation 0: the start formulation and mutations of it.
    util::Xoshiro256ss rng(opt.seed);
    std::vector<TriGenome> gs = {opt.start};
    while (static_cast<int>(gs.size()) < opt.population) gs.push_back(mutate(opt.start, tp.genes, rng));
    const auto cs = ev->run(gs);
    for (size_t i = 0; i < cs.size(); ++i) pop.push_back(tp.encode(gs[i]), objectives_of(cs[i].fit, tp.with_period));
  }
  auto save = [&] {
    nlohmann::json popj = nlohmann::json::array();
    for (const auto& x : pop.get_x()) popj.push_back(genes_record(tp.decode(x)));
    write_atomic(state_path, nlohmann::json{{"settings", settings}, {"generation", gen}, {"population", popj}}.dump(1));
  };
  save();
  while (gen < opt.generations) {
    // One generation per call, seeded by (seed, generation): a resumed run continues exactly.
    uint64_t sm = opt.seed ^ (0x9e3779b97f4a7c15ull * static_cast<uint64_t>(gen + 1));
    const unsigned gseed = static_cast<unsigned>(util::splitmix64(sm));
    pagmo::nsga2 algo(1u, 0.9, 10., 1.0 / tp.n, 10., gseed);
    algo.set_bfe(pagmo::bfe{TriBatch{}});
    pop = algo.evolve(pop);
    ++gen;
    ++res.generations_run;
    save();
    std::vector<Candidate> all;
    for (const auto& k : ev->order) all.push_back(ev->cache.at(k));
    const auto front = pareto_front(all, with_period);
    say("generation " + std::to_string(gen) + "/" + std::to_string(opt.generations) + ": " +
        std::to_string(ev->cache.size()) + " designs evaluated, front " + std::to_string(front.size()));
  }
  // The front of every design this search evaluated (not only the last population).
  std::vector<Candidate> all;
  for (const auto& k : ev->order) all.push_back(ev->cache.at(k));
  res.front = pareto_front(all, with_period);
  res.evaluations = ev->evaluations;
  res.cache_hits = ev->hits;
  return res;
}

}  // namespace ru::dp
