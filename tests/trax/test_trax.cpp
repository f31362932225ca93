// TRaX model: micro-kernels against hand-computed schedules, the frame buffer against the
// renderer pixel for pixel, determinism, configuration errors.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "rayunits/render/render.hpp"
#include "rayunits/scene/scene.hpp"
#include "rayunits/trax/trax.hpp"

using namespace ru::trax;

namespace {

// A chip of one TM with `tps` TPs; every unit latency 1 unless a test says otherwise.
Config tiny(int tps = 1) {
  Config c = default_config();
  c.tms = 1;
  c.tps_per_tm = tps;
  c.atomic_latency = 1;
  return c;
}

// N dependent adds: the first reads the work item register.
FunctionWork add_chain(int n) {
  return FunctionWork(1, [n](uint64_t, Thread& t) {
    uint32_t r = Thread::kItemReg;
    for (int i = 0; i < n; ++i) r = t.emit(Op::FAdd, {r});
  });
}

::testing::AssertionResult chain_takes(const Config& c, int n, uint64_t expected) {
  FunctionWork w = add_chain(n);
  const SimStats s = simulate(c, w);
  if (s.cycles == expected) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "cycles " << s.cycles << ", expected " << expected;
}

}  // namespace

// Hand schedule, 1 TP, fp_add latency 2, atomic latency 1, N = 10:
//   cycle 0: Atomic (item 0), item register ready at 1
//   add k (k = 1..N) issues at 1 + 2(k-1) (each waits for the previous result), so add 10 at 19,
//   ready at 21; cycle 20: the next Atomic finds no work, the TP halts, ready at 21.
//   total = 2N + 1 = 21 cycles; a dependency stall between consecutive adds: N - 1 = 9.
TEST(TraxTiming, DependentAddChain) {
  Config c = tiny();
  c.unit(Unit::FpAdd).latency = 2;
  FunctionWork w = add_chain(10);
  const SimStats s = simulate(c, w);
  EXPECT_EQ(s.cycles, 21u);
  EXPECT_EQ(s.instructions, 12u);  // 2 atomics + 10 adds
  EXPECT_EQ(s.stall_dependency, 9u);
  EXPECT_EQ(s.stall_memory, 0u);
  EXPECT_EQ(s.stall_contention, 0u);
  EXPECT_EQ(s.unit_ops[static_cast<int>(Unit::FpAdd)], 10u);
  EXPECT_EQ(s.max_live_registers, 2u);  // at every add: its operand and its result
}

// Planted error: the same checker with latency 3 (adds at 1 + 3(k-1), total 3N + 1 = 31) must
// reject the latency-2 answer 21 and accept 31.
TEST(TraxTiming, PlantedLatencyChangeIsCaught) {
  Config c = tiny();
  c.unit(Unit::FpAdd).latency = 3;
  EXPECT_FALSE(chain_takes(c, 10, 21));
  EXPECT_TRUE(chain_takes(c, 10, 31));
  c.unit(Unit::FpAdd).latency = 2;
  EXPECT_TRUE(chain_takes(c, 10, 21));
}

