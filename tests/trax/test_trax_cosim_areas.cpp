// TRaX model: RTL-derived latencies, the area table, the issue observer of the co-simulation
// (hand-computed schedule, operand records against the golden models), study workloads.
#include <gtest/gtest.h>
#include <unistd.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rayunits/noise/fixed.hpp"
#include "rayunits/noise/texture.hpp"
#include "rayunits/render/render.hpp"
#include "rayunits/num/fp.hpp"
#include "rayunits/scene/scene.hpp"
#include "rayunits/synth/cell.hpp"
#include "rayunits/trax/studies.hpp"
#include "rayunits/trax/cosim.hpp"
#include "rayunits/trax/trax.hpp"
#include "rayunits/units/ray_box.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "../common/files.hpp"
#include "../common/run_rayunits.hpp"
#include "../common/temp_dir.hpp"

using namespace ru::trax;

// Box: add + mul + 3 cmp; robust: 4 add + 2 mul + div + cmp; mt: 5 add + 3 mul + div + cmp.
// Defaults 2, 2, 16, 1: box 2+2+3 = 7, robust 8+4+16+1 = 29, mt 10+6+16+1 = 33 (the Stages
// tb/trax builds); with add 3, mul 4, div 10, cmp 2: box 3+4+6 = 13, robust 12+8+10+2 = 32,
// mt 15+12+10+2 = 39.
TEST(TraxRtl, LatencyFollowsTheUnitsFpLevels) {
  Config c = default_config();
  EXPECT_EQ(c.unit(Unit::Box).latency, kLatencyRtl);
  EXPECT_EQ(rtl_latency(c, Unit::Box), 7);
  EXPECT_EQ(rtl_latency(c, Unit::Tri), 29);
  EXPECT_EQ(rtl_latency(c, Unit::Noise), 4);
  c.tri = "mt";
  EXPECT_EQ(rtl_latency(c, Unit::Tri), 33);
  c.unit(Unit::FpAdd).latency = 3;
  c.unit(Unit::FpMul).latency = 4;
  c.unit(Unit::FpDiv).latency = 10;
  c.unit(Unit::FpCmp).latency = 2;
  EXPECT_EQ(rtl_latency(c, Unit::Box), 13);
  EXPECT_EQ(rtl_latency(c, Unit::Tri), 39);
  c.tri = "robust";
  EXPECT_EQ(rtl_latency(c, Unit::Tri), 32);
  const Config r = resolve_config(c);
  EXPECT_EQ(r.unit(Unit::Box).latency, 13);
  EXPECT_EQ(r.unit(Unit::Tri).latency, 32);
  // an explicit latency is kept
  c.unit(Unit::Box).latency = 5;
  EXPECT_EQ(resolve_config(c).unit(Unit::Box).latency, 5);
}

