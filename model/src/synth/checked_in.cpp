// Checked-in synthesis rows (see checked_in.hpp).
#include "rayunits/synth/checked_in.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rayunits/synth/units.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace ru::synth {
namespace {

std::string where(const std::string& file, int line) { return file + ":" + std::to_string(line); }

// Checks the fields a lookup and the report read; throws one line naming the first bad one.
void check_row(const json& r, const std::string& at) {
  if (!r.is_object()) throw SynthError(at + ": malformed results row: expected a JSON object");
  auto need = [&](const char* k, bool ok, const char* what) {
    if (!r.contains(k)) throw SynthError(at + ": malformed results row: no \"" + k + "\"");
    if (!ok) throw SynthError(at + ": malformed results row: \"" + k + "\" is not " + what);
  };
  need("unit", r.contains("unit") && r["unit"].is_string(), "a string");
  need("top", r.contains("top") && r["top"].is_string(), "a string");
  need("flow", r.contains("flow") && r["flow"].is_string(), "a string");
  need("stages", r.contains("stages") && r["stages"].is_number_integer(), "an integer");
  need("rtl_hash", r.contains("rtl_hash") && r["rtl_hash"].is_string(), "a string");
  if (r["flow"].get<std::string>() != "generic") {
    for (const char* k : {"area_um2", "fmax_mhz", "target_clock_ps"})
      need(k, r.contains(k) && r[k].is_number(), "a number");
  }
}

// The commit recorded in a sweep job's deps.tool ("rayunits 0.1 model <commit>"): its last word.
std::string tool_commit(const json& job) {
  if (!job.contains("deps") || !job["deps"].is_object() || !job["deps"].contains("tool") ||
      !job["deps"]["tool"].is_string())
    return "";
  const std::string t = job["deps"]["tool"].get<std::string>();
  const size_t p = t.find_last_of(' ');
  return p == std::string::npos ? t : t.substr(p + 1);
}

std::string joined(const json& argv) {
  std::string s;
  if (!argv.is_array()) return s;
  for (const auto& a : argv) {
    if (!a.is_string()) continue;
    if (!s.empty()) s += " ";
    s += a.get<std::string>();
  }
  return s;
}

}  // namespace

CheckedInRows CheckedInRows::load(const std::vector<std::string>& paths) {
  CheckedInRows out;
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& p : paths) {
    if (fs::is_directory(p, ec)) {
      if (fs::is_regular_file(fs::path(p) / "results.jsonl", ec)) {
        files.push_back((fs::path(p) / "results.jsonl").string());
        continue;
      }
      std::vector<std::string> in_dir;
      for (const auto& e : fs::directory_iterator(p, ec))
        if (e.is_regular_file() && e.path().extension() == ".jsonl") in_dir.push_back(e.path().string());
      std::sort(in_dir.begin(), in_dir.end());
      files.insert(files.end(), in_dir.begin(), in_dir.end());
    } else if (fs::is_regular_file(p, ec)) {
      files.push_back(p);
    }
  }
  for (const auto& f : files) {
    std::ifstream in(f);
    if (!in) throw SynthError(f + ": cannot read");
    out.files_.push_back(f);
    std::string text;
    int lineno = 0;
    while (std::getline(in, text)) {
      ++lineno;
      if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
      const std::string at = where(f, lineno);
      json j;
      try {
        j = json::parse(text);
      } catch (const json::exception&) {
        throw SynthError(at + ": malformed results row: not JSON");
      }
      if (!j.is_object()) throw SynthError(at + ": malformed results row: expected a JSON object");
      if (j.contains("result") || j.contains("argv")) {
        // a sweep job: its rows under "result" (none when it failed)
        const bool failed = (j.contains("error") && j["error"].is_string() && !j["error"].get<std::string>().empty()) ||
                            (j.contains("exit") && j["exit"].is_number_integer() && j["exit"].get<int>() != 0);
        if (failed) continue;
        if (!j.contains("result") || !j["result"].is_array())
          throw SynthError(at + ": malformed results row: a sweep job without a \"result\" array");
        for (const auto& r : j["result"]) {
          check_row(r, at);
          out.rows_.push_back({r, f, lineno, joined(j.value("argv", json::array())), tool_commit(j)});
        }
        continue;
      }
      // synth/cell/run.py: a note line (a point without a curve) carries no measurement
      if (!j.contains("flow") && j.contains("note")) continue;
      check_row(j, at);
      CheckedInRow r{j, f, lineno, "", ""};
      if (j.contains("command") && j["command"].is_string()) r.command = j["command"].get<std::string>();
      if (j.contains("built_from") && j["built_from"].is_string()) r.commit = j["built_from"].get<std::string>();
      out.rows_.push_back(std::move(r));
    }
  }
  return out;
}

CheckedInLookup CheckedInRows::find(const std::string& top, const std::string& flow, double target_clock_ps,
                                    const std::string& placement, bool share, const std::string& rtl_hash) const {
  CheckedInLookup res;
  const CheckedInRow* stale = nullptr;
  for (const auto& r : rows_) {
    const json& j = r.row;
    if (j["top"].get<std::string>() != top || j["flow"].get<std::string>() != flow) continue;
    if (flow != "generic" && std::fabs(j["target_clock_ps"].get<double>() - target_clock_ps) > 0.5) continue;
    const std::string pl = j.contains("placement") && j["placement"].is_string() ? j["placement"].get<std::string>()
                                                                                  : "depth";
    if (pl != placement) continue;
    const bool sh = j.contains("resource_sharing") && j["resource_sharing"].is_boolean()
                        ? j["resource_sharing"].get<bool>()
                        : true;
    if (sh != share) continue;
    if (j["rtl_hash"].get<std::string>() == rtl_hash)
      res.row = &r;
    else
      stale = &r;
  }
  if (res.row) return res;
  if (stale)
    res.why_not = "stale: " + where(stale->file, stale->line) + " has rtl_hash " +
                  stale->row["rtl_hash"].get<std::string>() + ", the current RTL " + rtl_hash;
  else
    res.why_not = "no checked-in row";
  return res;
}

}  // namespace ru::synth