// Two TPs, one multiplier of width 1, latency 4, each item 3 independent muls (reading the item).
// TP priority rotates: cycle c serves TP (c mod 2) first.
//   c0: TP0 Atomic (item 0); TP1 wants the Atomic: taken -> contention
//   c1: TP1 Atomic (item 1); TP0 mul#1
//   c2: TP0 mul#2;  TP1 mul#1 blocked (unit taken) -> contention
//   c3: TP1 mul#1;  TP0 mul#3 -> contention
//   c4: TP0 mul#3 (ready 8); TP1 mul#2 -> contention
//   c5: TP1 mul#2;  TP0 Atomic: no work, halts (ready 6)
//   c6: TP1 mul#3 (ready 10)  c7: TP1 Atomic, halts (ready 8)
//   total 10 cycles, 4 contention stalls, 6 muls.
TEST(TraxTiming, TwoThreadsContendForOneUnit) {
  Config c = tiny(2);
  c.unit(Unit::FpMul) = {4, 1, 1, 0};
  FunctionWork w(2, [](uint64_t, Thread& t) {
    for (int i = 0; i < 3; ++i) t.emit(Op::FMul, {Thread::kItemReg});
  });
  const SimStats s = simulate(c, w);
  EXPECT_EQ(s.cycles, 10u);
  EXPECT_EQ(s.stall_contention, 4u);
  EXPECT_EQ(s.unit_ops[static_cast<int>(Unit::FpMul)], 6u);
  // Width 2: c1 TP0#1; c2 TP0#2 TP1#1; c3 TP1#2 TP0#3 (ready 7); c4 TP0 halts, TP1#3 (ready 8);
  // c5 TP1 halts (ready 6): total 8; only the c0 Atomic collision stalls.
  c.unit(Unit::FpMul).width = 2;
  FunctionWork w2(2, [](uint64_t, Thread& t) {
    for (int i = 0; i < 3; ++i) t.emit(Op::FMul, {Thread::kItemReg});
  });
  const SimStats s2 = simulate(c, w2);
  EXPECT_EQ(s2.cycles, 8u);
  EXPECT_EQ(s2.stall_contention, 1u);
  // count 2 x width 1 is the same capacity
  c.unit(Unit::FpMul).width = 1;
  c.unit(Unit::FpMul).count = 2;
  FunctionWork w3(2, [](uint64_t, Thread& t) {
    for (int i = 0; i < 3; ++i) t.emit(Op::FMul, {Thread::kItemReg});
  });
  EXPECT_EQ(simulate(c, w3).cycles, 8u);
}

// One TP: a load that misses everywhere, then a dependent load of the same line (an L1 hit).
// L1 latency 1, L2 latency 3, DRAM latency 100, 16 B/cycle, 64 B lines (transfer 4 cycles).
//   c0 Atomic, item ready at 1
//   c1 load#1: L1 miss, L2 request at 2 (bank free) -> L2 miss, DRAM at 2 + 3 = 5,
//      begins 5, channel busy to 9, data ready at 9 + 100 = 109
//   c109 load#2: L1 hit, ready 110;  c110 Atomic, halt, ready 111  -> 111 cycles
//   memory stalls: cycles 2..108 = 107
TEST(TraxTiming, LoadMissThenHit) {
  Config c = tiny();
  c.l1 = {32768, 4, 64, 1, 1};
  c.l2 = {524288, 8, 64, 3, 1};
  c.dram_latency = 100;
  c.dram_bytes_per_cycle = 16;
  FunctionWork w(1, [](uint64_t, Thread& t) {
    const uint32_t a = t.load(0x1000, Thread::kItemReg);
    t.load(0x1008, a);
  });
  const SimStats s = simulate(c, w);
  EXPECT_EQ(s.cycles, 111u);
  EXPECT_EQ(s.stall_memory, 107u);
  EXPECT_EQ(s.l1.accesses, 2u);
  EXPECT_EQ(s.l1.misses, 1u);
  EXPECT_EQ(s.l1.hits, 1u);
  EXPECT_EQ(s.l2.misses, 1u);
  EXPECT_EQ(s.dram_read_bytes, 64u);
  // Planted change: DRAM latency 50 -> 61 cycles.
  c.dram_latency = 50;
  FunctionWork w2(1, [](uint64_t, Thread& t) {
    const uint32_t a = t.load(0x1000, Thread::kItemReg);
    t.load(0x1008, a);
  });
  EXPECT_EQ(simulate(c, w2).cycles, 61u);
}

