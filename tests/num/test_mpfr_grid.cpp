// The model against the MPFR oracle on the format grid E {3,4,5,6,7,8,11} x M {1,2,3,7,10,16,
// 23,30,52}: every op, all four rounding modes, subnormals on and off.
//   fast (Grid/MpfrGrid): special x special operands in three of the eight configurations per
//     format (RNE with subnormals, RNE flush-to-zero, plus one that rotates over the grid so
//     every configuration is covered by several formats), random OperandGen sets in all eight;
//   long (LongGrid/LongMpfrGrid): special x special (fma: x a third of the specials) in every
//     configuration, and many more random sets.
#include "harness.hpp"

namespace ru::num::testing {
namespace {

struct GridCounts {
  uint64_t random;    // random operand sets per op and configuration
  bool all_specials;  // specials in every configuration (else three per format)
  bool fma_specials;  // special triples for fma
};

void run_cell(int E, int M, const GridCounts& n) {
  int cfg = 0;
  const int rotating = 1 + (E * 7 + M) % 7;  // a third configuration with specials (fast)
  for (bool sub : {true, false}) {
    for (Round r : kRounds) {
      const Format f = make_format(E, M, sub, r);
      const bool specials = n.all_specials || cfg == 0 || cfg == 4 || cfg == rotating;
      for (Op op : kAllOps) {
        Checker chk("model vs MPFR");
        if (specials && (op != Op::Fma || n.fma_specials)) run_specials(chk, f, op, oracle_op, model_op);
        const uint64_t seed = (static_cast<uint64_t>(E) << 40) ^ (static_cast<uint64_t>(M) << 32) ^
                              (static_cast<uint64_t>(cfg) << 8) ^ static_cast<uint64_t>(op);
        run_random(chk, f, op, n.random, seed, oracle_op, model_op);
        EXPECT_TRUE(chk.ok()) << chk.report();
      }
      ++cfg;
    }
  }
}

class MpfrGrid : public ::testing::TestWithParam<std::pair<int, int>> {};
TEST_P(MpfrGrid, AllOps) { run_cell(GetParam().first, GetParam().second, {scaled(4000), false, false}); }
INSTANTIATE_TEST_SUITE_P(Grid, MpfrGrid, ::testing::ValuesIn(grid_formats()), em_param_name);

class LongMpfrGrid : public ::testing::TestWithParam<std::pair<int, int>> {};
TEST_P(LongMpfrGrid, AllOps) { run_cell(GetParam().first, GetParam().second, {scaled(300000), true, true}); }
INSTANTIATE_TEST_SUITE_P(LongGrid, LongMpfrGrid, ::testing::ValuesIn(grid_formats()), em_param_name);

// Formats off the grid (edge_formats()): E = 2, E = 9 and 10 with M = 52, a few others.
class MpfrEdges : public ::testing::TestWithParam<std::pair<int, int>> {};
TEST_P(MpfrEdges, AllOps) { run_cell(GetParam().first, GetParam().second, {scaled(4000), false, false}); }
class LongMpfrEdges : public ::testing::TestWithParam<std::pair<int, int>> {};
TEST_P(LongMpfrEdges, AllOps) { run_cell(GetParam().first, GetParam().second, {scaled(300000), true, true}); }
INSTANTIATE_TEST_SUITE_P(Edges, MpfrEdges, ::testing::ValuesIn(edge_formats()), em_param_name);
INSTANTIATE_TEST_SUITE_P(LongEdges, LongMpfrEdges, ::testing::ValuesIn(edge_formats()), em_param_name);

}  // namespace
}  // namespace ru::num::testing
