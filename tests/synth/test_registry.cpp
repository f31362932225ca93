// The unit registry against its other copies: the RTL (MaxUsefulStages / OutRegs localparams,
// read with `verilator --xml-only`), rtl/README.md's table, and model/data/registry.json (what
// CMake reads). Each check is shown to catch a planted disagreement.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "rayunits/noise/fixed.hpp"
#include "rayunits/render/render.hpp"
#include "rayunits/synth/unit_models.hpp"
#include "rayunits/synth/units.hpp"

#include "../common/files.hpp"

namespace {

using namespace ru::synth;
using ru::num::Format;

using ru::test::slurp;

// $RU_RTL_DIR if set (to check another copy of the RTL), else the source tree's rtl/.
std::string rtl_dir() { return default_rtl_dir(); }

// Three formats per unit with a format (small, Kensler's, binary32), one configuration otherwise
// (noise: default parameters and a non-default shape).
std::vector<UnitConfig> configs_of(const UnitSpec& u) {
  std::vector<UnitConfig> v;
  if (u.uses_format) {
    for (const char* f : {"e5m10", "e7m16", "e8m23"}) v.push_back(UnitConfig{Format::parse(f), 0, {}, {}});
    // options that change the level chain (and so MaxUsefulStages)
    for (const auto& p : u.extra_params)
      if (p.name == "OptRecip") v.push_back(UnitConfig{Format::parse("e8m23"), 0, {{p.name, 1}}, {}});
  } else {
    v.push_back(UnitConfig{});
    UnitConfig c;
    c.params = {{"FracBits", 5}, {"IntBits", 3}, {"OutW", 12}};
    v.push_back(c);
  }
  return v;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& e : v) s += e + "\n";
  return s;
}

class RegistryRtl : public ::testing::TestWithParam<std::string> {};

// The registry's maximum useful Stages equals the RTL's MaxUsefulStages at three formats; at that
// Stages no register goes to the output, at one more exactly one does.
TEST_P(RegistryRtl, MaxUsefulStagesMatchRtl) {
  const UnitSpec& u = find_unit(GetParam());
  const auto bad = check_against_rtl(u, configs_of(u), rtl_dir());
  EXPECT_TRUE(bad.empty()) << joined(bad);
}

std::vector<std::string> unit_names_list() {
  std::vector<std::string> v;
  for (const auto& u : units()) v.push_back(u.name);
  return v;
}

// Every registered unit, read from the registry itself (a new unit is checked without an edit here).
INSTANTIATE_TEST_SUITE_P(Units, RegistryRtl, ::testing::ValuesIn(unit_names_list()),
                         [](const auto& info) { return info.param; });

// Permanent negative test: a registry entry off by one (either way) is reported, naming the unit
// and the format.
// The texture unit's useful maximum is its noise units' (ru_texture's MaxUsefulStages is matched to
// its registry entry above, the noise units' to theirs: this closes the chain).
TEST(Registry, TextureMaximumIsTheNoiseUnits) {
  const UnitSpec& t = find_unit("texture");
  for (const char* n : {"noise", "noise_trunc"}) EXPECT_EQ(t.max_stages(UnitConfig{}), find_unit(n).max_stages(UnitConfig{})) << n;
  // its smallest latency: one group + Stages + RootStages (what tb/texture's timing reference checks)
  UnitConfig c;
  c.stages = 4;
  EXPECT_EQ(t.latency(c), 1 + 4 + 2);
  c.params["RootStages"] = 0;
  EXPECT_EQ(t.latency(c), 5);
  EXPECT_EQ(find_unit("noise_trunc").latency(c), 4);
}

// The texture unit the renderer and the chip model compute (render::texture_config) is the one the
// registry's defaults build and the chip's area row measures (`rayunits trax areas --units texture`
// synthesizes the defaults): every field equal. A planted difference is seen.
TEST(Registry, TextureDefaultsAreTheRenderersUnit) {
  auto same = [](const ru::noise::TextureConfig& a, const ru::noise::TextureConfig& b) {
    return a.noise.frac_bits == b.noise.frac_bits && a.noise.int_bits == b.noise.int_bits &&
           a.noise.out_w == b.noise.out_w && a.noise.datapath == b.noise.datapath && a.octaves == b.octaves &&
           a.lac_shift == b.lac_shift && a.gain_shift == b.gain_shift && a.out_frac == b.out_frac;
  };
  const ru::noise::TextureConfig r = ru::render::texture_config(ru::render::NoiseMode::FixedTrunc);
  EXPECT_TRUE(same(models::texture_config(UnitConfig{}), r));
  UnitConfig planted;
  planted.params["OutF"] = 13;
  EXPECT_FALSE(same(models::texture_config(planted), r));
}

