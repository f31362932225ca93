// Trace writer/reader round trip, malformed files, and the synthetic generators.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "rayunits/units/exact.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/units/trace.hpp"

using namespace ru::units;

namespace {

std::string tmp_path(const char* name) {
  return std::string(RU_BINARY_DIR) + "/units_test_" + name + "_" + std::to_string(::getpid());
}

std::vector<unsigned char> slurp(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<unsigned char>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}
void spit(const std::string& p, const std::vector<unsigned char>& b) {
  std::ofstream f(p, std::ios::binary);
  f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, 8) == 0; }

TEST(UnitsTrace, RoundTripBitExact) {
  SynthTriOptions to;
  to.triangles = 20;
  SynthBoxOptions bo;
  bo.boxes = 20;
  Trace t;
  t.tris = synth_tri(to);
  t.boxes = synth_box(bo);
  t.tris[3].t_max = 7.25;
  t.boxes[1].inv.x = -INFINITY;
  t.boxes[2].o.y = -0.0;
  const std::string p = tmp_path("rt");
  write_trace(p, t);
  const auto bytes = slurp(p);
  ASSERT_EQ(bytes.size(), 32 + t.tris.size() * 144 + t.boxes.size() * 120);
  EXPECT_EQ(std::memcmp(bytes.data(), "RUTRACE\0", 8), 0);
  EXPECT_EQ(bytes[8], 1);                       // version 1, little endian
  EXPECT_EQ(bytes[16], t.tris.size() & 0xff);   // tri count
  EXPECT_EQ(bytes[32], 1);                      // first record kind: tri
  const Trace r = read_trace(p);
  ASSERT_EQ(r.tris.size(), t.tris.size());
  ASSERT_EQ(r.boxes.size(), t.boxes.size());
  for (size_t i = 0; i < t.tris.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(same_bits(r.tris[i].a[k], t.tris[i].a[k]));
      EXPECT_TRUE(same_bits(r.tris[i].d[k], t.tris[i].d[k]));
      EXPECT_TRUE(same_bits(r.tris[i].p2[k], t.tris[i].p2[k]));
    }
  EXPECT_EQ(r.tris[3].t_max, 7.25);
  for (size_t i = 0; i < t.boxes.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(same_bits(r.boxes[i].o[k], t.boxes[i].o[k]));
      EXPECT_TRUE(same_bits(r.boxes[i].inv[k], t.boxes[i].inv[k]));
      EXPECT_TRUE(same_bits(r.boxes[i].hi[k], t.boxes[i].hi[k]));
    }
  EXPECT_TRUE(same_bits(r.boxes[1].inv.x, -INFINITY));
  EXPECT_TRUE(same_bits(r.boxes[2].o.y, -0.0));
  std::remove(p.c_str());
}

std::string error_of(const std::vector<unsigned char>& bytes) {
  const std::string p = tmp_path("bad");
  spit(p, bytes);
  std::string msg;
  try {
    read_trace(p);
  } catch (const TraceError& e) {
    msg = e.what();
  }
  std::remove(p.c_str());
  return msg;
}

TEST(UnitsTrace, MalformedFilesGiveOneLineErrors) {
  Trace t;
  SynthTriOptions to;
  to.triangles = 2;
  to.rays_per_packet = 2;
  t.tris = synth_tri(to);
  const std::string p = tmp_path("good");
  write_trace(p, t);
  const auto good = slurp(p);
  std::remove(p.c_str());
  ASSERT_EQ(error_of(good), "");

  auto has = [](const std::string& msg, const char* what) {
    return msg.find(what) != std::string::npos && msg.find('\n') == std::string::npos;
  };
  EXPECT_TRUE(has(error_of({}), "not a rayunits trace: 0 bytes"));
  auto b = good;
  b[0] = 'X';
  EXPECT_TRUE(has(error_of(b), "bad magic"));
  b = good;
  b[8] = 7;
  EXPECT_TRUE(has(error_of(b), "unsupported trace version 7"));
  b = good;
  b[12] = 40;
  EXPECT_TRUE(has(error_of(b), "header size 40"));
  b = good;
  b.resize(b.size() - 5);
  EXPECT_TRUE(has(error_of(b), "truncated tri record (139 bytes left, need 144)"));
  b = good;
  b[32 + 144] = 9;
  EXPECT_TRUE(has(error_of(b), "byte 176: unknown record kind 9"));
  b = good;
  b[36] = 1;
  EXPECT_TRUE(has(error_of(b), "reserved field"));
  b = good;
  b[16] = 5;
  EXPECT_TRUE(has(error_of(b), "header says 5 tri + 0 box records, the file holds 4 + 0"));
  b = good;
  b.push_back(1);
  EXPECT_TRUE(has(error_of(b), "truncated record header"));
  // Missing file.
  std::string msg;
  try {
    read_trace("/nonexistent/dir/x.trace");
  } catch (const TraceError& e) {
    msg = e.what();
  }
  EXPECT_TRUE(has(msg, "cannot open"));
}

TEST(UnitsSynthetic, DeterministicAndQuarterHits) {
  SynthTriOptions o;
  o.triangles = 300;
  o.rays_per_packet = 16;
  const auto a = synth_tri(o), b = synth_tri(o);
  ASSERT_EQ(a.size(), 4800u);
  size_t hits = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(same_bits(a[i].d.z, b[i].d.z) && same_bits(a[i].p1.x, b[i].p1.x));
    hits += exact_tri(a[i].a, a[i].d, a[i].p0, a[i].p1, a[i].p2, a[i].t_min, a[i].t_max).hit;
  }
  const double rate = static_cast<double>(hits) / static_cast<double>(a.size());
  EXPECT_NEAR(rate, 0.25, 0.03) << "hit rate " << rate;
  o.seed = 2;
  EXPECT_FALSE(same_bits(synth_tri(o)[0].a.x, a[0].a.x));
}

TEST(UnitsSynthetic, BoxWorkloadHasSpecialRays) {
  SynthBoxOptions o;
  o.boxes = 300;
  const auto recs = synth_box(o);
  size_t hits = 0, inf_inv = 0, on_plane = 0, finite_tmax = 0;
  for (const BoxRecord& r : recs) {
    hits += exact_slab(r.o, r.inv, r.lo, r.hi, r.t_min, r.t_max).hit;
    for (int k = 0; k < 3; ++k) {
      if (std::isinf(r.inv[k])) {
        ++inf_inv;
        on_plane += r.o[k] == r.lo[k] || r.o[k] == r.hi[k];
      }
    }
    finite_tmax += std::isfinite(r.t_max);
  }
  const double rate = static_cast<double>(hits) / static_cast<double>(recs.size());
  EXPECT_GT(rate, 0.3);
  EXPECT_LT(rate, 0.7);
  EXPECT_GT(inf_inv, recs.size() / 20);
  EXPECT_GT(on_plane, recs.size() / 50);
  EXPECT_GT(finite_tmax, recs.size() / 6);
}

}  // namespace
