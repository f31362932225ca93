// rayunits dp: the datapath IR (docs/DATAPATH.md) — list the named designs, print a graph, count
// its operations, emit its SystemVerilog module.
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/dp/emit.hpp"
#include "rayunits/dp/formulas.hpp"
#include "rayunits/synth/process.hpp"

namespace ru::cli {
namespace {

namespace fs = std::filesystem;

// A design name, a genome name of the search (sv-f0-o0-..., box-r1-f0-m0), or a file in the text form
// (docs/DATAPATH.md).
// origin: what emit writes as the module's origin line (empty for a graph file).
// wide: "DE,DM" for a genome with mixed precision (-w1..3): the exponent and fraction bits its wide
// format adds to the unit's.
dp::Graph load(const std::string& what, std::string& origin, const std::string& wide) {
  for (const auto& d : dp::designs())
    if (d.name == what) return origin = d.origin(), d.make();
  if (what.rfind("sv-", 0) == 0 || what.rfind("mt-", 0) == 0) {  // a genome of the search (dp/formulas.hpp)
    try {
      dp::TriGenome g = dp::parse_genome_name(what);
      if (!wide.empty()) {
        int de = -1, dm = -1;
        char tail = 0;
        if (std::sscanf(wide.c_str(), "%d,%d%c", &de, &dm, &tail) != 2 || de < 0 || dm < 0 || de + dm == 0)
          throw UsageError("--wide '" + wide + "': exponent and fraction bits to add, DE,DM (e.g. 1,7: e7m16 -> e8m23)");
        g.wide_de = de, g.wide_dm = dm;
      }
      origin = "genome " + dp::genome_name(g) +
               (g.wide ? " wide +" + std::to_string(g.wide_de) + " +" + std::to_string(g.wide_dm) : std::string());
      return dp::tri_graph(g);
    } catch (const dp::IrError& e) {
      throw UsageError(e.what());
    }
  }
  if (what.rfind("box-", 0) == 0) {  // a ray-box design of `rayunits search box`
    try {
      const dp::BoxGenome g = dp::parse_box_genome_name(what);
      origin = "genome " + dp::box_genome_name(g);
      return dp::box_graph(g);
    } catch (const dp::IrError& e) {
      throw UsageError(e.what());
    }
  }
  if (what.find('/') != std::string::npos || what.find('.') != std::string::npos) {
    if (!fs::is_regular_file(what)) throw UsageError("no such graph file: " + what);
    try {
      return dp::Graph::parse(synth::read_file(what));
    } catch (const dp::IrError& e) {
      throw UsageError(what + ": " + e.what());
    }
  }
  try {
    dp::find_design(what);
  } catch (const dp::IrError& e) {
    throw UsageError(std::string(e.what()) + "; or a graph file (a path)");
  }
  return {};
}

int run_dp(int argc, char** argv) {
  CLI::App app{"The datapath IR (docs/DATAPATH.md): `list` the named designs; `print`, `count` or `emit` a "
               "design, a genome of `rayunits search tri` (sv-f0-o0-d0-a0-q0-i0-t0-p0, mt-q1-i0-p0), a ray-box design of `rayunits search box` (box-r1-f0-m0) or a graph file. emit writes DIR/MODULE.sv (the module, registers placed by the level "
               "chain) and DIR/MODULE.f (its RTL file list).",
               "rayunits dp"};
  app.require_subcommand(1);
  auto* list = app.add_subcommand("list", "the named designs");
  std::string what, module, out = ".", wide;
  auto* print = app.add_subcommand("print", "the graph in the text form");
  print->add_option("design", what, "design name or graph file")->required();
  auto* count = app.add_subcommand("count", "operations per unit kind and the FP depth (levels)");
  count->add_option("design", what, "design name or graph file")->required();
  auto* emit = app.add_subcommand("emit", "SystemVerilog module and file list");
  emit->add_option("design", what, "design name or graph file")->required();
  emit->add_option("--module", module, "module name (default ru_dp_<design>)");
  emit->add_option("--out", out, "output directory (default .)");
  for (auto* c : {print, count, emit})
    c->add_option("--wide", wide, "DE,DM: the wide format of a mixed-precision genome (-w1..3), the unit's plus DE "
                                  "exponent and DM fraction bits");
  if (!parse_args(app, argc, argv)) return 0;

  if (list->parsed()) {
    for (const auto& d : dp::designs())
      std::printf("%-22s %-28s %s\n", d.name.c_str(), d.genome.c_str(), d.summary.c_str());
    return 0;
  }
  std::string origin;
  const dp::Graph g = load(what, origin, wide);
  if (print->parsed()) {
    std::fputs(g.print().c_str(), stdout);
  } else if (count->parsed()) {
    for (const auto& [k, n] : g.op_counts()) std::printf("%s %d\n", k.c_str(), n);
    std::printf("levels %d\n", g.fp_depth());
  } else {
    if (module.empty()) {
      if (what.find('/') != std::string::npos || what.find('.') != std::string::npos)
        throw UsageError("emit: --module is needed for a graph file");
      module = "ru_dp_" + what;
    }
    std::string sv;
    try {
      sv = dp::emit_sv(g, module, origin);
    } catch (const dp::IrError& e) {
      throw UsageError(e.what());
    }
    if (!fs::is_directory(out)) throw UsageError("--out: no such directory: " + out);
    synth::write_file_atomic((fs::path(out) / (module + ".sv")).string(), sv);
    synth::write_file_atomic((fs::path(out) / (module + ".f")).string(), dp::emit_filelist(module, g));
    std::printf("wrote %s/%s.sv and %s.f\n", out.c_str(), module.c_str(), module.c_str());
  }
  return 0;
}

}  // namespace

RU_COMMAND("dp", "datapath IR: list, print, count or emit (SystemVerilog) a design", run_dp);

}  // namespace ru::cli
