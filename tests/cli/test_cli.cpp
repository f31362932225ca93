// Tests of the `rayunits` command as a user runs it: the built binary, its output and exit codes.
// Expected values are derived by hand from the format definition (docs/FORMAT.md), not taken
// from the implementation; the derivation is in the comment next to each case.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "rayunits/noise/fixed.hpp"
#include "rayunits/util/csv.hpp"
#include "rayunits/util/process.hpp"

namespace fs = std::filesystem;

namespace {

std::string binary() {
  const char* env = std::getenv("RU_RAYUNITS");  // override for out-of-tree runs
  if (env && *env) return env;
  return std::string(RU_BINARY_DIR) + "/model/cli/rayunits";
}

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

void write_file(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
}

std::string quote(const std::string& s) { return ru::util::shell_quote(s); }

// A scratch directory per test, removed at the end.
class TempDir {
 public:
  TempDir() {
    std::string t = (fs::temp_directory_path() / "ru_test_cli_XXXXXX").string();
    if (!mkdtemp(t.data())) throw std::runtime_error("mkdtemp failed");
    p_ = t;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(p_, ec);
  }
  const fs::path& path() const { return p_; }

 private:
  fs::path p_;
};

struct Proc {
  int code = -1;
  std::string out, err;
};

// Runs `rayunits <args>` (args are shell words, already quoted where needed) with `input` on
// stdin and `env` (e.g. "RU_PYTHON=/x") in the environment.
Proc run(const std::string& args, const std::string& input = "", const std::string& env = "") {
  TempDir io;
  write_file(io.path() / "in", input);
  std::string cmd = (env.empty() ? "" : "env " + env + " ") + quote(binary()) + " " + args + " < " +
                    quote((io.path() / "in").string()) + " > " + quote((io.path() / "out").string()) + " 2> " +
                    quote((io.path() / "err").string());
  int st = std::system(cmd.c_str());
  Proc r;
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.out = read_file(io.path() / "out");
  r.err = read_file(io.path() / "err");
  return r;
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  std::string l;
  while (std::getline(ss, l)) v.push_back(l);
  return v;
}

// The line of `formats` output for one format.
std::string format_row(const std::string& out, const std::string& name) {
  for (const auto& l : lines(out))
    if (l.rfind(name + " ", 0) == 0) return l;
  return "";
}

// One clear error line, non-zero exit, nothing on stdout.
void expect_one_line_error(const Proc& r, const std::string& must_contain) {
  EXPECT_NE(r.code, 0);
  EXPECT_EQ(count_lines(r.err), 1) << "stderr: " << r.err;
  EXPECT_NE(r.err.find(must_contain), std::string::npos) << "stderr: " << r.err;
  EXPECT_EQ(r.out, "");
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(binary())) << "rayunits binary not found at " << binary()
                                      << " (build the 'rayunits' target first, or set RU_RAYUNITS)";
  }
};

// ------------------------------------------------------------------------------ help, errors
TEST_F(Cli, HelpListsCommands) {
  Proc r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* c : {"fp", "formats", "report", "bench fp"}) EXPECT_NE(r.out.find(c), std::string::npos) << c;
  Proc f = run("fp --help");
  EXPECT_EQ(f.code, 0);
  EXPECT_NE(f.out.find("--batch"), std::string::npos);
  EXPECT_NE(f.out.find("--round"), std::string::npos);
  Proc rep = run("report --help");
  EXPECT_EQ(rep.code, 0);
  EXPECT_NE(rep.out.find("--out"), std::string::npos);
}

TEST_F(Cli, BadInputsGiveOneLineAndNonZeroExit) {
  expect_one_line_error(run("frobnicate"), "unknown command 'frobnicate'");
  expect_one_line_error(run("fp e1m4 add 1 2"), "invalid format e1m4");
  expect_one_line_error(run("fp e12m4 add 1 2"), "[2,11]");
  expect_one_line_error(run("fp e8m56 add 1 2"), "64");
  expect_one_line_error(run("fp e5m10 add 1 1.5x"), "bad number '1.5x'");
  expect_one_line_error(run("fp e5m10 add 1 0x10000"), "does not fit");
  expect_one_line_error(run("fp e5m10 mull 1 2"), "unknown operation 'mull'");
  expect_one_line_error(run("fp e5m10 add 1"), "add takes 2 operands, got 1");
  expect_one_line_error(run("fp e5m10 add 1 2 --round up"), "unknown rounding mode 'up'");
  expect_one_line_error(run("fp e5m10 add 1 2 --bogus"), "--bogus");
  expect_one_line_error(run("formats e1m4"), "invalid format e1m4");
  expect_one_line_error(run("report --exp 4..12 --out x"), "--exp");
  expect_one_line_error(run("report --sections nosuch --out x"), "unknown report section 'nosuch'");
}