// The noise units' FracBits range in the registry is the model's (which mirrors the RTL's elaboration
// check, exercised at both ends by the lint configurations): every value inside is accepted, one
// past either end is rejected (the truncated datapath's table limits it to 12).
TEST(Registry, NoiseFracBitsRangeIsTheModels) {
  for (const char* name : {"noise", "noise_trunc"}) {
    const UnitSpec& u = find_unit(name);
    const auto it = std::find_if(u.extra_params.begin(), u.extra_params.end(), [](const ExtraParam& p) { return p.name == "FracBits"; });
    ASSERT_NE(it, u.extra_params.end()) << name;
    auto config = [&](long long b) {
      ru::noise::FixedConfig c{static_cast<int>(b), 8, 10};
      if (std::string(name) == "noise_trunc") c.datapath = ru::noise::NoiseDatapath::kTrunc;
      return c;
    };
    for (long long b = it->lo; b <= it->hi; ++b) EXPECT_NO_THROW(ru::noise::FixedNoise{config(b)}) << name << " " << b;
    EXPECT_THROW(ru::noise::FixedNoise{config(it->lo - 1)}, std::invalid_argument) << name;
    EXPECT_THROW(ru::noise::FixedNoise{config(it->hi + 1)}, std::invalid_argument) << name;
  }
}

TEST(Registry, OffByOneRegistryIsCaught) {
  for (const char* name : {"fp_add", "fp_mul", "noise"}) {
    for (const char* delta : {"-1", "+1"}) {
      UnitSpec u = find_unit(name);
      u.max_stages_expr = "(" + u.max_stages_expr + ")" + delta;
      std::vector<UnitConfig> cfgs = {configs_of(u).front()};
      if (u.uses_format) cfgs = {UnitConfig{Format::parse("e8m23"), 0, {}, {}}};
      const auto bad = check_against_rtl(u, cfgs, rtl_dir());
      ASSERT_FALSE(bad.empty()) << name << delta;
      const std::string want = u.uses_format ? std::string(name) + " e8m23" : std::string(name);
      EXPECT_EQ(bad.front().rfind(want + ":", 0), 0u) << bad.front();
      EXPECT_NE(bad.front().find("MaxUsefulStages"), std::string::npos) << bad.front();
    }
  }
}

// A unit whose RTL lacks the localparams is reported, not silently accepted.
TEST(Registry, MissingLocalparamIsReported) {
  UnitSpec u = find_unit("fp_add");
  u.top = "ru_lzc";  // a building block: no MaxUsefulStages
  u.filelist = "ru_fp_add.f";
  u.params = {};
  const auto bad = check_against_rtl(u, {UnitConfig{Format::parse("e5m10"), 0, {}, {}}}, rtl_dir());
  ASSERT_EQ(bad.size(), 1u) << joined(bad);
  EXPECT_NE(bad[0].find("no localparam MaxUsefulStages"), std::string::npos) << bad[0];
}

// model/data/registry.json (read by CMake at configure time) is what `rayunits registry --json`
// writes today. Regenerate with: build/model/cli/rayunits registry --json model/data/registry.json
TEST(Registry, JsonIsCurrent) {
  const std::string path = std::string(RU_SOURCE_DIR) + "/model/data/registry.json";
  EXPECT_EQ(slurp(path), registry_json(units()))
      << path << " is stale: run `rayunits registry --json model/data/registry.json`";
  // ... and the comparison sees a planted change.
  std::vector<UnitSpec> planted = units();
  planted[1].ports[3].width = "W+1";
  EXPECT_NE(slurp(path), registry_json(planted));
}

