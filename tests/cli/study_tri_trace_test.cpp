// `rayunits study tri --trace FILE` (issue 14 §5: Tables 3.2-3.4 on captured traces): the trace
// path gives the same numbers as the in-memory synthetic path on a tiny case (and the comparison
// notices one missing record), and a malformed trace gives one error line and a non-zero exit.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "../common/files.hpp"

namespace {

std::string bin() { return std::string(RU_BINARY_DIR) + "/model/cli/rayunits"; }
std::string tmp(const std::string& name) {
  return std::string(RU_BINARY_DIR) + "/study_tri_trace_" + std::to_string(::getpid()) + "_" + name;
}

struct Out {
  int code = -1;
  std::string out, err;
};

using ru::test::slurp;

Out sh(const std::string& args) {
  const std::string base = tmp("cmd");
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

// A CSV without its '#' lines (they record the command and the source, which differ).
std::string numbers(const std::string& path) {
  std::istringstream in(slurp(path));
  std::string line, r;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') r += line + "\n";
  return r;
}

// The printed tables, from "Table 3.2" up to the "wrote" line.
std::string printed(const std::string& out) {
  const size_t a = out.find("Table 3.2"), b = out.find("\nwrote ");
  if (a == std::string::npos || b == std::string::npos || b < a) return "";
  return out.substr(a, b - a);
}

void rm_dir(const std::string& d) {
  for (const char* f : {"study_tri_tables.csv", "study_tri_formulas.csv", "study_tri_signs.csv"})
    std::remove((d + "/" + f).c_str());
  ::rmdir(d.c_str());
}

const char* kGrid = " --exp 6:7 --frac 9:10 --no-plot --quiet --threads 1";

}  // namespace

TEST(CliStudyTri, TracePathMatchesInMemoryPath) {
  const std::string tr = tmp("synth.trace"), a = tmp("mem"), b = tmp("file"), c = tmp("short");
  const Out m = sh("study tri --synthetic 48 --seed 3 --write-trace " + tr + " --out " + a + kGrid);
  ASSERT_EQ(m.code, 0) << m.err;
  const Out f = sh("study tri --trace " + tr + " --out " + b + kGrid);
  ASSERT_EQ(f.code, 0) << f.err;
  EXPECT_NE(m.out.find("48 records used"), std::string::npos) << m.out;
  EXPECT_NE(f.out.find("48 records used"), std::string::npos) << f.out;
  for (const char* csv : {"study_tri_tables.csv", "study_tri_formulas.csv", "study_tri_signs.csv"}) {
    const std::string x = numbers(a + "/" + csv), y = numbers(b + "/" + csv);
    EXPECT_GT(std::count(x.begin(), x.end(), '\n'), 4) << csv;  // header + rows for 4 formats
    EXPECT_EQ(x, y) << csv;
  }
  EXPECT_FALSE(printed(m.out).empty()) << m.out;
  EXPECT_EQ(printed(m.out), printed(f.out));
  // The comparison is sensitive: the same trace without its last record gives other numbers.
  const Out s = sh("study tri --trace " + tr + " --limit 47 --out " + c + kGrid);
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_NE(numbers(a + "/study_tri_tables.csv"), numbers(c + "/study_tri_tables.csv"));
  std::remove(tr.c_str());
  rm_dir(a);
  rm_dir(b);
  rm_dir(c);
}

TEST(CliStudyTri, MalformedTraceGivesOneErrorLine) {
  const std::string good = tmp("good.trace"), out = tmp("bad_out");
  const Out m = sh("study tri --synthetic 16 --write-trace " + good + " --out " + out + kGrid);
  ASSERT_EQ(m.code, 0) << m.err;
  const std::string bytes = slurp(good);
  ASSERT_EQ(bytes.size(), 32u + 16u * 144u);
  struct Case {
    const char* name;
    std::string content;
    const char* expect;  // part of the error line
  };
  std::string no_tris = bytes.substr(0, 32);
  std::memset(&no_tris[16], 0, 8);  // header only: 0 tri records, 0 box records
  std::string bad_kind = bytes;
  bad_kind[32] = 7;
  const Case cases[] = {
      {"magic.trace", "NOTATRACE" + bytes.substr(9), "magic"},
      {"truncated.trace", bytes.substr(0, bytes.size() - 10), "byte"},
      {"short.trace", bytes.substr(0, 12), "byte"},
      {"kind.trace", bad_kind, "byte 32"},
      {"empty.trace", no_tris, "holds no ray-triangle records"},
  };
  for (const Case& k : cases) {
    const std::string p = tmp(k.name);
    std::ofstream(p, std::ios::binary) << k.content;
    const Out r = sh("study tri --trace " + p + " --out " + out + kGrid);
    EXPECT_EQ(r.code, 2) << k.name;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << k.name << ": " << r.err;
    EXPECT_NE(r.err.find(p), std::string::npos) << k.name << ": " << r.err;
    EXPECT_NE(r.err.find(k.expect), std::string::npos) << k.name << ": " << r.err;
    EXPECT_EQ(r.out.find("Table 3.2"), std::string::npos) << k.name;
    std::remove(p.c_str());
  }
  const Out missing = sh("study tri --trace " + tmp("no_such.trace") + " --out " + out + kGrid);
  EXPECT_EQ(missing.code, 2);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  const Out both = sh("study tri --trace " + good + " --synthetic 8 --out " + out + kGrid);
  EXPECT_EQ(both.code, 2);
  EXPECT_EQ(std::count(both.err.begin(), both.err.end(), '\n'), 1) << both.err;
  std::remove(good.c_str());
  rm_dir(out);
}

// `study tri-outputs` (issue 14 §3): a tiny run prints its tables and checks deferred's outputs;
// bad input gives one error line.
TEST(CliStudyTri, TriOutputsRunsAndRejectsBadInput) {
  const std::string csv = tmp("outputs.csv"), good = tmp("outputs.trace"), out = tmp("outputs_dir");
  const Out r = sh("study tri-outputs --synthetic 64 --exp 7 --frac 10:11 --threads 1 --quiet --csv " + csv);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("deferred outputs differing from Fig. 3.6's (must be 0): 0"), std::string::npos) << r.out;
  const std::string rows = numbers(csv);
  EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 3) << rows;  // header + 2 formats
  // the trace path gives the same CSV as the in-memory one
  ASSERT_EQ(sh("study tri --synthetic 64 --write-trace " + good + " --out " + out + kGrid).code, 0);
  const std::string csv2 = tmp("outputs2.csv");
  ASSERT_EQ(sh("study tri-outputs --trace " + good + " --exp 7 --frac 10:11 --threads 1 --quiet --csv " + csv2).code, 0);
  EXPECT_EQ(numbers(csv2), rows);
  for (const char* bad : {"--exp 7 --table-exp 9", "--exp 1:3", "--synthetic 8 --trace x.trace",
                          "--trace /nonexistent/t.trace"}) {
    const Out b = sh(std::string("study tri-outputs --quiet --csv ") + tmp("bad.csv") + " " + bad);
    EXPECT_EQ(b.code, 2) << bad;
    EXPECT_EQ(std::count(b.err.begin(), b.err.end(), '\n'), 1) << bad << ": " << b.err;
  }
  std::remove(csv.c_str());
  std::remove(csv2.c_str());
  std::remove(good.c_str());
  std::remove(tmp("bad.csv").c_str());
  rm_dir(out);
}