// ------------------------------------------------------------------------------ formats
TEST_F(Cli, FormatsTable) {
  Proc r = run("formats");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* n : {"e2m1", "e4m3", "e5m2", "e3m4", "e5m10", "e6m12", "e7m16", "e8m23", "e11m52"})
    EXPECT_NE(format_row(r.out, n), "") << n;
  // e7m16: bias 2^6-1 = 63; max = (2-2^-16)*2^63 = 2^64-2^47 = 18446603336221196288 ~ 1.84466e+19;
  // epsilon 2^-16; min normal 2^(1-63) = 2^-62; min subnormal 2^(-62-16) = 2^-78; width 24.
  std::string e7 = format_row(r.out, "e7m16");
  for (const char* s : {" 24 ", " 63 ", "1.84466e+19", "(2^-16)", "(2^-62)", "(2^-78)"})
    EXPECT_NE(e7.find(s), std::string::npos) << s << " in: " << e7;
  // e5m10: bias 15; max (2-2^-10)*2^15 = 65504; min normal 2^-14; min subnormal 2^-24.
  std::string h = format_row(r.out, "e5m10");
  for (const char* s : {" 16 ", "65504", "(2^-10)", "(2^-14)", "(2^-24)"})
    EXPECT_NE(h.find(s), std::string::npos) << s << " in: " << h;
  // e2m1: bias 1; max (2-1/2)*2 = 3; epsilon 2^-1; min normal 2^0; min subnormal 2^-1.
  std::string q = format_row(r.out, "e2m1");
  EXPECT_NE(q.find("  3 "), std::string::npos) << q;
  EXPECT_NE(q.find("1 (2^0)"), std::string::npos) << q;
  // e11m52 = binary64: min subnormal 2^-1074.
  EXPECT_NE(format_row(r.out, "e11m52").find("(2^-1074)"), std::string::npos);
  EXPECT_NE(r.out.find("-ftz"), std::string::npos);  // the flush-to-zero note

  Proc f = run("formats --ftz e7m16");
  ASSERT_EQ(f.code, 0);
  EXPECT_NE(format_row(f.out, "e7m16-ftz").find("none (flushed)"), std::string::npos) << f.out;
}

// ------------------------------------------------------------------------------ fp (one op)
TEST_F(Cli, FpSingleOperation) {
  // 1.5 = 1.1b*2^0: exponent 63 = 0x3f, fraction .1b = 0x8000 -> 0x3f8000.
  // 3.25 = 1.101b*2^1: exponent 64, fraction 0xa000 -> 0x40a000.
  // 4.875 = 1.00111b*2^2: exponent 65 = 0x41, fraction .00111b = 0x3800 -> 0x413800, exact.
  Proc r = run("fp e7m16 mul 1.5 3.25");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_NE(r.out.find("0x3f8000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0x40a000"), std::string::npos) << r.out;
  std::regex res(R"(mul\s+0x413800\s+4\.875\b)");
  EXPECT_TRUE(std::regex_search(r.out, res)) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(flags\s+-)"))) << r.out;

  // 1/3 = 0.010101...b = 1.0101...b*2^-2: exponent 125 -> 0x3e800000; fraction 23 bits
  // 0101...010 (0x2aaaaa), next bits 1010... -> guard 1, sticky 1 -> RNE rounds up: 0x3eaaaaab,
  // RTZ truncates: 0x3eaaaaaa. Inexact either way.
  Proc d = run("fp e8m23 div 1 3");
  EXPECT_TRUE(std::regex_search(d.out, std::regex(R"(div\s+0x3eaaaaab\s)"))) << d.out;
  EXPECT_TRUE(std::regex_search(d.out, std::regex(R"(flags\s+x \(inexact\))"))) << d.out;
  Proc dz = run("fp e8m23 div 1 3 --round rtz");
  EXPECT_TRUE(std::regex_search(dz.out, std::regex(R"(div\s+0x3eaaaaaa\s)"))) << dz.out;

  // Negative decimal operand: -1.5*2 = -3 = -1.1b*2^1: sign, exponent 16 -> 0xc000|0x0200 = 0xc200.
  Proc n = run("fp e5m10 mul -1.5 2");
  EXPECT_TRUE(std::regex_search(n.out, std::regex(R"(mul\s+0xc200\s+-3\b)"))) << n.out << n.err;

  // 0.1 = 1.6*2^-4: exponent 11 -> 0x2c00; 0.6*1024 = 614.4 -> 614 = 0x266: 0x2e66 =
  // 1638/16384 = 0.0999755859375 exactly; the input was rounded and says so.
  Proc p = run("fp e5m10 add 0.1 0");
  EXPECT_NE(p.out.find("0x2e66"), std::string::npos) << p.out;
  EXPECT_NE(p.out.find("0.0999755859375"), std::string::npos) << p.out;
  EXPECT_NE(p.out.find("rounded from 0.1"), std::string::npos) << p.out;

  // Overflow: 65504 + 65504 = 131008 > max -> RNE: +INF 0x7c00, flags overflow+inexact.
  Proc o = run("fp e5m10 add 65504 65504");
  EXPECT_TRUE(std::regex_search(o.out, std::regex(R"(add\s+0x7c00\s+inf)"))) << o.out;
  EXPECT_TRUE(std::regex_search(o.out, std::regex(R"(flags\s+ox )"))) << o.out;

  // Min normal 2^-14 (0x0400) * 0.5 = 2^-15: a subnormal, exact: 0x0200, no flags.
  // With --ftz the tiny result flushes to +0 with underflow+inexact.
  Proc s = run("fp e5m10 mul 0x0400 0.5");
  EXPECT_TRUE(std::regex_search(s.out, std::regex(R"(mul\s+0x200\s)"))) << s.out;
  EXPECT_TRUE(std::regex_search(s.out, std::regex(R"(flags\s+- )"))) << s.out;
  Proc z = run("fp e5m10 mul 0x0400 0.5 --ftz");
  EXPECT_TRUE(std::regex_search(z.out, std::regex(R"(mul\s+0x0\s+0\b)"))) << z.out;
  EXPECT_TRUE(std::regex_search(z.out, std::regex(R"(flags\s+ux )"))) << z.out;

  // sqrt(-1): invalid, canonical NaN 0 11111 1000000000 = 0x7e00.
  Proc q = run("fp e5m10 sqrt -1");
  EXPECT_TRUE(std::regex_search(q.out, std::regex(R"(sqrt\s+0x7e00\s+nan)"))) << q.out << q.err;
  EXPECT_TRUE(std::regex_search(q.out, std::regex(R"(flags\s+i )"))) << q.out;

  // Comparison: 1 < 2 is true -> 0x1.
  Proc c = run("fp e5m10 lt 1 2");
  EXPECT_TRUE(std::regex_search(c.out, std::regex(R"(lt\s+0x1\s+true)"))) << c.out;
}

