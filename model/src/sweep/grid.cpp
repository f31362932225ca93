// rayunits sweep: grid files, their kinds and keys, expansion into jobs (rayunits/sweep/sweep.hpp).
#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstring>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "rayunits/num/format.hpp"
#include "rayunits/render/render.hpp"
#include "rayunits/scene/scene.hpp"
#include "rayunits/sweep/sweep.hpp"
#include "rayunits/rtl/cache.hpp"
#include "rayunits/synth/args.hpp"
#include "rayunits/synth/cell.hpp"
#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/units/mesh.hpp"
#include "rayunits/util/git.hpp"
#include "rayunits/util/hash.hpp"

#ifndef RU_VERSION
#define RU_VERSION "0"
#endif

namespace ru::sweep {

using nlohmann::json;
namespace fs = std::filesystem;

std::string tool_id(const std::string& source_dir) {
  const std::string model = util::git_tree_id(source_dir, "model");
  return std::string("rayunits ") + RU_VERSION + " model " + (model.empty() ? "unknown" : model);
}

namespace {

enum class T { Str, Int, Bool, Num, IntOrMax };

// How a key's value becomes arguments and what it must satisfy.
struct Key {
  std::string name;
  T type;
  std::string option;  // "--format"; "" with a positional key (synth `unit`)
  std::function<void(const json&)> check;           // throws (the message) on a bad value
  std::function<std::vector<std::string>(const json&)> emit;  // default: --option=value / --option
  std::string help;
};

struct Kind {
  std::string name;               // "synth", "study box", ...
  std::vector<std::string> cmd;   // {"synth"}, {"study", "box"}
  std::vector<Key> keys;
  std::vector<std::string> required;
  bool params_table = false;      // [param] sub-table (synth --param Name=V)
  // Checks the whole job (combinations), returns a skip reason or "", fills deps, appends the
  // output arguments and sets job.result.
  std::function<std::string(Job&, const ExpandOptions&)> finish;
};

std::string value_text(const json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer()) return std::to_string(v.get<long long>());
  std::ostringstream o;
  o.precision(17);
  o << v.get<double>();
  return o.str();
}

std::string type_name(T t) {
  switch (t) {
    case T::Str: return "a string";
    case T::Int: return "an integer";
    case T::Bool: return "true or false";
    case T::Num: return "a number";
    case T::IntOrMax: return "an integer or \"max\"";
  }
  return "?";
}

// The value of a TOML scalar as JSON if it has type t; nullopt otherwise.
std::optional<json> typed(const toml::node& n, T t) {
  if (t == T::Str || t == T::IntOrMax)
    if (auto s = n.value_exact<std::string>()) return json(*s);
  if (t == T::Int || t == T::IntOrMax || t == T::Num)
    if (auto i = n.value_exact<int64_t>()) return t == T::Num ? json(static_cast<double>(*i)) : json(*i);
  if (t == T::Num)
    if (auto d = n.value_exact<double>(); d && std::isfinite(*d)) return json(*d);
  if (t == T::Bool)
    if (auto b = n.value_exact<bool>()) return json(*b);
  return std::nullopt;
}

std::function<void(const json&)> one_of(std::vector<std::string> allowed) {
  return [allowed](const json& v) {
    std::string list;
    for (const auto& a : allowed) {
      if (v.get<std::string>() == a) return;
      list += (list.empty() ? "" : ", ") + a;
    }
    throw std::runtime_error("unknown value '" + v.get<std::string>() + "' (accepted: " + list + ")");
  };
}

std::function<void(const json&)> int_range(long long lo, long long hi) {
  return [lo, hi](const json& v) {
    if (!v.is_number_integer()) return;  // IntOrMax strings are checked by their own rule
    const long long x = v.get<long long>();
    if (x < lo || x > hi)
      throw std::runtime_error("must be in " + std::to_string(lo) + ".." + std::to_string(hi) + " (got " +
                               std::to_string(x) + ")");
  };
}

std::function<void(const json&)> num_range(double lo, double hi) {
  return [lo, hi](const json& v) {
    const double x = v.get<double>();
    if (!(x >= lo && x <= hi))
      throw std::runtime_error("must be in " + value_text(json(lo)) + ".." + value_text(json(hi)) + " (got " +
                               value_text(v) + ")");
  };
}

void check_format(const json& v) { num::Format::parse(v.get<std::string>()); }

// A program name or path passed literally (it is executed as given, never through a shell).
void check_program(const json& v) {
  const std::string s = v.get<std::string>();
  if (s.empty() || s[0] == '-') throw std::runtime_error("expects a program name or path, got '" + s + "'");
}

void check_existing_file(const json& v) {
  if (!fs::is_regular_file(v.get<std::string>()))
    throw std::runtime_error("no such file '" + v.get<std::string>() + "'");
}

std::string file_hash(const std::string& path) { return util::fnv1a64_hex(synth::read_file(path)); }

std::string param_or(const json& p, const std::string& k, const std::string& dflt = "") {
  return p.contains(k) ? value_text(p[k]) : dflt;
}

// ---- synth ----------------------------------------------------------------------------------

std::string yosys_version_cached(const std::string& yosys) {
  static std::mutex m;
  static std::map<std::string, std::string> cache;
  std::lock_guard<std::mutex> l(m);
  auto it = cache.find(yosys);
  if (it != cache.end()) return it->second;
  std::string v;
  try {
    v = synth::yosys_version(yosys);
  } catch (const std::exception&) {
    v = "missing";
  }
  return cache[yosys] = v;
}

// The unit configuration of a synth or rtl job (keys unit, format, round, ftz, stages, param.X):
// drops the format keys of units without a format, resolves stages = "max". Returns a reason
// when the point lies outside the unit's Stages range (the job is skipped), else "".
std::string unit_config_of(Job& j, synth::UnitConfig& c) {
  json& p = j.params;
  const synth::UnitSpec& u = synth::find_unit(p.at("unit").get<std::string>());
  if (!u.uses_format)
    for (const char* k : {"format", "round", "ftz"}) p.erase(k);
  if (u.uses_format) {
    if (!p.contains("format")) throw GridError("key 'format': required for unit " + u.name);
    c.fmt = num::Format::parse(p["format"].get<std::string>());
    if (p.value("ftz", false)) c.fmt.subnormals = false;
    if (p.contains("round")) c.fmt.round = num::parse_round(p["round"].get<std::string>());
  }
  for (auto it = p.begin(); it != p.end(); ++it)
    if (it.key().rfind("param.", 0) == 0) c.params[it.key().substr(6)] = it.value().get<long long>();
  const int maxs = u.max_stages(c);
  if (p.at("stages").is_string()) p["stages"] = maxs;  // "max" (checked by the key)
  c.stages = p["stages"].get<int>();
  if (c.stages > maxs || c.stages < u.min_stages)
    return "stages " + std::to_string(c.stages) + " outside the unit's range " + std::to_string(u.min_stages) + ".." +
           std::to_string(maxs);
  try {
    synth::check_config(u, c);
  } catch (const std::exception& e) {
    throw GridError(std::string("keys unit/format/stages/param: ") + e.what());
  }
  return "";
}

std::string finish_synth(Job& j, const ExpandOptions&) {
  json& p = j.params;
  synth::UnitConfig c;
  if (std::string skip = unit_config_of(j, c); !skip.empty()) return skip;
  const synth::UnitSpec& u = synth::find_unit(p.at("unit").get<std::string>());
  // Flow option combinations (as `rayunits synth` checks them).
  const std::string flow = param_or(p, "flow", p.contains("clock") ? "osu018" : "generic");
  const bool cell = synth::is_cell_flow(flow);
  if (cell)
    for (const char* k : {"fpga", "device"})
      if (p.contains(k) && (p[k].is_string() || p[k].get<bool>()))
        throw GridError(std::string("key '") + k + "': applies to the generic flow, not to flow " + flow);
  if (p.contains("clock") && !cell) throw GridError("key 'clock': needs a cell-library flow, not flow " + flow);
  if (!cell && (param_or(p, "placement", "depth") != "depth" || p.value("stage_periods", false)))
    throw GridError("key 'placement'/'stage_periods': needs a cell-library flow (flow = \"osu018\")");

  const std::string rtl = p.contains("rtl") ? p["rtl"].get<std::string>() : synth::default_rtl_dir();
  std::string src;
  try {
    src = synth::sources_hash(synth::resolve_sources(u, rtl));
  } catch (const std::exception& e) {
    throw GridError(std::string("unit ") + u.name + ": " + e.what());
  }
  j.deps["rtl_sources"] = src;
  j.deps["yosys"] = yosys_version_cached(param_or(p, "yosys", "yosys"));
  if (cell) {  // the cell library's liberty file (areas and timing)
    try {
      j.deps["liberty"] = file_hash(synth::cell_library(flow).liberty);
    } catch (const std::exception&) {
      j.deps["liberty"] = "missing";  // the job fails with the flow's own message
    }
  }
  j.result = j.out_dir + "/synth.jsonl";
  j.argv.push_back("--json=" + j.result);
  return "";
}

// The keys of a unit configuration (synth and rtl jobs), and `rtl` (an RTL source directory).
std::vector<Key> unit_keys() {
  return {
      {"unit", T::Str, "", [](const json& v) { synth::find_unit(v.get<std::string>()); }, {}, "registry unit name"},
      {"format", T::Str, "--format", check_format, {}, "eXmY[-ftz]"},
      {"stages", T::IntOrMax, "--stages",
       [](const json& v) {
         if (v.is_string() && v.get<std::string>() != "max")
           throw std::runtime_error("expects an integer or \"max\", got '" + v.get<std::string>() + "'");
         int_range(0, 1000)(v);
       },
       {}, "latency in cycles, or \"max\""},
      {"round", T::Str, "--round", one_of({"rne", "rtz", "rdn", "rup"}), {}, "rounding mode"},
      {"ftz", T::Bool, "--ftz", {}, {}, "flush to zero"},
      {"rtl", T::Str, "--rtl",
       [](const json& v) {
         if (!fs::is_directory(v.get<std::string>()))
           throw std::runtime_error("no such directory '" + v.get<std::string>() + "'");
       },
       {}, "RTL directory"},
  };
}

Kind synth_kind() {
  Kind k;
  k.name = "synth";
  k.cmd = {"synth"};
  k.required = {"unit", "stages"};
  k.params_table = true;
  auto flag = [](const char* n, const char* help) { return Key{n, T::Bool, std::string("--") + n, {}, {}, help}; };
  k.keys = unit_keys();
  k.keys.insert(k.keys.end(), {
      {"flow", T::Str, "--flow", [](const json& v) { synth::check_flow_name(v.get<std::string>()); }, {},
       "generic, osu018, osu035, osu050"},
      {"clock", T::Str, "--clock", [](const json& v) { synth::parse_clock_list("clock", v.get<std::string>()); },
       {}, "target clock(s), e.g. 400MHz or 2.5ns,2ns"},
      {"placement", T::Str, "--placement", one_of({"depth", "delay"}), {}, "register placement"},
      {"device", T::Str, "--device", one_of({"hx8k", "up5k"}), {}, "iCE40 device"},
      {"timeout", T::Int, "--timeout", int_range(1, 1000000), {}, "tool timeout in seconds"},
      {"yosys", T::Str, "--yosys", check_program, {}, "yosys binary"},
      {"sta", T::Str, "--sta", check_program, {}, "OpenSTA binary"},
      {"nextpnr", T::Str, "--nextpnr", check_program, {}, "nextpnr-ice40 binary"},
      // Flags, emitted in this order (they take effect in command-line order).
      flag("generic_only", "skip both FPGA flows"),
      flag("no_ice40", "skip synth_ice40"),
      flag("no_xilinx", "skip synth_xilinx"),
      flag("fpga", "iCE40 place and route"),
      flag("no_share", "synth -noshare"),
      flag("stage_periods", "per-stage periods (cell flow)"),
      flag("keep", "keep the tool's temp directory (its path in the log)"),
  });
  for (Key& key : k.keys)  // option names use dashes: generic_only -> --generic-only
    for (char& ch : key.option)
      if (ch == '_') ch = '-';
  k.finish = finish_synth;
  return k;
}

// ---- rtl: one configuration under the scoreboard (rayunits rtl; builds cached by content) -----

Kind rtl_kind() {
  Kind k;
  k.name = "rtl";
  k.cmd = {"rtl"};
  k.required = {"unit", "stages"};
  k.params_table = true;
  k.keys = unit_keys();
  k.keys.push_back({"vectors", T::Int, "--vectors", int_range(1, 1000000000), {}, "random vectors per test"});
  k.keys.push_back({"seed", T::Int, "--seed", int_range(0, 2000000000), {}, "seed of the random vectors"});
  k.keys.push_back({"long", T::Bool, "--long", {}, {}, "also the plan's Long_ tests"});
  k.finish = [](Job& j, const ExpandOptions&) {
    synth::UnitConfig c;
    if (std::string skip = unit_config_of(j, c); !skip.empty()) return skip;
    rtl::Request r;
    r.unit = &synth::find_unit(j.params.at("unit").get<std::string>());
    r.cfg = c;
    if (j.params.contains("rtl")) r.rtl_dir = j.params["rtl"].get<std::string>();
    try {  // unit, configuration, RTL, harness and model sources, Verilator and compiler versions
      j.deps["rtl_build"] = rtl::build_key(r).hash;
    } catch (const rtl::RtlError& e) {
      j.deps["rtl_build"] = "unavailable";  // the job fails with the command's own message
    }
    j.result = j.out_dir + "/rtl.jsonl";
    j.argv.push_back("--json=" + j.result);
    return std::string();
  };
  return k;
}

// ---- study box / study tri ------------------------------------------------------------------

std::vector<Key> study_common_keys() {
  return {
      {"synthetic", T::Int, "--synthetic", int_range(1, 100000000), {}, "synthetic pairs"},
      {"seed", T::Int, "--seed", int_range(0, (1ll << 62)), {}, "seed of the synthetic trace"},
      {"scale", T::Num, "--scale", num_range(1e-30, 1e30), {}, "scene scale"},
      {"limit", T::Int, "--limit", int_range(1, 1ll << 40), {}, "first N records"},
      {"threads", T::Int, "--threads", int_range(1, 64), {}, "worker threads of the job"},
      {"trace", T::Str, "--trace", check_existing_file, {}, "binary trace file"},
      {"ftz", T::Bool, "--ftz", {}, {}, "flush-to-zero formats"},
  };
}

std::string finish_study_deps(Job& j) {
  if (j.params.contains("trace")) j.deps["trace"] = file_hash(j.params["trace"].get<std::string>());
  return "";
}

Kind study_box_kind() {
  Kind k;
  k.name = "study box";
  k.cmd = {"study", "box"};
  k.keys = study_common_keys();
  k.keys.push_back({"format", T::Str, "--formats", check_format, {}, "one format per job (eXmY)"});
  k.keys.push_back({"adversarial", T::Int, "--adversarial", int_range(0, 100000000), {}, "adversarial pairs"});
  k.finish = [](Job& j, const ExpandOptions&) {
    j.result = j.out_dir + "/study_box.csv";
    j.argv.push_back("--csv=" + j.result);
    j.argv.push_back("--quiet");
    return finish_study_deps(j);
  };
  return k;
}

Kind study_tri_kind() {
  Kind k;
  k.name = "study tri";
  k.cmd = {"study", "tri"};
  k.keys = study_common_keys();
  auto single = [](const char* opt) {
    return [opt](const json& v) {
      const std::string s = std::to_string(v.get<long long>());
      return std::vector<std::string>{std::string(opt) + "=" + s + ":" + s};
    };
  };
  k.keys.push_back({"exp", T::Int, "--exp", int_range(2, 11), single("--exp"), "exponent bits of the job"});
  k.keys.push_back({"frac", T::Int, "--frac", int_range(1, 52), single("--frac"), "fraction bits of the job"});
  k.keys.push_back({"scale_spread", T::Num, "--scale-spread", num_range(0, 300), {}, "decades of scale spread"});
  k.keys.push_back({"max_width", T::Int, "--max-width", int_range(4, 64), {}, "skip wider formats"});
  k.keys.push_back({"no_decisions", T::Bool, "--no-decisions", {}, {}, "skip the decision counts"});
  k.finish = [](Job& j, const ExpandOptions&) {
    j.result = j.out_dir + "/study_tri_tables.csv";
    j.argv.push_back("--out=" + j.out_dir);
    j.argv.push_back("--no-plot");
    j.argv.push_back("--quiet");
    return finish_study_deps(j);
  };
  return k;
}

// ---- render ---------------------------------------------------------------------------------

void check_scene(const json& v) {
  const std::string s = v.get<std::string>();
  const std::string base = s.substr(0, s.find('@'));
  for (const auto& n : scene::builtin_scene_names())
    if (n == base) {
      if (base.size() < s.size()) {
        char* end = nullptr;
        const double f = std::strtod(s.c_str() + base.size() + 1, &end);
        if (!*end && f > 0 && std::isfinite(f)) return;
      } else {
        return;
      }
    }
  throw std::runtime_error("unknown scene '" + s + "' (scenes: " + scene::scene_name_help() + ")");
}

void check_render_format(const json& v) {
  const std::string s = v.get<std::string>();
  if (s != "double" && s != "float") num::Format::parse(s);
}

// Exactly one of `scene` and `mesh` (render, trax, study watertight/image); a mesh file's content
// is part of the job's hash.
void scene_or_mesh(Job& j, const std::string& what) {
  if (j.params.contains("mesh") == j.params.contains("scene"))
    throw GridError("key 'scene'/'mesh': " + what + " needs exactly one of scene and mesh");
  if (j.params.contains("mesh")) j.deps["mesh"] = file_hash(j.params["mesh"].get<std::string>());
}

// A check that runs a renderer option parser (parse_tri, parse_box, ...) on the value.
template <class F>
std::function<void(const json&)> parses(F f) {
  return [f](const json& v) { f(v.get<std::string>()); };
}

// The `size` key of renders, image studies and the chip model: "WxH" or "N".
Key size_key(const char* help) {
  return {"size", T::Str, "--size",
          [](const json& v) {
            int w, h;
            render::parse_size(v.get<std::string>(), &w, &h);
          },
          {}, help};
}

Kind render_kind() {
  Kind k;
  k.name = "render";
  k.cmd = {"render"};
  k.keys = {
      {"scene", T::Str, "--scene", check_scene, {}, "built-in scene"},
      {"mesh", T::Str, "--mesh", check_existing_file, {}, "mesh file"},
      {"up", T::Str, "--up", one_of({"y", "z"}), {}, "up axis of the mesh"},
      {"format", T::Str, "--format", check_render_format, {}, "double, float or eXmY"},
      {"tri", T::Str, "--tri", parses(render::parse_tri), {}, "robust | mt"},
      {"box", T::Str, "--box", parses(render::parse_box), {}, "plain | conservative"},
      {"bvh", T::Str, "--bvh", parses(render::parse_bvh), {}, "sah | median"},
      {"noise", T::Str, "--noise", parses(render::parse_noise), {}, "float | fixed | fixed-trunc"},
      {"leaf", T::Int, "--leaf", int_range(1, 64), {}, "triangles per leaf"},
      size_key("WxH or N"),
      {"threads", T::Int, "--threads", int_range(1, 64), {}, "render threads"},
      {"no_shadows", T::Bool, "--no-shadows", {}, {}, "primary rays only"},
      {"compare", T::Bool, "--compare", {}, {}, "also render in double: errors and PSNR against it"},
  };
  k.finish = [](Job& j, const ExpandOptions&) {
    scene_or_mesh(j, "a render job");
    j.result = j.out_dir + "/render.jsonl";
    j.argv.push_back("--out=" + j.out_dir + "/image.png");
    j.argv.push_back("--json=" + j.result);
    j.argv.push_back("--quiet");
    return std::string();
  };
  return k;
}

// ---- study watertight / study image / study noise ----------------------------------------------

Kind study_watertight_kind() {
  Kind k;
  k.name = "study watertight";
  k.cmd = {"study", "watertight"};
  k.keys = {
      {"scene", T::Str, "--scene",
       [](const json& v) {
         const std::string names = units::builtin_mesh_names();  // "icosphere, icosphere4, ..."
         std::istringstream in(names);
         for (std::string n; std::getline(in >> std::ws, n, ',');)
           if (n == v.get<std::string>()) return;
         throw std::runtime_error("unknown closed mesh '" + v.get<std::string>() + "' (scenes: " + names + ")");
       },
       {}, "built-in closed mesh"},
      {"mesh", T::Str, "--mesh", check_existing_file, {}, "closed mesh file"},
      {"format", T::Str, "--format", check_format, {}, "eXmY[-ftz]"},
      {"tri", T::Str, "--tri", one_of({"robust", "mt", "exact"}), {}, "robust | mt | exact"},
      {"rays", T::Int, "--rays", int_range(2, 1ll << 40), {}, "rays per class"},
      {"near_vertex", T::Int, "--near-vertex", int_range(0, 1ll << 40), {}, "rays aimed near vertices"},
      {"scale", T::Num, "--scale", num_range(1e-30, 1e30), {}, "coordinate scale"},
      {"seed", T::Int, "--seed", int_range(0, 1ll << 62), {}, "random seed"},
      {"threads", T::Int, "--threads", int_range(1, 64), {}, "worker threads of the job"},
      {"tie_break", T::Bool, "--tie-break", {}, {}, "robust: Fig. 3.6's tie-break"},
  };
  k.finish = [](Job& j, const ExpandOptions&) {
    scene_or_mesh(j, "a watertight study");
    j.result = j.out_dir + "/watertight.csv";
    j.argv.push_back("--csv=" + j.result);
    j.argv.push_back("--quiet");
    return std::string();
  };
  return k;
}

Kind study_image_kind() {
  Kind k;
  k.name = "study image";
  k.cmd = {"study", "image"};
  auto single = [](const char* opt) {
    return [opt](const json& v) { return std::vector<std::string>{std::string(opt) + "=" + value_text(v)}; };
  };
  k.keys = {
      {"scene", T::Str, "--scene", check_scene, {}, "built-in scene"},
      {"mesh", T::Str, "--mesh", check_existing_file, {}, "mesh file"},
      {"up", T::Str, "--up", one_of({"y", "z"}), {}, "up axis of the mesh"},
      {"exp", T::Int, "--exp", int_range(2, 11), single("--exp"), "exponent bits of the job"},
      {"frac", T::Int, "--frac", int_range(1, 52), single("--frac"), "fraction bits of the job"},
      {"tri", T::Str, "--tri", parses(render::parse_tri), {}, "robust | mt"},
      size_key("WxH"),
      {"bvh", T::Str, "--bvh", parses(render::parse_bvh), {}, "median | sah"},
      {"box", T::Str, "--box", parses(render::parse_box), {}, "plain | conservative"},
      {"noise", T::Str, "--noise", parses(render::parse_noise), {}, "float | fixed | fixed-trunc"},
      {"threads", T::Int, "--threads", int_range(1, 64), {}, "render threads"},
  };
  k.required = {"exp", "frac"};
  k.finish = [](Job& j, const ExpandOptions&) {
    scene_or_mesh(j, "an image study");
    j.result = j.out_dir + "/image_errors.csv";
    j.argv.push_back("--out=" + j.out_dir);
    j.argv.push_back("--no-plot");
    return std::string();
  };
  return k;
}

Kind study_noise_kind() {
  Kind k;
  k.name = "study noise";
  k.cmd = {"noise", "study"};
  k.keys = {
      {"size", T::Int, "--size",
       [](const json& v) {
         const long long n = v.get<long long>();
         if (n < 64 || n > 8192 || (n & (n - 1))) throw std::runtime_error("expects a power of two in 64..8192");
       },
       {}, "pixels per side of the spectral images"},
      {"error_samples", T::Int, "--error-samples", int_range(1, 100000000), {}, "random inputs per width"},
      {"range_samples", T::Int, "--range-samples", int_range(1, 100000000), {}, "output-range samples"},
      {"min_bits", T::Int, "--min-bits", int_range(1, 20), {}, "smallest fraction width"},
      {"max_bits", T::Int, "--max-bits", int_range(1, 20), {}, "largest fraction width"},
      {"seed", T::Int, "--seed", int_range(0, 1ll << 62), {}, "sampling seed"},
  };
  k.finish = [](Job& j, const ExpandOptions&) {
    j.result = j.out_dir + "/noise_error_vs_bits.csv";  // spectra and range tables beside it
    j.argv.push_back("--out=" + j.out_dir);
    j.argv.push_back("--no-plot");
    j.argv.push_back("--quiet");
    return std::string();
  };
  return k;
}

// ---- trax: the chip model on a scene --------------------------------------------------------

Kind trax_kind() {
  Kind k;
  k.name = "trax";
  k.cmd = {"trax"};
  k.keys = {
      {"scene", T::Str, "--scene", check_scene, {}, "built-in scene"},
      {"mesh", T::Str, "--mesh", check_existing_file, {}, "mesh file"},
      {"up", T::Str, "--up", one_of({"y", "z"}), {}, "up axis of the mesh"},
      {"format", T::Str, "--format", check_render_format, {}, "float or eXmY (chip.format)"},
      {"tri", T::Str, "--tri", parses(render::parse_tri), {}, "robust | mt"},
      {"traversal", T::Str, "--traversal", one_of({"stack", "stackless"}), {}, "BVH traversal"},
      size_key("WxH or N"),
      {"config", T::Str, "--config", check_existing_file, {}, "chip configuration TOML"},
      {"cosim", T::Bool, "--cosim", {}, {}, "co-simulate the units with their RTL"},
  };
  k.finish = [](Job& j, const ExpandOptions&) {
    scene_or_mesh(j, "a trax job");
    if (j.params.contains("format") && j.params["format"].get<std::string>() == "double")
      throw GridError("key 'format': the chip model takes float or eXmY, not double");
    if (j.params.contains("config")) j.deps["config"] = file_hash(j.params["config"].get<std::string>());
    j.result = j.out_dir + "/summary.json";
    j.argv.push_back("--out=" + j.out_dir);
    j.argv.push_back("--quiet");
    return std::string();
  };
  return k;
}

// ---- search: a formulation search (rayunits search tri, docs/DATAPATH.md) ------------------------

Kind search_kind() {
  Kind k;
  k.name = "search";
  k.cmd = {"search", "tri"};
  k.required = {"format", "clock"};
  k.keys = {
      {"format", T::Str, "--format", check_format, {}, "eXmY[-ftz]"},
      {"clock", T::Str, "--clock", [](const json& v) { synth::parse_clock_ps("clock", v.get<std::string>()); }, {},
       "target clock (250MHz, 4ns)"},
      {"budget", T::Int, "--budget", int_range(8, 1ll << 30), {}, "evaluations"},
      {"population", T::Int, "--population", int_range(8, 1ll << 20), {}, "NSGA-II population (multiple of 4)"},
      {"seed", T::Int, "--seed", int_range(0, 1ll << 62), {}, "seed"},
      {"start", T::Str, "--start", {}, {}, "start formulation or genome name"},
      {"trace", T::Str, "--trace", check_existing_file, {}, "binary trace file"},
      {"records", T::Int, "--records", int_range(1, 1ll << 40), {}, "records used"},
      {"scene", T::Str, "--mesh", {}, {}, "built-in closed mesh (icosphere, torus, ...)"},
      {"mesh", T::Str, "--mesh", check_existing_file, {}, "closed mesh file"},
      {"mesh_rays", T::Int, "--mesh-rays", int_range(0, 1ll << 40), {}, "watertightness rays"},
      {"rows", T::Str, "--rows", {}, {}, "directory of cell-flow rows"},
      {"threads", T::Int, "--threads", int_range(1, 64), {}, "evaluation threads of the job"},
      {"epsilon", T::Num, "--epsilon", num_range(1e-9, 1e9), {}, "epsilon-box size of the reported front"},
      {"no_characterize", T::Bool, "--no-characterize", {}, {}, "use only existing cell rows"},
      {"no_verify", T::Bool, "--no-verify", {}, {}, "skip the cycle-by-cycle verification"},
      {"fused", T::Bool, "--fused", {}, {}, "also move over fused multiply-adds"},
  };
  for (Key& key : k.keys)
    for (char& ch : key.option)
      if (ch == '_') ch = '-';
  k.finish = [](Job& j, const ExpandOptions&) {
    if (j.params.contains("scene") && j.params.contains("mesh"))
      throw GridError("a search job takes at most one of 'scene' and 'mesh'");
    if (j.params.contains("trace")) j.deps["trace"] = file_hash(j.params["trace"].get<std::string>());
    if (j.params.contains("mesh")) j.deps["mesh"] = file_hash(j.params["mesh"].get<std::string>());
    j.result = j.out_dir + "/front.csv";  // reported designs and the references, one row each
    j.argv.push_back("--out=" + j.out_dir);
    j.argv.push_back("--quiet");
    return std::string();
  };
  return k;
}

const std::vector<Kind>& kinds() {
  static const std::vector<Kind> k = {synth_kind(),      rtl_kind(),          study_box_kind(),
                                      study_tri_kind(),  study_watertight_kind(), study_image_kind(),
                                      study_noise_kind(), render_kind(),       trax_kind(),
                                      search_kind()};
  return k;
}

const Kind* find_kind(const std::string& name) {
  for (const Kind& k : kinds())
    if (k.name == name) return &k;
  return nullptr;
}

// ---- parsing --------------------------------------------------------------------------------

struct Axis {
  std::string key;
  std::vector<json> values;
};

struct Ctx {
  std::string source;
  fs::path base;  // directory of the grid file (relative paths)
  [[noreturn]] void fail(const toml::node* n, const std::string& key, const std::string& msg) const {
    std::string where = source;
    if (n && n->source().begin.line) where += ":" + std::to_string(n->source().begin.line);
    throw GridError(where + ": key '" + key + "': " + msg);
  }
};

const Key* find_key(const Kind& k, const std::string& name) {
  for (const Key& key : k.keys)
    if (key.name == name) return &key;
  return nullptr;
}

std::string key_list(const Kind& k) {
  std::string s;
  for (const Key& key : k.keys) s += (s.empty() ? "" : ", ") + key.name;
  if (k.params_table) s += ", param.NAME";
  return s;
}

// One value (scalar) of key, typed and checked; paths made absolute relative to the grid file.
json read_value(const Ctx& cx, const Key& key, const toml::node& n, const std::string& name) {
  std::optional<json> v = typed(n, key.type);
  if (!v) cx.fail(&n, name, "must be " + type_name(key.type) + (n.is_array() ? " (no nested arrays)" : ""));
  if (v->is_string() && (key.name == "rtl" || key.name == "trace" || key.name == "mesh" || key.name == "config" ||
                          key.name == "rows")) {
    fs::path p(v->get<std::string>());
    if (!p.empty() && p.is_relative()) *v = (cx.base / p).lexically_normal().string();
  }
  if (key.check) {
    try {
      key.check(*v);
    } catch (const std::exception& e) {
      cx.fail(&n, name, e.what());
    }
  }
  return *v;
}

// Values of one entry: an array is an axis (at least one value), a scalar a one-value axis.
std::vector<json> read_values(const Ctx& cx, const Key& key, const toml::node& n, const std::string& name) {
  std::vector<json> out;
  if (const toml::array* a = n.as_array()) {
    if (a->empty()) cx.fail(&n, name, "empty axis (give at least one value)");
    for (const toml::node& e : *a) out.push_back(read_value(cx, key, e, name));
    std::set<std::string> seen;
    for (const json& v : out)
      if (!seen.insert(v.dump()).second) cx.fail(&n, name, "value " + v.dump() + " appears twice in the axis");
  } else {
    out.push_back(read_value(cx, key, n, name));
  }
  return out;
}

std::string job_label(const Job& j) {
  std::string s = j.kind;
  if (j.params.contains("unit")) s += " " + j.params["unit"].get<std::string>();
  for (auto it = j.params.begin(); it != j.params.end(); ++it)
    if (it.key() != "unit") s += " " + it.key() + "=" + value_text(it.value());
  return s;
}

std::vector<std::string> emit(const Key& key, const json& v) {
  if (key.emit) return key.emit(v);
  if (key.type == T::Bool) return v.get<bool>() ? std::vector<std::string>{key.option} : std::vector<std::string>{};
  if (key.option.empty()) return {value_text(v)};
  return {key.option + "=" + value_text(v)};
}

const char* const kHashDir = "out/{hash}";

void expand_one(const Ctx& cx, const toml::table& t, std::size_t grid_index, const ExpandOptions& opt,
                const std::string& tool, Expansion& out, std::set<std::string>& hashes) {
  const std::string pre = grid_index == SIZE_MAX ? "" : "grid[" + std::to_string(grid_index) + "].";
  const toml::node* kn = t.get("kind");
  if (!kn) cx.fail(nullptr, pre + "kind", "missing (kinds: synth, rtl, study, render, trax)");
  const auto kv = kn->value_exact<std::string>();
  if (!kv) cx.fail(kn, pre + "kind", "must be a string (kinds: synth, rtl, study, render, trax)");
  std::string kind = *kv;
  if (kind == "study") {
    const toml::node* sn = t.get("study");
    const auto sv = sn ? sn->value_exact<std::string>() : std::nullopt;
    if (!sv || !find_kind("study " + *sv))
      cx.fail(sn ? sn : kn, pre + "study", "kind \"study\" needs study = \"box\", \"tri\", \"watertight\", \"image\" or \"noise\"");
    kind += " " + *sv;
  }
  const Kind* k = find_kind(kind);
  if (!k) cx.fail(kn, pre + "kind", "unknown kind '" + kind + "' (kinds: synth, rtl, study, render, trax)");

  std::vector<Axis> axes;
  for (const auto& [kk, v] : t) {
    const std::string name(kk.str());
    if (name == "kind" || name == "name" || name == "description" || (name == "study" && k->name.rfind("study ", 0) == 0))
      continue;
    if (name == "param" && k->params_table) {
      const toml::table* pt = v.as_table();
      if (!pt) cx.fail(&v, pre + name, "must be a table ([param] Name = value or [values])");
      for (const auto& [pk, pv] : *pt) {
        const std::string pname = "param." + std::string(pk.str());
        const std::string id(pk.str());
        if (id.empty() || id.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_") !=
                              std::string::npos)
          cx.fail(&pv, pre + pname, "a parameter name is letters, digits and _");
        const Key pkey{pname, T::Int, "--param", int_range(-1000000, 1000000),
                       [id](const json& x) { return std::vector<std::string>{"--param=" + id + "=" + value_text(x)}; },
                       ""};
        axes.push_back({pname, read_values(cx, pkey, pv, pre + pname)});
      }
      continue;
    }
    const Key* key = find_key(*k, name);
    if (!key) cx.fail(&v, pre + name, "unknown key for kind " + k->name + " (keys: " + key_list(*k) + ")");
    axes.push_back({name, read_values(cx, *key, v, pre + name)});
  }
  for (const std::string& r : k->required) {
    bool have = false;
    for (const Axis& a : axes) have = have || a.key == r;
    if (!have) cx.fail(nullptr, pre + r, "required for kind " + k->name);
  }

  // The product of the axes, the last axis varying fastest.
  std::vector<std::size_t> pos(axes.size(), 0);
  for (bool done = false; !done;) {
    Job j;
    j.grid = grid_index == SIZE_MAX ? 0 : grid_index;
    j.kind = k->name;
    j.params = json::object();
    for (std::size_t a = 0; a < axes.size(); ++a) j.params[axes[a].key] = axes[a].values[pos[a]];
    j.deps = json::object();
    j.deps["tool"] = tool;
    j.out_dir = kHashDir;  // the hash is not known yet
    std::string skip;
    try {
      // finish may rewrite params (stages "max" -> its value), so argv is built after it; it
      // appends output arguments to argv, which are moved behind the parameters below.
      skip = k->finish(j, opt);
    } catch (const GridError& e) {
      throw GridError(cx.source + ": " + pre + e.what() + " (job " + job_label(j) + ")");
    } catch (const std::exception& e) {
      throw GridError(cx.source + ": " + pre + "job " + job_label(j) + ": " + e.what());
    }
    const std::vector<std::string> outputs = j.argv;
    j.argv = {"rayunits"};
    j.argv.insert(j.argv.end(), k->cmd.begin(), k->cmd.end());
    for (const Key& key : k->keys)  // table order: positional first, flags in their order
      if (j.params.contains(key.name))
        for (auto& s : emit(key, j.params[key.name])) j.argv.push_back(s);
    for (auto it = j.params.begin(); it != j.params.end(); ++it)
      if (it.key().rfind("param.", 0) == 0)
        j.argv.push_back("--param=" + it.key().substr(6) + "=" + value_text(it.value()));
    j.label = job_label(j);
    if (!skip.empty()) {
      out.skipped.push_back(j.label + ": " + skip);
    } else {
      j.hash = util::fnv1a64_hex(json{{"kind", j.kind}, {"params", j.params}, {"deps", j.deps}}.dump());
      // The output paths name the hash: recompute them now that it is known.
      j.out_dir = "out/" + j.hash;
      auto fix = [&](std::string s) {
        const std::size_t at = s.find(kHashDir);
        if (at != std::string::npos) s.replace(at, std::strlen(kHashDir), j.out_dir);
        return s;
      };
      j.result = fix(j.result);
      for (const auto& s : outputs) j.argv.push_back(fix(s));
      if (opt.check_job) {
        try {
          opt.check_job(j);
        } catch (const std::exception& e) {
          throw GridError(cx.source + ": " + pre + "job " + j.label + ": " + e.what());
        }
      }
      if (!hashes.insert(j.hash).second) {
        out.skipped.push_back(j.label + ": same job as an earlier point");
      } else {
        j.index = out.jobs.size();
        out.jobs.push_back(std::move(j));
      }
    }
    done = true;
    for (std::size_t a = axes.size(); a-- > 0;) {
      if (++pos[a] < axes[a].values.size()) {
        done = false;
        break;
      }
      pos[a] = 0;
    }
  }
}

}  // namespace

