// Long suite: big scenes (CGAL demo bunny) and full annealing schedules.
#include <gtest/gtest.h>

#include "rayunits/bvh/rotate.hpp"
#include "rayunits/render/render.hpp"

using namespace ru::render;

TEST(LongRender, BunnyFloatEqualsE8m23BitForBit) {
  if (ru::scene::find_demo_mesh("bunny").empty()) GTEST_SKIP() << "libcgal-demo not installed (scripts/install-deps.sh --long)";
  ru::scene::Scene s = ru::scene::make_scene("bunny");
  ASSERT_EQ(s.tris.size(), 75408u);
  for (TriAlgo a : {TriAlgo::Robust, TriAlgo::MT}) {
    RenderOptions f;
    f.width = f.height = 96;
    f.tri = a;
    f.format = "float";
    RenderOptions e = f;
    e.format = "e8m23";
    Image x = render(s, f), y = render(s, e);
    ASSERT_EQ(x.rgb.size(), y.rgb.size());
    EXPECT_EQ(std::memcmp(x.rgb.data(), y.rgb.data(), x.rgb.size() * sizeof(float)), 0) << tri_name(a);
    int lit = 0;
    for (float v : x.rgb) lit += v > 0;
    EXPECT_GT(lit, 96 * 96);  // the bunny fills a good part of the frame
  }
}

TEST(LongBvh, FullAnnealingScheduleBeatsHillClimbingOnArch) {
  ru::scene::Scene s = ru::scene::make_scene("arch");
  auto pb = ru::bvh::triangle_boxes(s);
  ru::bvh::Bvh h = ru::bvh::build_sah(pb), a = h;
  auto hs = ru::bvh::hill_climb(h);
  ru::bvh::AnnealOptions o;  // N = 1250, f = 50, h = 0.15
  auto as = ru::bvh::anneal(a, ru::bvh::SahParams{}, o);
  EXPECT_EQ(ru::bvh::validate(a, pb), "");
  EXPECT_LT(as.cost_after, hs.cost_after);
  EXPECT_EQ(as.passes, static_cast<int>(as.cost_per_pass.size()));
  EXPECT_GE(as.passes, 1250);
}