// ------------------------------------------------------------------------------ fp --batch
TEST_F(Cli, BatchResultsAndFlags) {
  // Every expected line derived by hand (docs/FORMAT.md):
  const std::string input =
      // 1 + 2^-11 (0x1000: exponent -11+15 = 4) is halfway between 1 and 1+2^-10: RNE keeps the
      // even 1.0, RUP goes up to 0x3c01; inexact.
      "e5m10 add 0x3c00 0x1000 rne\n"
      "e5m10 add 0x3c00 0x1000 rup\n"
      "\n"
      "# comment lines and blank lines give no output\n"
      // max+max overflows: RNE -> INF, RTZ -> max finite; both overflow+inexact.
      "e5m10 add 0x7bff 0x7bff rne\n"
      "e5m10 add 0x7bff 0x7bff rtz\n"
      // 1/0 -> +INF, divide-by-zero; 0/0 -> canonical NaN, invalid.
      "e5m10 div 0x3c00 0x0 rne\n"
      "e5m10 div 0x0 0x0 rne\n"
      // sqrt(-1) invalid; sqrt(4) = 2 exact.
      "e5m10 sqrt 0xbc00 rne\n"
      "e5m10 sqrt 0x4400 rne\n"
      // 2^-14 * 0.5 = 2^-15: exact subnormal 0x200 (no flags); -ftz flushes: 0x0 ux.
      "e5m10 mul 0x0400 0x3800 rne\n"
      "e5m10-ftz mul 0x0400 0x3800 rne\n"
      // min subnormal 2^-24 * 0.5 = 2^-25, a tie between 0 and 2^-24: RNE -> 0 (even), RUP -> 0x1;
      // tiny and inexact: underflow+inexact.
      "e5m10 mul 0x0001 0x3800 rne\n"
      "e5m10 mul 0x0001 0x3800 rup\n"
      // x - x = +0, but -0 under RDN.
      "e5m10 sub 0x3c00 0x3c00 rne\n"
      "e5m10 sub 0x3c00 0x3c00 rdn\n"
      // min/max: -0 < +0; a quiet NaN operand is ignored silently, a signaling one raises invalid.
      "e5m10 max 0x0 0x8000 rne\n"
      "e5m10 min 0x0 0x8000 rne\n"
      "e5m10 min 0x7e00 0x3c00 rne\n"
      "e5m10 min 0x7c01 0x3c00 rne\n"
      // comparisons: 1 <= 1; qNaN == qNaN is false and quiet; lt on NaN is signaling (invalid).
      "e5m10 le 0x3c00 0x3c00 rne\n"
      "e5m10 eq 0x7e00 0x7e00 rne\n"
      "e5m10 lt 0x7e00 0x3c00 rne\n"
      "e5m10 eq 0x0 0x8000 rne\n"
      // fma is fused: 65504*2 - 65504 = 65504 exactly, no intermediate overflow.
      "e5m10 fma 0x7bff 0x4000 0xfbff rne\n"
      // 1*1 + 1 = 2 = 0x4000; line ends with CRLF.
      "e5m10 fma 0x3c00 0x3c00 0x3c00 rtz\r\n"
      // binary32: 1/3 -> 0x3eaaaaab (see FpSingleOperation); sqrt(2) = 1.41421356..., the float
      // below is 0x3fb504f3 = 1.41421353816986083984375 (error 2.4e-8 < half ulp 6e-8), so RNE
      // and RTZ give 0x3fb504f3 and RUP 0x3fb504f4.
      "e8m23 div 0x3f800000 0x40400000 rne\n"
      "e8m23 sqrt 0x40000000 rtz\n"
      "e8m23 sqrt 0x40000000 rup\n"
      // binary64: 1 + 2^-53 is a tie: RNE -> 1.0, RUP -> next double.
      "e11m52 add 0x3ff0000000000000 0x3ca0000000000000 rne\n"
      "e11m52 add 0x3ff0000000000000 0x3ca0000000000000 rup\n"
      // e2m1 (bias 1): 0x3 = 0 01 1 = 1.5; 1.5+1.5 = 3 = 0 10 1 = 0x5; 3*3 = 9 > max 3 -> INF 0x6.
      "e2m1 add 0x3 0x3 rne\n"
      "e2m1 mul 0x5 0x5 rne\n"
      // upper-case hex digits are accepted; last line without a newline.
      "e8m23 mul 0x3FC00000 0x40000000 rne";
  const std::string expected =
      "0x3c00 x\n0x3c01 x\n"
      "0x7c00 ox\n0x7bff ox\n"
      "0x7c00 z\n0x7e00 i\n"
      "0x7e00 i\n0x4000 -\n"
      "0x200 -\n0x0 ux\n"
      "0x0 ux\n0x1 ux\n"
      "0x0 -\n0x8000 -\n"
      "0x0 -\n0x8000 -\n0x3c00 -\n0x3c00 i\n"
      "0x1 -\n0x0 -\n0x0 i\n0x1 -\n"
      "0x7bff -\n"
      "0x4000 -\n"
      "0x3eaaaaab x\n0x3fb504f3 x\n0x3fb504f4 x\n"
      "0x3ff0000000000000 x\n0x3ff0000000000001 x\n"
      "0x5 -\n0x6 ox\n"
      "0x40400000 -\n";
  Proc r = run("fp --batch", input);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(r.out, expected);
}

