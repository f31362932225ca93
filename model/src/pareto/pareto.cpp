// rayunits pareto: fronts, targets, the profile plan (rayunits/pareto/pareto.hpp).
#include "rayunits/pareto/pareto.hpp"

#include <glob.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "rayunits/num/format.hpp"
#include "rayunits/sweep/sweep.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/util/csv.hpp"

namespace ru::pareto {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string read_text(const std::string& path) {
  try {
    return synth::read_file(path);
  } catch (const std::exception& e) {
    throw ParetoError(e.what());
  }
}

bool ends_with(const std::string& s, const std::string& e) {
  return s.size() >= e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

void flatten_into(const json& j, const std::string& prefix, Row& out) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string k = prefix.empty() ? it.key() : prefix + "." + it.key();
    const json& v = it.value();
    if (v.is_object()) {
      flatten_into(v, k, out);
    } else if (v.is_array()) {
      std::string s;
      bool scalars = true;
      for (const auto& e : v) {
        if (e.is_structured()) { scalars = false; break; }
        s += (s.empty() ? "" : ";") + (e.is_string() ? e.get<std::string>() : e.dump());
      }
      if (scalars) out[k] = s;
    } else {
      out[k] = v;
    }
  }
}

// A CSV cell as a JSON scalar: a number when the whole cell is one, else the string.
json csv_value(const std::string& c) {
  if (c.empty()) return nullptr;
  char* end = nullptr;
  const double d = std::strtod(c.c_str(), &end);
  if (end && *end == '\0' && std::isfinite(d)) return d;
  return c;
}

std::optional<double> number(const Row& r, const std::string& f) {
  auto it = r.find(f);
  if (it == r.end()) return std::nullopt;
  if (it->is_number()) {
    const double d = it->get<double>();
    if (std::isfinite(d)) return d;
    return std::nullopt;
  }
  if (it->is_boolean()) return it->get<bool>() ? 1.0 : 0.0;
  return std::nullopt;
}

std::string text(const Row& r, const std::string& f) {
  auto it = r.find(f);
  if (it == r.end() || it->is_null()) return "";
  if (it->is_string()) return it->get<std::string>();
  if (it->is_number_integer() || it->is_boolean()) return it->dump();
  if (it->is_number()) {
    const double d = it->get<double>();
    if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 1e15) return std::to_string(static_cast<long long>(d));
    std::ostringstream s;
    s.precision(10);
    s << d;
    return s.str();
  }
  return it->dump();
}

const std::map<std::string, std::vector<std::string>>& aliases() {
  static const std::map<std::string, std::vector<std::string>> a = {
      {"area", {"area_um2", "area_mm2", "area_nand2"}},
      {"fmax", {"fmax_mhz", "rays_per_s", "clock_mhz", "fmax_est_mhz"}},
      {"error", {"error_pct", "error_fraction", "unit_roundoff"}},
  };
  return a;
}

std::string fmt_num(double v) {
  std::ostringstream s;
  if (std::fabs(v) >= 1e4 && std::fabs(v) < 1e15) {
    s << std::fixed;
    s.precision(0);
  } else {
    s.precision(4);
  }
  s << v;
  return s.str();
}

bool better_or_equal(const Point& a, const Point& b, const std::vector<Axis>& axes, bool* strictly) {
  *strictly = false;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const double x = axes[k].minimize ? a.v[k] : -a.v[k];
    const double y = axes[k].minimize ? b.v[k] : -b.v[k];
    if (x > y) return false;
    if (x < y) *strictly = true;
  }
  return true;
}

}  // namespace

Row flatten(const json& j) {
  Row r = Row::object();
  if (j.is_object()) flatten_into(j, "", r);
  return r;
}

void derive(Row& r) {
  if (!r.contains("exp_bits") || !r.contains("frac_bits")) {
    const std::string f = text(r, "format");
    if (!f.empty()) {
      try {
        const num::Format fm = num::Format::parse(f);
        r["exp_bits"] = fm.exp_bits;
        r["frac_bits"] = fm.frac_bits;
      } catch (const std::exception&) {  // "float", "double" or another name: no widths
      }
    }
  }
  const auto m = number(r, "frac_bits");
  if (m && !r.contains("unit_roundoff")) {
    const std::string rd = text(r, "round");
    const bool nearest = rd.empty() || rd == "rne" || rd == "rna" || rd == "0";
    r["unit_roundoff"] = std::ldexp(1.0, -static_cast<int>(*m) - (nearest ? 1 : 0));
  }
}

