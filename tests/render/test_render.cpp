// Renderer: format consistency (float == e8m23, double == e11m52 bit for bit), an independent
// shading oracle, image metrics, traces, threads, profiles.
#include <gtest/gtest.h>
#include <unistd.h>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include "rayunits/bvh/rotate.hpp"
#include "rayunits/render/render.hpp"
#include "rayunits/units/trace.hpp"

using namespace ru::render;
using ru::scene::make_scene;
using ru::scene::Scene;

namespace {

RenderOptions small(const std::string& fmt, int size = 24) {
  RenderOptions o;
  o.width = o.height = size;
  o.format = fmt;
  o.progress = false;
  return o;
}

bool same_bits(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

int lit_pixels(const Image& im) {
  int n = 0;
  for (size_t i = 0; i < im.rgb.size(); i += 3) n += im.rgb[i] + im.rgb[i + 1] + im.rgb[i + 2] > 0;
  return n;
}

}  // namespace

// The emulated format at e8m23 / e11m52 must reproduce native float / double exactly: every
// operation of the render goes through the same unit models in the same order.
TEST(Render, EmulatedFormatsEqualNativeBitForBit) {
  Scene s = make_scene("default");
  for (TriAlgo tri : {TriAlgo::Robust, TriAlgo::MT})
    for (ru::units::BoxMode box : {ru::units::BoxMode::Plain, ru::units::BoxMode::Conservative}) {
      SCOPED_TRACE(std::string(tri_name(tri)) + (box == ru::units::BoxMode::Plain ? " plain" : " conservative"));
      RenderOptions f = small("float"), e = small("e8m23");
      f.tri = e.tri = tri;
      f.box = e.box = box;
      Image a = render(s, f), b = render(s, e);
      EXPECT_GT(lit_pixels(a), 200);
      EXPECT_TRUE(same_bits(a, b));
    }
  RenderOptions d = small("double"), e = small("e11m52");
  d.noise = e.noise = NoiseMode::Fixed;
  EXPECT_TRUE(same_bits(render(s, d), render(s, e)));
  // ... and the Mirth median build in the format gives the same tree as in float.
  RenderOptions mf = small("float"), me = small("e8m23");
  mf.bvh = me.bvh = BvhKind::Median;
  EXPECT_TRUE(same_bits(render(s, mf), render(s, me)));
}

// RenderOptions::fma: the shading's multiply-adds fused. The format model's fma at e8m23 / e11m52
// must equal std::fma in float / double bit for bit on scenes that reach every fused site
// (camera, hit point, cross and dot products, colour blends, marble / wood / turbulence
// materials, octave sums, the smoke's volume); and fusing must change the image in every type (so
// a path that silently stayed unfused, in either type, would be caught by the equality).
TEST(Render, FmaEmulatedEqualsStdFmaBitForBit) {
  for (const char* name : {"default", "noisy", "smoke"}) {
    SCOPED_TRACE(name);
    Scene s = make_scene(name);
    RenderOptions f = small("float", 32), e = small("e8m23", 32);
    RenderOptions fp = f, ep = e;
    f.fma = e.fma = true;
    const Image a = render(s, f), b = render(s, e);
    EXPECT_GT(lit_pixels(a), 200);
    EXPECT_TRUE(same_bits(a, b));
    EXPECT_FALSE(same_bits(a, render(s, fp)));
    EXPECT_FALSE(same_bits(b, render(s, ep)));
  }
  Scene s = make_scene("noisy");
  RenderOptions d = small("double"), e = small("e11m52");
  d.fma = e.fma = true;
  EXPECT_TRUE(same_bits(render(s, d), render(s, e)));
}

TEST(Render, ReducedFormatsDifferAndCountFlags) {
  Scene s = make_scene("default");
  RenderStats st;
  Image ref = render(s, small("double"));
  Image lo = render(s, small("e5m6"), &st);
  ImageDiff d = compare(lo, ref);
  EXPECT_GT(d.errors, 0u);  // 6 fraction bits are visibly wrong
  EXPECT_GT(st.soft.ops, 100000u);
  EXPECT_GT(st.soft.inexact, 0u);
  EXPECT_THROW(render(s, small("e1m3")), ru::num::FormatError);
  EXPECT_THROW(render(s, small("half")), ru::num::FormatError);
}

TEST(Render, ThreadCountDoesNotChangeTheImage) {
  Scene s = make_scene("arch");
  RenderOptions a = small("float", 40), b = a;
  a.threads = 1;
  b.threads = 2;
  RenderStats sa, sb;
  EXPECT_TRUE(same_bits(render(s, a, &sa), render(s, b, &sb)));
  EXPECT_EQ(sa.box_tests, sb.box_tests);
  EXPECT_EQ(sa.tri_tests, sb.tri_tests);
}

// Independent shading oracle: one big triangle facing the camera, light straight ahead;
// the centre pixel must be C * (Ka + Kd cos(angle)), computed here in double from the geometry.
TEST(Render, LambertPlusAmbientMatchesHandComputation) {
  Scene s;
  s.materials.push_back({"red", ru::scene::MaterialKind::Constant, {0.8, 0.4, 0.2}, {}, 1.0});
  s.tris.push_back({{{-10, 5, -10}, {10, 5, -10}, {0, 5, 10}}, 0});
  s.camera = {{0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 30.0};
  s.light = {3, 0, 4};  // in front of the plane y = 5, off to the side
  RenderOptions o = small("double", 9);
  Image im = render(s, o);
  // Centre pixel ray hits (0, 5, 0); N = (0, -1, 0) toward the viewer; L = light - hit.
  const double lx = 3, ly = -5, lz = 4, cosang = 5.0 / std::sqrt(lx * lx + ly * ly + lz * lz);
  const double want[3] = {0.8 * (0.1 + 0.9 * cosang), 0.4 * (0.1 + 0.9 * cosang), 0.2 * (0.1 + 0.9 * cosang)};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(im.at(4, 4)[k], want[k], 1e-6);
  // Fused multiply-adds give the same value (to double rounding).
  RenderOptions fo = o;
  fo.fma = true;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(render(s, fo).at(4, 4)[k], want[k], 1e-6);
  // Without shadow rays the same value.
  RenderOptions ns = o;
  ns.shadows = false;
  EXPECT_NEAR(render(s, ns).at(4, 4)[0], want[0], 1e-6);
  // Background (no hit) is black.
  s.tris.resize(1);
  s.camera.look_at = {0, -1, 0};
  Image bg = render(s, o);
  for (float v : bg.rgb) EXPECT_EQ(v, 0.0f);
}

TEST(Render, ShadowOccluderDarkensExactlyToAmbient) {
  Scene s;
  s.materials.push_back({"w", ru::scene::MaterialKind::Constant, {1.0, 1.0, 1.0}, {}, 1.0});
  s.tris.push_back({{{-10, 5, -10}, {10, 5, -10}, {0, 5, 10}}, 0});
  // A large occluder square between the plane and a light at (0, -5, 0)... light behind the camera.
  s.tris.push_back({{{-1, -2, -1}, {1, -2, -1}, {0, -2, 1}}, 0});
  s.camera = {{0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 30.0};
  s.light = {0, -5, 0};
  Image im = render(s, small("double", 9));
  // The centre pixel: the shadow ray from (0,5,0) to (0,-5,0) passes (0,-2,0), inside the occluder.
  for (int k = 0; k < 3; ++k) EXPECT_EQ(im.at(4, 4)[k], 0.1f);  // 1.0 * Ka, stored as float
}

TEST(Render, CompareMetricsByHand) {
  Image a;
  a.width = a.height = 10;
  a.rgb.assign(300, 0.5f);
  Image b = a;
  EXPECT_EQ(compare(a, b).errors, 0u);
  EXPECT_TRUE(std::isinf(compare(a, b).psnr));
  b.at(3, 4)[1] = 0.5f + 0.125f;  // one channel of one pixel off by 0.125 (> 10 %)
  ImageDiff d = compare(b, a);
  EXPECT_EQ(d.errors, 1u);
  EXPECT_DOUBLE_EQ(d.mse, 0.125 * 0.125 / 300.0);
  EXPECT_NEAR(d.psnr, 10.0 * std::log10(300.0 / (0.125 * 0.125)), 1e-9);
  b.at(3, 4)[1] = 0.5f + 0.0625f;  // within 10 %
  EXPECT_EQ(compare(b, a).errors, 0u);
  Image c;
  c.width = 5;
  c.height = 10;
  c.rgb.assign(150, 0.f);
  EXPECT_THROW(compare(a, c), std::invalid_argument);
}

TEST(Render, PngRoundTrip) {
  Image a = render(make_scene("cornell"), small("float", 20));
  char path[] = "/tmp/ru-render-XXXXXX.png";
  int fd = mkstemps(path, 4);
  ASSERT_GE(fd, 0);
  close(fd);
  write_png(path, a);
  int w, h, n;
  unsigned char* px = stbi_load(path, &w, &h, &n, 3);
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(w, 20);
  EXPECT_EQ(h, 20);
  for (int i = 0; i < 20 * 20 * 3; ++i) ASSERT_EQ(px[i], static_cast<unsigned char>(std::lround(a.rgb[i] * 255.0)));
  stbi_image_free(px);
  unlink(path);
  EXPECT_THROW(write_png("/nonexistent/dir/x.png", a), std::runtime_error);
}

// The trace holds exactly the pairs the renderer tested, in the units' trace format.
TEST(Render, TraceRecordsTheTestedPairs) {
  Scene s = make_scene("cornell");
  char path[] = "/tmp/ru-trace-XXXXXX";
  int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  close(fd);
  RenderOptions o = small("e7m16", 8);
  o.trace_path = path;
  RenderStats st;
  render(s, o, &st);
  ru::units::Trace t = ru::units::read_trace(path);
  EXPECT_EQ(t.boxes.size(), st.box_tests);
  EXPECT_EQ(t.tris.size(), st.tri_tests);
  EXPECT_EQ(st.trace_boxes, st.box_tests);
  ASSERT_FALSE(t.boxes.empty());
  // The first record is the first primary ray against the scene's root box.
  const ru::num::Format f = ru::num::Format::parse("e7m16");
  auto r16 = [&](double x) { return ru::num::to_double(f, ru::num::from_double(f, x).bits); };
  const auto& b0 = t.boxes[0];
  EXPECT_EQ(b0.o.x, r16(s.camera.eye.x));
  EXPECT_NE(b0.o.x, s.camera.eye.x);  // 2.775 is not an e7m16 value
  EXPECT_EQ(b0.lo.x, r16(s.bounds_lo().x));
  EXPECT_EQ(b0.hi.z, r16(s.bounds_hi().z));
  EXPECT_EQ(b0.t_min, ru::num::to_double(f, ru::num::from_double(f, 1e-3).bits));  // epsilon in e7m16
  EXPECT_NE(b0.t_min, 1e-3);
  for (const auto& r : t.tris) EXPECT_LT(r.t_min, r.t_max);
  // A limit truncates.
  o.trace_limit = 10;
  render(s, o, &st);
  ru::units::Trace t2 = ru::units::read_trace(path);
  EXPECT_EQ(t2.boxes.size() + t2.tris.size(), 10u);
  EXPECT_TRUE(st.trace_truncated);
  unlink(path);
}

// A different tree over the same triangles (rotations, child reordering) must not change a
// double render with the robust test: the closest hit is the same whatever the visit order.
TEST(Render, RotatedTreeRendersTheSameImage) {
  Scene s = make_scene("default");
  ru::bvh::Bvh b = ru::bvh::build_sah(s);
  RenderOptions o = small("double", 32);
  o.topology = &b;
  Image before = render(s, o);
  ru::bvh::hill_climb(b);
  RenderStats st;
  Image after = render(s, o, &st);
  EXPECT_TRUE(same_bits(before, after));
  EXPECT_DOUBLE_EQ(st.sah_cost, ru::bvh::sah_cost(b));
}

TEST(Render, ProbeRecordsValuesAndMatchesDouble) {
  Scene s = make_scene("default");
  ExpHistogram all, inputs;
  RenderOptions p = small("probe", 16);
  p.profile_all = &all;
  p.profile_inputs = &inputs;
  Image a = render(s, p), b = render(s, small("double", 16));
  EXPECT_TRUE(same_bits(a, b));
  EXPECT_GT(all.finite_nonzero(), 100000u);
  EXPECT_GT(inputs.finite_nonzero(), 1000u);
  // Inputs are ray origins/directions and vertices: the largest is the camera's distance-ish.
  EXPECT_LE(inputs.max_abs, 10.0);
  EXPECT_GE(inputs.max_abs, 4.0);
  // Scaling the scene by 1e-6 (about 2^-20) shifts the smallest operands' exponents by -20.
  ExpHistogram all6, in6;
  p.profile_all = &all6;
  p.profile_inputs = &in6;
  render(make_scene("default@1e-6"), p);
  // (the largest operands of the scaled scene are the unit-length-ish primary ray directions)
  EXPECT_NEAR(in6.min_exp() - inputs.min_exp(), -20, 1);
  EXPECT_LE(in6.max_exp(), 0);
  EXPECT_GE(inputs.max_exp(), 2);
}

TEST(Render, ScaledScenesRenderTheSamePicture) {
  Image ref = render(make_scene("default"), small("double", 32));
  for (const char* n : {"default@1e-6", "default@1e+6"}) {
    SCOPED_TRACE(n);
    ImageDiff d = compare(render(make_scene(n), small("double", 32)), ref);
    EXPECT_LE(d.errors, 2u);  // only rounding differences at silhouette pixels
    EXPECT_GT(d.psnr, 40.0);
  }
}