std::string kinds_help() {
  std::string s;
  for (const Kind& k : kinds()) {
    s += "  " + k.name + ": ";
    std::string keys;
    for (const Key& key : k.keys) keys += (keys.empty() ? "" : " ") + key.name;
    if (k.params_table) keys += " [param] NAME";
    s += keys + "\n";
  }
  return s;
}

Expansion expand_grid(const std::string& text, const std::string& source, const ExpandOptions& opt) {
  Ctx cx{source, fs::path(source).has_parent_path() ? fs::absolute(source).parent_path() : fs::current_path()};
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw GridError(source + ":" + std::to_string(e.source().begin.line) + ": " + std::string(e.description()));
  }
  const std::string tool = opt.tool.empty() ? tool_id(opt.source_dir.empty() ? RU_SOURCE_DIR : opt.source_dir)
                                            : opt.tool;
  Expansion out;
  std::set<std::string> hashes;
  if (const toml::node* g = root.get("grid")) {
    const toml::array* arr = g->as_array();
    if (!arr || !arr->is_array_of_tables()) cx.fail(g, "grid", "must be an array of tables ([[grid]])");
    for (const auto& [kk, v] : root)
      if (kk != "grid" && kk != "name" && kk != "description")
        cx.fail(&v, std::string(kk.str()), "unknown top-level key beside [[grid]] tables (put it into a grid)");
    if (arr->empty()) cx.fail(g, "grid", "no grid");
    for (std::size_t i = 0; i < arr->size(); ++i) expand_one(cx, *arr->get(i)->as_table(), i, opt, tool, out, hashes);
  } else {
    expand_one(cx, root, SIZE_MAX, opt, tool, out, hashes);
  }
  if (out.jobs.empty()) throw GridError(source + ": the grid has no job (every point was skipped)");
  return out;
}

