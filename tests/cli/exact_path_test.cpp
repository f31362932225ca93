// `rayunits study exact-path` and `study watertight --tri exact` through the command: the claim
// that ray_tri_exact's fast path decides >= 99.9 % of a real render's ray/triangle tests at
// e8m23 (measured, can fail), and one-line errors for bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "../common/files.hpp"

namespace {

std::string bin() { return std::string(RU_BINARY_DIR) + "/model/cli/rayunits"; }

struct Out {
  int code = -1;
  std::string out, err;
};

using ru::test::slurp;

Out sh(const std::string& args) {
  const std::string base = std::string(RU_BINARY_DIR) + "/exact_path_test_" + std::to_string(::getpid());
  const std::string cmd = bin() + " " + args + " > " + base + ".out 2> " + base + ".err";
  const int st = std::system(cmd.c_str());
  Out o;
  o.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  o.out = slurp(base + ".out");
  o.err = slurp(base + ".err");
  std::remove((base + ".out").c_str());
  std::remove((base + ".err").c_str());
  return o;
}

}  // namespace

TEST(CliExactPath, FastPathDecidesARealRender) {
  const std::string dir = RU_BINARY_DIR;
  const std::string tr = dir + "/exact_path_" + std::to_string(::getpid()) + ".trace";
  const std::string png = dir + "/exact_path_" + std::to_string(::getpid()) + ".png";
  const Out r = sh("render --scene default --format e8m23 --size 64 --threads 1 --quiet --out " + png +
                   " --trace-out " + tr);
  ASSERT_EQ(r.code, 0) << r.err;
  const Out s = sh("study exact-path --trace " + tr + " --format e8m23 --threads 1");
  ASSERT_EQ(s.code, 0) << s.err;
  unsigned long long tests = 0, slow = 0;
  double fast = 0;
  const size_t at = s.out.rfind("tests=");
  ASSERT_NE(at, std::string::npos) << s.out;
  ASSERT_EQ(std::sscanf(s.out.c_str() + at, "tests=%llu slow=%llu fast_percent=%lf", &tests, &slow, &fast), 3);
  EXPECT_GT(tests, 5000u);
  EXPECT_GE(fast, 99.9) << s.out;
  EXPECT_NE(s.out.find("decisions that differ: "), std::string::npos);
  // A trace of another format is refused with one line.
  const Out bad = sh("study exact-path --trace " + tr + " --format e5m10");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("not in e5m10"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  std::remove(tr.c_str());
  std::remove(png.c_str());
  const Out missing = sh("study exact-path --trace " + dir + "/no_such.trace");
  EXPECT_NE(missing.code, 0);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
}

TEST(CliExactPath, WatertightExactRowAndBadInput) {
  const Out r = sh("study watertight --scene icosphere --format e6m12 --tri exact --rays 200 --near-vertex 100 --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("leaks=0 double_hits=0 rays=300"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("near-vertex"), std::string::npos) << r.out;
  for (const char* bad : {"--tri exact --tie-break", "--scale 0", "--scale nan", "--near-vertex -3"}) {
    const Out b = sh(std::string("study watertight --scene icosphere --rays 10 --quiet ") + bad);
    EXPECT_EQ(b.code, 2) << bad;
    EXPECT_EQ(std::count(b.err.begin(), b.err.end(), '\n'), 1) << bad << ": " << b.err;
  }
}
