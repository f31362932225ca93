// TRaX model: RTL-derived unit latencies ("rtl"), synthesized unit areas ("synth", um2) and the STA
// chip clock ("sta") from the committed area table model/data/trax/areas.json (docs/TRAX.md
// "Area model"): rows of `rayunits trax areas`, i.e. the synthesis rows of `rayunits synth --json`
// (cell-library flow osu018: area_um2 and the STA fmax_mhz of the area-oriented mapping).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>

#include "rayunits/num/format.hpp"
#include "rayunits/synth/cell.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/trax/config.hpp"

namespace ru::trax {

namespace {

std::string format_name(const Config& c) { return num::Format::parse(c.format == "float" ? "e8m23" : c.format).name(); }

std::string fmt1(double v, const char* f = "%.1f") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

struct Row {
  double area = 0;      // um2 (cell rows; generic rows: NAND2-eq x NAND2X1, an estimate)
  double fmax_mhz = 0;  // STA (cell rows); 0 for generic rows
  bool cell = false;    // a cell-library row (else a generic NAND2-eq row)
  std::string command, format, flow;
};
using Table = std::map<std::string, Row>;  // key "unit|format|stages"

struct Loaded {
  Table rows;
  double nand2_um2 = 0;
  std::string nand2_from;  // "NAND2X1 of LIBERTY"
};

std::string key(const std::string& unit, const std::string& fmt, int stages) {
  return unit + "|" + fmt + "|" + std::to_string(stages);
}


std::string joined_units() {
  std::string j;
  for (const auto& u : area_table_units()) j += (j.empty() ? "" : ", ") + u;
  return j;
}

// One row of the file -> Row, or a one-line reason (what is wrong) in *why.
bool parse_row(const nlohmann::json& r, double nand2_um2, std::string* k, Row* row, std::string* why) {
  auto fail = [&](const std::string& m) {
    *why = m;
    return false;
  };
  if (!r.is_object()) return fail("not a JSON object");
  if (!r.contains("unit") || !r["unit"].is_string()) return fail("no string \"unit\"");
  const std::string unit = r["unit"].get<std::string>();
  if (std::find(area_table_units().begin(), area_table_units().end(), unit) == area_table_units().end())
    return fail("unit '" + unit + "' is not a TRaX unit (" + joined_units() + ")");
  if (!r.contains("stages") || !r["stages"].is_number_integer() || r["stages"].get<int>() < 0)
    return fail("no integer \"stages\" >= 0");
  const int stages = r["stages"].get<int>();
  std::string fmt = "-";
  const bool fmtless = !synth::find_unit(unit).uses_format;
  if (fmtless) {
    if (r.contains("format") && !r["format"].is_null() && r["format"] != "-")
      return fail("the " + unit + " unit has no format (got " + r["format"].dump() + ")");
  } else {
    if (!r.contains("format") || !r["format"].is_string()) return fail("no string \"format\"");
    try {
      const num::Format F = num::Format::parse(r["format"].get<std::string>());
      F.validate();
      fmt = F.name();
    } catch (const std::exception& e) {
      return fail(std::string("format: ") + e.what());
    }
    if (fmt != r["format"].get<std::string>()) return fail("format '" + r["format"].get<std::string>() + "' is not canonical (" + fmt + ")");
  }
  if (!r.contains("command") || !r["command"].is_string()) return fail("no string \"command\"");
  row->command = r["command"].get<std::string>();
  // The command must be the one that measured this row (catches a row edited by hand).
  std::istringstream cs(row->command);
  std::vector<std::string> w;
  for (std::string t; cs >> t;) w.push_back(t);
  auto opt = [&](const std::string& o) -> std::string {
    for (size_t i = 0; i + 1 < w.size(); ++i)
      if (w[i] == o) return w[i + 1];
    return "";
  };
  if (w.size() < 3 || w[0] != "rayunits" || w[1] != "synth") return fail("command is not `rayunits synth ...`");
  if (w[2] != unit) return fail("command synthesizes '" + w[2] + "', the row says unit '" + unit + "'");
  if (opt("--stages") != std::to_string(stages))
    return fail("command has --stages " + (opt("--stages").empty() ? std::string("(none)") : opt("--stages")) +
                ", the row says stages " + std::to_string(stages));
  if (!fmtless && opt("--format") != fmt)
    return fail("command has --format " + (opt("--format").empty() ? std::string("(none)") : opt("--format")) +
                ", the row says format " + fmt);
  row->flow = r.value("flow", std::string("generic"));
  if (!r.contains("flow") || !r["flow"].is_string()) return fail("no string \"flow\"");
  row->cell = synth::is_cell_flow(row->flow);
  if (row->cell) {
    if (opt("--flow") != row->flow) return fail("command has no --flow " + row->flow);
    for (const char* f : {"area_um2", "fmax_mhz"})
      if (!r.contains(f) || !r[f].is_number() || !(r[f].get<double>() > 0))
        return fail(std::string("no number \"") + f + "\" > 0 (a cell-flow row)");
    row->area = r["area_um2"].get<double>();
    row->fmax_mhz = r["fmax_mhz"].get<double>();
  } else if (row->flow == "generic") {
    if (!r.contains("area_nand2") || !r["area_nand2"].is_number() || !(r["area_nand2"].get<double>() > 0))
      return fail("no number \"area_nand2\" > 0 (a generic-flow row)");
    row->area = r["area_nand2"].get<double>() * nand2_um2;
  } else {
    return fail("unknown flow '" + row->flow + "' (" + synth::flow_names_list() + ")");
  }
  if (std::find(w.begin(), w.end(), "--param") != w.end())
    return fail("command sets --param (the table holds each unit at its registry defaults only)");
  row->format = fmt;
  *k = key(unit, fmt, stages);
  return true;
}

// Parsed tables by path and content (the file is re-read on every call, ~0.1 MB: a table
// changed on disk, or another $RU_TRAX_AREAS, is never served from a stale cache).
std::shared_ptr<const Loaded> load_table() {
  static std::mutex mu;
  static std::map<std::pair<std::string, std::string>, std::shared_ptr<const Loaded>> cache;
  const std::string path = area_table_path();
  const std::string where = "trax area table " + path + ": ";
  std::ifstream in(path);
  if (!in) throw ConfigError(where + "cannot open the file (set RU_TRAX_AREAS, or give every unit a numeric area)");
  std::ostringstream text;
  text << in.rdbuf();
  std::lock_guard<std::mutex> lock(mu);
  auto ck = std::make_pair(path, text.str());
  auto it = cache.find(ck);
  if (it != cache.end()) return it->second;
  Loaded t;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(ck.second);
  } catch (const std::exception& e) {
    throw ConfigError(where + "not JSON: " + e.what());
  }
  if (!j.is_object() || !j.contains("rows") || !j["rows"].is_array()) throw ConfigError(where + "no \"rows\" array");
  const auto& n = j.value("nand2_cell", nlohmann::json());
  if (!n.is_object() || !n.contains("area_um2") || !n["area_um2"].is_number() || !(n["area_um2"].get<double>() > 0))
    throw ConfigError(where + "no \"nand2_cell\" with \"area_um2\" > 0 (written by `rayunits trax areas` from the liberty)");
  t.nand2_um2 = n["area_um2"].get<double>();
  t.nand2_from = n.value("cell", std::string("NAND2X1")) + " of " + n.value("liberty", std::string("?"));
  std::string lib;  // the one cell library of the table's cell rows
  for (size_t i = 0; i < j["rows"].size(); ++i) {
    const auto& r = j["rows"][i];
    std::string k, why;
    Row row;
    if (!parse_row(r, t.nand2_um2, &k, &row, &why)) {
      std::string what = "row " + std::to_string(i + 1);
      if (r.is_object() && r.contains("unit") && r["unit"].is_string()) {
        what += " (" + r["unit"].get<std::string>();
        if (r.contains("format") && r["format"].is_string()) what += " " + r["format"].get<std::string>();
        if (r.contains("stages") && r["stages"].is_number_integer()) what += " Stages " + std::to_string(r["stages"].get<int>());
        what += ")";
      }
      throw ConfigError(where + what + ": " + why);
    }
    if (row.cell) {
      if (!lib.empty() && lib != row.flow)
        throw ConfigError(where + "row " + std::to_string(i + 1) + ": flow " + row.flow + " mixed with " + lib +
                          " rows (one cell library per table)");
      lib = row.flow;
    }
    auto old = t.rows.find(k);
    if (old != t.rows.end()) {
      if (old->second.cell == row.cell)
        throw ConfigError(where + "row " + std::to_string(i + 1) + ": a second row for " + k + " in flow " + row.flow);
      if (old->second.cell) continue;  // a cell-flow row is preferred to a generic one
    }
    t.rows[k] = row;
  }
  if (cache.size() > 16) cache.clear();  // tests write many small tables (callers hold shared_ptrs)
  return cache.emplace(std::move(ck), std::make_shared<const Loaded>(std::move(t))).first->second;
}

// The Stages the synthesized RTL can have: the latency, limited to the unit's useful maximum for
// the format (further latency cycles are output registers, not modelled in the area).
int synth_stages(const std::string& unit, const std::string& fmt, int latency) {
  const synth::UnitSpec& u = synth::find_unit(unit);
  synth::UnitConfig uc;
  if (fmt != "-") uc.fmt = num::Format::parse(fmt);
  return std::min(latency, u.max_stages(uc));
}

const Row* lookup(const Loaded& T, const std::string& unit, const std::string& fmt, int latency) {
  const Table& t = T.rows;
  auto it = t.find(key(unit, fmt, synth_stages(unit, fmt, latency)));
  return it == t.end() ? nullptr : &it->second;
}

std::string row_how(const Loaded& T, const Row& r) {
  return r.cell ? "measured" : "estimate (generic flow: NAND2-eq x " + T.nand2_from + ")";
}

// A missing FP row: scaled from the measured row of the same unit and Stages whose format is
// closest in width: fp_add, fp_cmp in proportion to the width W, fp_mul, fp_div to (M+1)^2.
bool scaled_estimate(const Loaded& T, const std::string& unit, const std::string& fmt, int latency, Row* out) {
  const num::Format F = num::Format::parse(fmt);
  const int st = synth_stages(unit, fmt, latency);
  const std::string prefix = unit + "|";
  const Row* best = nullptr;
  num::Format bf;
  std::pair<int, int> best_score{0, 0};
  for (const auto& [k, row] : T.rows) {
    if (k.compare(0, prefix.size(), prefix) != 0) continue;
    const auto bar = k.rfind('|');
    const std::string rf = k.substr(prefix.size(), bar - prefix.size());
    if (rf == "-") continue;
    const int rs = std::stoi(k.substr(bar + 1));
    const num::Format G = num::Format::parse(rf);
    // closest Stages first, then closest width
    const auto score = std::make_pair(std::abs(rs - st), std::abs(G.width() - F.width()));
    if (!best || score < best_score) {
      best = &row;
      bf = G;
      best_score = score;
    }
  }
  if (!best) return false;
  const bool quad = unit == "fp_mul" || unit == "fp_div" || unit == "fp_sqrt";
  const double f = quad ? double(F.frac_bits + 1) * (F.frac_bits + 1) / (double(bf.frac_bits + 1) * (bf.frac_bits + 1))
                        : double(F.width()) / bf.width();
  *out = *best;
  out->area = best->area * f;
  out->command = "scaled from the measured " + bf.name() + " row (" + (quad ? "(M+1)^2" : "width") +
                 "; its STA Fmax kept): " + best->command;
  return true;
}

// A measured row of `unit` at the Stages of `latency` in a format other than fmt (closest width).
const Row* measured_other_format(const Loaded& T, const std::string& unit, const std::string& fmt, int latency) {
  const num::Format F = num::Format::parse(fmt);
  const Row* best = nullptr;
  int best_d = 1 << 20;
  for (const auto& [k, row] : T.rows) {
    if (k.compare(0, unit.size() + 1, unit + "|") != 0 || row.format == fmt || row.format == "-") continue;
    if (std::stoi(k.substr(k.rfind('|') + 1)) != synth_stages(unit, row.format, latency)) continue;
    const int d = std::abs(num::Format::parse(row.format).width() - F.width());
    if (d < best_d) {
      best = &row;
      best_d = d;
    }
  }
  return best;
}

// The measured row of an FP unit of c's format at its latency (throws ConfigError if absent).
const Row& fp_row_at(const Loaded& T, const Config& c, const char* unit, Unit which) {
  const std::string fmt = num::Format::parse(c.format).name();
  const Row* r = lookup(T, unit, fmt, c.unit(which).latency);
  if (!r) throw ConfigError(std::string("no row for ") + unit + " " + fmt);
  return *r;
}

}  // namespace

