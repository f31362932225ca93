// TRaX model configuration: defaults, TOML reading with one-line errors naming the key.
#include "rayunits/trax/config.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/render/render.hpp"

namespace ru::trax {

namespace {
const char* const kUnitNames[kUnits] = {"fp_add", "fp_mul", "fp_div", "fp_sqrt", "fp_cmp", "fp_fma",
                                        "conv",   "int",    "branch", "box",     "tri",    "noise", "texture"};

std::string fmt_num(double v) {
  std::ostringstream o;
  o.precision(12);
  o << v;
  return o.str();
}

bool pow2(long long v) { return v > 0 && (v & (v - 1)) == 0; }

struct Reader {
  std::string src;
  [[noreturn]] void fail(const std::string& key, const std::string& msg) const {
    throw ConfigError("trax config " + src + ": key '" + key + "': " + msg);
  }
  long long integer(const toml::node& n, const std::string& key, long long lo, long long hi) const {
    const auto v = n.value_exact<int64_t>();
    if (!v) fail(key, "must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    if (*v < lo || *v > hi)
      fail(key, "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + " (got " + std::to_string(*v) + ")");
    return *v;
  }
  double number(const toml::node& n, const std::string& key, double lo, double hi) const {
    std::optional<double> v;
    if (auto i = n.value_exact<int64_t>()) v = static_cast<double>(*i);
    if (auto d = n.value_exact<double>()) v = *d;
    if (!v || !std::isfinite(*v)) fail(key, "must be a number in " + fmt_num(lo) + ".." + fmt_num(hi));
    if (*v < lo || *v > hi) fail(key, "must be in " + fmt_num(lo) + ".." + fmt_num(hi) + " (got " + fmt_num(*v) + ")");
    return *v;
  }
  std::string choice(const toml::node& n, const std::string& key, const std::vector<std::string>& allowed) const {
    const auto v = n.value_exact<std::string>();
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    if (!v) fail(key, "must be a string (accepted: " + list + ")");
    for (const auto& a : allowed)
      if (*v == a) return *v;
    fail(key, "unknown value '" + *v + "' (accepted: " + list + ")");
  }
  const toml::table& table(const toml::node& n, const std::string& key) const {
    const toml::table* t = n.as_table();
    if (!t) fail(key, "must be a table ([" + key + "])");
    return *t;
  }
};

void read_cache(const Reader& R, const toml::table& t, const std::string& sec, CacheCfg& c) {
  for (const auto& [k, v] : t) {
    const std::string key = sec + "." + std::string(k.str());
    if (k == "size") c.size = static_cast<uint64_t>(R.integer(v, key, 64, 1ll << 32));
    else if (k == "banks") c.banks = static_cast<int>(R.integer(v, key, 1, 1024));
    else if (k == "line") c.line = static_cast<int>(R.integer(v, key, 4, 4096));
    else if (k == "latency") c.latency = static_cast<int>(R.integer(v, key, 1, 100000));
    else if (k == "ways") c.ways = static_cast<int>(R.integer(v, key, 1, 1024));
    else if (k == "interleave" && sec == "l1") c.word_interleave = R.choice(v, key, {"line", "word"}) == "word";
    else
      R.fail(key, "unknown key (accepted in [" + sec + "]: size, banks, line, latency, ways" +
                      (sec == "l1" ? ", interleave)" : ")"));
  }
}

void check_cache(const Reader& R, const CacheCfg& c, const std::string& sec) {
  if (!pow2(c.banks)) R.fail(sec + ".banks", "must be a power of two (got " + std::to_string(c.banks) + ")");
  if (!pow2(c.line)) R.fail(sec + ".line", "must be a power of two (got " + std::to_string(c.line) + ")");
  if (!pow2(c.ways)) R.fail(sec + ".ways", "must be a power of two (got " + std::to_string(c.ways) + ")");
  const uint64_t set_bytes = static_cast<uint64_t>(c.line) * c.ways;
  if (c.size % set_bytes != 0 || !pow2(static_cast<long long>(c.size / set_bytes)))
    R.fail(sec + ".size", "must be line x ways x (a power of two) bytes (got " + std::to_string(c.size) + ")");
}
}  // namespace

const char* unit_name(Unit u) { return kUnitNames[static_cast<int>(u)]; }
std::string unit_names() {
  std::string s;
  for (int i = 0; i < kUnits; ++i) s += (i ? ", " : "") + std::string(kUnitNames[i]);
  return s;
}

int Config::value_bits() const { return num::Format::parse(format == "float" ? "e8m23" : format).width(); }
int Config::value_bytes() const { return value_bits() <= 32 ? 4 : 8; }

Config default_config() {
  Config c;
  // latency, count per TM, width, area. "synth" areas (um2) and STA clocks come from the area
  // table model/data/trax/areas.json (cell-flow rows) for the chip's format and the unit's
  // Stages (docs/TRAX.md "Area model" says which rows are measured and which composed); "rtl"
  // latencies are the RTL Stages derived by rtl_latency(); conv/int/branch are ru_fp_cvt,
  // ru_int_alu and ru_branch (issue 16; an area_nand2 estimate can still be configured).
  c.unit(Unit::FpAdd) = {2, 4, 1, kAreaSynth, 0, 0};
  c.unit(Unit::FpMul) = {2, 4, 1, kAreaSynth, 0, 0};
  c.unit(Unit::FpDiv) = {16, 1, 1, kAreaSynth, 0, 0};
  c.unit(Unit::FpSqrt) = {16, 1, 1, kAreaSynth, 0, 0};
  c.unit(Unit::FpCmp) = {1, 4, 1, kAreaSynth, 0, 0};
  // ru_fp_fma at Stages 4 = the add and mul latencies it replaces; used only with chip.fma
  c.unit(Unit::FpFma) = {4, 2, 1, kAreaSynth, 0, 0};
  c.unit(Unit::Conv) = {1, 2, 1, kAreaSynth, 0, 0};    // ru_fp_cvt (i2f, f2i) at the format, Stages 1
  c.unit(Unit::Int) = {1, 8, 1, kAreaSynth, 0, 0};     // ru_int_alu, IntW 32, Stages 1
  c.unit(Unit::Branch) = {1, 8, 1, kAreaSynth, 0, 0};  // ru_branch, IntW 32, PcW 32, Stages 1
  c.unit(Unit::Box) = {kLatencyRtl, 2, 1, kAreaSynth, 0, 0};
  c.unit(Unit::Tri) = {kLatencyRtl, 1, 1, kAreaSynth, 0, 0};
  c.unit(Unit::Noise) = {kLatencyRtl, 1, 1, kAreaSynth, 0, 0};
  // width = the noise units inside (ru_texture's Units): a request of n octaves occupies it for
  // ceil(n / width) cycles; latency "rtl" = their Stages (a request takes ceil(n / width) more)
  c.unit(Unit::Texture) = {kLatencyRtl, 1, 4, kAreaSynth, 0, 0};
  return c;
}

void Config::validate(const std::string& source) const {
  Reader R{source};
  if (tms < 1 || tms > 4096) R.fail("chip.tms", "must be in 1..4096");
  if (tps_per_tm < 1 || tps_per_tm > 4096) R.fail("chip.tps_per_tm", "must be in 1..4096");
  if (!(clock_mhz > 0) && clock_mhz != kClockSta) R.fail("chip.clock_mhz", "must be > 0 or \"sta\"");
  if (texture == "unit" && noise == "float")
    R.fail("chip.texture", "\"unit\" needs a fixed noise (chip.noise = \"fixed-trunc\" or \"fixed\")");
  {
    const int w = units[static_cast<int>(Unit::Texture)].width;
    if (w != 1 && w != 2 && w != 4 && w != 8) R.fail("units.texture.width", "the noise units inside: 1, 2, 4 or 8");
  }
  if (format != "float") {
    try {
      num::Format::parse(format).validate();
    } catch (const std::exception& e) {
      R.fail("chip.format", e.what());
    }
  }
  for (int i = 0; i < kUnits; ++i) {
    const UnitCfg& u = units[i];
    const std::string k = std::string("units.") + kUnitNames[i];
    const bool rtl_ok = i == static_cast<int>(Unit::Box) || i == static_cast<int>(Unit::Tri) ||
                        i == static_cast<int>(Unit::Noise) || i == static_cast<int>(Unit::Texture);
    if (u.latency < 1 && !(u.latency == kLatencyRtl && rtl_ok))
      R.fail(k + ".latency", rtl_ok ? "must be >= 1 or \"rtl\"" : "must be >= 1");
    if (u.count < 1) R.fail(k + ".count", "must be >= 1");
    if (u.width < 1) R.fail(k + ".width", "must be >= 1");
    const bool synth_ok = i <= static_cast<int>(Unit::Branch) || rtl_ok;  // every unit has RTL since issue 16
    if (u.area == kAreaNand2) {
      if (!(u.area_nand2 > 0)) R.fail(k + ".area_nand2", "must be > 0");
    } else if (u.area < 0 && !(u.area == kAreaSynth && synth_ok)) {
      R.fail(k + ".area", synth_ok ? "must be >= 0 or \"synth\"" : "must be >= 0");
    }
  }
  check_cache(R, l1, "l1");
  check_cache(R, l2, "l2");
  if (l2.line < l1.line) R.fail("l2.line", "must be >= l1.line");
  if (!(dram_bytes_per_cycle > 0)) R.fail("dram.bytes_per_cycle", "must be > 0");
  if (scene_storage != "format" && scene_storage != "word") R.fail("chip.scene_storage", "must be format or word");
  try {
    render::check_box_format(box_format, format);
  } catch (const std::exception& e) {
    R.fail("chip.box_format", e.what());
  }
  if (!(array_efficiency > 0 && array_efficiency <= 1)) R.fail("area.array_efficiency", "must be in (0, 1]");
}

Config parse_config(const std::string& text, const std::string& source, const Config& base) {
  Reader R{source};
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream o;
    o << "trax config " << source << ": line " << e.source().begin.line << ": " << e.description();
    throw ConfigError(o.str());
  }
  Config c = base;
  for (const auto& [sk, sv] : root) {
    const std::string sec(sk.str());
    if (sec == "chip") {
      for (const auto& [k, v] : R.table(sv, sec)) {
        const std::string key = sec + "." + std::string(k.str());
        if (k == "tms") c.tms = static_cast<int>(R.integer(v, key, 1, 4096));
        else if (k == "tps_per_tm") c.tps_per_tm = static_cast<int>(R.integer(v, key, 1, 4096));
        else if (k == "clock_mhz") {
          if (v.value_exact<std::string>()) {
            if (*v.value_exact<std::string>() != "sta") R.fail(key, "must be a number (MHz) or \"sta\"");
            c.clock_mhz = kClockSta;
          } else {
            c.clock_mhz = R.number(v, key, 1e-3, 1e6);
          }
        }
        else if (k == "format") {
          const auto s = v.value_exact<std::string>();
          if (!s) R.fail(key, "must be a string (float or eXmY[-ftz])");
          c.format = *s;
          if (c.format != "float") {
            try {
              num::Format::parse(c.format).validate();
            } catch (const std::exception& e) {
              R.fail(key, e.what());
            }
          }
        } else if (k == "tri") c.tri = R.choice(v, key, {"robust", "mt"});
        else if (k == "box") c.box = R.choice(v, key, {"plain", "conservative"});
        else if (k == "noise") c.noise = R.choice(v, key, {"fixed-trunc", "fixed", "float"});
        else if (k == "texture") c.texture = R.choice(v, key, {"shader", "unit"});
        else if (k == "traversal") c.traversal = R.choice(v, key, {"stack", "stackless"});
        else if (k == "bvh") c.bvh = R.choice(v, key, {"sah", "median"});
        else if (k == "leaf_size") c.leaf_size = static_cast<int>(R.integer(v, key, 1, 64));
        else if (k == "fp_registers_per_thread")
          c.fp_registers_per_thread = static_cast<int>(R.integer(v, key, 0, 65536));
        else if (k == "int_registers_per_thread")
          c.int_registers_per_thread = static_cast<int>(R.integer(v, key, 0, 65536));
        else if (k == "scene_storage") c.scene_storage = R.choice(v, key, {"format", "word"});
        else if (k == "box_format") {
          const auto s = v.value_exact<std::string>();
          if (!s) R.fail(key, "must be a string (\"\" or eXmY)");
          c.box_format = *s;
        }
        else if (k == "fma") {
          const auto b = v.value_exact<bool>();
          if (!b) R.fail(key, "must be true or false");
          c.fma = *b;
        }
        else if (k == "local_store_bytes") c.local_store_bytes = static_cast<int>(R.integer(v, key, 0, 1 << 24));
        else if (k == "framebuffer_bytes_per_pixel")
          c.framebuffer_bytes_per_pixel = static_cast<int>(R.integer(v, key, 1, 64));
        else
          R.fail(key, "unknown key (accepted in [chip]: tms, tps_per_tm, clock_mhz, format, tri, box, noise, texture, "
                      "traversal, bvh, leaf_size, fp_registers_per_thread, int_registers_per_thread, "
                      "local_store_bytes, framebuffer_bytes_per_pixel, scene_storage, box_format, fma)");
      }
    } else if (sec == "units") {
      for (const auto& [uk, uv] : R.table(sv, sec)) {
        const std::string uname(uk.str());
        int idx = -1;
        for (int i = 0; i < kUnits; ++i)
          if (uname == kUnitNames[i]) idx = i;
        if (idx < 0) R.fail("units." + uname, "unknown unit (units: " + unit_names() + ")");
        UnitCfg& u = c.units[idx];
        bool has_area = false, has_nand2 = false;
        for (const auto& [k, v] : R.table(uv, "units." + uname)) {
          const std::string key = "units." + uname + "." + std::string(k.str());
          if (k == "latency") {
            if (v.value_exact<std::string>() && *v.value_exact<std::string>() == "rtl") {
              if (idx != static_cast<int>(Unit::Box) && idx != static_cast<int>(Unit::Tri) &&
                  idx != static_cast<int>(Unit::Noise) && idx != static_cast<int>(Unit::Texture))
                R.fail(key, "\"rtl\" is accepted for box, tri, noise and texture only");
              u.latency = kLatencyRtl;
            } else {
              u.latency = static_cast<int>(R.integer(v, key, 1, 100000));
            }
          } else if (k == "count") u.count = static_cast<int>(R.integer(v, key, 1, 4096));
          else if (k == "width") u.width = static_cast<int>(R.integer(v, key, 1, 4096));
          else if (k == "area") {
            if (v.value_exact<std::string>() && *v.value_exact<std::string>() == "synth") {
              u.area = kAreaSynth;
            } else {
              u.area = R.number(v, key, 0, 1e12);
            }
            u.area_nand2 = 0;
            has_area = true;
          } else if (k == "area_nand2") {
            u.area_nand2 = R.number(v, key, 1e-9, 1e12);
            u.area = kAreaNand2;
            has_nand2 = true;
          }
          else R.fail(key, "unknown key (accepted: latency, count, width, area, area_nand2)");
          if (has_area && has_nand2)
            R.fail("units." + uname, "give area (um2 or \"synth\") or area_nand2 (an estimate in NAND2-eq), not both");
        }
      }
    } else if (sec == "atomic") {
      for (const auto& [k, v] : R.table(sv, sec)) {
        const std::string key = sec + "." + std::string(k.str());
        if (k == "latency") c.atomic_latency = static_cast<int>(R.integer(v, key, 1, 100000));
        else R.fail(key, "unknown key (accepted in [atomic]: latency)");
      }
    } else if (sec == "local_store") {
      for (const auto& [k, v] : R.table(sv, sec)) {
        const std::string key = sec + "." + std::string(k.str());
        if (k == "latency") c.local_store_latency = static_cast<int>(R.integer(v, key, 1, 100000));
        else R.fail(key, "unknown key (accepted in [local_store]: latency)");
      }
    } else if (sec == "l1") {
      read_cache(R, R.table(sv, sec), sec, c.l1);
    } else if (sec == "l2") {
      read_cache(R, R.table(sv, sec), sec, c.l2);
    } else if (sec == "dram") {
      for (const auto& [k, v] : R.table(sv, sec)) {
        const std::string key = sec + "." + std::string(k.str());
        if (k == "latency") c.dram_latency = static_cast<int>(R.integer(v, key, 1, 1000000));
        else if (k == "bytes_per_cycle") c.dram_bytes_per_cycle = R.number(v, key, 1e-3, 1e6);
        else R.fail(key, "unknown key (accepted in [dram]: latency, bytes_per_cycle)");
      }
    } else if (sec == "area") {
      for (const auto& [k, v] : R.table(sv, sec)) {
        const std::string key = sec + "." + std::string(k.str());
        if (k == "feature_um") c.feature_um = R.number(v, key, 1e-3, 10);
        else if (k == "sram_cell_f2") c.sram_cell_f2 = R.number(v, key, 1, 1e4);
        else if (k == "sram_cell_aspect") c.sram_cell_aspect = R.number(v, key, 0.1, 10);
        else if (k == "wire_pitch_f") c.wire_pitch_f = R.number(v, key, 0, 100);
        else if (k == "array_efficiency") c.array_efficiency = R.number(v, key, 0.01, 1);
        else if (k == "regfile_read_ports") c.regfile_read_ports = static_cast<int>(R.integer(v, key, 1, 64));
        else if (k == "regfile_write_ports") c.regfile_write_ports = static_cast<int>(R.integer(v, key, 1, 64));
        else if (k == "address_bits") c.address_bits = static_cast<int>(R.integer(v, key, 16, 64));
        else
          R.fail(key, "unknown key (accepted in [area]: feature_um, sram_cell_f2, sram_cell_aspect, wire_pitch_f, "
                      "array_efficiency, regfile_read_ports, regfile_write_ports, address_bits)");
      }
    } else if (sec == "energy") {
      for (const auto& [k, v] : R.table(sv, sec)) {
        const std::string key = sec + "." + std::string(k.str());
        if (k == "sram_pj_64b_8kib") c.sram_pj_64b_8kib = R.number(v, key, 0, 1e6);
        else if (k == "sram_capacity_exponent") c.sram_capacity_exponent = R.number(v, key, 0, 2);
        else if (k == "dram_pj_per_bit") c.dram_pj_per_bit = R.number(v, key, 0, 1e6);
        else
          R.fail(key, "unknown key (accepted in [energy]: sram_pj_64b_8kib, sram_capacity_exponent, dram_pj_per_bit)");
      }
    } else {
      R.fail(sec, "unknown section (accepted: chip, units, atomic, local_store, l1, l2, dram, area, energy)");
    }
  }
  c.validate(source);
  return c;
}

Config load_config(const std::string& path, const Config& base) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError("trax config " + path + ": cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_config(ss.str(), path, base);
}

std::string to_toml(const Config& c) {
  std::ostringstream o;
  o.precision(17);
  o << "[chip]\n"
    << "tms = " << c.tms << "\ntps_per_tm = " << c.tps_per_tm << "\nclock_mhz = ";
  if (c.clock_mhz == kClockSta)
    o << "\"sta\"";
  else
    o << fmt_num(c.clock_mhz) << (std::floor(c.clock_mhz) == c.clock_mhz ? ".0" : "");
  o << "\nformat = \"" << c.format << "\"\ntri = \""
    << c.tri << "\"\nbox = \"" << c.box << "\"\nnoise = \"" << c.noise << "\"\ntexture = \"" << c.texture
    << "\"\ntraversal = \"" << c.traversal
    << "\"\nbvh = \"" << c.bvh << "\"\nleaf_size = " << c.leaf_size
    << "\nfp_registers_per_thread = " << c.fp_registers_per_thread
    << "\nint_registers_per_thread = " << c.int_registers_per_thread << "\nlocal_store_bytes = " << c.local_store_bytes
    << "\nframebuffer_bytes_per_pixel = " << c.framebuffer_bytes_per_pixel << "\nscene_storage = \"" << c.scene_storage
    << "\"\nbox_format = \"" << c.box_format << "\"\nfma = " << (c.fma ? "true" : "false") << "\n";
  for (int i = 0; i < kUnits; ++i) {
    const UnitCfg& u = c.units[i];
    o << "\n[units." << kUnitNames[i] << "]\nlatency = ";
    if (u.latency == kLatencyRtl)
      o << "\"rtl\"";
    else
      o << u.latency;
    o << "\ncount = " << u.count << "\nwidth = " << u.width << (u.area == kAreaNand2 ? "\narea_nand2 = " : "\narea = ");
    if (u.area == kAreaNand2)
      o << fmt_num(u.area_nand2) << (std::floor(u.area_nand2) == u.area_nand2 ? ".0" : "");
    else if (u.area == kAreaSynth)
      o << "\"synth\"";
    else
      o << fmt_num(u.area) << (std::floor(u.area) == u.area ? ".0" : "");
    o << "\n";
  }
  o << "\n[atomic]\nlatency = " << c.atomic_latency << "\n\n[local_store]\nlatency = " << c.local_store_latency << "\n";
  for (const auto* p : {&c.l1, &c.l2}) {
    o << "\n[" << (p == &c.l1 ? "l1" : "l2") << "]\nsize = " << p->size << "\nbanks = " << p->banks
      << "\nline = " << p->line << "\nlatency = " << p->latency << "\nways = " << p->ways << "\n";
    if (p == &c.l1) o << "interleave = \"" << (p->word_interleave ? "word" : "line") << "\"\n";
  }
  o << "\n[dram]\nlatency = " << c.dram_latency << "\nbytes_per_cycle = " << fmt_num(c.dram_bytes_per_cycle)
    << (std::floor(c.dram_bytes_per_cycle) == c.dram_bytes_per_cycle ? ".0" : "") << "\n";
  auto real = [&](double v) { return fmt_num(v) + (std::floor(v) == v ? ".0" : ""); };
  o << "\n[area]\nfeature_um = " << real(c.feature_um) << "\nsram_cell_f2 = " << real(c.sram_cell_f2)
    << "\nsram_cell_aspect = " << real(c.sram_cell_aspect) << "\nwire_pitch_f = " << real(c.wire_pitch_f)
    << "\narray_efficiency = " << real(c.array_efficiency) << "\nregfile_read_ports = " << c.regfile_read_ports
    << "\nregfile_write_ports = " << c.regfile_write_ports << "\naddress_bits = " << c.address_bits << "\n";
  o << "\n[energy]\nsram_pj_64b_8kib = " << real(c.sram_pj_64b_8kib) << "\nsram_capacity_exponent = "
    << real(c.sram_capacity_exponent) << "\ndram_pj_per_bit = " << real(c.dram_pj_per_bit) << "\n";
  return o.str();
}

}  // namespace ru::trax
