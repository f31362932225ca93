// `rayunits bench sweep` runs end to end on tiny settings and prints its result lines
// (the figures themselves are benchmarks, not checked here); bad options are one line.
#include <gtest/gtest.h>

#include <regex>

#include "../common/run_rayunits.hpp"

TEST(BenchSweep, TinyRunPrintsTheFigures) {
  const auto r = ru::test::run_rayunits(
      {"bench", "sweep", "--repeats", "1", "--cpu-jobs", "2", "--pairs", "100", "--trivial-jobs", "3", "--rtl-configs", "1"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(CPU-bound \(2 x study box 100 pairs\): 1 worker median [0-9.]+ s, 2 workers median [0-9.]+ s, speedup median x[0-9.]+)")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(trivial \(3 x study box 1 pair\): median [0-9.]+ ms/job wall, engine overhead median -?[0-9.]+ ms/job)")))
      << r.out;
  // One configuration, a fresh cache: built by the first sweep, a hit in the repeated one.
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(Verilator build cache \(1 rtl jobs, .*hit rate 0/1 on the first sweep, 1/1 on the repeated sweep)")))
      << r.out;
  const auto bad = ru::test::run_rayunits({"bench", "sweep", "--cpu-jobs", "1"});
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--cpu-jobs"), std::string::npos) << bad.err;
}