namespace {
// A private area table (RU_TRAX_AREAS) for the duration of a test.
struct AreaTable {
  std::string path;
  explicit AreaTable(const std::string& name, const std::string& json) {
    // per process: ctest -j runs these tests as concurrent processes with the same names
    path = ::testing::TempDir() + "/" + std::to_string(::getpid()) + "_" + name;
    std::ofstream(path) << json;
    setenv("RU_TRAX_AREAS", path.c_str(), 1);
  }
  ~AreaTable() {
    unsetenv("RU_TRAX_AREAS");
    std::remove(path.c_str());
  }
};
// A cell-flow row as `rayunits trax areas` writes it (the fields the model reads).
std::string row(const char* unit, const char* fmt, int stages, double area, double fmax = 100) {
  const bool noise = std::strncmp(unit, "noise", 5) == 0 || std::strcmp(unit, "texture") == 0 ||
                     std::strcmp(unit, "int_alu") == 0 || std::strcmp(unit, "branch") == 0;  // no format
  return std::string("{\"unit\": \"") + unit + "\", \"format\": " + (noise ? "null" : "\"" + std::string(fmt) + "\"") +
         ", \"stages\": " + std::to_string(stages) + ", \"flow\": \"osu018\", \"area_um2\": " + std::to_string(area) +
         ", \"fmax_mhz\": " + std::to_string(fmax) + ", \"command\": \"rayunits synth " + unit +
         (noise ? std::string() : " --format " + std::string(fmt)) + " --stages " + std::to_string(stages) +
         " --flow osu018 --clock 1000000ps --timeout 1800 --json -\"}";
}
// NAND2X1 = 10 um2 in the test tables: conv 1500 NAND2-eq -> 15000 um2.
std::string table_json(const std::string& rows) {
  return "{\"nand2_cell\": {\"cell\": \"NAND2X1\", \"area_um2\": 10, \"liberty\": \"test.lib\"}, \"rows\": [" + rows +
         "]}";
}
std::string fp_rows() {
  return row("fp_add", "e8m23", 2, 100, 200) + ", " + row("fp_mul", "e8m23", 2, 1000, 150) + ", " +
         row("fp_div", "e8m23", 16, 5000, 300) + ", " + row("fp_sqrt", "e8m23", 16, 2500, 320) + ", " +
         row("fp_cmp", "e8m23", 1, 10, 400) + ", " + row("noise_trunc", "-", 4, 777, 120) + ", " +
         row("noise", "-", 4, 1234, 110) + ", " + row("texture", "-", 4, 4321, 150) + ", " +
         row("fp_cvt", "e8m23", 1, 60, 500) + ", " + row("int_alu", "-", 1, 40, 600) + ", " +
         row("branch", "-", 1, 20, 700);
}
std::string resolve_error(const std::string& json, const Config& c = default_config()) {
  AreaTable t("areas_err.json", json);
  try {
    resolve_config(c);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// Composition and scaling by hand: add 100, mul 1000, div 5000, cmp 10 um2 (e8m23, Stages 2 2 16 1):
//   box = 6*100 + 6*1000 + 7*10 = 6670; robust = 43*100 + 39*1000 + 3*5000 + 20*10 = 58500;
//   mt = 24*100 + 27*1000 + 5000 + 5*10 = 34450. e5m10 from the e8m23 rows: add, cmp by width
//   16/32 -> 50, 5; mul by (11/24)^2 -> 210.0694..; div: Stages 14 (e5m10's maximum) from the
//   Stages-16 row (closest), (11/24)^2 -> 1050.347..
// Clocks (Fmax add 200, mul 150, div 300, cmp 400, noise 120 MHz): box composed = its slowest FP
//   part min(200, 150, 400) = 150, tri min(200, 150, 300, 400) = 150 (estimates); the "sta" chip
//   clock over every configured unit = noise's 120.
TEST(TraxAreas, MeasuredComposedAndScaledRows) {
  AreaTable t("areas_a.json", table_json(fp_rows()));
  Config c = default_config();
  std::vector<AreaSource> src;
  Config r = resolve_config(c, &src);
  EXPECT_EQ(r.unit(Unit::FpAdd).area, 100);
  EXPECT_EQ(r.unit(Unit::FpSqrt).area, 2500);  // its own row (fp_sqrt has RTL), not fp_div's
  EXPECT_EQ(r.unit(Unit::Noise).area, 777);  // noise_trunc's row (chip.noise = fixed-trunc)
  EXPECT_EQ(r.unit(Unit::Box).area, 6670);
  EXPECT_EQ(r.unit(Unit::Tri).area, 58500);
  EXPECT_EQ(r.unit(Unit::Conv).area, 60);  // ru_fp_cvt's row (issue 16; int, branch likewise)
  EXPECT_EQ(r.unit(Unit::Int).area, 40);
  EXPECT_EQ(r.unit(Unit::Branch).area, 20);
  EXPECT_EQ(r.unit(Unit::Box).fmax_mhz, 150);
  EXPECT_EQ(r.unit(Unit::Tri).fmax_mhz, 150);
  EXPECT_EQ(r.unit(Unit::Conv).fmax_mhz, 500);
  EXPECT_EQ(r.clock_mhz, 120);
  EXPECT_EQ(r.nand2_um2, 10);
  ASSERT_EQ(src.size(), size_t(kUnits));
  EXPECT_EQ(src[int(Unit::Box)].how, "composed");
  EXPECT_EQ(src[int(Unit::FpAdd)].how, "measured");
  EXPECT_EQ(src[int(Unit::Conv)].how, "measured");
  EXPECT_EQ(src[int(Unit::Int)].unit, "int_alu");
  {  // an area_nand2 estimate is still accepted: NAND2-eq x NAND2X1 (10 um2 here), not timed
    Config e = c;
    e.unit(Unit::Conv).area = kAreaNand2;
    e.unit(Unit::Conv).area_nand2 = 1500;
    std::vector<AreaSource> es;
    const Config er = resolve_config(e, &es);
    EXPECT_EQ(er.unit(Unit::Conv).area, 15000);
    EXPECT_EQ(er.unit(Unit::Conv).fmax_mhz, 0);
    EXPECT_EQ(es[int(Unit::Conv)].how, "estimate");
    EXPECT_NE(es[int(Unit::Conv)].detail.find("1500 NAND2-eq"), std::string::npos) << es[int(Unit::Conv)].detail;
  }
  c.tri = "mt";
  EXPECT_EQ(resolve_config(c).unit(Unit::Tri).area, 34450);
  c.format = "e5m10";
  r = resolve_config(c);
  EXPECT_DOUBLE_EQ(r.unit(Unit::FpAdd).area, 50);
  EXPECT_DOUBLE_EQ(r.unit(Unit::FpCmp).area, 5);
  EXPECT_DOUBLE_EQ(r.unit(Unit::Conv).area, 30);  // scaled by width from the e8m23 row
  EXPECT_DOUBLE_EQ(r.unit(Unit::Int).area, 40);   // no format: the same row
  EXPECT_NEAR(r.unit(Unit::FpMul).area, 1000.0 * 121 / 576, 1e-9);
  EXPECT_NEAR(r.unit(Unit::FpDiv).area, 5000.0 * 121 / 576, 1e-9);
  EXPECT_NEAR(r.unit(Unit::FpSqrt).area, 2500.0 * 121 / 576, 1e-9);  // e5m10's maximum 13, from Stages 16
  EXPECT_NEAR(r.unit(Unit::Box).area, 6 * 50 + 6 * 1000.0 * 121 / 576 + 7 * 5, 1e-9);  // plain composition
  c.clock_mhz = 500;  // a configured clock is kept
  EXPECT_EQ(resolve_config(c).clock_mhz, 500);
}

// chip.noise picks the noise unit's row: fixed-trunc (the default) ru_noise_trunc's, fixed
// ru_noise's, float none (no unit, not charged); a missing row is one line naming the unit.
TEST(TraxAreas, ChipNoiseSelectsItsUnitsRow) {
  AreaTable t("areas_n.json", table_json(fp_rows()));
  Config c = default_config();
  EXPECT_EQ(c.noise, "fixed-trunc");
  std::vector<AreaSource> src;
  EXPECT_EQ(resolve_config(c, &src).unit(Unit::Noise).area, 777);
  EXPECT_EQ(src[int(Unit::Noise)].unit, "noise_trunc");
  c.noise = "fixed";
  const Config f = resolve_config(c, &src);
  EXPECT_EQ(f.unit(Unit::Noise).area, 1234);
  EXPECT_EQ(f.clock_mhz, 110);  // ru_noise's Fmax is the slowest
  EXPECT_EQ(src[int(Unit::Noise)].unit, "noise");
  const std::string m = resolve_error(table_json(row("fp_add", "e8m23", 2, 100, 200) + ", " + row("fp_mul", "e8m23", 2, 1000, 150) + ", " +
                                                 row("fp_div", "e8m23", 16, 5000, 300) + ", " + row("fp_sqrt", "e8m23", 16, 2500, 320) + ", " +
                                                 row("fp_cmp", "e8m23", 1, 10, 400) + ", " + row("fp_cvt", "e8m23", 1, 60, 500) + ", " +
                                                 row("int_alu", "-", 1, 40, 600) + ", " + row("branch", "-", 1, 20, 700) + ", " +
                                                 row("noise", "-", 4, 1234, 110)));
  EXPECT_NE(m.find("no row for noise_trunc Stages 4"), std::string::npos) << m;
  EXPECT_NE(m.find("--units noise_trunc"), std::string::npos) << m;
}

// A measured box row (e8m23, Stages 7) = 2 x its composition 6670, Fmax 90: another format's box
// is its composition scaled by the same factor 2; its Fmax 90 x (slowest FP part e5m10 /
// e8m23) = 90 x 150/150 (the e5m10 parts are scaled from the e8m23 rows, Fmax kept).
TEST(TraxAreas, CompositionScaledToAMeasuredRow) {
  AreaTable t("areas_c.json", table_json(fp_rows() + ", " + row("ray_box", "e8m23", 7, 13340, 90)));
  Config c = default_config();
  EXPECT_EQ(resolve_config(c).unit(Unit::Box).area, 13340);
  EXPECT_EQ(resolve_config(c).unit(Unit::Box).fmax_mhz, 90);
  EXPECT_EQ(resolve_config(c).clock_mhz, 90);
  c.format = "e5m10";
  std::vector<AreaSource> src;
  const Config r = resolve_config(c, &src);
  EXPECT_NEAR(r.unit(Unit::Box).area, 2 * (6 * 50 + 6 * 1000.0 * 121 / 576 + 7 * 5), 1e-9);
  EXPECT_NEAR(r.unit(Unit::Box).fmax_mhz, 90, 1e-9);
  EXPECT_EQ(src[int(Unit::Box)].how, "composed, scaled");
  EXPECT_NE(src[int(Unit::Box)].fmax_how.find("estimate"), std::string::npos);
}

TEST(TraxAreas, MissingRowIsOneLineNamingIt) {
  const std::string m = resolve_error(table_json(row("fp_add", "e8m23", 2, 100)));
  EXPECT_NE(m.find("no row for fp_mul e8m23 Stages 2"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos);
  AreaTable t("areas_b.json", table_json(row("fp_add", "e8m23", 2, 100)));
  Config c = default_config();
  for (int u = 0; u < kUnits; ++u) c.units[u].area = 1;  // numbers: no rows needed (the NAND2X1 area is)
  c.clock_mhz = 1000;
  EXPECT_NO_THROW(resolve_config(c));
  c.clock_mhz = kClockSta;  // but no unit has an STA clock then
  try {
    resolve_config(c);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("chip.clock_mhz = \"sta\": no configured unit has an STA clock"),
              std::string::npos)
        << e.what();
  }
}

// Planted errors in the table: each is one line naming the row and what is wrong.
TEST(TraxAreas, MalformedTableIsOneLineNamingTheRow) {
  auto one_line = [](const std::string& m, const std::string& want) {
    EXPECT_NE(m.find(want), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.rfind("trax area table ", 0), 0u) << m;
  };
  const std::string good = fp_rows();
  // a row whose unit is not what its command synthesized (a hand edit)
  std::string wrong_unit = row("fp_mul", "e8m23", 2, 1000);
  wrong_unit.replace(wrong_unit.find("\"unit\": \"fp_mul\""), 16, "\"unit\": \"fp_add\"");
  one_line(resolve_error(table_json(good + ", " + wrong_unit)),
           "row 12 (fp_add e8m23 Stages 2): command synthesizes 'fp_mul', the row says unit 'fp_add'");
  // a row whose format differs from its command's
  std::string wrong_fmt = row("fp_add", "e7m16", 2, 100);
  wrong_fmt.replace(wrong_fmt.find("\"format\": \"e7m16\""), 17, "\"format\": \"e8m23\"");
  one_line(resolve_error(table_json(wrong_fmt + ", " + good)),
           "row 1 (fp_add e8m23 Stages 2): command has --format e7m16, the row says format e8m23");
  std::string wrong_st = row("fp_add", "e8m23", 3, 100);
  wrong_st.replace(wrong_st.find("\"stages\": 3"), 11, "\"stages\": 2");
  one_line(resolve_error(table_json(wrong_st + ", " + good)), "command has --stages 3, the row says stages 2");
  // a cell-flow row without its area / clock
  std::string no_area = row("fp_add", "e8m23", 2, 100);
  no_area.replace(no_area.find("\"area_um2\""), 10, "\"area_xx\"");
  one_line(resolve_error(table_json(no_area)), "row 1 (fp_add e8m23 Stages 2): no number \"area_um2\" > 0");
  one_line(resolve_error(table_json(row("fp_add", "e8m23", 2, 100, 0))), "no number \"fmax_mhz\" > 0");
  one_line(resolve_error(table_json(row("fp_dot3", "e8m23", 2, 100))), "unit 'fp_dot3' is not a TRaX unit");
  one_line(resolve_error(table_json(good + ", " + row("fp_add", "e8m23", 2, 100))),
           "row 12: a second row for fp_add|e8m23|2 in flow osu018");
  one_line(resolve_error(table_json(row("fp_add", "e9m99", 2, 100))), "row 1 (fp_add e9m99 Stages 2): format:");
  one_line(resolve_error("{\"rows\": [" + good + "]}"), "no \"nand2_cell\"");
  one_line(resolve_error("{\"rows\": [" + good), "not JSON");
  one_line(resolve_error("{\"rowz\": []}"), "no \"rows\" array");
  setenv("RU_TRAX_AREAS", "/nonexistent/areas.json", 1);
  try {
    resolve_config(default_config());
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    one_line(e.what(), "trax area table /nonexistent/areas.json: cannot open the file");
  }
  unsetenv("RU_TRAX_AREAS");
}

// The checked-in table (model/data/trax/areas.json): every row valid and from the cell flow, the
// rows the default chip needs measured for every format of the formats study (FP units, box) and
// at e8m23 (both triangle units, both noise units), the NAND2X1 area equal to the liberty's (read from it,
// when the liberty is installed), and the default chip's clock = its slowest unit's STA Fmax.
TEST(TraxAreas, CheckedInTableIsComplete) {
  const std::string path = std::string(RU_SOURCE_DIR) + "/model/data/trax/areas.json";
  setenv("RU_TRAX_AREAS", path.c_str(), 1);
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in);
  for (const auto& r : j.at("rows")) {
    EXPECT_EQ(r.at("flow"), "osu018") << r.at("command");
    EXPECT_EQ(r.at("target_clock_ps"), 1000000.0) << r.at("command");  // the documented area-oriented mapping
  }
  const std::string lib = j.at("nand2_cell").at("liberty").get<std::string>();
  if (std::ifstream(lib)) {
    const auto parsed = ru::synth::parse_liberty("osu018", lib);
    EXPECT_EQ(j.at("nand2_cell").at("area_um2").get<double>(), parsed.area.at("NAND2X1"));
  }
  std::vector<std::string> fmts = kDefaultFormats;
  fmts.push_back("e5m6");
  fmts.push_back("e7m14");
  for (const std::string& f : fmts) {
    Config c = default_config();
    c.format = f;
    c.fma = true;  // the fp_fma unit too (chip.fma)
    std::vector<AreaSource> src;
    const Config r = resolve_config(c, &src);
    // every unit but the triangle unit (composed at most formats) measured: no estimate left
    for (Unit u : {Unit::FpAdd, Unit::FpMul, Unit::FpDiv, Unit::FpSqrt, Unit::FpCmp, Unit::FpFma, Unit::Conv,
                   Unit::Int, Unit::Branch, Unit::Box, Unit::Noise})
      EXPECT_EQ(src[int(u)].how, "measured") << f << " " << unit_name(u);
    EXPECT_GT(r.clock_mhz, 0) << f;
    c.fma = false;  // no fp_fma on the chip: no row needed, none charged
    const Config n = resolve_config(c, &src);
    EXPECT_EQ(n.unit(Unit::FpFma).area, 0) << f;
    EXPECT_EQ(src[int(Unit::FpFma)].how, "not used (chip.fma = false)") << f;
  }
  for (const char* tri : {"robust", "mt"}) {
    Config c = default_config();
    c.tri = tri;
    std::vector<AreaSource> src;
    const Config r = resolve_config(c, &src);
    double slowest = 0;
    for (Unit u : {Unit::FpAdd, Unit::FpMul, Unit::FpDiv, Unit::FpSqrt, Unit::FpCmp, Unit::Conv, Unit::Int,
                   Unit::Branch, Unit::Box, Unit::Tri, Unit::Noise}) {
      EXPECT_EQ(src[int(u)].how, "measured")
          << tri << " " << unit_name(u);
      EXPECT_GT(r.unit(u).fmax_mhz, 0);
      if (slowest == 0 || r.unit(u).fmax_mhz < slowest) slowest = r.unit(u).fmax_mhz;
    }
    EXPECT_EQ(r.clock_mhz, slowest) << tri;
  }
  {  // the baseline noise unit (chip.noise = fixed) is measured too
    Config c = default_config();
    c.noise = "fixed";
    std::vector<AreaSource> src;
    resolve_config(c, &src);
    EXPECT_EQ(src[int(Unit::Noise)].how, "measured");
    EXPECT_EQ(src[int(Unit::Noise)].unit, "noise");
  }
  unsetenv("RU_TRAX_AREAS");
}

// The planted error of the issue: the checked-in table with one row's format changed is refused.
TEST(TraxAreas, CheckedInTableWithAPlantedErrorIsRefused) {
  std::ifstream in(std::string(RU_SOURCE_DIR) + "/model/data/trax/areas.json");
  nlohmann::json j = nlohmann::json::parse(in);
  auto& rows = j.at("rows");
  size_t k = 0;
  while (k < rows.size() && !(rows[k].at("unit") == "fp_mul" && rows[k].at("format") == "e8m23")) ++k;
  ASSERT_LT(k, rows.size());
  rows[k]["format"] = "e7m16";  // e.g. a row copied under the wrong format
  const std::string m = resolve_error(j.dump(1));
  EXPECT_NE(m.find("row " + std::to_string(k + 1) + " (fp_mul e7m16 Stages 2): command has --format e8m23, the "
                   "row says format e7m16"),
            std::string::npos)
      << m;
  rows[k]["format"] = "e8m23";
  rows[k]["unit"] = "fp_add";  // the wrong unit
  EXPECT_NE(resolve_error(j.dump(1)).find("command synthesizes 'fp_mul', the row says unit 'fp_add'"),
            std::string::npos);
  rows[k]["unit"] = "fp_mul";
  EXPECT_EQ(resolve_error(j.dump(1)), "");  // restored: accepted
}

TEST(TraxConfig, RtlAndSynthKeywords) {
  auto msg = [](const std::string& text) -> std::string {
    try {
      parse_config(text, "t.toml");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(msg("[units.box]\nlatency = \"rtl\"\narea = \"synth\"\n"), "");
  EXPECT_EQ(parse_config("[units.tri]\nlatency = 12\n", "t").unit(Unit::Tri).latency, 12);
  EXPECT_NE(msg("[units.fp_add]\nlatency = \"rtl\"\n").find("key 'units.fp_add.latency'"), std::string::npos);
  EXPECT_EQ(msg("[units.conv]\narea = \"synth\"\n"), "");  // every unit has RTL since issue 16
  EXPECT_NE(msg("[units.conv]\nlatency = \"rtl\"\n").find("key 'units.conv.latency'"), std::string::npos);
  EXPECT_NE(msg("[units.box]\nlatency = \"fast\"\n").find("key 'units.box.latency'"), std::string::npos);
  // the chip clock: "sta" (default) or MHz; NAND2-eq estimates: area_nand2, not together with area
  EXPECT_EQ(default_config().clock_mhz, kClockSta);
  EXPECT_EQ(parse_config("[chip]\nclock_mhz = 250.0\n", "t").clock_mhz, 250);
  EXPECT_EQ(parse_config("[chip]\nclock_mhz = \"sta\"\n", "t").clock_mhz, kClockSta);
  EXPECT_NE(msg("[chip]\nclock_mhz = \"fast\"\n").find("key 'chip.clock_mhz'"), std::string::npos);
  const Config n = parse_config("[units.int]\narea_nand2 = 700.0\n", "t");
  EXPECT_EQ(n.unit(Unit::Int).area, kAreaNand2);
  EXPECT_EQ(n.unit(Unit::Int).area_nand2, 700);
  EXPECT_EQ(to_toml(parse_config(to_toml(n), "rt")), to_toml(n));
  EXPECT_NE(msg("[units.int]\narea_nand2 = 700.0\narea = 5.0\n").find("not both"), std::string::npos);
  EXPECT_NE(msg("[units.int]\narea_nand2 = -1.0\n").find("key 'units.int.area_nand2'"), std::string::npos);
}

// ------------------------------------------------------------------ the issue observer
namespace {
struct Seen {
  uint64_t cycle;
  int tp, slot;
  uint64_t index;
};
struct Recorder : IssueObserver {
  std::vector<Seen> v;
  void issue(const UnitIssue& u) override { v.push_back({u.cycle, u.tp, u.slot, u.index}); }
};
}  // namespace

// 1 TM, 2 TPs, box latency 4, 2 items; each item: 3 independent BOX ops (no sources).
//   cycle 0: TP0 atomic (item 0).  cycle 1: TP1 atomic (item 1; the atomic unit is chip-wide,
//   one per cycle); TP0 box #0.  cycle 2 (priority TP0): TP0 box #1, TP1 box #0.
//   count 1: cycle 2 TP0 slot 0, TP1 contention; cycle 3 (priority TP1): TP1 box #0 slot 0,
//   TP0 waits; cycle 4 (TP0 first): TP0 box #2, TP1 waits; cycle 5: TP1 box #1; cycle 6: TP1 box #2.
//   count 2: cycle 2: TP0 #1 slot 0, TP1 #0 slot 1; cycle 3 (TP1 first): TP1 #1 slot 0, TP0 #2 slot 1;
//   cycle 4: TP1 #2 slot 0.
TEST(TraxObserver, HandScheduleOfUnitIssues) {
  Config c = default_config();
  c.tms = 1;
  c.tps_per_tm = 2;
  c.unit(Unit::Box).latency = 4;
  auto work = [] {
    return FunctionWork(2, [](uint64_t, Thread& t) {
      for (int k = 0; k < 3; ++k) t.emit(Op::Box, {});
    });
  };
  c.unit(Unit::Box).count = 1;
  {
    Recorder rec;
    FunctionWork w = work();
    const SimStats s = simulate(c, w, false, &rec);
    const std::vector<Seen> want = {{1, 0, 0, 0}, {2, 0, 0, 1}, {3, 1, 0, 0}, {4, 0, 0, 2}, {5, 1, 0, 1}, {6, 1, 0, 2}};
    ASSERT_EQ(rec.v.size(), want.size());
    for (size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(rec.v[i].cycle, want[i].cycle) << i;
      EXPECT_EQ(rec.v[i].tp, want[i].tp) << i;
      EXPECT_EQ(rec.v[i].slot, want[i].slot) << i;
      EXPECT_EQ(rec.v[i].index, want[i].index) << i;
    }
    EXPECT_EQ(s.observed, 6u);
  }
  c.unit(Unit::Box).count = 2;
  {
    Recorder rec;
    FunctionWork w = work();
    simulate(c, w, false, &rec);
    const std::vector<Seen> want = {{1, 0, 0, 0}, {2, 0, 0, 1}, {2, 1, 1, 0}, {3, 1, 0, 1}, {3, 0, 1, 2}, {4, 1, 0, 2}};
    ASSERT_EQ(rec.v.size(), want.size());
    for (size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(rec.v[i].cycle, want[i].cycle) << i;
      EXPECT_EQ(rec.v[i].tp, want[i].tp) << i;
      EXPECT_EQ(rec.v[i].slot, want[i].slot) << i;
    }
  }
}

namespace {
// Recomputes every recorded BOX / TRI from its recorded inputs with the golden models and
// compares with the recorded outputs (the record layout the companion relies on).
struct Checker : IssueObserver {
  ru::num::Format fmt;
  bool mt = false, swap_box_planes = false, full_noise = false;
  uint64_t boxes = 0, tris = 0, noises = 0, textures = 0, bad = 0;
  void issue(const UnitIssue& u) override {
    using ru::num::Soft;
    ru::num::SoftScope scope(fmt);
    auto S = [&](int k) { return Soft::from_bits(u.data[k]); };
    auto V = [&](int k) { return ru::units::Vec3<Soft>{S(k), S(k + 1), S(k + 2)}; };
    if (u.op == Op::Box) {
      ++boxes;
      const auto r = swap_box_planes ? ru::units::ray_box(V(0), V(3), V(9), V(6), S(12), S(13))
                                     : ru::units::ray_box(V(0), V(3), V(6), V(9), S(12), S(13));
      if (uint64_t(r.hit) != u.data[14] || r.t_enter.bits != u.data[15] || r.t_exit.bits != u.data[16]) ++bad;
    } else if (u.op == Op::Tri) {
      ++tris;
      const auto r = mt ? ru::units::ray_tri_mt(V(0), V(3), V(6), V(9), V(12), S(15), S(16))
                        : ru::units::ray_tri_robust(V(0), V(3), V(6), V(9), V(12), S(15), S(16));
      if (uint64_t(r.hit) != u.data[17] || uint64_t(r.why) != u.data[18] || r.t.bits != u.data[19] ||
          r.beta.bits != u.data[20] || r.gamma.bits != u.data[21])
        ++bad;
    } else if (u.op == Op::Texture) {
      ++textures;
      static const ru::noise::FixedTexture tx{ru::render::texture_config(ru::render::NoiseMode::FixedTrunc)};
      const int w = tx.config().in_w();
      auto sx = [w](uint64_t v) { return static_cast<int64_t>(v << (64 - w)) >> (64 - w); };
      const int64_t v = tx.eval(static_cast<ru::noise::TextureMode>(u.data[3]), static_cast<int>(u.data[4]), sx(u.data[0]),
                                sx(u.data[1]), sx(u.data[2]));
      if ((static_cast<uint64_t>(v) & ((1ull << tx.config().out_w()) - 1)) != u.data[5]) ++bad;
    } else {
      ++noises;
      // the chip's default unit, ru_noise_trunc (chip.noise = fixed-trunc)
      static const ru::noise::FixedNoise trunc{ru::noise::default_config(ru::noise::NoiseDatapath::kTrunc)},
          full{ru::noise::default_config(ru::noise::NoiseDatapath::kFull)};
      const ru::noise::FixedNoise& fx = full_noise ? full : trunc;
      auto sx = [](uint64_t w) { return static_cast<int64_t>(w << 48) >> 48; };  // 16-bit words
      if ((static_cast<uint64_t>(fx.eval(sx(u.data[0]), sx(u.data[1]), sx(u.data[2]))) & 1023) != u.data[3]) ++bad;
    }
  }
};
}  // namespace

TEST(TraxObserver, OperandRecordsReproduceTheGoldenResults) {
  Config c = default_config();
  c.tms = 2;
  c.tps_per_tm = 8;
  c.format = "e6m12";
  const ru::scene::Scene s = ru::scene::make_scene("default");
  Checker k;
  k.fmt = ru::num::Format::parse("e6m12");
  RunOptions ro;
  ro.observer = &k;
  const TraxResult r = run_trax(s, c, 8, 8, ro);
  EXPECT_EQ(k.bad, 0u);
  EXPECT_EQ(k.boxes, r.box_tests);
  EXPECT_EQ(k.tris, r.tri_tests);
  EXPECT_EQ(k.noises, r.noise_evals);
  EXPECT_GT(k.noises, 0u);
  EXPECT_EQ(r.sim.observed, k.boxes + k.tris + k.noises);
  // A checker run over the same chip (or another configuration of it).
  auto checked = [&](Checker& x, const Config& cc) {
    x.fmt = k.fmt;
    ro.observer = &x;
    return run_trax(s, cc, 8, 8, ro);
  };
  // Planted error: the checker with the box planes swapped must disagree.
  Checker p;
  p.swap_box_planes = true;
  checked(p, c);
  EXPECT_GT(p.bad, 0u);
  // The NOISE records are ru_noise_trunc's (the default chip.noise): checked with ru_noise's
  // model they disagree; with chip.noise = fixed they are ru_noise's.
  Checker q;
  q.full_noise = true;
  checked(q, c);
  EXPECT_GT(q.bad, 0u);
  Checker f;
  f.full_noise = true;
  Config cf = c;
  cf.noise = "fixed";
  const TraxResult rf = checked(f, cf);
  EXPECT_EQ(f.bad, 0u);
  EXPECT_EQ(f.noises, rf.noise_evals);
  // chip.texture = "unit": the TEXTURE records are the texture unit's words and results
  Checker tk;
  Config ct = c;
  ct.texture = "unit";
  const TraxResult rt = checked(tk, ct);
  EXPECT_EQ(tk.bad, 0u);
  EXPECT_GT(tk.textures, 0u);
  EXPECT_EQ(tk.textures, rt.texture_evals);
  EXPECT_EQ(tk.noises, 0u);
}

TEST(TraxCosim, MissingCompanionIsOneLine) {
  cosim::Client cl("/nonexistent/tb_trax_cosim");
  try {
    cl.start(resolve_config(default_config()));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("is not built"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos);
  }
  EXPECT_EQ(cosim::header_line(resolve_config(default_config())),
            "rayunits-trax-cosim 1 format=e8m23 tms=4 box=plain:7:2 tri=robust:29:1 noise=fixed-trunc:4:1");
}

// ------------------------------------------------------------------ study workloads
TEST(TraxStudies, SoftwareNoiseAndRayWorkloads) {
  Config c = default_config();
  c.tms = 2;
  c.tps_per_tm = 8;
  const ru::scene::Scene s = ru::scene::make_scene("default");
  RunOptions ro;
  const TraxResult hw = run_trax(s, c, 8, 8, ro);
  ro.software_noise = true;
  const TraxResult sw = run_trax(s, c, 8, 8, ro);
  EXPECT_EQ(sw.image.rgb, hw.image.rgb);  // same values, other instructions
  EXPECT_EQ(sw.software_noise_evals, hw.noise_evals);
  EXPECT_EQ(sw.sim.unit_ops[static_cast<int>(Unit::Noise)], 0u);
  EXPECT_GT(sw.sim.instructions, hw.sim.instructions + 150 * hw.noise_evals);
  for (const auto& it : sw.area.items) EXPECT_EQ(it.name.find("noise"), std::string::npos);
  ro.software_noise = false;
  ro.workload = "primary";
  const TraxResult p = run_trax(s, c, 8, 8, ro);
  EXPECT_EQ(p.primary_rays, 64u);
  EXPECT_EQ(p.shadow_rays + p.bounce_rays, 0u);
  uint64_t hits = 0;
  for (size_t i = 0; i < p.image.rgb.size(); i += 3) hits += p.image.rgb[i] > 0;
  ro.workload = "shadow";
  const TraxResult sh = run_trax(s, c, 8, 8, ro);
  EXPECT_EQ(sh.shadow_rays, hits);
  ro.workload = "diffuse";
  const TraxResult d = run_trax(s, c, 8, 8, ro);
  EXPECT_EQ(d.bounce_rays, hits);
  EXPECT_GT(d.sim.cycles, p.sim.cycles);
  ro.workload = "bogus";
  EXPECT_THROW(run_trax(s, c, 8, 8, ro), std::invalid_argument);
}

// ---- `rayunits trax areas` itself (ctest label long: it runs the cell flow, ~5 s) ----
namespace {
struct Cli {
  int code;
  std::string out, err;
};
using ru::test::slurp;
Cli trax_areas(const std::string& args) {
  const std::string d = ::testing::TempDir();
  const std::string o = d + "/trax_areas.out", e = d + "/trax_areas.err";
  const std::string cmd = "nice -n 5 '" + std::string(RU_BINARY_DIR) + "/model/cli/rayunits' trax areas " + args +
                          " >'" + o + "' 2>'" + e + "'";
  const int st = std::system(cmd.c_str());
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, slurp(o), slurp(e)};
}
bool have_cell_flow() {
  return std::ifstream("/usr/share/qflow/tech/osu018/osu018_stdcells.lib").good() &&
         std::system("command -v sta >/dev/null 2>&1 && command -v yosys >/dev/null 2>&1") == 0;
}
}  // namespace

// Measures two small rows into a fresh table, resumes without re-measuring, reads the table into
// the model, and reproduces the checked-in rows of the same RTL (same rtl_hash) exactly.
TEST(LongTraxAreas, MeasuresResumesAndReproducesTheCheckedInRows) {
  if (!have_cell_flow()) GTEST_SKIP() << "osu018 liberty, yosys or sta not installed";
  const std::string out = ::testing::TempDir() + "/trax_areas_long.json";
  std::remove(out.c_str());
  Cli r = trax_areas("--formats e5m6 --units fp_add,fp_cmp --out '" + out + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("fp_add e5m6 Stages 2: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("STA Fmax"), std::string::npos) << r.out;
  r = trax_areas("--formats e5m6 --units fp_add,fp_cmp --skip-present --out '" + out + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("fp_cmp e5m6 Stages 1: in the table (--skip-present)"), std::string::npos) << r.out;
  const nlohmann::json fresh = nlohmann::json::parse(slurp(out));
  ASSERT_EQ(fresh.at("rows").size(), 2u);
  const nlohmann::json checked = nlohmann::json::parse(slurp(std::string(RU_SOURCE_DIR) + "/model/data/trax/areas.json"));
  for (const auto& f : fresh.at("rows")) {
    EXPECT_EQ(f.at("command").get<std::string>().rfind("rayunits synth " + f.at("unit").get<std::string>(), 0), 0u);
    for (const auto& c : checked.at("rows"))
      if (c.at("command") == f.at("command") && c.value("rtl_hash", "") == f.value("rtl_hash", "x")) {
        EXPECT_EQ(c.at("area_um2"), f.at("area_um2")) << c.at("command");
        EXPECT_EQ(c.at("fmax_mhz"), f.at("fmax_mhz")) << c.at("command");
      }
  }
  // the fresh table is accepted by the model (the other units numeric)
  setenv("RU_TRAX_AREAS", out.c_str(), 1);
  Config c = default_config();
  c.format = "e5m6";
  for (Unit u : {Unit::FpMul, Unit::FpDiv, Unit::FpSqrt, Unit::Conv, Unit::Int, Unit::Branch, Unit::Box, Unit::Tri,
                 Unit::Noise, Unit::Texture})
    c.unit(u).area = 1;
  const Config rc = resolve_config(c);
  EXPECT_EQ(rc.unit(Unit::FpAdd).area, fresh.at("rows")[0].at("area_um2").get<double>());
  EXPECT_EQ(rc.clock_mhz, fresh.at("rows")[0].at("fmax_mhz").get<double>());  // fp_add is slower than fp_cmp
  unsetenv("RU_TRAX_AREAS");
  // bad input: one line, exit 2, nothing measured
  r = trax_areas("--units fp_add,fp_dot3 --out '" + out + "'");
  EXPECT_EQ(r.code, 2);
  std::string accepted;
  for (const std::string& u : area_table_units()) accepted += (accepted.empty() ? "" : ", ") + u;
  EXPECT_NE(accepted.find("fp_fma"), std::string::npos);
  EXPECT_EQ(r.err, "rayunits trax areas: error: --units: 'fp_dot3' is not a TRaX unit (accepted: " + accepted + ")\n");
  r = trax_areas("--flow osu999 --out '" + out + "'");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("unknown flow 'osu999'"), std::string::npos) << r.err;
}

// chip.fma with --cosim-fp (issue 16): the companion is built with ru_fp_fma at the chip's
// latency (--cosim-build, a fresh rtl build cache), every fused result of the frame equals the
// RTL's, and a planted bit flip in the 4th FFMA result sent stops the run naming the FFMA.
TEST(LongTraxCosim, FmaChipResultsEqualTheRtlAndAPlantedFlipIsCaught) {
  ru::test::TempDir d("ru_fma_cosim");
  const std::string cfg = (d.p / "fma.toml").string();
  std::ofstream(cfg) << "[chip]\nfma = true\n";
  setenv("RU_RTL_CACHE", (d.p / "cache").c_str(), 1);
  const std::vector<std::string> base = {"trax", "--scene", "noisy", "--size", "8x8", "--config", cfg,
                                         "--cosim-fp", "--cosim-build", "--quiet"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = base;
    a.insert(a.end(), extra.begin(), extra.end());
    return ru::test::run_rayunits(a, 1800);
  };
  const auto ok = with({"--out", (d.p / "ok").string()});
  EXPECT_EQ(ok.code, 0) << ok.out << ok.err;
  const std::regex fma_count("fp_fma=([0-9]+)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(ok.out, m, fma_count)) << ok.out;
  EXPECT_GT(std::stoull(m[1]), 1000u) << ok.out;
  const auto bad = with({"--cosim-inject", "3", "--cosim-inject-op", "ffma", "--out", (d.p / "bad").string()});
  unsetenv("RU_RTL_CACHE");
  EXPECT_EQ(bad.code, 1) << bad.out << bad.err;
  EXPECT_NE(bad.err.find("MISMATCH in cycle"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("RTL fp_fma_e8m23_s4"), std::string::npos) << bad.err;
}
