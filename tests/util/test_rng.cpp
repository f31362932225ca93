// Pins the first outputs of every pseudo-random stream of the project, as each area uses it.
// The expected numbers were printed by the code BEFORE the generators were merged into
// rayunits/util/rng.hpp (a scratch program linked against the old library, with the old tb
// harness and CLI/test copies pasted verbatim): every former copy's stream must stay bit for
// bit what it was, because published numbers and checked-in tables depend on them.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "rayunits/noise/tables.hpp"
#include "rayunits/num/patterns.hpp"
#include "rayunits/report/accuracy.hpp"
#include "rayunits/scene/scene.hpp"
#include "rayunits/units/synthetic.hpp"
#include "rayunits/util/rng.hpp"

namespace {

using u64 = std::uint64_t;
using V = std::vector<u64>;

u64 dbits(double d) {
  u64 u;
  std::memcpy(&u, &d, 8);
  return u;
}

// FNV-1a over the triangle count and every vertex coordinate's bits.
u64 scene_hash(const ru::scene::Scene& s) {
  u64 h = 1469598103934665603ull;
  auto mix = [&](u64 x) {
    for (int i = 0; i < 8; ++i) h = (h ^ ((x >> (8 * i)) & 0xff)) * 1099511628211ull;
  };
  mix(s.tris.size());
  for (const auto& t : s.tris)
    for (const auto& p : t.p) {
      mix(dbits(p.x));
      mix(dbits(p.y));
      mix(dbits(p.z));
    }
  return h;
}

template <class F>
V take(int n, F f) {
  V v;
  for (int i = 0; i < n; ++i) v.push_back(f());
  return v;
}

// --- splitmix64 streams ------------------------------------------------------------------

TEST(RngPin, Splitmix64Seed1) {  // model/cli/cmd_bench_fp.cpp operands, tests/num/test_format.cpp mix
  u64 s = 1;
  EXPECT_EQ(take(8, [&] { return ru::util::splitmix64(s); }),
            (V{0x910a2dec89025cc1ull, 0xbeeb8da1658eec67ull, 0xf893a2eefb32555eull, 0x71c18690ee42c90bull,
               0x71bb54d8d101b5b9ull, 0xc34d0bff90150280ull, 0xe099ec6cd7363ca5ull, 0x85e7bb0f12278575ull}));
}

TEST(RngPin, Splitmix64Seed42AsObject) {  // scene/procedural.cpp (arch scene: Rng(42))
  ru::util::SplitMix64 g(42);
  EXPECT_EQ(take(8, [&] { return g.next(); }),
            (V{0xbdd732262feb6e95ull, 0x28efe333b266f103ull, 0x47526757130f9f52ull, 0x581ce1ff0e4ae394ull,
               0x09bc585a244823f2ull, 0xde4431fa3c80db06ull, 0x37e9671c45376d5dull, 0xccf635ee9e9e2fa4ull}));
}

TEST(RngPin, Splitmix64NoiseTableSeed) {  // noise/tables_gen.cpp, the checked-in noise tables
  u64 s = ru::noise::kTableSeed;
  EXPECT_EQ(take(8, [&] { return ru::util::splitmix64(s); }),
            (V{0xe396fdfb46683a90ull, 0x4142c16333a10a74ull, 0x3c00ba9a133b5fa7ull, 0x70d9b96a5a45c534ull,
               0xe5f3707d35363113ull, 0xc2b1bd6c14f33999ull, 0x1e1f7c6abeeeb2e1ull, 0x0850d928c3681482ull}));
  EXPECT_EQ(s, 0x3d213c3f66b952b1ull);
}

TEST(RngPin, Splitmix64RunUniform) {  // tests/num/harness.cpp run_uniform, seed 3
  u64 x = 3 * 0x2545F4914F6CDD1Dull + 1;
  EXPECT_EQ(take(8, [&] { return ru::util::splitmix64(x); }),
            (V{0x2bb4d12762ae4eb0ull, 0xe21be7e1e91af93eull, 0x3ee432045868e815ull, 0xaecd38c6fc0f1ac2ull,
               0x01b96494d7ad9a58ull, 0x8ad75df28fe76c33ull, 0x651d02370dafee7cull, 0xbd64162af2e75b00ull}));
}

// --- xoshiro256** streams ------------------------------------------------------------------

const V kXoshiroSeed1 = {0xb3f2af6d0fc710c5ull, 0x853b559647364ceaull, 0x92f89756082a4514ull,
                         0x642e1c7bc266a3a7ull, 0xb27a48e29a233673ull, 0x24c123126ffda722ull,
                         0x123004ef8df510e6ull, 0x61954dcc47b1e89dull};

TEST(RngPin, Xoshiro256ssSeed1) {  // tb/src/harness.cpp Rng(1) and units::Rng(1) (the same stream)
  ru::util::Xoshiro256ss g(1);
  EXPECT_EQ(take(8, [&] { return g.next(); }), kXoshiroSeed1);
}

TEST(RngPin, TbRngBelowChanceMixSeed) {  // tb/src/harness.cpp: Rng::below (Lemire), chance, mix_seed
  ru::util::Xoshiro256ss g(2024);
  EXPECT_EQ(take(8, [&] { return ru::util::bounded_lemire(g, 37); }), (V{2, 28, 2, 5, 28, 9, 14, 9}));
  ru::util::Xoshiro256ss c(5);
  u64 bits = 0;
  for (int i = 0; i < 64; ++i) bits |= u64(ru::util::bounded_lemire(c, 3) < 1) << i;
  EXPECT_EQ(bits, 0x4418a9400c400801ull);
  EXPECT_EQ(ru::util::mix_seed(1, "fp_add"), 0x27d41aa111a17030ull);
  EXPECT_EQ(ru::util::mix_seed(0, ""), 0x4ea0537ff367da6bull);
  EXPECT_EQ(ru::util::mix_seed(0xdeadbeef, "random"), 0xe0dedcb0d51386e9ull);
}

TEST(RngPin, UnitsRng) {  // units/synthetic.cpp Rng: next, below (modulo rejection), uniform, unit_vector
  ru::units::Rng a(1);
  EXPECT_EQ(take(8, [&] { return a.next(); }), kXoshiroSeed1);
  ru::units::Rng b(12345);
  EXPECT_EQ(take(8, [&] { return b.below(1000); }), (V{483, 998, 256, 395, 344, 396, 809, 710}));
  ru::units::Rng c(7);
  V got = take(4, [&] { return dbits(c.uniform(-1.0, 3.0)); });
  const auto u = c.unit_vector();
  got.push_back(dbits(u.x));
  got.push_back(dbits(u.y));
  got.push_back(dbits(u.z));
  EXPECT_EQ(got, (V{0x3ffcd63ebdd3be5cull, 0x3fbd70f6593d20a0ull, 0x4002de3a6932a58full, 0x400765270e63d00eull,
                    0x3fb54231e021a8ffull, 0x3fddc9a3a6d9d6a6ull, 0x3fec329f1eb00a26ull}));
}

TEST(RngPin, OperandGen) {  // num/patterns.cpp OperandGen (format-mixed seed, Lemire below)
  ru::num::OperandGen g(ru::num::Format{8, 23}, 1);
  EXPECT_EQ(take(8, [&] { return g.next(); }),
            (V{0x019e979dull, 0x007ffffeull, 0x849843ceull, 0xbf400000ull, 0xe2ffffffull, 0xd77f07ffull,
               0xf5ce317aull, 0xcaf6e6cbull}));
  ru::num::OperandGen h(ru::num::Format{5, 10}, 0x1234);
  V p;
  for (int i = 0; i < 4; ++i) {
    u64 a, b;
    h.pair(a, b);
    p.push_back(a);
    p.push_back(b);
  }
  EXPECT_EQ(p, (V{0x1990, 0x0bd1, 0xbe00, 0x3a00, 0x3000, 0xde69, 0x5a00, 0x5d12}));
  ru::num::OperandGen k(ru::num::Format{11, 52}, 99);
  V t;
  for (int i = 0; i < 2; ++i) {
    u64 a, b, c;
    k.triple(a, b, c);
    t.insert(t.end(), {a, b, c});
  }
  EXPECT_EQ(t, (V{0x8c9ffffffffffff1ull, 0x30206af13f901d57ull, 0xeaa4e7b7aa66c1a0ull, 0xb870000000000006ull,
                  0x346ffffffffffff3ull, 0x001cf6f9da932bcfull}));
}

TEST(RngPin, ProceduralScenes) {  // scene/procedural.cpp: arch (Rng(42)) and balls (Rng(7))
  EXPECT_EQ(scene_hash(ru::scene::make_scene("arch")), 0x0be4b53247cca5b7ull);
  EXPECT_EQ(scene_hash(ru::scene::make_animation_frame("balls", 1, 4)), 0xcda79ddd150924a7ull);
  EXPECT_EQ(scene_hash(ru::scene::make_animation_frame("balls", 3, 4)), 0x34323b77593c065full);
}

TEST(RngPin, AccuracyWorkload) {  // report/accuracy.cpp make_workload (multiply-shift below)
  const ru::report::Workload w = ru::report::make_workload(3, 1, -10, 10);
  V got;
  for (int k = 0; k < ru::report::kAccOps; ++k)
    for (size_t i = 0; i < w.in[k].size() && i < 4; ++i) got.push_back(dbits(w.in[k][i]));
  EXPECT_EQ(got, (V{0x400beeb8da1658eeull, 0x3fe71bb54d8d101bull, 0x40785e7bb0f12278ull, 0x4056775dc7701564ull,
                    0x403e263183773ef6ull, 0x3f67ef1fd0ed1548ull, 0xbfb0c43407dc177bull, 0x4030b331645445bcull,
                    0x400bf8c59bb00355ull, 0xc03dca0c749607e2ull, 0xbf9a7ff0d388687full, 0x406530e0e6118e96ull,
                    0xbfd167587272751eull, 0x3f8f55540b2bff06ull, 0x4001180b23a1075bull,
                    0x400b86c9a98359e0ull}));
}

TEST(RngPin, BoundedHelpers) {  // the three [0, n) mappings, on one known stream
  ru::util::Xoshiro256ss a(12345);
  EXPECT_EQ(take(8, [&] { return ru::util::bounded_modulo(a, 1000); }), (V{483, 998, 256, 395, 344, 396, 809, 710}));
  ru::util::SplitMix64 s(1);
  // accuracy's exponent draw: e = emin + bounded_mulshift(g, span) with the seed-1 stream
  EXPECT_EQ(ru::util::bounded_mulshift(s, 21), (0x910a2dec89025cc1ull * (unsigned __int128)21) >> 64);
  EXPECT_EQ(ru::util::unit_double(~0ull), 1.0 - 0x1p-53);
  EXPECT_EQ(ru::util::unit_double(0), 0.0);
}

}  // namespace