const std::vector<std::string>& area_table_units() {
  static const std::vector<std::string> u = {"fp_add",  "fp_mul",     "fp_div",         "fp_sqrt",
                                             "fp_cmp",  "fp_fma",     "fp_cvt",         "int_alu",        "branch",
                                             "ray_box", "ray_tri_robust", "ray_tri_mt", "noise_trunc",
                                             "noise",   "texture"};
  return u;
}

Unit area_table_unit(const std::string& u) {
  if (u == "fp_add") return Unit::FpAdd;
  if (u == "fp_mul") return Unit::FpMul;
  if (u == "fp_div") return Unit::FpDiv;
  if (u == "fp_sqrt") return Unit::FpSqrt;
  if (u == "fp_cmp") return Unit::FpCmp;
  if (u == "fp_fma") return Unit::FpFma;
  if (u == "fp_cvt") return Unit::Conv;
  if (u == "int_alu") return Unit::Int;
  if (u == "branch") return Unit::Branch;
  if (u == "ray_box") return Unit::Box;
  if (u == "noise" || u == "noise_trunc") return Unit::Noise;
  if (u == "texture") return Unit::Texture;
  if (u == "ray_tri_robust" || u == "ray_tri_mt") return Unit::Tri;
  throw ConfigError("'" + u + "' is not a TRaX unit (accepted: " + joined_units() + ")");
}