std::vector<std::string> expand_inputs(const std::vector<std::string>& inputs) {
  std::vector<std::string> out;
  for (const auto& in : inputs) {
    if (in.find_first_of("*?[") == std::string::npos) {
      out.push_back(in);
      continue;
    }
    glob_t g{};
    const int rc = ::glob(in.c_str(), 0, nullptr, &g);
    if (rc == 0)
      for (std::size_t i = 0; i < g.gl_pathc; ++i) out.push_back(g.gl_pathv[i]);
    globfree(&g);
    if (rc != 0) throw ParetoError("input pattern '" + in + "' matches no file");
  }
  return out;
}

std::vector<Row> load_rows(const std::string& path) {
  std::vector<Row> rows;
  auto add = [&](Row r) {
    derive(r);
    r["source"] = path;
    rows.push_back(std::move(r));
  };
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    if (!fs::exists(fs::path(path) / "results.jsonl"))
      throw ParetoError("'" + path + "' is a directory without results.jsonl (not a `rayunits sweep` directory)");
    // The current grid's jobs, as results.csv shows them (not the rows of earlier RTL).
    for (const auto& sr : sweep::current_results(path)) {
      if (sr.value("status", "") != "ok" || !sr.contains("result") || !sr["result"].is_array()) continue;
      Row base = Row::object();
      if (sr.contains("params")) flatten_into(sr["params"], "", base);
      base["kind"] = sr.value("kind", "");
      base["hash"] = sr.value("hash", "");
      for (const auto& res : sr["result"]) {
        Row r = base;
        if (res.is_object()) flatten_into(res, "", r);
        add(std::move(r));
      }
    }
    return rows;
  }
  if (!fs::exists(path, ec)) throw ParetoError("no such file or directory: '" + path + "'");
  const std::string t = read_text(path);
  if (ends_with(path, ".csv")) {
    const auto recs = util::csv_parse(t, '#');
    if (recs.empty()) throw ParetoError("'" + path + "': empty CSV (a header row is needed)");
    const auto& h = recs[0];
    for (std::size_t i = 1; i < recs.size(); ++i) {
      if (recs[i].size() != h.size())
        throw ParetoError("'" + path + "': record " + std::to_string(i + 1) + " has " +
                          std::to_string(recs[i].size()) + " cells, the header " + std::to_string(h.size()));
      Row r = Row::object();
      for (std::size_t c = 0; c < h.size(); ++c) r[h[c]] = csv_value(recs[i][c]);
      add(std::move(r));
    }
    return rows;
  }
  if (ends_with(path, ".jsonl")) {
    std::istringstream in(t);
    std::size_t n = 0;
    for (std::string line; std::getline(in, line);) {
      ++n;
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      json j;
      try {
        j = json::parse(line);
      } catch (const std::exception& e) {
        throw ParetoError("'" + path + "' line " + std::to_string(n) + ": not JSON (" + e.what() + ")");
      }
      if (!j.is_object()) throw ParetoError("'" + path + "' line " + std::to_string(n) + ": not a JSON object");
      add(flatten(j));
    }
    return rows;
  }
  if (ends_with(path, ".json")) {
    json j;
    try {
      j = json::parse(t);
    } catch (const std::exception& e) {
      throw ParetoError("'" + path + "': not JSON (" + e.what() + ")");
    }
    const json* arr = &j;
    if (j.is_object() && j.contains("rows") && j["rows"].is_array()) arr = &j["rows"];
    if (!arr->is_array())
      throw ParetoError("'" + path + "': a JSON array of rows (or an object with \"rows\") is expected");
    for (const auto& e : *arr)
      if (e.is_object()) add(flatten(e));
    return rows;
  }
  throw ParetoError("'" + path + "': unknown input; accepted: a sweep directory, .jsonl, .json, .csv");
}

bool axis_direction_minimize(const std::string& f) {
  if (f == "fmax") return false;
  for (const char* k : {"fmax", "clock", "rays_per_s", "throughput", "psnr", "_per_", "speed", "mhz", "ghz"})
    if (f.find(k) != std::string::npos) return false;
  return true;
}