// Two loads in the same cycle to the same L1 bank: one TP stalls a cycle (bank conflict), then
// hits the line still in flight (a pending hit: ready when the fill arrives). fp_add latency 1.
// Item 0 does two dependent adds before its load, item 1 one add, so both loads want cycle 3:
//   c0 TP0 Atomic (item 0, ready 1); TP1 collides on the Atomic
//   c1 TP1 Atomic (item 1, ready 2); TP0 add#1      c2 TP0 add#2; TP1 add#1 (both ready 3)
//   c3 TP1 first: load miss -> L2 at 4, miss, DRAM at 4 + 3 = 7, busy to 11, ready 111;
//      TP0: same bank taken -> memory stall (bank conflict)
//   c4 TP0 load: line in flight -> pending hit, ready 111; TP1 Atomic: no work, halts
//   c5 TP0 Atomic, halts                                          -> 111 cycles
// Bank mapping ([l1] interleave): two loads in the same cycle (as in BankConflictThenPendingHit)
// to 0x2000 and 0x2004 share line 0x2000 -- one bank when line-interleaved (a conflict), banks 0
// and 1 when word-interleaved (4-byte words: 0x800 mod 4 = 0, 0x801 mod 4 = 1); 0x2000 and 0x2040
// are banks 0 and 1 by line but both bank 0 by word (0x810 mod 4 = 0).
TEST(TraxTiming, WordInterleavedBanks) {
  struct Case {
    bool word;
    uint64_t second;
    uint64_t conflicts;
  };
  for (const Case& k : {Case{false, 0x2004, 1}, Case{true, 0x2004, 0}, Case{false, 0x2040, 0}, Case{true, 0x2040, 1}}) {
    Config c = tiny(2);
    c.unit(Unit::FpAdd).latency = 1;
    c.l1.word_interleave = k.word;
    FunctionWork w(2, [&](uint64_t item, Thread& t) {
      uint32_t r = t.emit(Op::FAdd, {Thread::kItemReg});
      if (item == 0) r = t.emit(Op::FAdd, {r});
      t.load(item == 0 ? 0x2000 : k.second, r);
    });
    EXPECT_EQ(simulate(c, w).bank_conflicts, k.conflicts) << (k.word ? "word " : "line ") << std::hex << k.second;
  }
}

TEST(TraxTiming, BankConflictThenPendingHit) {
  Config c = tiny(2);
  c.unit(Unit::FpAdd).latency = 1;
  FunctionWork w(2, [](uint64_t item, Thread& t) {
    uint32_t r = t.emit(Op::FAdd, {Thread::kItemReg});
    if (item == 0) r = t.emit(Op::FAdd, {r});
    t.load(0x2000, r);
  });
  const SimStats s = simulate(c, w);
  EXPECT_EQ(s.bank_conflicts, 1u);
  EXPECT_EQ(s.l1.misses, 1u);
  EXPECT_EQ(s.l1.pending_hits, 1u);
  EXPECT_EQ(s.l2.accesses, 1u);
  EXPECT_EQ(s.cycles, 111u);
  // Different banks (line 0x2000 -> bank 0, line 0x2040 -> bank 1): no conflict, two misses;
  // the second L2 request (c3 + 1 = 4, another L2 bank) reaches DRAM at 7 but the channel is
  // busy until 11: ready 11 + 4 + 100 = 115.
  FunctionWork w2(2, [](uint64_t item, Thread& t) {
    uint32_t r = t.emit(Op::FAdd, {Thread::kItemReg});
    if (item == 0) r = t.emit(Op::FAdd, {r});
    t.load(item == 0 ? 0x2000 : 0x2040, r);
  });
  const SimStats s2 = simulate(c, w2);
  EXPECT_EQ(s2.bank_conflicts, 0u);
  EXPECT_EQ(s2.l1.misses, 2u);
  EXPECT_EQ(s2.cycles, 115u);
}

namespace {
ru::scene::Scene scene16() { return ru::scene::make_scene("default"); }

void expect_same_image(const Config& c, int w, int h, bool check_counts, const char* scene = "default") {
  const ru::scene::Scene s = ru::scene::make_scene(scene);
  const TraxResult r = run_trax(s, c, w, h);
  ru::render::RenderOptions o = render_options(c, w, h);
  if (c.format == "float") o.format = "float";  // native float: must equal the emulated e8m23
  ru::render::RenderStats st;
  const ru::render::Image ref = ru::render::render(s, o, &st);
  ASSERT_EQ(ref.rgb.size(), r.image.rgb.size());
  size_t diff = 0;
  for (size_t i = 0; i < ref.rgb.size(); ++i)
    if (std::memcmp(&ref.rgb[i], &r.image.rgb[i], sizeof(float)) != 0) ++diff;
  EXPECT_EQ(diff, 0u) << c.format << " " << c.tri << " " << c.traversal;
  EXPECT_EQ(r.primary_rays, st.primary_rays);
  EXPECT_EQ(r.shadow_rays, st.shadow_rays);
  EXPECT_EQ(r.noise_evals, st.noise_evals);
  EXPECT_EQ(r.texture_evals, st.texture_evals);
  EXPECT_EQ(r.sim.unit_ops[static_cast<int>(Unit::Texture)], st.texture_evals);
  if (check_counts) {  // the stack traversal tests exactly the renderer's pairs
    EXPECT_EQ(r.box_tests, st.box_tests);
    EXPECT_EQ(r.tri_tests, st.tri_tests);
  }
  EXPECT_GT(r.sim.cycles, 0u);
}
}  // namespace