int area_table_latency(Config& c, const std::string& u) {
  const Unit t = area_table_unit(u);
  if (t == Unit::Tri) c.tri = u == "ray_tri_mt" ? "mt" : "robust";
  if (t == Unit::Noise) c.noise = u == "noise" ? "fixed" : "fixed-trunc";
  if (t == Unit::Box || t == Unit::Tri || t == Unit::Noise || t == Unit::Texture) return rtl_latency(c, t);
  return c.unit(t).latency;
}

std::string area_table_path() {
  if (const char* e = std::getenv("RU_TRAX_AREAS"); e && *e) return e;
#ifdef RU_SOURCE_DIR
  return std::string(RU_SOURCE_DIR) + "/model/data/trax/areas.json";
#else
  return "model/data/trax/areas.json";
#endif
}

std::string noise_unit(const Config& c) { return c.noise == "fixed" ? "noise" : "noise_trunc"; }

int rtl_latency(const Config& c, Unit u) {
  const int add = c.unit(Unit::FpAdd).latency, mul = c.unit(Unit::FpMul).latency,
            div = c.unit(Unit::FpDiv).latency, cmp = c.unit(Unit::FpCmp).latency;
  switch (u) {
    case Unit::Box: return add + mul + 3 * cmp;
    case Unit::Tri: return c.tri == "mt" ? 5 * add + 3 * mul + div + cmp : 4 * add + 2 * mul + div + cmp;
    case Unit::Noise: return 4;
    case Unit::Texture: return 4;  // its Stages (a request takes ceil(n / width) + RootStages more)
    default: return c.unit(u).latency;
  }
}