Expansion expand_grid_file(const std::string& path, const ExpandOptions& opt) {
  if (!fs::is_regular_file(path)) throw GridError("cannot read grid file '" + path + "'");
  return expand_grid(synth::read_file(path), path, opt);
}

json job_json(const Job& j) {
  return json{{"index", j.index}, {"grid", j.grid},     {"kind", j.kind},     {"label", j.label},
              {"hash", j.hash},   {"params", j.params}, {"deps", j.deps},     {"argv", j.argv},
              {"out_dir", j.out_dir}, {"result", j.result}};
}

Job job_from_json(const json& v) {
  Job j;
  j.index = v.at("index").get<std::size_t>();
  j.grid = v.at("grid").get<std::size_t>();
  j.kind = v.at("kind").get<std::string>();
  j.label = v.at("label").get<std::string>();
  j.hash = v.at("hash").get<std::string>();
  j.params = v.at("params");
  j.deps = v.at("deps");
  j.argv = v.at("argv").get<std::vector<std::string>>();
  j.out_dir = v.at("out_dir").get<std::string>();
  j.result = v.at("result").get<std::string>();
  return j;
}

std::string jobs_jsonl(const std::vector<Job>& jobs) {
  std::string s;
  for (const Job& j : jobs) s += job_json(j).dump() + "\n";
  return s;
}

}  // namespace ru::sweep