TEST_F(Cli, BatchStopsAtTheFirstMalformedLine) {
  Proc r = run("fp --batch", "e5m10 add 0x3c00 0x3c00 rne\ne5m10 mul 0x3c00 0x4000 rne\ne5m10 add 0x3c00 rne\n"
                            "e5m10 add 0x3c00 0x3c00 rne\n");
  EXPECT_NE(r.code, 0);
  EXPECT_EQ(r.out, "0x4000 -\n0x4000 -\n");  // lines 1-2 only, nothing bogus for line 3
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("line 3"), std::string::npos) << r.err;

  const char* bad[][2] = {
      {"e5m10 add 0x1 0x10000 rne", "does not fit"},
      {"e5m10 mull 0x1 0x1 rne", "unknown operation 'mull'"},
      {"e5m10 add 0x1 0x1 near", "unknown rounding mode 'near'"},
      {"e1m4 add 0x1 0x1 rne", "invalid format e1m4"},
      {"e5m10 add 0x1 0x1g rne", "non-hex"},
      {"e5m10 add 1.0 0x1 rne", "not a 0x bit pattern"},
      {"e5m10 add 0x 0x1 rne", "not a 0x bit pattern"},
      {"e5m10 sqrt 0x1 0x1 rne", "sqrt takes 1 operand"},
      {"e5m10 fma 0x1 0x1 rne", "fma takes 3 operands"},
      {"e5m10 add", "got 2 fields"},
      {"e11m52 add 0x10000000000000000 0x1 rne", "does not fit"},
  };
  for (const auto& b : bad) {
    Proc e = run("fp --batch", std::string("# header\n") + b[0] + "\n");
    EXPECT_NE(e.code, 0) << b[0];
    EXPECT_EQ(e.out, "") << b[0];
    EXPECT_EQ(count_lines(e.err), 1) << b[0] << ": " << e.err;
    EXPECT_NE(e.err.find("line 2"), std::string::npos) << b[0] << ": " << e.err;
    EXPECT_NE(e.err.find(b[1]), std::string::npos) << b[0] << ": " << e.err;
  }
  expect_one_line_error(run("fp --batch e5m10"), "--batch");
}

TEST_F(Cli, BatchManyLines) {
  // 200k lines through the buffered reader/writer (chunk boundaries fall mid-line).
  // k*1.0 for k = 1..2048 is exact in e5m10 (11-bit significand): 1.0 * k = k.
  std::string in, want;
  char buf[96];
  for (int i = 0; i < 200000; ++i) {
    int k = 1 + i % 2048;  // k in [1, 2048], exact in e5m10
    int e = 0;
    double m = std::frexp(static_cast<double>(k), &e);  // k = m*2^e, m in [0.5,1)
    // k = 1.f * 2^(e-1): exponent field e-1+15, fraction (2m-1)*2^10
    unsigned bits = static_cast<unsigned>((e - 1 + 15) << 10) | static_cast<unsigned>((2 * m - 1) * 1024);
    std::snprintf(buf, sizeof buf, "e5m10 mul 0x3c00 0x%x rne\n", bits);
    in += buf;
    std::snprintf(buf, sizeof buf, "0x%x -\n", bits);
    want += buf;
  }
  Proc r = run("fp --batch", in);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out == want) << "output differs (" << r.out.size() << " vs " << want.size() << " bytes)";
}

