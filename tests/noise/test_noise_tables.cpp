// The noise table generator and its two generated files (C++ header, Verilog include).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "rayunits/noise/tables.hpp"

namespace ru::noise {
namespace {

std::string read_file(const std::string& rel) {
  std::ifstream in(std::string(RU_SOURCE_DIR) + "/" + rel, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const TableSet& generated() {
  static const TableSet t = generate_tables();
  return t;
}

TEST(NoiseTables, GeneratedFilesAreUpToDate) {
  // The checked-in header and Verilog include must be exactly what the generator writes now.
  EXPECT_EQ(read_file(kGeneratedHeaderPath), render_cpp_header(generated()))
      << kGeneratedHeaderPath << " differs from the generator: run scripts/gen_noise_tables.sh";
  EXPECT_EQ(read_file(kGeneratedSvhPath), render_svh(generated()))
      << kGeneratedSvhPath << " differs from the generator: run scripts/gen_noise_tables.sh";
}

TEST(NoiseTables, DriftIsDetected) {
  // Planted errors: one changed gradient bit or permutation entry changes both renderings.
  TableSet t = generated();
  t.grad64_q16[17][1] += 1;
  EXPECT_NE(render_svh(t), render_svh(generated()));
  EXPECT_NE(render_cpp_header(t), render_cpp_header(generated()));
  TableSet u = generated();
  std::swap(u.perm_y[3], u.perm_y[200]);
  EXPECT_NE(render_svh(u), render_svh(generated()));
  EXPECT_NE(render_cpp_header(u), render_cpp_header(generated()));
}

TEST(NoiseTables, BuiltinEqualsGenerator) {
  const TableSet& b = builtin_tables();
  const TableSet& g = generated();
  EXPECT_EQ(b.seed, g.seed);
  EXPECT_EQ(b.perm_x, g.perm_x);
  EXPECT_EQ(b.perm_y, g.perm_y);
  EXPECT_EQ(b.perm_z, g.perm_z);
  ASSERT_EQ(b.grad256.size(), 256u);
  ASSERT_EQ(b.grad64.size(), 64u);
  for (int i = 0; i < 256; ++i) {
    EXPECT_EQ(b.grad256[i].x, g.grad256[i].x);
    EXPECT_EQ(b.grad256[i].y, g.grad256[i].y);
    EXPECT_EQ(b.grad256[i].z, g.grad256[i].z);
  }
  for (int i = 0; i < 64; ++i) {
    EXPECT_EQ(b.grad64[i].x, g.grad64[i].x);
    EXPECT_EQ(b.grad64[i].z, g.grad64[i].z);
    EXPECT_EQ(b.grad64_q16[i], g.grad64_q16[i]);
  }
}

TEST(NoiseTables, PermutationsArePermutationsAndDistinct) {
  const TableSet& t = builtin_tables();
  for (const auto* p : {&t.perm_x, &t.perm_y, &t.perm_z, &kPerlinPermutation}) {
    std::set<int> s(p->begin(), p->end());
    EXPECT_EQ(s.size(), 256u);
  }
  EXPECT_NE(t.perm_x, t.perm_y);
  EXPECT_NE(t.perm_y, t.perm_z);
  EXPECT_NE(t.perm_x, t.perm_z);
  // Perlin's published table starts 151, 160, 137, 91 and ends 156, 180.
  EXPECT_EQ(kPerlinPermutation[0], 151);
  EXPECT_EQ(kPerlinPermutation[3], 91);
  EXPECT_EQ(kPerlinPermutation[255], 180);
}

TEST(NoiseTables, GradientsAreRelaxedUnitVectors) {
  const TableSet& g = generated();
  for (const auto* tab : {&g.grad256, &g.grad64}) {
    Vec3 mean{};
    for (const Vec3& v : *tab) {
      EXPECT_NEAR(std::sqrt(dot(v, v)), 1.0, 1e-15);
      mean = mean + v;
    }
    mean = (1.0 / tab->size()) * mean;
    EXPECT_LT(std::sqrt(dot(mean, mean)), 0.01);  // a relaxed set has (almost) no dipole moment
  }
  // Relaxation lowers the Coulomb energy and spreads the closest pair apart.
  for (const RelaxStats* r : {&g.relax256, &g.relax64}) {
    EXPECT_LT(r->energy_final, r->energy_initial * 0.96);
    EXPECT_GT(r->min_dist_final, 2 * r->min_dist_initial);
    EXPECT_LT(r->max_tangential_force, 1e-3);  // (near) equilibrium
  }
  // Independent reference: the minimum energy of 64 charges on the unit sphere (Thomson
  // problem, published tables) is 1765.802577927. The relaxed set must be within 0.001% of it.
  EXPECT_NEAR(g.relax64.energy_final, 1765.802577927, 1765.8 * 1e-5);
  EXPECT_DOUBLE_EQ(coulomb_energy(g.grad64), g.relax64.energy_final);
}

TEST(NoiseTables, Q16IsRoundedGradient) {
  const TableSet& t = builtin_tables();
  for (int i = 0; i < 64; ++i) {
    const double c[3] = {t.grad64[i].x, t.grad64[i].y, t.grad64[i].z};
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(std::fabs(t.grad64_q16[i][a] - c[a] * 65536.0), 0.5);
      EXPECT_LE(std::abs(t.grad64_q16[i][a]), 65536);
    }
  }
}

// The Verilog include, read back with a parser independent of the generator's code: every
// hash entry i must be {P[(i+1) mod 256] mod 64, P[i] mod 64}, every gradient {z, y, x} in Q1.16.
TEST(NoiseTables, SvhEncodesTheTables) {
  const TableSet& t = builtin_tables();
  const std::string svh = read_file(kGeneratedSvhPath);
  std::regex hash_re(R"(8'd(\d+): ru_noise_hash_([xyz]) = \{6'd(\d+), 6'd(\d+)\};)");
  int hash_entries = 0;
  for (auto it = std::sregex_iterator(svh.begin(), svh.end(), hash_re); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    int i = std::stoi(m[1]), hi = std::stoi(m[3]), lo = std::stoi(m[4]);
    const auto& p = m[2] == "x" ? t.perm_x : m[2] == "y" ? t.perm_y : t.perm_z;
    EXPECT_EQ(lo, p[i] % 64) << m[0];
    EXPECT_EQ(hi, p[(i + 1) % 256] % 64) << m[0];
    ++hash_entries;
  }
  EXPECT_EQ(hash_entries, 3 * 256);
  std::regex grad_re(
      R"(6'd(\d+): ru_noise_grad = \{ru_noise_gq\((-?)18'sd(\d+)\), ru_noise_gq\((-?)18'sd(\d+)\), ru_noise_gq\((-?)18'sd(\d+)\)\};)");
  int grad_entries = 0;
  for (auto it = std::sregex_iterator(svh.begin(), svh.end(), grad_re); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    int i = std::stoi(m[1]);
    auto val = [&](int k) { return (m[k] == "-" ? -1 : 1) * std::stoi(m[k + 1]); };
    EXPECT_EQ(val(2), t.grad64_q16[i][2]);
    EXPECT_EQ(val(4), t.grad64_q16[i][1]);
    EXPECT_EQ(val(6), t.grad64_q16[i][0]);
    ++grad_entries;
  }
  EXPECT_EQ(grad_entries, 64);
}

TEST(NoiseTables, GeneratorIsDeterministicAndSeeded) {
  TableSet a = generate_tables(12345), b = generate_tables(12345);
  EXPECT_EQ(a.perm_x, b.perm_x);
  EXPECT_EQ(a.grad64_q16, b.grad64_q16);
  EXPECT_NE(a.perm_x, generated().perm_x);
}

}  // namespace
}  // namespace ru::noise