Axis parse_axis(const std::string& spec) {
  Axis a;
  const auto c = spec.rfind(':');
  a.field = c == std::string::npos ? spec : spec.substr(0, c);
  if (a.field.empty()) throw ParetoError("axis '" + spec + "': empty field name; accepted: FIELD, FIELD:min, FIELD:max");
  if (c == std::string::npos) {
    a.minimize = axis_direction_minimize(a.field);
  } else {
    const std::string d = spec.substr(c + 1);
    if (d == "min") a.minimize = true;
    else if (d == "max") a.minimize = false;
    else throw ParetoError("axis '" + spec + "': direction '" + d + "'; accepted: min, max");
  }
  return a;
}

Result compute(const std::vector<Row>& rows, const Options& opt) {
  if (opt.axes.size() < 2 || opt.axes.size() > 3) throw ParetoError("a front needs 2 or 3 axes");
  Result res;
  res.axes = opt.axes;
  std::vector<std::string> by = opt.group_by;
  if (by.empty()) {
    for (const auto& r : rows)
      if (r.contains("unit")) { by = {"unit"}; break; }
  }
  std::vector<std::string> label = opt.label;
  if (label.empty()) label = {"format", "stages", "round", "target_clock_ps", "tri", "box", "scene"};

  // Rows passing --where, by group (first appearance order).
  std::vector<std::string> order;
  std::map<std::string, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    bool ok = true;
    for (const auto& [k, v] : opt.where)
      if (text(rows[i], k) != v) { ok = false; break; }
    if (!ok) continue;
    std::string g;
    for (const auto& k : by) {
      const std::string v = text(rows[i], k);
      g += (g.empty() ? "" : " ") + (k == "unit" || by.size() == 1 ? v : k + "=" + v);
    }
    if (g.empty()) g = "all";
    if (!groups.count(g)) order.push_back(g);
    groups[g].push_back(i);
  }
  if (order.empty()) throw ParetoError("no rows" + std::string(opt.where.empty() ? "" : " match --where"));

  for (const auto& gname : order) {
    const auto& idx = groups[gname];
    Group g;
    g.name = gname;
    for (const auto& a : opt.axes) {
      std::vector<std::string> cands = {a.field};
      if (aliases().count(a.field)) cands = aliases().at(a.field);
      std::string pick;
      for (const auto& c : cands) {  // the first candidate every row of the group has
        bool all = true;
        for (auto i : idx) all = all && number(rows[i], c).has_value();
        if (all) { pick = c; break; }
      }
      if (pick.empty())
        for (const auto& c : cands) {  // else the first any row has (rows without it are left out)
          bool any = false;
          for (auto i : idx) any = any || number(rows[i], c).has_value();
          if (any) { pick = c; break; }
        }
      if (pick.empty()) {
        std::string acc;
        for (const auto& c : cands) acc += (acc.empty() ? "" : ", ") + c;
        g.fields.clear();
        res.skipped.push_back("group '" + gname + "': no row has a number in field " +
                              (cands.size() > 1 ? "'" + a.field + "' (" + acc + ")" : "'" + a.field + "'"));
        break;
      }
      g.fields.push_back(pick);
    }
    if (g.fields.size() != opt.axes.size()) continue;
    const std::size_t first = res.points.size();
    for (auto i : idx) {
      Point p;
      p.row = i;
      p.group = gname;
      bool ok = true;
      for (const auto& f : g.fields) {
        const auto v = number(rows[i], f);
        if (!v) { ok = false; break; }
        p.v.push_back(*v);
      }
      if (!ok) { ++g.no_value; continue; }
      for (const auto& k : label) {
        const std::string v = text(rows[i], k);
        if (v.empty()) continue;
        std::string s = v;
        if (k == "stages") s = "s" + v;
        else if (k == "target_clock_ps") s = v + "ps";
        else if (k == "round" && v == "rne") continue;
        p.label += (p.label.empty() ? "" : " ") + s;
      }
      if (p.label.empty()) p.label = "#" + std::to_string(i);
      res.points.push_back(std::move(p));
    }
    for (std::size_t a = first; a < res.points.size(); ++a) {
      for (std::size_t b = first; b < res.points.size(); ++b) {
        bool strictly = false;
        if (a != b && better_or_equal(res.points[b], res.points[a], opt.axes, &strictly) && strictly) {
          res.points[a].dominated = true;
          res.points[a].dominated_by = b;
          break;
        }
      }
    }
    g.points = res.points.size() - first;
    for (std::size_t a = first; a < res.points.size(); ++a) g.front += !res.points[a].dominated;
    res.groups.push_back(std::move(g));
  }
  if (res.groups.empty()) throw ParetoError(res.skipped.size() == 1 ? res.skipped[0] : res.skipped[0] + " (and every other group)");
  return res;
}