ChipClock sta_clock(const Config& c, const std::vector<AreaSource>& sources, const std::vector<bool>& used) {
  ChipClock k;
  int at = -1;
  std::string untimed;
  for (int i = 0; i < kUnits; ++i) {
    if (!used.empty() && !used[i]) continue;
    if (!unit_on_chip(c, static_cast<Unit>(i))) continue;
    const UnitCfg& u = c.units[i];
    const char* name = unit_name(static_cast<Unit>(i));
    if (!(u.fmax_mhz > 0)) {
      untimed += std::string(untimed.empty() ? "" : ", ") + name;
      continue;
    }
    if (at < 0 || u.fmax_mhz < k.mhz) {
      k.mhz = u.fmax_mhz;
      k.unit = name;
      at = i;
    }
  }
  if (at < 0)
    throw ConfigError("chip.clock_mhz = \"sta\": no " + std::string(used.empty() ? "configured" : "used") +
                      " unit has an STA clock in the area table (" + area_table_path() +
                      "); give chip.clock_mhz a number");
  // sources[i] is unit i (resolve_config)
  const AreaSource* s = static_cast<size_t>(at) < sources.size() ? &sources[at] : nullptr;
  k.how = "STA Fmax of the slowest " + std::string(used.empty() ? "configured" : "used") + " unit: " + k.unit +
          (s && s->unit != k.unit ? " (" + s->unit + ")" : "") + " at Stages " + std::to_string(c.units[at].latency) +
          ", " + fmt1(k.mhz) + " MHz" + (s && !s->fmax_how.empty() && s->fmax_how != "STA" ? " [" + s->fmax_how + "]" : "") +
          "; before placement (no wire load); not timed: " + (untimed.empty() ? std::string("none") : untimed) +
          ", memories";
  return k;
}

