// rayunits dp: SystemVerilog from a datapath graph (issue 18 §1, the RTL emitter).
//
// emit_sv() writes one module that instantiates the project's FP units (ru_fp_add for add and
// sub, ru_fp_mul, ru_fp_div, ru_fp_cmp for lt/gt/le/ge/eq/min/max) and places its pipeline
// registers with the project's one mechanism, the level chain of ru_pipe_pkg
// (rtl/ru_level_chain.svh), exactly as the hand-written ray units do:
//   * every FP unit node gets a level: the latest ready level of its operands (an input or a
//     constant is ready at level 0, a unit node's result at its level + 1; Boolean gates,
//     selects, neg and abs are wiring and gates: ready with their last operand);
//   * a level's kind (its segment weights in the chain) is the heaviest kind among its nodes
//     (div > mul > add > cmp); instances of that kind get the level's cut selection
//     (lcut(k)), the others automatic placement; every instance of level k has latency lat(k);
//     an fma counts as a multiplier for its level's kind (the chain's kind table has no fma kind:
//     emit.cpp says why) and always places its registers automatically;
//   * a value used at a later level than it is ready passes a ru_pipe delay line of
//     span(ready, use) cycles; the outputs are delayed to the last level.
// Ports: clk_i, rst_ni, in_valid_i, one W-bit input <name>_i per graph input (W = 1+ExpW+FracW),
// out_valid_o (in_valid_i delayed by Stages), one output <name>_o per graph output (W bits, or
// 1 bit for a Boolean). Parameters ExpW, FracW, Stages, Subnormals, Round as every FP unit.
// Constants must be 0, +-inf or +-2^k (the emitted encoding; an elaboration check rejects a
// power of two that is not a normal number of the format). A node with its own rounding mode
// (Node::round) passes it as the instance's Round; sgn/nan/inf are bit tests of the value.
#pragma once

#include <string>
#include <vector>

#include "rayunits/dp/ir.hpp"

namespace ru::dp {

struct Levels {
  std::vector<int> level;  // per node: its level (unit nodes), -1 for others
  std::vector<int> ready;  // per node: the level at whose start its value exists
  std::vector<int> kind;   // per level: 0 add, 1 mul, 2 div, 3 cmp (ru_fp_pkg::KAdd ...)
  int nlev = 0;
};
Levels levels(const Graph& g);

// origin, when not empty, is written as the header's second line ("// origin: ..."); the named
// designs and the search's modules name their genome there, which scripts/search_table.py reads.
std::string emit_sv(const Graph& g, const std::string& module, const std::string& origin = "");

// The emitted module's maximum useful Stages as a registry expression in L and M (every cut
// position of every level registered, minus one): a level of kind add has 6 segments, mul L+5
// (L = csa_levels(M+1)), div M+6, cmp 3 (ru_fp_pkg add_nseg/mul_nseg/div_nseg/cmp_nseg; checked
// against the emitted RTL's MaxUsefulStages by RegistryRtl.MaxUsefulStagesMatchRtl; an fma level
// is a mul level). E.g.
// "2*L+M+42" for Fig. 3.6.
std::string max_stages_expr(const Graph& g);

// The RTL files an emitted module needs, in compile order (names under rtl/): those of every
// emitted module, and of g's (ru_fp_fma.sv when g has an fma).
std::vector<std::string> emit_sources();
std::vector<std::string> emit_sources(const Graph& g);
// The file list of g's emitted module (emit_sources(g), then MODULE.sv; one per line): MODULE.f.
std::string emit_filelist(const std::string& module, const Graph& g);

}  // namespace ru::dp