// ------------------------------------------------------------------------------ report
TEST_F(Cli, ReportTinyGrid) {
  TempDir t;
  fs::path out = t.path() / "rep";
  Proc r = run("report --sections accuracy --out " + quote(out.string()) + " --exp 8 --frac 10..11 --samples 3000 --seed 7");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("index.md"), std::string::npos);
  EXPECT_NE(r.err.find("report: accuracy:"), std::string::npos) << r.err;  // progress on stderr
  for (const char* f : {"index.md", "meta.json", "accuracy.csv", "accuracy_mean.png", "accuracy_max.png",
                        "accuracy_range.png", "accuracy_vs_m.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  std::string png = read_file(out / "accuracy_mean.png");
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::string idx = read_file(out / "index.md");
  EXPECT_NE(idx.find("| seed | 7 |"), std::string::npos) << idx;
  EXPECT_NE(idx.find("| commit |"), std::string::npos);
  EXPECT_NE(idx.find("--samples 3000"), std::string::npos);  // the command line
  EXPECT_NE(idx.find("accuracy_mean.png"), std::string::npos);
  std::string meta = read_file(out / "meta.json");
  EXPECT_NE(meta.find("\"seed\": 7"), std::string::npos) << meta;
  // 2 cells x 4 ops + header
  EXPECT_EQ(count_lines(read_file(out / "accuracy.csv")), 9);
  // only the report itself is left in the parent: no temporary directories
  int entries = 0;
  for (const auto& e : fs::directory_iterator(t.path())) {
    ++entries;
    EXPECT_EQ(e.path().filename(), "rep");
  }
  EXPECT_EQ(entries, 1);

  // A second run replaces the report (it carries the .rayunits-report marker).
  Proc again = run("report --sections accuracy --quiet --no-plots --out " + quote(out.string()) + " --exp 8 --frac 10 --samples 500");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(again.err.find("report: accuracy:"), std::string::npos);  // --quiet
  EXPECT_EQ(count_lines(read_file(out / "accuracy.csv")), 5);
  EXPECT_FALSE(fs::exists(out / "accuracy_mean.png"));  // the old report is gone, not merged
}

// Parses accuracy.csv into (format, op) -> columns.
std::map<std::string, std::map<std::string, std::string>> read_accuracy(const fs::path& csv) {
  std::map<std::string, std::map<std::string, std::string>> m;
  const auto rows = ru::util::csv_read_file(csv.string());
  if (rows.empty()) return m;
  const auto& head = rows[0];
  for (size_t i = 1; i < rows.size(); ++i) {
    std::map<std::string, std::string> row;
    for (size_t k = 0; k < head.size() && k < rows[i].size(); ++k) row[head[k]] = rows[i][k];
    m[row["format"] + " " + row["op"]] = row;
  }
  return m;
}

TEST_F(Cli, ReportErrorsAreBoundedByTheMath) {
  // e11m52 holds the workload's doubles exactly, so add/mul/div make one rounding each:
  // relative error <= u = 2^-53 (and > 0 on 2000 random samples). e8m23: both inputs and the
  // product are rounded once each (no overflow/underflow for exponents -33..18):
  // |err| <= (1+2^-24)^3 - 1. e5m10 (max 65504) must overflow on values up to 2^19.
  TempDir t;
  fs::path out = t.path() / "rep";
  Proc r = run("report --sections accuracy --quiet --no-plots --out " + quote(out.string()) + " --exp 5..11 --frac 10..52 --samples 2000",
               "", "RU_PYTHON=/nonexistent/python3");  // --no-plots needs no python
  ASSERT_EQ(r.code, 0) << r.err;
  auto m = read_accuracy(out / "accuracy.csv");
  for (const char* op : {"add", "mul", "div"}) {
    auto& row = m[std::string("e11m52 ") + op];
    ASSERT_FALSE(row.empty()) << op;
    double mx = std::stod(row["max_rel_err"]), mean = std::stod(row["mean_rel_err"]);
    EXPECT_LE(mx, std::ldexp(1.0, -53)) << op;
    EXPECT_GT(mean, 0.0) << op;
    EXPECT_EQ(row["overflow"], "0");
    EXPECT_EQ(row["underflow"], "0");
    EXPECT_EQ(row["used"], "2000");
  }
  auto& mul32 = m["e8m23 mul"];
  ASSERT_FALSE(mul32.empty());
  const double u = std::ldexp(1.0, -24);
  EXPECT_LE(std::stod(mul32["max_rel_err"]), (1 + u) * (1 + u) * (1 + u) - 1);
  EXPECT_GT(std::stod(mul32["max_rel_err"]), u / 2);  // three roundings: the max is not tiny
  EXPECT_EQ(mul32["overflow"], "0");
  EXPECT_GT(std::stol(m["e5m10 mul"]["overflow"]), 0);
  EXPECT_GT(std::stol(m["e5m10 mul"]["underflow"]), 0);  // products down to 2^-66
}

TEST_F(Cli, ReportOutputErrors) {
  TempDir t;
  // Out dir below a regular file: cannot be created.
  write_file(t.path() / "file", "x");
  expect_one_line_error(run("report --sections accuracy --no-plots --out " + quote((t.path() / "file" / "rep").string()) + " --exp 8 --frac 10"),
                        "cannot");
  // An existing directory that is not a report is never replaced.
  fs::create_directories(t.path() / "mine");
  write_file(t.path() / "mine" / "keep.txt", "precious");
  expect_one_line_error(run("report --sections accuracy --no-plots --out " + quote((t.path() / "mine").string()) + " --exp 8 --frac 10"),
                        "not a rayunits report");
  EXPECT_EQ(read_file(t.path() / "mine" / "keep.txt"), "precious");
  // No python with matplotlib: a clear error and nothing left behind.
  fs::path out = t.path() / "rep";
  expect_one_line_error(run("report --sections accuracy --out " + quote(out.string()) + " --exp 8 --frac 10 --samples 100", "",
                            "RU_PYTHON=/nonexistent/python3"),
                        "matplotlib");
  EXPECT_FALSE(fs::exists(out));
  // A plot script that fails mid-run: error, and no report or temporary directory left.
  fs::create_directories(t.path() / "scripts");
  write_file(t.path() / "scripts" / "plot_accuracy.py", "import sys\nsys.exit(3)\n");
  Proc f = run("report --sections accuracy --quiet --out " + quote(out.string()) + " --exp 8 --frac 10 --samples 100", "",
              "RU_SCRIPTS_DIR=" + quote((t.path() / "scripts").string()));
  EXPECT_NE(f.code, 0);
  EXPECT_NE(f.err.find("plot_accuracy.py failed"), std::string::npos) << f.err;
  EXPECT_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(t.path()))
    EXPECT_EQ(e.path().filename().string().find(".rep."), std::string::npos) << e.path();
}