bool Target::met(double x) const {
  if (op == ">=") return x >= value;
  if (op == "<=") return x <= value;
  if (op == ">") return x > value;
  return x < value;
}

double Target::margin(double x) const { return op[0] == '>' ? x - value : value - x; }

Target parse_target(const std::string& spec) {
  for (const char* op : {">=", "<=", ">", "<"}) {
    const auto p = spec.find(op);
    if (p == std::string::npos) continue;
    Target t;
    t.field = spec.substr(0, p);
    t.op = op;
    const std::string v = spec.substr(p + std::string(op).size());
    char* end = nullptr;
    t.value = std::strtod(v.c_str(), &end);
    if (t.field.empty() || v.empty() || !end || *end != '\0' || !std::isfinite(t.value))
      throw ParetoError("target '" + spec + "': accepted: FIELD>=NUMBER, FIELD<=NUMBER, FIELD>NUMBER, FIELD<NUMBER");
    return t;
  }
  throw ParetoError("target '" + spec + "': no comparison; accepted: FIELD>=NUMBER, FIELD<=NUMBER, FIELD>NUMBER, FIELD<NUMBER");
}

std::vector<Pick> cheapest(const Result& res, const std::vector<Row>& rows, const std::vector<Target>& targets,
                           std::size_t cost_axis) {
  std::vector<Pick> picks;
  if (cost_axis >= res.axes.size()) throw ParetoError("cost axis out of range");
  for (const auto& g : res.groups) {
    Pick pk;
    pk.group = g.name;
    for (std::size_t i = 0; i < res.points.size(); ++i) {
      const Point& p = res.points[i];
      if (p.group != g.name) continue;
      bool ok = true, has = true;
      double val = 0, margin = 0;
      for (std::size_t t = 0; t < targets.size(); ++t) {
        const auto v = number(rows[p.row], targets[t].field);
        if (!v) { has = false; ok = false; break; }
        ok = ok && targets[t].met(*v);
        if (t == 0) { val = *v; margin = targets[t].margin(*v); }
      }
      pk.candidates += has;
      if (!ok) continue;
      auto key = [&](const Point& q) {
        std::vector<double> k;
        k.push_back(res.axes[cost_axis].minimize ? q.v[cost_axis] : -q.v[cost_axis]);
        for (std::size_t a = 0; a < res.axes.size(); ++a)
          if (a != cost_axis) k.push_back(res.axes[a].minimize ? q.v[a] : -q.v[a]);
        return k;
      };
      if (!pk.point || key(p) < key(res.points[*pk.point])) {
        pk.point = i;
        pk.value = val;
        pk.margin = margin;
      }
    }
    picks.push_back(pk);
  }
  return picks;
}

