// `rayunits gen`: a self-contained synthesis-ready directory per unit configuration.
#include "rayunits/synth/gen.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "rayunits/synth/process.hpp"

namespace ru::synth {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string num_str(double v, int prec) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

// A directory that does not exist yet next to `target` (for the staging / replaced copies).
std::string sibling_temp(const fs::path& target, const char* tag) {
  const std::string tmpl =
      (target.parent_path() / ("." + target.filename().string() + tag + "XXXXXX")).string();
  std::vector<char> buf(tmpl.begin(), tmpl.end());
  buf.push_back('\0');
  if (!::mkdtemp(buf.data())) throw SynthError("cannot create a directory next to '" + target.string() + "'");
  return buf.data();
}

}  // namespace

ClockSearch find_stages_for_clock(const UnitSpec& u, UnitConfig c, double clock_ps, const FlowOptions& o,
                                  const std::function<void(const std::string&)>& progress) {
  if (!is_cell_flow(o.flow)) throw SynthError("a target clock needs a cell-library flow (osu018, osu035, osu050)");
  FlowOptions fo = o;
  fo.clocks_ps = {clock_ps};
  ClockSearch cs;
  std::map<int, SynthResult> done;
  auto probe = [&](int stages) -> bool {
    c.stages = stages;
    SynthResult r = run_synth(u, c, fo);
    const CellRun& run = r.cell.runs.front();
    const bool met = run.sta.slack_ps >= 0;
    cs.probes.push_back({{"stages", stages},
                         {"fmax_mhz", std::round(run.fmax_mhz * 10) / 10},
                         {"slack_ps", std::round(run.sta.slack_ps * 10) / 10},
                         {"met", met},
                         {"area_um2", std::round(run.area.total * 100) / 100}});
    if (progress)
      progress("gen: " + config_args(u, c) + ": " + num_str(run.fmax_mhz, 1) + " MHz, slack " +
               num_str(run.sta.slack_ps, 0) + " ps at " + num_str(clock_ps, 0) + " ps: " + (met ? "met" : "missed"));
    done.emplace(stages, std::move(r));
    return met;
  };
  const int lo0 = u.min_stages, hi0 = u.max_stages(c);
  if (!probe(hi0)) {
    const CellRun& run = done.at(hi0).cell.runs.front();
    throw SynthError(u.name + " does not reach " + num_str(1e6 / clock_ps, 1) + " MHz (" + num_str(clock_ps, 0) +
                     " ps) in " + o.flow + ": at its maximum useful Stages " + std::to_string(hi0) + " it reaches " +
                     num_str(run.fmax_mhz, 1) + " MHz (" + num_str(run.achieved_ps, 0) + " ps)");
  }
  int lo = lo0, hi = hi0;  // hi meets; find the smallest meeting count in lo..hi
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (probe(mid))
      hi = mid;
    else
      lo = mid + 1;
  }
  cs.stages = hi;
  cs.result = done.at(hi);
  return cs;
}

json datasheet_json(const UnitSpec& u, const UnitConfig& c, const std::vector<std::string>& files,
                    const std::optional<SynthResult>& synth) {
  json ds;
  ds["top"] = wrapper_name(u, c);
  ds["unit"] = u.name;
  ds["rtl_module"] = u.top;
  ds["summary"] = u.summary;
  ds["generated_by"] = "rayunits gen " + config_args(u, c);
  if (u.uses_format) {
    ds["format"] = {{"name", c.fmt.name()},   {"exp_bits", c.fmt.exp_bits}, {"frac_bits", c.fmt.frac_bits},
                    {"width", c.fmt.width()}, {"bias", c.fmt.bias()},       {"subnormals", c.fmt.subnormals}};
    ds["round"] = num::round_name(c.fmt.round);
  } else {
    ds["format"] = nullptr;
    ds["round"] = nullptr;
  }
  ds["latency"] = u.latency(c);
  ds["throughput"] = 1;
  ds["throughput_unit"] = "operations per cycle";
  // a unit with a handshake: latency is its smallest (Stages, or UnitSpec::min_latency), 1 per
  // cycle its peak throughput
  ds["handshake"] = u.handshake;
  json params = json::object();
  for (const auto& [k, v] : params_for(u, c)) params[k] = v;
  ds["parameters"] = params;
  ds["placement"] = c.seg_weights.empty() ? "depth" : "delay";
  ds["seg_weights"] = c.seg_weights.empty() ? json(nullptr) : json(c.seg_weights);  // SegW, segment 0 first
  json ports = json::array();
  for (const auto& p : ports_for(u, c))
    ports.push_back({{"name", p.name},
                     {"direction", p.dir == PortDir::In ? "input" : "output"},
                     {"width", p.width},
                     {"description", p.doc}});
  ds["ports"] = ports;
  ds["files"] = files;
  if (synth && synth->cell.run) {
    json row = to_json(*synth);
    for (const char* k : {"seconds", "step_seconds", "temp_dir"}) row.erase(k);
    for (const char* k : {"flow", "library", "target_clock_mhz", "target_clock_ps", "met", "slack_ps", "fmax_mhz",
                          "period_ps", "period_fo4", "area_um2", "area_comb_um2", "area_seq_um2"})
      ds[k] = row[k];
    ds["synthesis"] = row;
  } else if (synth) {
    json row = to_json(*synth);
    row.erase("seconds");
    row.erase("step_seconds");
    row.erase("temp_dir");
    ds["area_nand2"] = row["area_nand2"];
    ds["depth"] = row["depth"];
    ds["fmax_est_mhz"] = row["fmax_est_mhz"];
    ds["reg_bits"] = row["reg_bits"];
    ds["transistors_cmos"] = row["transistors_cmos"];
    ds["synthesis"] = row;
  } else {
    ds["area_nand2"] = nullptr;
    ds["depth"] = nullptr;
    ds["fmax_est_mhz"] = nullptr;
    ds["synthesis"] = nullptr;
  }
  return ds;
}

