// `rayunits synth` and `rayunits synth-sweep`: the open synthesis flow (synth/README.md).
#include <cstdio>
#include <cstring>
#include <string>

#include "command.hpp"
#include "rayunits/synth/args.hpp"
#include "rayunits/synth/flow.hpp"
#include "rayunits/synth/process.hpp"
#include "rayunits/synth/sweep.hpp"

namespace {

using namespace ru::synth;

void synth_help() {
  std::printf(
      "usage: rayunits synth <unit> --format eXmY --stages N [--round rne|rtz|rdn|rup] [--ftz]\n"
      "                      [--param Name=V]... [--json FILE|-] [flow options]\n\n"
      "Synthesizes the unit's wrapper with Yosys and reports cell counts, NAND2-equivalent area,\n"
      "transistors (stat -tech cmos), register bits, the gate depth of the worst pipeline stage\n"
      "(ltp -noff), an estimated Fmax (delay model in synth/README.md), iCE40 LUTs (and nextpnr\n"
      "Fmax with --fpga) and Xilinx 7-series LUT/DSP counts.\n\n"
      "units: %s\n\n"
      "  --format eXmY[-ftz]  number format; --ftz: flush to zero; --round: rounding mode (default rne)\n"
      "  --stages N    latency in cycles, 0..the unit's useful maximum (rtl/README.md)\n"
      "  --param N=V   a unit-specific parameter (e.g. noise: FracBits, IntBits, OutW)\n"
      "  --json FILE   also write the result as one JSON object (\"-\": JSON on stdout, no table)\n\n%s",
      unit_names().c_str(), kFlowOptionsHelp);
}

int run_synth_cmd(int argc, char** argv) {
  std::string unit, json_out;
  ConfigArgs ca;
  FlowOptions fo;
  for (int i = 1; i < argc; ++i) {
    ArgCursor a{argc, argv, i, argv[i]};
    if (size_t eq = a.opt.find('='); a.opt.rfind("--", 0) == 0 && eq != std::string::npos) a.opt.resize(eq);
    if (a.opt == "--help" || a.opt == "-h") {
      synth_help();
      return 0;
    }
    if (a.opt == "--json")
      json_out = a.value();
    else if (parse_config_option(a, ca) || parse_flow_option(a, fo)) {
    } else if (a.opt[0] == '-' && a.opt != "-") {
      throw ru::cli::UsageError("unknown option '" + a.opt + "' (see rayunits synth --help)");
    } else if (unit.empty()) {
      unit = a.opt;
    } else {
      throw ru::cli::UsageError("unexpected argument '" + a.opt + "' (one unit per run)");
    }
    i = a.i;
  }
  if (unit.empty()) throw ru::cli::UsageError("missing unit (units: " + unit_names() + ")");
  const UnitSpec& u = find_unit(unit);
  const UnitConfig c = make_config(u, ca);
  install_interrupt_handler();
  const SynthResult r = run_synth(u, c, fo);
  const std::string row = to_json(r).dump() + "\n";
  if (json_out == "-") {
    std::fputs(row.c_str(), stdout);
  } else {
    std::fputs(format_table(r).c_str(), stdout);
    if (!json_out.empty()) write_file_atomic(json_out, row);
  }
  return 0;
}

void sweep_help() {
  std::printf(
      "usage: rayunits synth-sweep --out DIR [--units a,b] [--formats eXmY,...] [--stages 0,1,2,max]\n"
      "                            [--round MODE] [-j N] [--resume] [--no-plot] [--python PATH]\n"
      "                            [flow options]\n\n"
      "Synthesizes every (unit, format, stages) point in parallel (progress on stderr) and writes\n"
      "DIR/synth_sweep.csv, DIR/synth_sweep.json (meta + one row per point, as `synth --json`),\n"
      "DIR/points/<top>.json and DIR/synth_sweep.png (area vs fraction bits, Fmax vs stages).\n"
      "Stage counts above a unit's maximum are skipped; \"max\" is each unit's maximum.\n\n"
      "defaults: --units fp_add,fp_mul,fp_div --formats e5m10,e6m12,e7m16,e8m23\n"
      "          --stages 0,1,2,3,4,max -j 2\n"
      "  --resume      reuse DIR/points/*.json written by an earlier run with the same flow options\n\n%s",
      kFlowOptionsHelp);
}

int run_sweep_cmd(int argc, char** argv) {
  SweepOptions so;
  std::string cmd = "rayunits synth-sweep";
  for (int i = 1; i < argc; ++i) cmd += std::string(" ") + argv[i];
  so.command = cmd;
  for (int i = 1; i < argc; ++i) {
    ArgCursor a{argc, argv, i, argv[i]};
    if (size_t eq = a.opt.find('='); a.opt.rfind("--", 0) == 0 && eq != std::string::npos) a.opt.resize(eq);
    if (a.opt == "--help" || a.opt == "-h") {
      sweep_help();
      return 0;
    }
    if (a.opt == "--units")
      so.units = split_list(a.value());
    else if (a.opt == "--formats")
      so.formats = split_list(a.value());
    else if (a.opt == "--stages")
      so.stages = split_list(a.value());
    else if (a.opt == "--round")
      so.round = a.value();
    else if (a.opt == "-j" || a.opt == "--jobs")
      so.jobs = parse_int(a.opt, a.value(), 1, 256);
    else if (a.opt.rfind("-j", 0) == 0 && a.opt.size() > 2)
      so.jobs = parse_int("-j", a.opt.substr(2), 1, 256);
    else if (a.opt == "--out")
      so.out_dir = a.value();
    else if (a.opt == "--resume")
      so.resume = true;
    else if (a.opt == "--no-plot")
      so.plot = false;
    else if (a.opt == "--python")
      so.python = a.value();
    else if (parse_flow_option(a, so.flow)) {
    } else {
      throw ru::cli::UsageError("unknown argument '" + a.opt + "' (see rayunits synth-sweep --help)");
    }
    i = a.i;
  }
  if (so.out_dir.empty()) throw ru::cli::UsageError("--out DIR is required");
  install_interrupt_handler();
  const int failed = run_sweep(so, [](const std::string& s) {
    std::fprintf(stderr, "%s\n", s.c_str());
    std::fflush(stderr);
  });
  if (failed > 0) {
    std::fprintf(stderr, "rayunits synth-sweep: error: %d point(s) failed (rows with \"error\" in %s)\n",
                 failed, (so.out_dir + "/synth_sweep.json").c_str());
    return 1;
  }
  return 0;
}

}  // namespace

RU_COMMAND("synth", "synthesize one unit with Yosys: area, depth, Fmax estimate, FPGA LUTs", run_synth_cmd);
RU_COMMAND("synth-sweep", "synthesize a grid of units/formats/stages in parallel: CSV, JSON, plot",
           run_sweep_cmd);