ProfilePlan plan_from_profile(const json& prof, const std::vector<Row>& rows, const Axis& cost,
                              const std::vector<Target>& unit_targets) {
  ProfilePlan plan;
  try {
    plan.scene = prof.at("scene").get<std::string>();
    plan.units = prof.at("units").get<std::vector<std::string>>();
    const json& tg = prof.at("target");
    plan.max_error_fraction = tg.at("max_error_fraction").get<double>();
    plan.min_psnr = tg.at("min_psnr").get<double>();
    if (!prof.at("fraction_widths").is_array()) throw std::runtime_error("fraction_widths is not an array");
  } catch (const std::exception& e) {
    throw ParetoError(std::string("not a `rayunits profile --json` file (") + e.what() + ")");
  }
  if (!prof.contains("recommended_exp_bits") || !prof["recommended_exp_bits"].is_number_integer() ||
      prof["recommended_exp_bits"].get<int>() <= 0)
    throw ParetoError("the profile recommends no exponent width (no width avoided overflow): no format to plan");
  const int e = prof["recommended_exp_bits"].get<int>();
  std::vector<std::string> cands = {cost.field};
  if (aliases().count(cost.field)) cands = aliases().at(cost.field);
  // The cost field: the first candidate some unit row has.
  for (const auto& c : cands) {
    for (const auto& r : rows)
      if (number(r, c)) { plan.cost_field = c; break; }
    if (!plan.cost_field.empty()) break;
  }
  if (plan.cost_field.empty()) throw ParetoError("no row has a number in the cost field '" + cost.field + "'");
  const bool minimize = cost.minimize;
  for (const auto& fw : prof["fraction_widths"]) {
    const int m = fw.at("frac_bits").get<int>();
    const std::string measured = "e" + std::to_string(e) + "m" + std::to_string(m);
    // The measured format, and every format of the rows with this fraction width and a wider
    // exponent (assumed no worse: a wider exponent only removes overflow and underflow).
    std::vector<std::string> fmts = {measured};
    for (const auto& r : rows) {
      const auto re = number(r, "exp_bits"), rm = number(r, "frac_bits");
      const std::string f = text(r, "format");
      if (re && rm && static_cast<int>(*rm) == m && static_cast<int>(*re) > e &&
          std::find(fmts.begin(), fmts.end(), f) == fmts.end())
        fmts.push_back(f);
    }
    std::sort(fmts.begin() + 1, fmts.end());
    for (const auto& fmt : fmts) {
      ProfileChoice ch;
      ch.format = fmt;
      ch.measured_at = measured;
      ch.meets = fw.value("meets", false);
      const double px = fw.value("pixels", 0.0);
      ch.error_fraction = px > 0 ? fw.value("errors", 0.0) / px : 0;
      ch.psnr = fw.contains("psnr") && fw["psnr"].is_number() ? fw["psnr"].get<double>() : INFINITY;
      for (const auto& u : plan.units) {
        std::optional<std::size_t> best;
        for (std::size_t i = 0; i < rows.size(); ++i) {
          const Row& r = rows[i];
          if (text(r, "unit") != u) continue;
          const bool unit_has_format = r.contains("format") && !r["format"].is_null();
          if (unit_has_format && text(r, "format") != ch.format) continue;
          const auto v = number(r, plan.cost_field);
          if (!v) continue;
          bool ok = true;
          for (const auto& t : unit_targets) {
            const auto tv = number(r, t.field);
            ok = ok && tv && t.met(*tv);
          }
          if (!ok) continue;
          const double key = minimize ? *v : -*v;
          if (!best || key < (minimize ? 1 : -1) * *number(rows[*best], plan.cost_field)) best = i;
        }
        if (best) {
          ch.unit_rows.push_back({u, *best});
          ch.cost += *number(rows[*best], plan.cost_field);
        } else {
          ch.missing.push_back(u);
        }
      }
      plan.formats.push_back(ch);
    }
  }
  for (std::size_t i = 0; i < plan.formats.size(); ++i) {
    const auto& c = plan.formats[i];
    if (!c.meets || !c.missing.empty()) continue;
    if (!plan.pick || (minimize ? c.cost < plan.formats[*plan.pick].cost : c.cost > plan.formats[*plan.pick].cost))
      plan.pick = i;
  }
  return plan;
}

std::string points_csv(const Result& res, const std::vector<Row>& rows) {
  std::vector<std::string> extra;  // every other field, first-seen order
  std::map<std::string, bool> seen;
  for (const auto& p : res.points)
    for (auto it = rows[p.row].begin(); it != rows[p.row].end(); ++it)
      if (!seen[it.key()]) { seen[it.key()] = true; extra.push_back(it.key()); }
  std::vector<std::string> head = {"group", "label"};
  for (std::size_t a = 0; a < res.axes.size(); ++a) head.push_back("axis" + std::to_string(a + 1));
  for (std::size_t a = 0; a < res.axes.size(); ++a) head.push_back("axis" + std::to_string(a + 1) + "_field");
  head.push_back("dominated");
  head.push_back("dominated_by");
  for (const auto& e : extra) head.push_back(e);
  std::string out = util::csv_row(head);
  std::map<std::string, const Group*> gi;
  for (const auto& g : res.groups) gi[g.name] = &g;
  for (const auto& p : res.points) {
    std::vector<std::string> c = {p.group, p.label};
    for (double v : p.v) c.push_back(fmt_num(v));
    for (const auto& f : gi[p.group]->fields) c.push_back(f);
    c.push_back(p.dominated ? "1" : "0");
    c.push_back(p.dominated ? res.points[p.dominated_by].label : "");
    for (const auto& e : extra) c.push_back(text(rows[p.row], e));
    out += util::csv_row(c);
  }
  return out;
}