TEST(TraxImage, FloatEqualsRendererPixelForPixel) {
  Config c = default_config();
  c.format = "float";
  expect_same_image(c, 16, 16, true);
}

TEST(TraxImage, ReducedFormatsEqualRenderer) {
  Config c = default_config();
  c.format = "e6m12";
  c.tri = "mt";
  expect_same_image(c, 16, 12, true);
  c.format = "e5m10";
  c.tri = "robust";
  c.noise = "float";
  expect_same_image(c, 12, 16, true);
}

// Scene data in the format (issue 16): packed values change addresses, not values (the image is
// the renderer's in both layouts; "word" is the layout before issue 16); boxes in a narrower
// format rounded outward (chip.box_format) give the renderer's --box-format image too.
TEST(TraxImage, SceneStorageAndBoxFormatEqualRenderer) {
  Config c = default_config();
  c.format = "e6m12";
  expect_same_image(c, 12, 12, true);
  c.scene_storage = "word";
  expect_same_image(c, 12, 12, true);
  c.scene_storage = "format";
  c.box_format = "e5m8";
  expect_same_image(c, 12, 12, true);
  c.box_format = "e7m8";  // exponent wider than e6m12's: refused with one line naming the key
  EXPECT_THROW(c.validate("test"), ConfigError);
  c.box_format = "e5m8-ftz";
  EXPECT_THROW(c.validate("test"), ConfigError);
}

// chip.fma (issue 16): the kernel's multiply-adds on the fp_fma unit give the renderer's --fma
// image (materials, volume, camera, shading); the fused pairs leave FMUL and FADD (each FFMA
// replaces one of each where the branches are the same), and without chip.fma no FFMA is issued and no fp_fma unit is on the chip.
TEST(TraxImage, FmaEqualsRenderer) {
  for (const char* scene : {"noisy", "smoke"}) {
    SCOPED_TRACE(scene);
    Config c = default_config();
    c.format = "e6m12";
    const TraxResult plain = run_trax(ru::scene::make_scene(scene), c, 8, 8);
    c.fma = true;
    expect_same_image(c, 8, 8, true, scene);
    const TraxResult fused = run_trax(ru::scene::make_scene(scene), c, 8, 8);
    const auto ops = [](const TraxResult& r, Op op) { return r.sim.op_count[static_cast<int>(op)]; };
    EXPECT_EQ(ops(plain, Op::FFma), 0u);
    EXPECT_EQ(plain.sim.unit_ops[static_cast<int>(Unit::FpFma)], 0u);
    const uint64_t n = ops(fused, Op::FFma);
    EXPECT_GT(n, 64u * 20u);
    EXPECT_EQ(fused.sim.unit_ops[static_cast<int>(Unit::FpFma)], n);
    EXPECT_GT(fused.area.units, plain.area.units);
    if (std::string(scene) == "smoke") continue;  // its density test branches on the fused values
    // noisy: the same branches taken (same unit tests), so each FFMA replaces one FMUL and one FADD
    EXPECT_EQ(ops(plain, Op::Box), ops(fused, Op::Box));
    EXPECT_EQ(ops(plain, Op::Tri), ops(fused, Op::Tri));
    EXPECT_EQ(ops(plain, Op::FCmp), ops(fused, Op::FCmp));
    EXPECT_EQ(ops(plain, Op::FMul) - ops(fused, Op::FMul), n);
    EXPECT_EQ(ops(plain, Op::FAdd) - ops(fused, Op::FAdd), n);
  }
}

