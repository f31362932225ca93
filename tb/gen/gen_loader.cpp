// rayunits tb: tb_gen_loader — the cycle-by-cycle scoreboard on a module made by `rayunits gen`.
//
//   tb_gen_loader --dut=libdut.so --datasheet=DIR/datasheet.json [--config-name=NAME] [--tag=T]...
//                 [tb options] [gtest options]
//   (or RU_GEN_DUT / RU_GEN_DATASHEET in the environment)
//   --config-name  the configuration's name (suite <unit>_<NAME>; default gen_<format>_s<N>, from
//                  the top), e.g. gls_e5m10_s2 for the gate-level netlist of tb/gls
//   --tag          adds a tag to the configuration (e.g. exhaustive); "selftest" is always set
//
// A generated wrapper only exists after `rayunits` has run, so it cannot be verilated at CMake
// configure time like the fixed test matrix. Instead tb/gen/gen_test.cmake verilates it at test
// time and compiles the model plus a small glue into a shared object, which this executable
// dlopen()s. The .so holds only the Verilated model and its port binding; the Verilator runtime,
// the harness and the floating-point test plan live here (the executable exports its symbols).
//
// What the generated module is supposed to be is read from its datasheet, not from the .so:
// unit, top, format, rounding mode and latency (the harness's Stages). So a run checks that the
// wrapper behaves, cycle by cycle and bit for bit, as its datasheet says. The configuration is
// tagged "selftest": the planted-error tests run on the generated wrapper too.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <exception>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayunits/tb/fp.hpp"
#include "rayunits/tb/testing.hpp"

namespace {

using nlohmann::json;

// Symbols of the shared object (written by gen_test.cmake, see gen_glue.cpp.in).
using MakeDutFn = ru::tb::Dut* (*)(const ru::tb::DutOptions*);
using TopFn = const char* (*)();

std::runtime_error err(const std::string& m) { return std::runtime_error(m); }

const json& field(const json& j, const char* key, const std::string& file) {
  if (!j.is_object() || !j.contains(key) || j.at(key).is_null())
    throw err(file + ": no field '" + key + "'");
  return j.at(key);
}

int64_t int_field(const json& j, const char* key, const std::string& file) {
  const json& v = field(j, key, file);
  if (!v.is_number_integer()) throw err(file + ": field '" + std::string(key) + "' is not an integer");
  return v.get<int64_t>();
}

// Registers the generated module as one configuration of its unit's test plan.
void load(const std::string& dut_path, const std::string& ds_path, const std::string& name,
          const std::vector<std::string>& tags) {
  std::ifstream in(ds_path);
  if (!in) throw err("cannot read the datasheet " + ds_path);
  json ds;
  try {
    ds = json::parse(in);
  } catch (const std::exception& e) {
    throw err(ds_path + ": not valid JSON (" + e.what() + ")");
  }
  const std::string unit = field(ds, "unit", ds_path).get<std::string>();
  const std::string top = field(ds, "top", ds_path).get<std::string>();
  if (!ru::tb::fp_unit_spec(unit))
    throw err(ds_path + ": unit '" + unit + "' is not a floating-point unit (this loader runs the FP test plan)");
  const json& fmt = field(ds, "format", ds_path);
  const std::string round = field(ds, "round", ds_path).get<std::string>();
  static const char* const kRounds[] = {"rne", "rtz", "rdn", "rup"};
  int64_t round_code = -1;
  for (int i = 0; i < 4; ++i)
    if (round == kRounds[i]) round_code = i;
  if (round_code < 0) throw err(ds_path + ": unknown rounding mode '" + round + "'");
  const int64_t latency = int_field(ds, "latency", ds_path);
  if (latency < 0) throw err(ds_path + ": negative latency");

  // A name without '/' would be searched in the library path: always load this very file.
  const std::string so = dut_path.find('/') == std::string::npos ? "./" + dut_path : dut_path;
  void* h = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) throw err(std::string("cannot load the DUT: ") + dlerror());
  auto make = reinterpret_cast<MakeDutFn>(dlsym(h, "ru_gen_make_dut"));
  auto top_fn = reinterpret_cast<TopFn>(dlsym(h, "ru_gen_dut_top"));
  if (!make || !top_fn) throw err(dut_path + ": no ru_gen_make_dut/ru_gen_dut_top (not built by tb/gen/gen_test.cmake?)");
  if (top != top_fn())
    throw err(dut_path + " holds the model of " + top_fn() + ", the datasheet describes " + top);

  ru::tb::ConfigDesc d;
  d.unit = unit;
  const std::string stem = "ru_" + unit + "_";
  d.name = "gen_" + (top.rfind(stem, 0) == 0 ? top.substr(stem.size()) : top);  // gen_e7m16_s3
  if (!name.empty()) d.name = name;  // --config-name, e.g. gls_e5m10_s2
  d.prefix = "V" + top;
  d.params = {{"ExpW", int_field(fmt, "exp_bits", ds_path)},
              {"FracW", int_field(fmt, "frac_bits", ds_path)},
              {"Subnormals", field(fmt, "subnormals", ds_path).get<bool>() ? 1 : 0},
              {"Round", round_code},
              {"Stages", latency}};
  d.tags = {"selftest"};
  for (const std::string& t : tags)
    if (t != "selftest") d.tags.push_back(t);
  d.make = [make](const ru::tb::DutOptions& o) {
    std::unique_ptr<ru::tb::Dut> p(make(&o));
    if (!p) throw std::runtime_error("ru_gen_make_dut returned null");
    return p;
  };
  ru::tb::fp_format(d);  // validates the format (throws FormatError)
  ru::tb::registered_configs().push_back(std::move(d));
  std::cerr << "tb_gen_loader: " << top << " (" << unit << " " << field(fmt, "name", ds_path).get<std::string>()
            << " " << round << ", latency " << latency << ") from " << dut_path << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string dut, ds, name;
  std::vector<std::string> tags;
  if (const char* e = std::getenv("RU_GEN_DUT")) dut = e;
  if (const char* e = std::getenv("RU_GEN_DATASHEET")) ds = e;
  int out = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--dut=", 0) == 0)
      dut = a.substr(6);
    else if (a.rfind("--datasheet=", 0) == 0)
      ds = a.substr(12);
    else if (a.rfind("--config-name=", 0) == 0)
      name = a.substr(14);
    else if (a.rfind("--tag=", 0) == 0)
      tags.push_back(a.substr(6));
    else
      argv[out++] = argv[i];
  }
  argc = out;
  argv[argc] = nullptr;
  if (!ru::tb::parse_options(argc, argv)) return 2;
  if (dut.empty() || ds.empty()) {
    std::cerr << "error: tb_gen_loader needs --dut=<model .so> and --datasheet=<datasheet.json> "
                 "(or RU_GEN_DUT, RU_GEN_DATASHEET); see tb/gen/README.md\n";
    return 2;
  }
  // Rerun hints printed with a mismatch must name the same DUT.
  ru::tb::global_options().argv0 += " --dut=" + dut + " --datasheet=" + ds;
  if (!name.empty()) ru::tb::global_options().argv0 += " --config-name=" + name;
  for (const std::string& t : tags) ru::tb::global_options().argv0 += " --tag=" + t;
  ::testing::InitGoogleTest(&argc, argv);
  try {
    load(dut, ds, name, tags);
    if (!ru::tb::register_all_tests()) return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
  if (!::testing::GTEST_FLAG(list_tests))
    std::cerr << "tb: seed=" << ru::tb::global_options().seed << " (reproduce with --seed=N or RU_SEED=N)\n";
  return RUN_ALL_TESTS();
}