// The study sections run the project's commands in-process (tiny parameters here); their tables
// come from the CSVs those commands wrote, and every command line is in index.md.
TEST_F(Cli, ReportStudySections) {
  TempDir t;
  fs::path out = t.path() / "rep";
  Proc r = run("report --quiet --no-plots --out " + quote(out.string()) +
               " --sections accuracy,synthesis,intersection,noise --exp 5 --frac 10 --samples 200"
               " --param synthesis.units=fp_add --param synthesis.formats=e5m10 --param synthesis.stages=0,1"
               " --param synthesis.fpga=0 --param intersection.tri_pairs=256 --param intersection.box_pairs=2000"
               " --param intersection.rays=400 --param intersection.watertight_formats=e5m10"
               " --param intersection.synth=0 --param noise.size=64 --param noise.error_samples=2000"
               " --param noise.range_samples=20000 --param noise.synth=0");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string idx = read_file(out / "index.md");
  for (const char* f : {"synth/synth_sweep.csv", "synth.txt", "tri.txt", "box.csv", "watertight.csv",
                        "watertight_sweep/results.jsonl", "noise/noise_summary.md", "noise.txt"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  // command lines relative to the report directory, reproducible with `cd REPORT && ...`
  EXPECT_NE(idx.find("rayunits synth-sweep --out synth --units fp_add"), std::string::npos) << idx;
  EXPECT_NE(idx.find("rayunits study box --synthetic 2000"), std::string::npos) << idx;
  const std::string body = idx.substr(idx.find("## Contents"));  // after the report's own command line
  EXPECT_EQ(body.find(t.path().string()), std::string::npos) << "absolute paths leaked into the sections";
  EXPECT_EQ(count_lines(r.err), 1) << r.err;  // "report: done"; the commands' progress went to .log files
  EXPECT_TRUE(fs::exists(out / "synth.log"));
  // the synthesis table: two rows of fp_add e5m10, Stages 1 has registers
  EXPECT_NE(idx.find("| fp_add | e5m10 | 0 |"), std::string::npos) << idx;
  EXPECT_NE(idx.find("| fp_add | e5m10 | 1 |"), std::string::npos) << idx;
  // cost from the cell-library flow; the fo4-v1 estimate never as a frequency
  // (the report's cell table: area and STA Fmax at the fastest and the smallest mapping, osu018)
  EXPECT_NE(idx.find("area (um2, fastest) | Fmax (MHz, fastest)"), std::string::npos) << idx;
  EXPECT_NE(idx.find("osu018"), std::string::npos) << idx;
  EXPECT_EQ(idx.find("Fmax est."), std::string::npos) << idx;
  EXPECT_TRUE(fs::exists(out / "synth_osu018.jsonl"));
  // speed and accuracy side by side: the accuracy section ran first in the same report
  EXPECT_NE(idx.find("mean rel. error"), std::string::npos) << idx;
  {
    // ... with the accuracy section's own numbers (its accuracy.csv row e5m10 add, column 6)
    std::ifstream csv(out / "accuracy.csv");
    std::string line, mean;
    while (std::getline(csv, line))
      if (line.rfind("5,10,e5m10,add,", 0) == 0) {
        std::stringstream ss(line);
        for (int i = 0; i <= 6 && std::getline(ss, mean, ','); ++i) {
        }
      }
    ASSERT_FALSE(mean.empty());
    char b[32];
    std::snprintf(b, sizeof b, "%.3g", std::atof(mean.c_str()));
    const size_t side = idx.find("Speed and accuracy side by side");
    ASSERT_NE(side, std::string::npos);
    const size_t row = idx.find("| fp_add | e5m10 |", side);
    ASSERT_NE(row, std::string::npos) << idx.substr(side);
    // | unit | format | area | Fmax | mean rel. error | max rel. error | out of range |
    std::vector<std::string> cells;
    std::stringstream rs(idx.substr(row + 1, idx.find('\n', row) - row - 1));
    for (std::string c; std::getline(rs, c, '|');) cells.push_back(c.substr(c.find_first_not_of(' ')));
    ASSERT_GE(cells.size(), 5u);
    EXPECT_EQ(cells[4].substr(0, cells[4].find(' ')), b) << idx.substr(row, 200);
  }
  // watertightness rows for both algorithms
  EXPECT_NE(idx.find("| e5m10 | robust |"), std::string::npos) << idx;
  EXPECT_NE(idx.find("| e5m10 | mt |"), std::string::npos) << idx;
  // a failing study stops the report with its own error line and leaves nothing behind
  fs::path bad = t.path() / "bad";
  expect_one_line_error(run("report --quiet --no-plots --out " + quote(bad.string()) +
                            " --sections intersection --param intersection.tri_pairs=64 --param intersection.box_pairs=100"
                            " --param intersection.watertight_formats=e99m1"),
                        "study watertight");
  EXPECT_FALSE(fs::exists(bad));
}

// The sections' synthesis parts (slow: the cell flow on three e4m3 ray units, measured now: no
// checked-in rows for that format), with plots; the noise rows are read or measured.
using LongCli = Cli;
TEST_F(LongCli, ReportSynthesisPartsWithPlots) {
  TempDir t;
  fs::path out = t.path() / "rep";
  Proc r = run("report --quiet --out " + quote(out.string()) +
               " --sections noise,intersection --param noise.size=64 --param noise.error_samples=2000"
               " --param noise.range_samples=20000 --param noise.stages=0 --param intersection.tri_pairs=256"
               " --param intersection.box_pairs=2000 --param intersection.rays=400"
               " --param intersection.watertight_formats=e5m10 --param intersection.synth_formats=e4m3");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string idx = read_file(out / "index.md");
  EXPECT_NE(idx.find("Ratios (combinational, Stages 0): noise / e8m23 fp_add = "), std::string::npos) << idx;
  EXPECT_NE(idx.find("| e4m3 |"), std::string::npos) << idx;  // robust vs MT area row
  EXPECT_NE(idx.find("noise / fp_dot3 = "), std::string::npos) << idx;  // the cell-flow ratio line
  EXPECT_TRUE(fs::exists(out / "noise_osu018.jsonl"));
  EXPECT_TRUE(fs::exists(out / "ray_osu018.jsonl"));
  // e4m3 has no checked-in row: the three units ran in the sweep engine, one job each
  const std::string res = read_file(out / "ray_osu018_sweep" / "results.jsonl");
  EXPECT_EQ(std::count(res.begin(), res.end(), '\n'), 3) << res;
}

// ------------------------------------------------------------------------------ bench fp
TEST_F(Cli, BenchFpPrintsTheRatioLineLast) {
  Proc r = run("bench fp --format e5m10 --n 512 --reps 1 --min-time 0.001 --no-oracle");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("differ"), std::string::npos) << r.err;  // model == MPFR on every operand
  auto ls = lines(r.out);
  ASSERT_FALSE(ls.empty());
  EXPECT_TRUE(std::regex_match(ls.back(), std::regex(R"(ratio add=[0-9]+\.[0-9] mul=[0-9]+\.[0-9] div=[0-9]+\.[0-9] fma=[0-9]+\.[0-9])")))
      << ls.back();
  expect_one_line_error(run("bench fp --format e1m2"), "invalid format");
}

// bench render: the native line, the emulated ratio line, the target verdicts only at the
// issue's setting, and one-line errors.
TEST_F(Cli, BenchRenderSmallScene) {
  Proc r = run("bench render --scene default --size 32x24 --repeats 3 --emulated e5m10 --threads 2");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(native float: median [0-9.]+ s/frame over 3 = [0-9.]+ frames/s)")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(emulated e5m10: median [0-9.]+ s/frame over 1 = [0-9.]+x native wall-clock)")))
      << r.out;
  EXPECT_NE(r.out.find("n/a for these settings"), std::string::npos) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(768 primary \+ [0-9]+ shadow rays)"))) << r.out;
  expect_one_line_error(run("bench render --scene default --emulated e1m2"), "invalid format");
  expect_one_line_error(run("bench render --scene nope"), "unknown scene");
  expect_one_line_error(run("bench render --scene default --tri fast"), "unknown triangle test");
}