// Bytes per node and per triangle follow the format (packed values; header and parent link 16 B,
// nodes 4-byte aligned) or are the old 32-bit words (nodes 16-byte aligned).
TEST(TraxLayout, BytesPerNodeAndTriangle) {
  struct Case {
    const char* format;
    const char* storage;
    const char* box;
    uint64_t bits, node, tri;
  };
  for (const Case& k : {Case{"e8m23", "word", "", 32, 48, 36}, Case{"e8m23", "format", "", 32, 40, 36},
                        Case{"e6m12", "format", "", 19, 32, 22}, Case{"e5m10", "format", "", 16, 28, 18},
                        Case{"e7m16", "format", "", 24, 36, 27}, Case{"e6m12", "format", "e5m8", 19, 28, 22},
                        Case{"e6m12", "word", "e5m8", 32, 48, 36}}) {
    Config c = default_config();
    c.format = k.format;
    c.scene_storage = k.storage;
    c.box_format = k.box;
    const TraxResult r = run_trax(scene16(), c, 2, 2);
    EXPECT_EQ(r.value_bits, k.bits) << k.format << " " << k.storage << " " << k.box;
    EXPECT_EQ(r.node_bytes, k.node) << k.format << " " << k.storage << " " << k.box;
    EXPECT_EQ(r.tri_bytes, k.tri) << k.format << " " << k.storage << " " << k.box;
  }
}

// chip.texture = "unit": one TEXTURE per procedural sample, the renderer's texture-unit image.
TEST(TraxImage, TextureUnitEqualsRenderer) {
  Config c = default_config();
  c.format = "e7m16";
  c.texture = "unit";
  expect_same_image(c, 16, 16, true);
  const TraxResult r = run_trax(scene16(), c, 16, 16);
  EXPECT_GT(r.texture_evals, 0u);
  EXPECT_EQ(r.sim.unit_ops[static_cast<int>(Unit::Noise)], 0u);  // no NOISE instruction left
  c.noise = "float";  // the unit is fixed point: refused with one line
  EXPECT_THROW(c.validate("test"), ConfigError);
}

// The smoke volume (Fig. 4.1): marched by the same kernel, with the noise unit and with the
// texture unit (one fbm TEXTURE per step); hundreds of noise evaluations per pixel, and the
// volume changes the image (it is not skipped).
TEST(TraxImage, SmokeVolumeEqualsRenderer) {
  Config c = default_config();
  c.format = "e7m16";
  expect_same_image(c, 8, 8, true, "smoke");
  const TraxResult r = run_trax(ru::scene::make_scene("smoke"), c, 8, 8);
  EXPECT_GT(r.noise_evals, 64u * 300u);
  const TraxResult plain = run_trax(ru::scene::make_scene("noisy"), c, 8, 8);
  EXPECT_NE(std::memcmp(r.image.rgb.data(), plain.image.rgb.data(), r.image.rgb.size() * sizeof(r.image.rgb[0])), 0);
  c.texture = "unit";
  expect_same_image(c, 8, 8, true, "smoke");
}

// Hand schedule of the texture unit's occupancy (one TP, 4 independent requests of 8 octaves on
// one unit with width 4: K = 2 cycles each, latency Stages 4 + RootStages 2 + K):
//   c0 Atomic (item ready at 1); requests issue at 1, 3, 5, 7 (each waits for the unit, 1 cycle
//   of contention in between); the last is ready at 7 + 2 + 6 = 15; c8 Atomic: no work, halt
//   (ready 9). Total 15 cycles, 3 contention stalls. With width 8 (K = 1): 1, 2, 3, 4 -> ready
//   4 + 1 + 6 = 11, no stall.
TEST(TraxTiming, TextureUnitOccupancy) {
  for (const int width : {4, 8}) {
    Config c = tiny();
    c.unit(Unit::Texture) = {4, 1, width, 0};
    FunctionWork w(1, [](uint64_t, Thread& t) {
      for (int i = 0; i < 4; ++i) {
        t.emit(Op::Texture, {Thread::kItemReg});
        t.stream().code.back().aux = 8;
      }
    });
    const SimStats st = simulate(c, w);
    EXPECT_EQ(st.cycles, width == 4 ? 15u : 11u) << width;
    EXPECT_EQ(st.stall_contention, width == 4 ? 3u : 0u) << width;
    EXPECT_EQ(st.unit_ops[static_cast<int>(Unit::Texture)], 4u);
  }
}