// rtl/README.md's "useful max Stages" table (the documentation) agrees with the registry: the
// table is parsed, not copied here.
TEST(Registry, RtlReadmeTableAgrees) {
  const std::string md = slurp(rtl_dir() + "/README.md");
  auto row = [&](const std::string& head) {
    const std::regex re("\\| " + head + " \\|([^\\n]*)\\|\\s*\\n");
    std::smatch m;
    EXPECT_TRUE(std::regex_search(md, m, re)) << "row '" << head << "' not found in rtl/README.md";
    std::vector<std::string> cells;
    std::string s = m[1].str(), cell;
    std::stringstream ss(s);
    while (std::getline(ss, cell, '|')) {
      cell.erase(0, cell.find_first_not_of(' '));
      cell.erase(cell.find_last_not_of(' ') + 1);
      cells.push_back(cell);
    }
    return cells;
  };
  const auto fmts = row("format");
  const auto maxs = row("max Stages mul / div / dot3");
  const auto sqrts = row("max Stages sqrt");
  const auto fmas = row("max Stages fma");
  ASSERT_EQ(fmts.size(), maxs.size());
  ASSERT_EQ(fmts.size(), sqrts.size());
  ASSERT_EQ(fmts.size(), fmas.size());
  ASSERT_GE(fmts.size(), 3u);
  for (size_t i = 0; i < fmts.size(); ++i) {
    SCOPED_TRACE(fmts[i]);
    const UnitConfig c{Format::parse(fmts[i]), 0, {}, {}};
    int mul = -1, div = -1, dot3 = -1;
    ASSERT_EQ(std::sscanf(maxs[i].c_str(), "%d / %d / %d", &mul, &div, &dot3), 3) << maxs[i];
    EXPECT_EQ(find_unit("fp_mul").max_stages(c), mul);
    EXPECT_EQ(find_unit("fp_div").max_stages(c), div);
    EXPECT_EQ(find_unit("fp_dot3").max_stages(c), dot3);
    EXPECT_EQ(find_unit("fp_sqrt").max_stages(c), std::stoi(sqrts[i])) << sqrts[i];
    EXPECT_EQ(find_unit("fp_fma").max_stages(c), std::stoi(fmas[i])) << fmas[i];
  }
  // The units table: `| `ru_fp_add`  | ... | 5 |`.
  for (const char* name : {"fp_add", "fp_cmp", "fp_cvt"}) {
    const std::regex re("\\| `ru_" + std::string(name) + "` *\\|[^\\n]*\\| *([0-9]+) *\\|");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(md, m, re)) << name;
    EXPECT_EQ(find_unit(name).max_stages(UnitConfig{Format::parse("e8m23"), 0, {}, {}}), std::stoi(m[1].str()))
        << name;
  }
}

// The intersection and noise units' table of rtl/README.md ("| unit | useful max `Stages` | e2m1 |
// ..."): every number is the registry's maximum for that format (and the row's options), so the
// table is checked, not copied. Rows: "| `ru_<unit>` [`Opt=V`] (levels) | expr | n | n | ... |".
TEST(Registry, RtlReadmeLevelChainTableAgrees) {
  const std::string md = slurp(rtl_dir() + "/README.md");
  std::istringstream in(md);
  std::vector<std::string> fmts;
  size_t rows = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| unit | useful max `Stages` |", 0) == 0) {
      std::smatch m;
      for (std::regex re(R"((e\d+m\d+))"); std::regex_search(line, m, re); line = m.suffix()) fmts.push_back(m[1]);
      continue;
    }
    std::smatch m;
    if (fmts.empty() || !std::regex_search(line, m, std::regex(R"(^\| `ru_(ray_\w+)`( `(\w+)=(\d+)`)? \([^)]*\) \|[^|]*\|(.*)\|\s*$)")))
      continue;
    const UnitSpec& u = find_unit(m[1].str());
    std::vector<int> vals;  // -1: "—", a format the unit does not take
    std::stringstream cells(m[5].str());
    for (std::string c; std::getline(cells, c, '|');)
      vals.push_back(c.find_first_of("0123456789") == std::string::npos ? -1 : std::stoi(c));
    ASSERT_EQ(vals.size(), fmts.size()) << line;
    for (size_t i = 0; i < fmts.size(); ++i) {
      UnitConfig c{Format::parse(fmts[i]), 0, {}, {}};
      if (m[2].matched) c.params[m[3].str()] = std::stoll(m[4].str());
      if (vals[i] < 0) {
        EXPECT_THROW(check_config(u, c), SynthError) << line << ": '—' at " << fmts[i] << ", a format it takes";
        continue;
      }
      EXPECT_EQ(u.max_stages(c), vals[i]) << line << " at " << fmts[i];
    }
    ++rows;
  }
  EXPECT_EQ(fmts.size(), 8u);
  EXPECT_EQ(rows, 5u) << "ray_box, ray_tri_robust, ray_tri_robust OptRecip=1, ray_tri_mt, ray_tri_exact";
}