// noise eval prints both fixed-point units; each line's value is its model's at the quantized point
// (u = X / 2); with 4 fraction bits there is no truncated unit, and a bad width is one line.
TEST_F(Cli, NoiseEvalBothUnits) {
  Proc r = run("noise eval 3.14 42 7");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const auto dp : {ru::noise::NoiseDatapath::kFull, ru::noise::NoiseDatapath::kTrunc}) {
    const ru::noise::FixedNoise f(ru::noise::default_config(dp));
    const std::int64_t v = f.eval(f.quantize(3.14 / 2), f.quantize(42.0 / 2), f.quantize(7.0 / 2));
    const std::string line = "fixed (" + f.config().describe() + ")";
    const size_t at = r.out.find(line);
    ASSERT_NE(at, std::string::npos) << r.out;
    EXPECT_NE(r.out.find("(" + std::to_string(v) + ") = N", at), std::string::npos) << line << " " << v << "\n" << r.out;
  }
  Proc b4 = run("noise eval 1 2 3 --frac-bits 4 --out-w 6");
  ASSERT_EQ(b4.code, 0) << b4.err;
  EXPECT_EQ(b4.out.find("trunc"), std::string::npos) << b4.out;
  expect_one_line_error(run("noise eval 1 2 3 --frac-bits 3"), "fraction bits must be 4..16");
}