TEST(TraxImage, StacklessEqualsRenderer) {
  Config c = default_config();
  c.format = "e7m12";
  c.traversal = "stackless";
  expect_same_image(c, 16, 16, false);
}

// Planted error for the image comparison: the renderer in another format must differ.
TEST(TraxImage, PlantedFormatMismatchIsDetected) {
  Config c = default_config();
  const ru::scene::Scene s = scene16();
  const TraxResult r = run_trax(s, c, 16, 16);
  ru::render::RenderOptions o = render_options(c, 16, 16);
  o.format = "e5m6";
  const ru::render::Image other = ru::render::render(s, o);
  EXPECT_NE(std::memcmp(other.rgb.data(), r.image.rgb.data(), other.rgb.size() * sizeof(float)), 0);
}

TEST(TraxImage, DeterministicCyclesAndImage) {
  Config c = default_config();
  c.tms = 2;
  c.tps_per_tm = 8;
  const ru::scene::Scene s = scene16();
  const TraxResult a = run_trax(s, c, 12, 12), b = run_trax(s, c, 12, 12);
  EXPECT_EQ(a.sim.cycles, b.sim.cycles);
  EXPECT_EQ(a.sim.instructions, b.sim.instructions);
  EXPECT_EQ(a.sim.stall_memory, b.sim.stall_memory);
  EXPECT_EQ(a.sim.l1.hits, b.sim.l1.hits);
  EXPECT_EQ(a.image.rgb, b.image.rgb);
  // Units not used by the kernel are not charged: a scene without procedural materials has no
  // noise unit.
  EXPECT_GT(a.sim.unit_ops[static_cast<int>(Unit::Noise)], 0u);
  const TraxResult cb = run_trax(ru::scene::make_scene("cornell"), c, 8, 8);
  EXPECT_EQ(cb.sim.unit_ops[static_cast<int>(Unit::Noise)], 0u);
  for (const auto& it : cb.area.items) EXPECT_EQ(it.name.find("noise"), std::string::npos) << it.name;
  // ... and its "sta" clock is the slowest *used* unit's Fmax (noise, unused, does not count).
  double slowest = 0;
  for (int u = 0; u < kUnits; ++u)
    if (cb.sim.unit_ops[u] && cb.cfg.units[u].fmax_mhz > 0 && (slowest == 0 || cb.cfg.units[u].fmax_mhz < slowest))
      slowest = cb.cfg.units[u].fmax_mhz;
  EXPECT_GT(slowest, 0);
  EXPECT_EQ(cb.cfg.clock_mhz, slowest);
  EXPECT_EQ(cb.clock.mhz, slowest);
  EXPECT_NE(cb.clock.how.find("slowest used unit"), std::string::npos) << cb.clock.how;
  // memories have no cell-flow measurement: estimates, labelled so
  int memories = 0;
  for (const auto& it : cb.area.items)
    if (it.name.rfind("unit ", 0) != 0) {
      ++memories;
      EXPECT_TRUE(it.estimate) << it.name;
      EXPECT_NE(it.name.find("estimate"), std::string::npos) << it.name;
    }
  EXPECT_EQ(memories, 5);  // FP and integer register files, local stores, L1s, L2
  EXPECT_GE(cb.area.estimated, cb.area.memories);
  // Changing one latency changes the cycle count.
  c.unit(Unit::Box).latency += 10;
  EXPECT_NE(run_trax(s, c, 12, 12).sim.cycles, a.sim.cycles);
}