std::string datasheet_markdown(const json& ds) {
  std::ostringstream o;
  const json& f = ds["format"];
  o << "# " << ds["top"].get<std::string>() << "\n\n"
    << ds["summary"].get<std::string>() << ".\n\n"
    << "Generated by `" << ds["generated_by"].get<std::string>() << "`; wraps `"
    << ds["rtl_module"].get<std::string>() << "` with its parameters fixed.\n\n"
    << "| property | value |\n|---|---|\n";
  if (!f.is_null())
    o << "| format | " << f["name"].get<std::string>() << ": " << f["width"].get<int>() << " bits = 1 sign + "
      << f["exp_bits"].get<int>() << " exponent (bias " << f["bias"].get<int>() << ") + "
      << f["frac_bits"].get<int>() << " fraction |\n"
      << "| subnormals | " << (f["subnormals"].get<bool>() ? "yes" : "no (flush to zero)") << " |\n"
      << "| rounding | " << ds["round"].get<std::string>() << " |\n";
  if (ds["handshake"].get<bool>())
    o << "| latency | " << ds["latency"].get<int>() << " cycles or more (results in input order) |\n"
      << "| throughput | up to 1 operation per cycle: accepted while in_ready_o is high |\n";
  else
    o << "| latency | " << ds["latency"].get<int>() << " cycles |\n"
      << "| throughput | 1 operation per cycle (fully pipelined) |\n";
  if (!ds["synthesis"].is_null() && ds["synthesis"].contains("area_um2")) {
    const json& s = ds["synthesis"];
    const std::string lib = s["library"].get<std::string>();
    o << "| area | " << num_str(s["area_um2"].get<double>(), 0) << " um2 in " << lib << " (combinational "
      << num_str(s["area_comb_um2"].get<double>(), 0) << ", sequential " << num_str(s["area_seq_um2"].get<double>(), 0)
      << "; " << s["cell_count"].get<long>() << " cells), before placement |\n";
    if (!s["target_clock_ps"].is_null())
      o << "| target clock | " << num_str(1e6 / s["target_clock_ps"].get<double>(), 1) << " MHz ("
        << num_str(s["target_clock_ps"].get<double>(), 0) << " ps): "
        << (s["met"].get<bool>() ? "met" : "NOT met") << ", slack " << num_str(s["slack_ps"].get<double>(), 0)
        << " ps |\n";
    const json& p = s["critical_path"];
    o << "| Fmax (OpenSTA) | " << num_str(s["fmax_mhz"].get<double>(), 1) << " MHz = "
      << num_str(s["period_ps"].get<double>(), 0) << " ps = " << num_str(s["period_fo4"].get<double>(), 1)
      << " FO4 (FO4 " << num_str(s["fo4_ps"].get<double>(), 1) << " ps); critical path in segment "
      << (p["segment"].is_null() ? std::string("?") : std::to_string(p["segment"].get<int>())) << " of "
      << p["segments"].get<int>() << " |\n";
    if (ds.contains("clock_search")) {
      o << "| Stages search | ";
      for (const auto& pr : ds["clock_search"]["probes"])
        o << "Stages " << pr["stages"].get<int>() << ": " << num_str(pr["fmax_mhz"].get<double>(), 1) << " MHz"
          << (pr["met"].get<bool>() ? " (met); " : "; ");
      o << "smallest meeting: " << ds["latency"].get<int>() << " |\n";
    }
    o << "| synthesized with | " << s["yosys"].get<std::string>() << ", " << s["sta"].get<std::string>() << " |\n";
  } else if (!ds["synthesis"].is_null()) {
    const json& s = ds["synthesis"];
    o << "| area | " << num_str(s["area_nand2"].get<double>(), 1) << " NAND2-eq ("
      << s["cells_total"].get<long>() << " generic cells, " << s["reg_bits"].get<long>()
      << " register bits) |\n"
      << "| transistors | " << s["transistors_cmos"].get<long>()
      << (s["transistors_complete"].get<bool>()
              ? ""
              : "+ (" + std::to_string(s["transistors_uncounted_cells"].get<long>()) +
                    " flip-flops with reset/enable not counted by Yosys)")
      << " |\n"
      << "| worst stage | " << s["depth"].get<int>() << " gate levels (a " << s["delay_model"].get<std::string>()
      << " estimate of " << num_str(s["stage_delay_ps"].get<double>(), 0)
      << " ps; for a timing use --flow osu018, see synth/README.md) |\n";
    if (!s["ice40"].is_null()) {
      const json& i = s["ice40"];
      o << "| iCE40 " << i["device"].get<std::string>() << " | " << i["luts"].get<long>() << " LUT4, "
        << i["carries"].get<long>() << " carry, " << i["ffs"].get<long>() << " FF"
        << (i["fits"].get<bool>() ? "" : " (does not fit: " + i["reason"].get<std::string>() + ")");
      if (!i["fmax_mhz"].is_null())
        o << ", nextpnr Fmax " << num_str(i["fmax_mhz"].get<double>(), 1) << " MHz";
      o << " |\n";
    }
    if (!s["xilinx"].is_null()) {
      const json& x = s["xilinx"];
      o << "| Xilinx 7-series | " << x["luts"].get<long>() << " LUT, " << x["ffs"].get<long>() << " FF, "
        << x["dsps"].get<long>() << " DSP48E1, " << x["carry4"].get<long>() << " CARRY4 |\n";
    }
    o << "| synthesized with | " << s["yosys"].get<std::string>() << " |\n";
  } else {
    o << "| area, depth | not synthesized (generated with --no-synth) |\n";
  }
  o << "\n## Ports\n\n| port | direction | width | description |\n|---|---|---|---|\n";
  for (const auto& p : ds["ports"])
    o << "| `" << p["name"].get<std::string>() << "` | " << p["direction"].get<std::string>() << " | "
      << p["width"].get<int>() << " | " << p["description"].get<std::string>() << " |\n";
  o << "\n## Parameters of the wrapped unit\n\n| parameter | value |\n|---|---|\n";
  for (auto it = ds["parameters"].begin(); it != ds["parameters"].end(); ++it)
    o << "| " << it.key() << " | " << it.value().get<long long>() << " |\n";
  o << "\n## Files\n\n`files.f` lists the compile units in order (included files sit next to "
       "them).\nSynthesize with\n"
       "`cd <this dir> && yosys synth.ys` (generic gates, `check -assert`, statistics,\n"
       "longest path). Every source the wrapper needs is in this directory.\n\n";
  for (const auto& x : ds["files"]) o << "- `" << x.get<std::string>() << "`\n";
  return o.str();
}