// README.md lists the fast matrix's one-past-the-maximum Stages at e8m23 ("add 6, mul 12, ...");
// those numbers must be the registry's maximum + 1 (the registry is checked against the RTL above).
TEST(Registry, ReadmeOnePastTheMaximumAgrees) {
  const std::string md = slurp(std::string(RU_SOURCE_DIR) + "/README.md");
  std::string text;
  {
    const std::regex re("one past it, so the output-register path is covered: ([^)]*)\\)");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(md, m, re)) << "the fast-matrix sentence is not in README.md";
    text = m[1].str();
  }
  const std::map<std::string, std::string> unit_of = {
      {"add", "fp_add"}, {"mul", "fp_mul"},   {"div", "fp_div"},   {"sqrt", "fp_sqrt"}, {"fma", "fp_fma"}, {"cmp", "fp_cmp"},
      {"dot3", "fp_dot3"}, {"dot3_fused", "fp_dot3_fused"}, {"cvt", "fp_cvt"}, {"ray_box", "ray_box"}, {"ray_tri_robust", "ray_tri_robust"},
      {"ray_tri_mt", "ray_tri_mt"}, {"noise", "noise"}, {"noise_trunc", "noise_trunc"}, {"int_alu", "int_alu"},
      {"branch", "branch"}};
  // the units emitted from the datapath IR: their fast matrix is one past the maximum at e5m10
  {
    const std::regex re("at e5m10, one past their maximum: dp_ray_tri_robust ([0-9]+), dp_ray_tri_mt ([0-9]+)\\)");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(md, m, re)) << "the dp units' sentence is not in README.md";
    const UnitConfig c{Format::parse("e5m10"), 0, {}, {}};
    EXPECT_EQ(std::stoi(m[1].str()), find_unit("dp_ray_tri_robust").max_stages(c) + 1);
    EXPECT_EQ(std::stoi(m[2].str()), find_unit("dp_ray_tri_mt").max_stages(c) + 1);
    text = text.substr(0, text.find("; the units emitted"));
  }
  const std::regex item("([a-z_0-9]+)\\s+([0-9]+)");
  int seen = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), item); it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[1].str();
    ASSERT_TRUE(unit_of.count(name)) << "unknown unit '" << name << "' in README: " << text;
    const UnitSpec& u = find_unit(unit_of.at(name));
    UnitConfig c;
    if (u.uses_format) c.fmt = Format::parse("e8m23");
    EXPECT_EQ(std::stoi((*it)[2].str()), u.max_stages(c) + 1) << name;
    ++seen;
  }
  // + the two dp units above, + ray_tri_exact, whose fast matrix is Stages 2, + texture (Stages 4
  // and 1; the README says so)
  EXPECT_EQ(seen + 4, static_cast<int>(units().size())) << text;
  EXPECT_NE(md.find("ray_tri_exact at e5m10 Stages 2 and texture at Stages 4 and 1"), std::string::npos);
  EXPECT_EQ(find_unit("ray_tri_exact").tests, std::vector<std::string>{"e5m10:s2:selftest"});
  const std::vector<std::string>& tt = find_unit("texture").tests;
  ASSERT_EQ(tt.size(), 2u);
  EXPECT_EQ(tt[0].rfind("s4:", 0), 0u);
  EXPECT_EQ(tt[1].rfind("s1:", 0), 0u);
}

TEST(Registry, ExpressionsEvaluate) {
  const UnitSpec& mul = find_unit("fp_mul");
  const UnitConfig c{Format::parse("e8m23"), 0, {}, {}};
  EXPECT_EQ(eval_expr("W", mul, c), 32);
  EXPECT_EQ(eval_expr("3*W", mul, c), 96);
  EXPECT_EQ(eval_expr("L+4", mul, c), 11);  // csa_levels(24) = 7
  EXPECT_EQ(eval_expr("2*(E+M)-1", mul, c), 61);
  EXPECT_THROW(eval_expr("FracBits", mul, c), SynthError);  // not a parameter of fp_mul
  EXPECT_THROW(eval_expr("W+", mul, c), SynthError);
  EXPECT_THROW(eval_expr("(W", mul, c), SynthError);
  EXPECT_EQ(eval_expr("max(W, 40)", mul, c), 40);
  EXPECT_EQ(eval_expr("max(max(W, 2*M), E) + 1", mul, c), 47);
  EXPECT_THROW(eval_expr("max(W)", mul, c), SynthError);
  EXPECT_THROW(eval_expr("max W", mul, c), SynthError);
  const UnitSpec& noise = find_unit("noise");
  UnitConfig n;
  n.params["FracBits"] = 12;
  EXPECT_EQ(eval_expr("FracBits+IntBits", noise, n), 20);
  EXPECT_THROW(eval_expr("W", noise, n), SynthError);  // the noise unit has no format
  EXPECT_EQ(csa_levels(24), 7);
  EXPECT_EQ(csa_levels(2), 0);
}

}  // namespace