// The memory model by hand (docs/TRAX.md "Memories"): CACTI's 146 F^2 cell (10 F x 14.6 F) at
// F = 0.18 um is 4.7304 um2; a 2R1W register-file cell grows by 2 x 2.5 F per extra port each way:
// (14.6 + 10) F x (10 + 10) F = 492 F^2 = 15.9408 um2. A 32 KB direct-mapped cache of 64 B lines:
// 512 lines of 512 data bits + 17 tag bits (32 - 9 index - 6 offset) + 1 valid = 271,360 bits.
TEST(TraxArea, MemoryModelByHand) {
  Config c = default_config();
  EXPECT_NEAR(memory_cell_um2(c, 1, 0, 0), 4.7304, 1e-9);
  EXPECT_NEAR(memory_cell_um2(c, 0, 2, 1), 15.9408, 1e-9);
  EXPECT_DOUBLE_EQ(cache_bits(c, c.l1), 271360.0);
  CacheCfg four = c.l1;
  four.ways = 4;  // 128 sets: 2 more tag bits per line
  EXPECT_DOUBLE_EQ(cache_bits(c, four), 512.0 * (512 + 19 + 1));
  // The FP register file follows the format: 96 registers x 16 bits at e5m10, x 32 at e8m23.
  for (const char* f : {"e5m10", "e8m23"}) {
    c.format = f;
    const TraxResult r = run_trax(scene16(), c, 2, 2);
    const double bits = f[1] == '5' ? 16 : 32;
    bool seen = false;
    for (const auto& it : r.area.items)
      if (it.name.rfind("FP register files", 0) == 0) {
        seen = true;
        EXPECT_NEAR(it.each, 96 * bits * 15.9408 / 0.5, 1e-6) << f;
        EXPECT_EQ(it.count, 128);
      }
    EXPECT_TRUE(seen);
  }
}

// Memory access energy ([energy], docs/TRAX.md "Memory access energy"), by hand. The law at
// Horowitz's published points: a 64-bit read of 8 KB 10 pJ, 32 KB 20 pJ, 1 MB 100 pJ (the square
// root gives 113.1, within 13 %). One item: a scene load (1 FP write), an FP add of it with itself
// (2 FP reads, 1 FP write), a local store of the sum (1 FP read), an integer op on the item
// register (1 int read, 1 int write). With the defaults (e8m23):
//   FP file 96 x 32 bits = 384 B: 10 sqrt(384 / 8192) 32 / 64 = 1.0825318 pJ x 5 accesses
//   int file 32 x 32 bits = 128 B: 10 sqrt(1 / 64) / 2 = 0.625 pJ x 2
//   local store 512 B, 64 bits: 10 sqrt(1 / 16) = 2.5 pJ x 1
//   L1 32 KiB, a 32-bit value: 10 x 2 / 2 = 10 pJ x 1 (a miss)
//   L2 512 KiB, a 512-bit line: 10 x 8 x 8 = 640 pJ x 1
//   DRAM 64 B x 8 x 20.3125 = 10,400 pJ
TEST(TraxEnergy, MemoryAccessEnergyByHand) {
  Config c = tiny();
  EXPECT_DOUBLE_EQ(sram_access_pj(c, 8192, 64), 10.0);
  EXPECT_DOUBLE_EQ(sram_access_pj(c, 32768, 64), 20.0);
  EXPECT_NEAR(sram_access_pj(c, 1 << 20, 64), 113.137, 1e-3);
  FunctionWork w(1, [](uint64_t, Thread& t) {
    const uint32_t a = t.mark_fp(t.load(0x1000));
    const uint32_t b = t.emit(Op::FAdd, {a, a});
    t.emit(Op::StoreLocal, {b}, false);
    t.emit(Op::Int, {Thread::kItemReg});
  });
  c = resolve_config(c);
  const SimStats st = simulate(c, w);
  EXPECT_EQ(st.rf_reads_fp, 3u);
  EXPECT_EQ(st.rf_writes_fp, 2u);
  EXPECT_EQ(st.rf_reads_int, 1u);
  EXPECT_EQ(st.rf_writes_int, 1u);
  EXPECT_EQ(st.dram_read_bytes + st.dram_write_bytes, 64u);
  const Energy e = energy_estimate(c, st);
  ASSERT_EQ(e.items.size(), 6u);
  const double want[6][2] = {{5, 1.0825318}, {2, 0.625}, {1, 2.5}, {1, 10}, {1, 640}, {64, 162.5}};
  double total = 0;
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(e.items[k].accesses, static_cast<uint64_t>(want[k][0])) << e.items[k].name;
    EXPECT_NEAR(e.items[k].pj_each, want[k][1], 1e-6) << e.items[k].name;
    total += want[k][0] * want[k][1];
  }
  EXPECT_NEAR(e.total_pj, total, 1e-4);
  EXPECT_NEAR(total, 11059.16, 0.01);
  // the word layout charges a 32-bit word per load at any format; e5m10 packs 16 bits
  c.format = "e5m10";
  EXPECT_NEAR(energy_estimate(c, st).items[3].pj_each, 5.0, 1e-12);
  c.scene_storage = "word";
  EXPECT_NEAR(energy_estimate(c, st).items[3].pj_each, 10.0, 1e-12);
}