GenReport generate(const UnitSpec& u, const UnitConfig& request, const GenOptions& o) {
  check_config(u, request);
  // Delay-based placement: the weights come from a synthesis (the clock search's, or one here).
  UnitConfig c = request;
  std::optional<SynthResult> placed = o.reuse;
  if (o.flow.placement == "delay" && c.seg_weights.empty()) {
    if (!o.run_flow) throw SynthError("--placement delay needs the cell-library flow run (not --no-synth)");
    if (!placed) placed = run_synth(u, c, o.flow);
    c.seg_weights = placed->seg_weights;
  }
  if (o.out_dir.empty()) throw SynthError("--out DIR is required");
  const std::string rtl = o.flow.rtl_dir.empty() ? default_rtl_dir() : o.flow.rtl_dir;
  const Sources src = resolve_sources(u, rtl);
  if (o.run_flow) yosys_version(o.flow.yosys);  // fail early on a missing yosys

  const fs::path out = fs::absolute(o.out_dir).lexically_normal();
  std::error_code ec;
  const bool exists = fs::exists(out, ec);
  if (exists && !fs::is_directory(out, ec))
    throw SynthError("output '" + out.string() + "' exists and is not a directory");
  const bool nonempty = exists && !fs::is_empty(out, ec);
  if (nonempty && !o.force)
    throw SynthError("output directory '" + out.string() + "' is not empty (use --force to replace it)");
  if (nonempty) {
    // --force replaces only what gen wrote before: never a source tree given by mistake.
    bool ours = false;
    try {
      const json old = json::parse(read_file((out / "datasheet.json").string()));
      ours = old.value("generated_by", "").rfind("rayunits gen ", 0) == 0;
    } catch (const std::exception&) {
    }
    if (!ours)
      throw SynthError("--force replaces only a directory written by rayunits gen; '" + out.string() +
                       "' has no such datasheet.json (remove it yourself)");
  }
  if (!out.parent_path().empty()) fs::create_directories(out.parent_path(), ec);

  const std::string top = wrapper_name(u, c);
  const std::string stage = sibling_temp(out, ".tmp");
  GenReport rep;
  try {
    // Copies of the sources (flat), then the wrapper.
    // Flat copies: an `include "x" names a file next to the includer, so it stays valid.
    std::vector<std::string> names, inc_names;
    std::set<std::string> seen;
    auto copy = [&](const std::string& s, std::vector<std::string>& list) {
      const std::string n = fs::path(s).filename().string();
      if (!seen.insert(n).second) throw SynthError("two sources of " + u.name + " are named '" + n + "'");
      fs::copy_file(s, fs::path(stage) / n, fs::copy_options::overwrite_existing);
      fs::permissions(fs::path(stage) / n, fs::perms::owner_read | fs::perms::owner_write |
                                               fs::perms::group_read | fs::perms::others_read);
      list.push_back(n);
    };
    for (const auto& s : src.files) copy(s, names);
    for (const auto& s : src.includes) copy(s, inc_names);
    if (!seen.insert(top + ".sv").second)
      throw SynthError("a source is named like the wrapper '" + top + ".sv'");
    write_file_atomic(stage + "/" + top + ".sv", wrapper_verilog(u, c));
    names.push_back(top + ".sv");
    std::string fl;
    for (const auto& n : names) fl += n + "\n";
    write_file_atomic(stage + "/files.f", fl);
    write_file_atomic(stage + "/synth.ys", "# Generated by: rayunits gen " + config_args(u, c) +
                                               "\n# Run from this directory: yosys synth.ys\n" +
                                               generic_script(names, top, false, u.synth_share));

    std::optional<SynthResult> synth = placed;
    if (o.run_flow && !synth) {
      TempDir work("ru-gen-" + u.name + "-", o.flow.temp_parent);
      std::vector<std::string> abs;
      for (const auto& n : names) abs.push_back(stage + "/" + n);
      try {
        synth = run_flow(abs, top, ports_for(u, c), work.path(), o.flow);
      } catch (const SynthError&) {
        if (!interrupted()) work.keep();  // the message names a log in it
        throw;
      }
      label_result(*synth, u, c, src);
    }
    std::vector<std::string> files = names;
    for (const auto& n : inc_names) files.push_back(n);
    files.push_back("files.f");
    files.push_back("synth.ys");
    files.push_back("datasheet.json");
    files.push_back("datasheet.md");
    std::sort(files.begin(), files.end());
    json ds = datasheet_json(u, c, files, synth);
    if (!o.clock_search.is_null()) ds["clock_search"] = o.clock_search;
    write_file_atomic(stage + "/datasheet.json", ds.dump(2) + "\n");
    write_file_atomic(stage + "/datasheet.md", datasheet_markdown(ds));
    fs::permissions(stage, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                               fs::perms::others_read | fs::perms::others_exec);

    // Into place: an empty or missing out_dir is replaced by rename(); a non-empty one (--force)
    // is first moved aside and deleted after the new directory is in place.
    std::string old;
    if (nonempty) {
      old = sibling_temp(out, ".old");
      fs::remove(old);
      fs::rename(out, old);
    }
    fs::rename(stage, out, ec);
    if (ec) {
      if (!old.empty()) fs::rename(old, out);
      throw SynthError("cannot move the generated directory to '" + out.string() + "': " + ec.message());
    }
    if (!old.empty()) fs::remove_all(old, ec);
    rep.top = top;
    rep.dir = out.string();
    rep.files = files;
    rep.synth = synth;
  } catch (...) {
    fs::remove_all(stage, ec);
    throw;
  }
  return rep;
}

}  // namespace ru::synth