std::string front_markdown(const Result& res, const std::vector<Row>& rows, bool all) {
  (void)rows;
  std::ostringstream o;
  for (const auto& s : res.skipped) o << "Left out: " << s << ".\n\n";
  for (const auto& g : res.groups) {
    o << "#### " << g.name << ": " << g.front << " of " << g.points << " points on the front";
    if (g.no_value) o << " (" << g.no_value << " rows without a value on some axis left out)";
    o << "\n\n| point |";
    for (std::size_t a = 0; a < res.axes.size(); ++a)
      o << " " << g.fields[a] << " (" << (res.axes[a].minimize ? "min" : "max") << ") |";
    o << (all ? " front |\n|---|" : "\n|---|");
    for (std::size_t a = 0; a < res.axes.size(); ++a) o << "---:|";
    o << (all ? "---|\n" : "\n");
    for (const auto& p : res.points) {
      if (p.group != g.name || (!all && p.dominated)) continue;
      o << "| " << p.label << " |";
      for (double v : p.v) o << " " << fmt_num(v) << " |";
      if (all) o << " " << (p.dominated ? "dominated by " + res.points[p.dominated_by].label : "yes") << " |";
      o << "\n";
    }
    o << "\n";
  }
  return o.str();
}

std::string picks_markdown(const Result& res, const std::vector<Row>& rows, const std::vector<Target>& t,
                           const std::vector<Pick>& picks) {
  (void)rows;
  std::ostringstream o;
  std::string tt;
  for (const auto& x : t) tt += (tt.empty() ? "" : " and ") + x.field + x.op + fmt_num(x.value);
  o << "| group | cheapest meeting " << tt << " | ";
  for (std::size_t a = 0; a < res.axes.size(); ++a) o << res.axes[a].field << " | ";
  o << t[0].field << " | margin |\n|---|---|";
  for (std::size_t a = 0; a < res.axes.size() + 2; ++a) o << "---:|";
  o << "\n";
  for (const auto& pk : picks) {
    if (!pk.point) {
      o << "| " << pk.group << " | none of " << pk.candidates << " with a value meets it |";
      for (std::size_t a = 0; a < res.axes.size() + 2; ++a) o << " |";
      o << "\n";
      continue;
    }
    const Point& p = res.points[*pk.point];
    o << "| " << pk.group << " | " << p.label << " |";
    for (double v : p.v) o << " " << fmt_num(v) << " |";
    o << " " << fmt_num(pk.value) << " | " << fmt_num(pk.margin) << " |\n";
  }
  return o.str();
}

std::string plan_markdown(const ProfilePlan& p, const std::vector<Row>& rows) {
  std::ostringstream o;
  o << "Scene " << p.scene << ": units";
  for (const auto& u : p.units) o << " " << u;
  o << "; target error pixels <= " << fmt_num(100 * p.max_error_fraction) << " %, PSNR >= " << fmt_num(p.min_psnr)
    << " dB (measured by the profile at each fraction width); cost " << p.cost_field << " summed over the units\n\n";
  o << "| format | image measured at | error pixels % | PSNR dB | meets | " << p.cost_field
    << " | rows used | missing units |\n";
  o << "|---|---|---:|---:|---|---:|---|---|\n";
  for (std::size_t i = 0; i < p.formats.size(); ++i) {
    const auto& c = p.formats[i];
    std::string used, miss;
    for (const auto& [u, r] : c.unit_rows) {
      std::string s = text(rows[r], "stages");
      used += (used.empty() ? "" : ", ") + u + (s.empty() ? "" : " s" + s);
    }
    for (const auto& u : c.missing) miss += (miss.empty() ? "" : ", ") + u;
    o << "| " << c.format << (p.pick && *p.pick == i ? " **(pick)**" : "") << " | " << c.measured_at << " | "
      << fmt_num(100 * c.error_fraction)
      << " | " << (std::isinf(c.psnr) ? "inf" : fmt_num(c.psnr)) << " | " << (c.meets ? "yes" : "no") << " | "
      << (c.missing.empty() ? fmt_num(c.cost) : "") << " | " << used << " | " << miss << " |\n";
  }
  o << "\n";
  if (p.pick) {
    const auto& c = p.formats[*p.pick];
    o << "Cheapest configuration that meets the target: " << c.format
      << (c.format == c.measured_at ? "" : " (image error measured at " + c.measured_at + "; the wider exponent is assumed no worse)")
      << ", " << p.cost_field << " "
      << fmt_num(c.cost) << "; margin: error pixels " << fmt_num(100 * (p.max_error_fraction - c.error_fraction))
      << " percentage points below the limit, PSNR "
      << (std::isinf(c.psnr) ? std::string("inf") : fmt_num(c.psnr - p.min_psnr) + " dB") << " above it.\n";
  } else {
    o << "No format meets the target with a row for every unit (see 'missing units').\n";
  }
  return o.str();
}

}  // namespace ru::pareto
