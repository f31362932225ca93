// TRaX model: RTL-derived unit latencies ("rtl") and synthesized unit areas ("synth") from the
// committed area table model/data/trax/areas.json (docs/TRAX.md "Area model").
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "rayunits/num/format.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/trax/config.hpp"

namespace ru::trax {

namespace {

std::string format_name(const Config& c) { return num::Format::parse(c.format == "float" ? "e8m23" : c.format).name(); }

struct Row {
  double area = 0;
  std::string command, format;
};
using Table = std::map<std::string, Row>;  // key "unit|format|stages"

std::string key(const std::string& unit, const std::string& fmt, int stages) {
  return unit + "|" + fmt + "|" + std::to_string(stages);
}

std::string table_path() {
  if (const char* e = std::getenv("RU_TRAX_AREAS"); e && *e) return e;
#ifdef RU_SOURCE_DIR
  return std::string(RU_SOURCE_DIR) + "/model/data/trax/areas.json";
#else
  return "model/data/trax/areas.json";
#endif
}

const Table& table() {
  static std::mutex mu;
  static std::map<std::string, Table> cache;
  const std::string path = table_path();
  std::lock_guard<std::mutex> lock(mu);
  auto it = cache.find(path);
  if (it != cache.end()) return it->second;
  Table t;
  std::ifstream in(path);
  if (!in) throw ConfigError("trax area table " + path + ": cannot open the file (set RU_TRAX_AREAS or numeric areas)");
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    for (const auto& r : j.at("rows")) {
      Row row;
      row.area = r.at("area_nand2").get<double>();
      row.command = r.at("command").get<std::string>();
      row.format = r.at("format").get<std::string>();
      t[key(r.at("unit").get<std::string>(), r.at("format").get<std::string>(), r.at("stages").get<int>())] = row;
    }
  } catch (const std::exception& e) {
    throw ConfigError("trax area table " + path + ": " + e.what());
  }
  return cache.emplace(path, std::move(t)).first->second;
}

// The Stages the synthesized RTL can have: the latency, limited to the unit's useful maximum for
// the format (further latency cycles are output registers, not modelled in the area).
int synth_stages(const std::string& unit, const std::string& fmt, int latency) {
  const synth::UnitSpec& u = synth::find_unit(unit);
  synth::UnitConfig uc;
  if (fmt != "-") uc.fmt = num::Format::parse(fmt);
  return std::min(latency, u.max_stages(uc));
}

const Row* lookup(const std::string& unit, const std::string& fmt, int latency) {
  const Table& t = table();
  auto it = t.find(key(unit, fmt, synth_stages(unit, fmt, latency)));
  return it == t.end() ? nullptr : &it->second;
}

// A missing FP row: scaled from the measured row of the same unit and Stages whose format is
// closest in width: fp_add, fp_cmp in proportion to the width W, fp_mul, fp_div to (M+1)^2.
bool scaled_estimate(const std::string& unit, const std::string& fmt, int latency, double* area, std::string* how) {
  const num::Format F = num::Format::parse(fmt);
  const int st = synth_stages(unit, fmt, latency);
  const std::string prefix = unit + "|";
  const Row* best = nullptr;
  num::Format bf;
  std::pair<int, int> best_score{0, 0};
  for (const auto& [k, row] : table()) {
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
  const bool quad = unit == "fp_mul" || unit == "fp_div";
  const double f = quad ? double(F.frac_bits + 1) * (F.frac_bits + 1) / (double(bf.frac_bits + 1) * (bf.frac_bits + 1))
                        : double(F.width()) / bf.width();
  *area = best->area * f;
  *how = "scaled from the measured " + bf.name() + " row (" + (quad ? "(M+1)^2" : "width") + "): " + best->command;
  return true;
}

// A measured row of `unit` at the Stages of `latency` in a format other than fmt (closest width).
const Row* measured_other_format(const std::string& unit, const std::string& fmt, int latency) {
  const num::Format F = num::Format::parse(fmt);
  const Row* best = nullptr;
  int best_d = 1 << 20;
  for (const auto& [k, row] : table()) {
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

// The measured area of an FP unit of c's format at its latency (throws ConfigError if absent).
double fp_area_at(const Config& c, const char* unit, Unit which) {
  const std::string fmt = num::Format::parse(c.format).name();
  const Row* r = lookup(unit, fmt, c.unit(which).latency);
  if (!r) throw ConfigError(std::string("no row for ") + unit + " " + fmt);
  return r->area;
}

}  // namespace

int rtl_latency(const Config& c, Unit u) {
  const int add = c.unit(Unit::FpAdd).latency, mul = c.unit(Unit::FpMul).latency,
            div = c.unit(Unit::FpDiv).latency, cmp = c.unit(Unit::FpCmp).latency;
  switch (u) {
    case Unit::Box: return add + mul + 3 * cmp;
    case Unit::Tri: return c.tri == "mt" ? 5 * add + 3 * mul + div + cmp : 4 * add + 2 * mul + div + cmp;
    case Unit::Noise: return 4;
    default: return c.unit(u).latency;
  }
}

Config resolve_config(const Config& in, std::vector<AreaSource>* sources) {
  Config c = in;
  for (Unit u : {Unit::Box, Unit::Tri, Unit::Noise})
    if (c.unit(u).latency == kLatencyRtl) c.unit(u).latency = rtl_latency(c, u);
  const std::string fmt = format_name(c);
  std::map<std::string, Row> estimates;  // scaled rows (kept for this call)
  auto fp_row = [&](const char* unit, Unit which) -> const Row& {
    const int lat = c.unit(which).latency;
    const Row* r = lookup(unit, fmt, lat);
    if (r) return *r;
    Row e;
    if (scaled_estimate(unit, fmt, lat, &e.area, &e.command)) {
      e.command = "estimate: " + e.command;
      return estimates[unit] = e;
    }
    throw ConfigError("trax area table " + table_path() + ": no row for " + unit + " " + fmt + " Stages " +
                        std::to_string(synth_stages(unit, fmt, lat)) + " (measure it with `rayunits trax areas`, or give units." +
                        unit_name(which) + ".area a number)");
  };
  for (int i = 0; i < kUnits; ++i) {
    const Unit u = static_cast<Unit>(i);
    UnitCfg& k = c.units[i];
    AreaSource src;
    src.unit = unit_name(u);
    if (k.area != kAreaSynth) {
      src.how = (in.units[i].area == kAreaSynth) ? "measured" : "configured";
      if (sources) sources->push_back(src);
      continue;
    }
    std::string sunit;
    switch (u) {
      case Unit::FpAdd: sunit = "fp_add"; break;
      case Unit::FpMul: sunit = "fp_mul"; break;
      case Unit::FpDiv:
      case Unit::FpSqrt: sunit = "fp_div"; break;
      case Unit::FpCmp: sunit = "fp_cmp"; break;
      case Unit::Box: sunit = "ray_box"; break;
      case Unit::Tri: sunit = c.tri == "mt" ? "ray_tri_mt" : "ray_tri_robust"; break;
      case Unit::Noise: sunit = "noise"; break;
      default: break;
    }
    src.unit = u == Unit::FpSqrt ? "fp_sqrt" : sunit;
    const std::string f = u == Unit::Noise ? "-" : fmt;
    if (const Row* r = lookup(sunit, f, k.latency)) {
      k.area = r->area;
      src.how = u == Unit::FpSqrt ? "estimate (= fp_div, no RTL)" : "measured";
      src.detail = r->command;
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
      const double composed = na * fp_row("fp_add", Unit::FpAdd).area + nm * fp_row("fp_mul", Unit::FpMul).area +
                              nd * fp_row("fp_div", Unit::FpDiv).area + nc * fp_row("fp_cmp", Unit::FpCmp).area;
      std::ostringstream o;
      o << na << " fp_add + " << nm << " fp_mul + " << nd << " fp_div + " << nc << " fp_cmp (" << fmt << ")";
      k.area = composed;
      src.how = "composed";
      // A measured row of this unit and Stages in another format: scale it by the ratio of the
      // compositions (keeps the sweep on the measured unit's basis).
      if (const Row* m = measured_other_format(sunit, fmt, k.latency)) {
        try {
          Config other = c;
          other.format = m->format;
          const double comp_other =
              na * fp_area_at(other, "fp_add", Unit::FpAdd) + nm * fp_area_at(other, "fp_mul", Unit::FpMul) +
              nd * fp_area_at(other, "fp_div", Unit::FpDiv) + nc * fp_area_at(other, "fp_cmp", Unit::FpCmp);
          k.area = m->area * composed / comp_other;
          src.how = "composed, scaled";
          o << " x (measured " << m->format << " row / its composition): " << m->command;
        } catch (const ConfigError&) {
          // no FP rows for the other format: plain composition
        }
      }
      src.detail = o.str();
    } else if (u == Unit::Noise) {
      throw ConfigError("trax area table " + table_path() + ": no row for noise Stages " +
                        std::to_string(synth_stages("noise", "-", k.latency)) +
                        " (measure it with `rayunits trax areas --units noise`, or give units.noise.area a number)");
    } else {
      const Row& r = fp_row(sunit.c_str(), u);  // a scaled estimate, or throws naming the missing row
      k.area = r.area;
      src.how = "estimate";
      src.detail = r.command;
    }
    if (sources) sources->push_back(src);
  }
  c.validate();
  return c;
}

}  // namespace ru::trax