// render --noise fixed-trunc (ru_noise_trunc's model) against float noise: the reference's noise
// model is named on the line and in the JSON; the same image against itself is exact, the
// noise unit's is not; bad noise names and --compare-noise without --compare are one line and
// leave no PNG.
TEST_F(Cli, RenderCompareNoise) {
  TempDir d;
  const std::string png = (d.path() / "a.png").string(), js = (d.path() / "a.json").string();
  Proc r = run("render --scene default --format double --noise fixed-trunc --compare --compare-noise float --size 48x32 --quiet --out " +
               png + " --json " + js);
  ASSERT_EQ(r.code, 0) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(vs double \(noise float, texture shader\): [0-9]+ pixels .* PSNR ([0-9.]+|inf) dB)"))) << r.out;
  EXPECT_NE(m[1].str(), "inf") << "the noise unit's image equals the float-noise one: the reference did not switch";
  EXPECT_NE(read_file(js).find("\"noise\":\"float\""), std::string::npos) << read_file(js);
  Proc same = run("render --scene default --format double --noise fixed-trunc --compare --size 48x32 --quiet --out " + png);
  ASSERT_EQ(same.code, 0) << same.err;
  EXPECT_NE(same.out.find("vs double (noise fixed-trunc, texture shader): 0 pixels"), std::string::npos) << same.out;
  EXPECT_NE(same.out.find("PSNR inf dB"), std::string::npos) << same.out;
  const std::string bad = (d.path() / "b.png").string();
  expect_one_line_error(run("render --scene default --noise fixed-fast --out " + bad), "accepted: float, fixed, fixed-trunc");
  expect_one_line_error(run("render --scene default --noise fixed --compare-noise float --out " + bad), "--compare-noise needs --compare");
  EXPECT_FALSE(std::filesystem::exists(bad));
}

// render --texture unit (ru_texture's model): against the float shader it differs but stays
// close; against itself it is exact; float noise with the unit is one line and leaves no PNG.
TEST_F(Cli, RenderTextureUnit) {
  TempDir d;
  const std::string png = (d.path() / "t.png").string(), js = (d.path() / "t.json").string();
  Proc r = run("render --scene noisy --format double --noise fixed-trunc --texture unit --compare --compare-noise float "
               "--size 48x32 --quiet --out " + png + " --json " + js);
  ASSERT_EQ(r.code, 0) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(vs double \(noise float, texture shader\): [0-9]+ pixels .* PSNR ([0-9.]+|inf) dB)"))) << r.out;
  ASSERT_NE(m[1].str(), "inf");
  EXPECT_GT(std::stod(m[1].str()), 25.0);
  EXPECT_NE(read_file(js).find("\"texture\":\"unit\""), std::string::npos) << read_file(js);
  EXPECT_NE(read_file(js).find("\"texture_evals\":"), std::string::npos) << read_file(js);
  Proc same = run("render --scene noisy --format double --noise fixed-trunc --texture unit --compare --size 48x32 --quiet --out " + png);
  ASSERT_EQ(same.code, 0) << same.err;
  EXPECT_NE(same.out.find("vs double (noise fixed-trunc, texture unit): 0 pixels"), std::string::npos) << same.out;
  const std::string bad = (d.path() / "b.png").string();
  expect_one_line_error(run("render --scene noisy --texture unit --out " + bad), "--texture unit needs a fixed noise model");
  expect_one_line_error(run("render --scene noisy --noise fixed --texture gpu --out " + bad), "accepted: shader, unit");
  EXPECT_FALSE(std::filesystem::exists(bad));
}

}  // namespace