Config resolve_config(const Config& in, std::vector<AreaSource>* sources) {
  Config c = in;
  for (Unit u : {Unit::Box, Unit::Tri, Unit::Noise, Unit::Texture})
    if (c.unit(u).latency == kLatencyRtl) c.unit(u).latency = rtl_latency(c, u);
  const std::string fmt = format_name(c);
  const std::shared_ptr<const Loaded> table = load_table();  // held for this call
  const Loaded& T = *table;
  c.nand2_um2 = T.nand2_um2;
  std::vector<AreaSource> srcs;
  std::map<std::string, Row> estimates;  // scaled rows (kept for this call)
  auto fp_row = [&](const char* unit, Unit which) -> const Row& {
    const int lat = c.unit(which).latency;
    const Row* r = lookup(T, unit, fmt, lat);
    if (r) return *r;
    Row e;
    if (scaled_estimate(T, unit, fmt, lat, &e)) {
      e.command = "estimate: " + e.command;
      return estimates[unit] = e;
    }
    throw ConfigError("trax area table " + area_table_path() + ": no row for " + unit + " " + fmt + " Stages " +
                      std::to_string(synth_stages(unit, fmt, lat)) + " (measure it with `rayunits trax areas`, or give units." +
                      unit_name(which) + ".area a number)");
  };
  for (int i = 0; i < kUnits; ++i) {
    const Unit u = static_cast<Unit>(i);
    UnitCfg& k = c.units[i];
    AreaSource src;
    src.unit = unit_name(u);
    if (k.area == kAreaNand2) {
      k.area = k.area_nand2 * T.nand2_um2;
      src.how = "estimate";
      src.detail = fmt1(k.area_nand2, "%g") + " NAND2-eq (no RTL) x " + fmt1(T.nand2_um2, "%g") + " um2 (" +
                   T.nand2_from + ")";
      k.area_nand2 = 0;
      srcs.push_back(src);
      continue;
    }
    if (!unit_on_chip(c, u)) {  // no row needed (chip.fma = false: the kernel issues no FFMA)
      k.area = 0;
      src.how = "not used (chip.fma = false)";
      srcs.push_back(src);
      continue;
    }
    if (k.area != kAreaSynth) {
      src.how = "configured";
      srcs.push_back(src);
      continue;
    }
    std::string sunit;
    switch (u) {
      case Unit::FpAdd: sunit = "fp_add"; break;
      case Unit::FpMul: sunit = "fp_mul"; break;
      case Unit::FpDiv: sunit = "fp_div"; break;
      case Unit::FpSqrt: sunit = "fp_sqrt"; break;
      case Unit::FpCmp: sunit = "fp_cmp"; break;
      case Unit::FpFma: sunit = "fp_fma"; break;
      case Unit::Conv: sunit = "fp_cvt"; break;
      case Unit::Int: sunit = "int_alu"; break;
      case Unit::Branch: sunit = "branch"; break;
      case Unit::Box: sunit = "ray_box"; break;
      case Unit::Tri: sunit = c.tri == "mt" ? "ray_tri_mt" : "ray_tri_robust"; break;
      case Unit::Noise: sunit = noise_unit(c); break;
      case Unit::Texture: sunit = "texture"; break;
      default: break;
    }
    src.unit = sunit;
    if (u == Unit::Texture) {  // the table's texture rows are the registry defaults: Units 4, Octaves 8
      const long long def = synth::param_value(synth::find_unit("texture"), synth::UnitConfig{}, "Units");
      if (k.width != def)
        throw ConfigError("trax area table " + area_table_path() + ": the texture rows are ru_texture with Units " +
                          std::to_string(def) + " (units.texture.width = " + std::to_string(k.width) +
                          "): give units.texture.area a number");
    }
    const bool fmtless = !synth::find_unit(sunit).uses_format;  // the registry says (noise, texture, int, branch)
    const std::string f = fmtless ? "-" : fmt;
    if (const Row* r = lookup(T, sunit, f, k.latency)) {
      k.area = r->area;
      k.fmax_mhz = r->fmax_mhz;
      src.how = row_how(T, *r);
      src.detail = r->command;
      src.fmax_how = r->fmax_mhz > 0 ? "STA" : "";
    } else if (u == Unit::Box || u == Unit::Tri) {
      // composed from the chip's FP units of this format (at their latencies)
      int na, nm, nd, nc;
      if (u == Unit::Box) {
        na = 6, nm = 6, nd = 0, nc = 7;
      } else if (c.tri == "mt") {
        na = 24, nm = 27, nd = 1, nc = 5;
      } else {
        na = 43, nm = 39, nd = 3, nc = 20;
      }
      const Row &ra = fp_row("fp_add", Unit::FpAdd), &rm = fp_row("fp_mul", Unit::FpMul),
                &rd = fp_row("fp_div", Unit::FpDiv), &rc = fp_row("fp_cmp", Unit::FpCmp);
      const double composed = na * ra.area + nm * rm.area + nd * rd.area + nc * rc.area;
      // Its levels are pipelined like the chip's FP units: the slowest of them bounds its clock.
      auto slowest = [&](const Row& a, const Row& m, const Row& d, const Row& cm) {
        double s = std::min({a.fmax_mhz, m.fmax_mhz, cm.fmax_mhz});
        if (nd) s = std::min(s, d.fmax_mhz);
        return s;
      };
      const double parts_fmax = slowest(ra, rm, rd, rc);
      std::ostringstream o;
      o << na << " fp_add + " << nm << " fp_mul + " << nd << " fp_div + " << nc << " fp_cmp (" << fmt << ")";
      k.area = composed;
      k.fmax_mhz = parts_fmax;
      src.how = "composed";
      src.fmax_how = parts_fmax > 0 ? "estimate (composed: its slowest FP part)" : "";
      // A measured row of this unit and Stages in another format: scale it by the ratio of the
      // compositions (keeps the sweep on the measured unit's basis); its Fmax likewise by the
      // ratio of the slowest FP parts.
      if (const Row* m = measured_other_format(T, sunit, fmt, k.latency)) {
        try {
          Config other = c;
          other.format = m->format;
          const Row &oa = fp_row_at(T, other, "fp_add", Unit::FpAdd), &om = fp_row_at(T, other, "fp_mul", Unit::FpMul),
                    &od = fp_row_at(T, other, "fp_div", Unit::FpDiv), &oc = fp_row_at(T, other, "fp_cmp", Unit::FpCmp);
          const double comp_other = na * oa.area + nm * om.area + nd * od.area + nc * oc.area;
          k.area = m->area * composed / comp_other;
          src.how = "composed, scaled";
          o << " x (measured " << m->format << " row / its composition)";
          const double other_fmax = slowest(oa, om, od, oc);
          if (m->fmax_mhz > 0 && parts_fmax > 0 && other_fmax > 0) {
            k.fmax_mhz = m->fmax_mhz * parts_fmax / other_fmax;
            src.fmax_how = "estimate (composed, scaled: measured " + m->format + " Fmax x slowest FP part ratio)";
          }
          o << ": " << m->command;
        } catch (const ConfigError&) {
          // no FP rows for the other format: plain composition
        }
      }
      src.detail = o.str();
    } else if (fmtless) {
      throw ConfigError("trax area table " + area_table_path() + ": no row for " + sunit + " Stages " +
                        std::to_string(synth_stages(sunit, "-", k.latency)) + " (measure it with `rayunits trax areas --units " +
                        sunit + "`, or give units." + unit_name(u) + ".area a number)");
    } else {
      const Row& r = fp_row(sunit.c_str(), u);  // a scaled estimate, or throws naming the missing row
      k.area = r.area;
      k.fmax_mhz = r.fmax_mhz;
      src.how = "estimate";
      src.detail = r.command;
      src.fmax_how = r.fmax_mhz > 0 ? "estimate (of the row it is scaled from)" : "";
    }
    src.fmax_mhz = k.fmax_mhz;
    srcs.push_back(src);
  }
  if (c.clock_mhz == kClockSta) c.clock_mhz = sta_clock(c, srcs).mhz;
  c.validate();
  if (sources) *sources = srcs;
  return c;
}

}  // namespace ru::trax