TEST(TraxConfig, BadKeysGiveOneLineNamingTheKey) {
  auto msg = [](const std::string& text) -> std::string {
    try {
      parse_config(text, "t.toml");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(msg("[l1]\nbanks = 3\n").find("key 'l1.banks'"), std::string::npos);
  EXPECT_NE(msg("[units.fp_ad]\nlatency = 2\n").find("key 'units.fp_ad'"), std::string::npos);
  EXPECT_NE(msg("[units.fp_add]\nlatency = 0\n").find("key 'units.fp_add.latency'"), std::string::npos);
  EXPECT_NE(msg("[chip]\ntms = \"four\"\n").find("key 'chip.tms'"), std::string::npos);
  EXPECT_NE(msg("[chip]\nformat = \"e1m3\"\n").find("key 'chip.format'"), std::string::npos);
  EXPECT_NE(msg("[chip]\ntri = \"fast\"\n").find("accepted: robust, mt"), std::string::npos);
  EXPECT_NE(msg("[chip]\ncolour = 1\n").find("key 'chip.colour'"), std::string::npos);
  EXPECT_NE(msg("[cache]\nsize = 1\n").find("key 'cache'"), std::string::npos);
  EXPECT_NE(msg("[l2]\nsize = 1000\n").find("key 'l2.size'"), std::string::npos);
  EXPECT_NE(msg("[chip\n").find("t.toml: line 1"), std::string::npos);
  EXPECT_NE(msg("[energy]\ndram_pj = 3\n").find("key 'energy.dram_pj'"), std::string::npos);
  EXPECT_NE(msg("[energy]\nsram_capacity_exponent = 3\n").find("key 'energy.sram_capacity_exponent'"), std::string::npos);
  EXPECT_NE(msg("[chip]\nfma = 1\n").find("key 'chip.fma': must be true or false"), std::string::npos);
  for (const char* t : {"[l1]\nbanks = 3\n", "[chip]\ncolour = 1\n"}) EXPECT_EQ(msg(t).find('\n'), std::string::npos);
  EXPECT_EQ(msg("[chip]\ntms = 2\n"), "");
  EXPECT_THROW(load_config("/nonexistent/trax.toml"), ConfigError);
}

TEST(TraxConfig, DefaultFileMatchesBuiltInAndRoundTrips) {
  const Config file = load_config(std::string(RU_SOURCE_DIR) + "/model/data/trax/default.toml");
  EXPECT_EQ(to_toml(file), to_toml(default_config()));
  Config c = default_config();
  c.tms = 3;
  c.unit(Unit::Tri).latency = 31;
  c.l2.ways = 4;
  c.dram_bytes_per_cycle = 12.5;
  c.fma = true;
  c.dram_pj_per_bit = 41.0;
  EXPECT_EQ(to_toml(parse_config(to_toml(c), "rt")), to_toml(c));
  EXPECT_TRUE(parse_config(to_toml(c), "rt").fma);
}

TEST(TraxReport, SummaryLineFormat) {
  Config c = default_config();
  c.tms = 1;
  c.tps_per_tm = 4;
  c.clock_mhz = 1000;  // configured (the default is "sta": docs/TRAX.md)
  const TraxResult r = run_trax(ru::scene::make_scene("cornell"), c, 4, 4);
  const std::string line = summary_line(r);
  std::ostringstream want;
  want << "cycles=" << r.sim.cycles << " rays=" << r.rays() << " rays_per_s=";
  EXPECT_EQ(line.rfind(want.str(), 0), 0u) << line;
  EXPECT_NE(line.find(" (at 1000 MHz) area="), std::string::npos) << line;
  EXPECT_EQ(line.substr(line.size() - 3), "mm2") << line;
  // rays/s = rays / (cycles / clock)
  EXPECT_NEAR(r.rays_per_second(), double(r.rays()) * 1e9 / double(r.sim.cycles), 1e-6 * r.rays_per_second());
}
