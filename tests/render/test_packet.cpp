// The native renderer's packet traversal (render/tracer.hpp intersect_packet, render/pair_bvh.hpp)
// against the one-ray traversal (intersect_impl with the ray-box / ray-triangle golden models):
// for every ray the same hit, the same t (bit for bit) and, summed, the same numbers of box and
// triangle tests. Rays: camera quads, random packets, and special values that send lanes to the
// golden model (zero direction components: reciprocal +-INF, 0 * INF = NaN on slab planes;
// mixed octants; partial packets). Planted errors in the pair layout must be caught.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "rayunits/render/tracer.hpp"

using namespace ru::render;
using ru::render::kernel::Prepared;
using ru::render::kernel::Tracer;
using ru::units::Vec3;

namespace {

template <class T>
bool same_bits(T a, T b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

template <class T>
struct Case {
  Vec3<T> o[4], d[4];
  unsigned lanes = 15;
  T tmin = T(1e-3), tmax = T(INFINITY);
};

template <class T>
struct Outcome {
  uint64_t rays = 0, mismatches = 0, box_packet = 0, box_single = 0, tri_packet = 0, tri_single = 0;
  std::string first;
};

// Runs every case through the packet traversal of `packed` and the one-ray traversal of `ref`.
template <class T>
Outcome<T> compare(const Prepared<T>& packed, const Prepared<T>& ref, const RenderOptions& opt,
                   const std::vector<Case<T>>& cases) {
  Tracer<T> a(packed, opt), b(ref, opt);
  Outcome<T> out;
  for (bool any : {false, true})
    for (const Case<T>& c : cases) {
      typename Tracer<T>::Packet pk;
      pk.lanes = c.lanes;
      for (int j = 0; j < 4; ++j) {
        pk.ray[j] = a.make_ray(c.o[j], c.d[j]);
        pk.tmin[j] = c.tmin;
        pk.tmax[j] = c.tmax;
      }
      a.intersect_packet(pk, any);
      for (int j = 0; j < 4; ++j) {
        if (!(c.lanes >> j & 1u)) continue;
        ++out.rays;
        T tmax = c.tmax;
        const int64_t h = b.intersect_flat(b.make_ray(c.o[j], c.d[j]), c.tmin, tmax, any);
        if (h != pk.hit[j] || !same_bits(tmax, pk.tmax[j])) {
          if (out.mismatches++ == 0)
            out.first = "lane " + std::to_string(j) + (any ? " any" : " closest") + ": packet hit " +
                        std::to_string(pk.hit[j]) + " t " + std::to_string(double(pk.tmax[j])) + ", one-ray hit " +
                        std::to_string(h) + " t " + std::to_string(double(tmax));
        }
      }
    }
  out.box_packet = a.cnt.box;
  out.box_single = b.cnt.box;
  out.tri_packet = a.cnt.tri;
  out.tri_single = b.cnt.tri;
  return out;
}

// 2x2 pixel quads of the camera, every `step` pixels.
template <class T>
void camera_cases(const Prepared<T>& P, const RenderOptions& opt, int step, std::vector<Case<T>>* cases) {
  Tracer<T> tr(P, opt);
  for (int y = 0; y + 1 < opt.height; y += step)
    for (int x = 0; x + 1 < opt.width; x += step) {
      Case<T> c;
      c.tmin = P.eps;
      for (int j = 0; j < 4; ++j) {
        c.o[j] = P.eye;
        c.d[j] = tr.primary_dir(T(x + (j & 1) + 0.5), T(y + (j >> 1) + 0.5));
      }
      cases->push_back(c);
    }
}

// Random packets from inside the root box (one octant, or mixed), some partial; then the
// special values: zero direction components (+0 and -0), origins on child box planes.
template <class T>
void random_and_special_cases(const Prepared<T>& P, uint32_t seed, int n, std::vector<Case<T>>* cases) {
  std::mt19937 rng(seed);
  const auto& root = P.nodes[P.root];
  auto uni = [&](T lo, T hi) { return T(lo + (hi - lo) * std::uniform_real_distribution<double>(0, 1)(rng)); };
  for (int i = 0; i < n; ++i) {
    Case<T> c;
    c.tmin = P.eps;
    const bool mixed = i % 7 == 0;
    Vec3<T> base{uni(-1, 1), uni(-1, 1), uni(-1, 1)};
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 3; ++k) {
        c.o[j][k] = uni(root.lo[k], root.hi[k]);
        T dk = base[k] + uni(T(-0.05), T(0.05));
        if (!mixed && std::signbit(dk) != std::signbit(base[k])) dk = -dk;
        c.d[j][k] = dk;
      }
    }
    if (i % 5 == 0) c.lanes = 1u + rng() % 15u;  // partial packets
    cases->push_back(c);
  }
  // Special values: a zero direction component and the origin exactly on a child's slab plane
  // (the unit's 0 * INF case), in every octant, with +0 and -0.
  size_t interior = 0;
  for (size_t id = 0; id < P.nodes.size() && interior < 200; ++id) {
    const auto& nd = P.nodes[id];
    if (nd.left < 0) continue;
    ++interior;
    const auto& ch = P.nodes[nd.left];
    for (int k = 0; k < 3; ++k)
      for (int sgn = 0; sgn < 2; ++sgn) {
        Case<T> c;
        c.tmin = P.eps;
        for (int j = 0; j < 4; ++j) {
          for (int q = 0; q < 3; ++q) c.o[j][q] = uni(ch.lo[q], ch.hi[q]);
          c.o[j][k] = (j & 1) ? ch.lo[k] : ch.hi[k];  // on the plane
          c.d[j] = {uni(T(0.1), 1), uni(T(0.1), 1), uni(T(0.1), 1)};
          if (sgn) c.d[j] = {-c.d[j].x, -c.d[j].y, -c.d[j].z};
          c.d[j][k] = sgn ? T(-0.0) : T(0.0);
        }
        cases->push_back(c);
      }
  }
}

RenderOptions opts(const char* fmt, int size) {
  RenderOptions o;
  o.width = o.height = size;
  o.format = fmt;
  o.progress = false;
  return o;
}

template <class T>
void check_scene(const std::string& scene, const char* fmt, TriAlgo tri) {
  SCOPED_TRACE(scene + " " + fmt + " " + tri_name(tri));
  const auto s = ru::scene::make_scene(scene);
  RenderOptions o = opts(fmt, 64);
  o.tri = tri;
  const Prepared<T> P = kernel::prepare<T>(s, o, nullptr);
  ASSERT_FALSE(P.pairs.empty());
  std::vector<Case<T>> cases;
  camera_cases(P, o, 3, &cases);
  random_and_special_cases(P, 7, 3000, &cases);
  const auto r = compare(P, P, o, cases);
  EXPECT_GT(r.rays, 20000u);
  EXPECT_EQ(r.mismatches, 0u) << r.first;
  EXPECT_EQ(r.box_packet, r.box_single);
  EXPECT_EQ(r.tri_packet, r.tri_single);
  EXPECT_GT(r.tri_single, r.rays);  // the rays reach the leaves
}

}  // namespace

TEST(PacketTraversal, EqualsOneRayTraversalFloat) {
  for (const char* sc : {"default", "cornell", "arch", "sphere@1e-6", "arch@1e6"})
    for (TriAlgo t : {TriAlgo::Robust, TriAlgo::MT}) check_scene<float>(sc, "float", t);
}

TEST(PacketTraversal, EqualsOneRayTraversalDouble) {
  for (const char* sc : {"default", "arch"}) check_scene<double>(sc, "double", TriAlgo::Robust);
}

// packet_box_test lane by lane against the golden model (units::ray_box_reference): on every
// lane it decides, the same hit and t_enter bits; the lanes it hands back include every NaN and
// zero case. Random boxes and rays, plus the special values: zero direction components (+-INF
// reciprocals), origins on slab planes (0 * INF), zero-width boxes, infinite intervals.
// `plant`: the vector test gets t_max where t_min belongs (the lanes' entry starts from the
// wrong bound), which the same comparison must report.
struct LaneCount {
  size_t decided = 0, handed_back = 0, mismatches = 0;
};
template <class T, int Oct>
void packet_box_lanes(uint32_t seed, bool plant, LaneCount* n_out) {
  std::mt19937 rng(seed);
  auto uni = [&](double lo, double hi) { return T(std::uniform_real_distribution<double>(lo, hi)(rng)); };
  for (int it = 0; it < 20000; ++it) {
    kernel::PairNode<T> n;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 2; ++c) {
        T a = uni(-4, 4), b = uni(-4, 4);
        if (rng() % 8 == 0) b = a;  // zero width
        n.b[k][c] = std::min(a, b);
        n.b[k][c + 2] = std::max(a, b);
      }
    Vec3<T> o[4], inv[4];
    kernel::PacketRays<T> pr;
    const T tmin = rng() % 4 == 0 ? T(-INFINITY) : uni(-1, 1), tmax = rng() % 4 == 0 ? T(INFINITY) : uni(1, 8);
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 3; ++k) {
        const bool neg = (Oct >> k) & 1;
        T dk = uni(0.01, 2);
        const unsigned r = rng() % 10;
        if (r == 0) dk = T(0);                                    // 1/d = +-INF
        if (r == 1) o[j][k] = n.b[k][rng() % 4];                  // on a slab plane
        else o[j][k] = uni(-5, 5);
        if (r == 2) dk = T(1e-30);                                // huge reciprocal
        inv[j][k] = (neg ? T(-1) : T(1)) / dk;                    // sign bit as Oct says
      }
      pr.set(j, o[j], inv[j], tmin, tmax);
    }
    if (plant) pr.t_min = pr.t_max;
    for (int c = 0; c < 2; ++c) {
      typename kernel::PacketRays<T>::VT te;
      unsigned bad;
      const unsigned h = kernel::packet_box_test<T, Oct>(n, c, pr, 15u, &te, &bad);
      ASSERT_EQ(h & bad, 0u);
      const Vec3<T> lo{n.b[0][c], n.b[1][c], n.b[2][c]}, hi{n.b[0][c + 2], n.b[1][c + 2], n.b[2][c + 2]};
      for (int j = 0; j < 4; ++j) {
        const auto g = ru::units::ray_box_reference(o[j], inv[j], lo, hi, tmin, tmax);
        if (bad >> j & 1u) {
          ++n_out->handed_back;
          continue;
        }
        ++n_out->decided;
        if (bool(h >> j & 1u) != g.hit || (g.hit && !same_bits(T(te[j]), g.t_enter))) ++n_out->mismatches;
      }
    }
  }
}

TEST(PacketTraversal, BoxLanesEqualTheGoldenModel) {
  LaneCount n;
  packet_box_lanes<float, 0>(1, false, &n);
  packet_box_lanes<float, 5>(2, false, &n);
  packet_box_lanes<float, 7>(3, false, &n);
  packet_box_lanes<double, 2>(4, false, &n);
  packet_box_lanes<double, 6>(5, false, &n);
  EXPECT_EQ(n.mismatches, 0u);
  EXPECT_GT(n.decided, 300000u);
  EXPECT_GT(n.handed_back, 10000u);  // the special values reach the golden model
}

// The comparison above reports a planted error in the vector test's inputs.
TEST(PacketTraversal, BoxLaneCheckCatchesAPlantedError) {
  LaneCount n;
  packet_box_lanes<float, 0>(9, true, &n);
  EXPECT_GT(n.mismatches, 1000u);
}

// Planted errors in the pair layout (what only the packet path reads) are caught.
TEST(PacketTraversal, PlantedLayoutErrorsAreCaught) {
  const auto s = ru::scene::make_scene("default");
  const RenderOptions o = opts("float", 48);
  const Prepared<float> P = kernel::prepare<float>(s, o, nullptr);
  std::vector<Case<float>> cases;
  camera_cases(P, o, 2, &cases);
  random_and_special_cases(P, 11, 500, &cases);
  ASSERT_EQ(compare(P, P, o, cases).mismatches, 0u);
  auto caught = [&](const Prepared<float>& bad) {
    const auto r = compare(bad, P, o, cases);
    return r.mismatches > 0 || r.box_packet != r.box_single || r.tri_packet != r.tri_single;
  };
  {  // every box one ulp larger
    Prepared<float> bad = P;
    for (auto& n : bad.pairs)
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 2; ++c) {
          n.b[k][c] = std::nextafter(n.b[k][c], -INFINITY);
          n.b[k][c + 2] = std::nextafter(n.b[k][c + 2], INFINITY);
        }
    EXPECT_TRUE(caught(bad)) << "enlarged boxes";
  }
  {  // visit order from the wrong axis
    Prepared<float> bad = P;
    for (auto& n : bad.pairs) n.axis = static_cast<uint8_t>((n.axis + 1) % 3);
    EXPECT_TRUE(caught(bad)) << "wrong split axis";
  }
  {  // children swapped
    Prepared<float> bad = P;
    for (auto& n : bad.pairs) {
      std::swap(n.idx[0], n.idx[1]);
      std::swap(n.cnt[0], n.cnt[1]);
    }
    EXPECT_TRUE(caught(bad)) << "swapped children";
  }
  {  // leaves one triangle short
    Prepared<float> bad = P;
    for (auto& n : bad.pairs)
      if (n.cnt[0] > 1) --n.cnt[0];
    EXPECT_TRUE(caught(bad)) << "short leaves";
  }
}

// Odd image sizes give partial quads; the native render must still equal the emulated e8m23
// / e11m52 render bit for bit (the emulated path traces one ray at a time).
TEST(PacketTraversal, PartialQuadsRenderLikeTheEmulatedFormat) {
  const auto s = ru::scene::make_scene("default");
  RenderOptions f = opts("float", 0), e = opts("e8m23", 0);
  f.width = e.width = 25;
  f.height = e.height = 19;
  const Image a = render(s, f), b = render(s, e);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
  RenderOptions d = f, x = e;
  d.format = "double";
  x.format = "e11m52";
  const Image c = render(s, d), g = render(s, x);
  EXPECT_EQ(std::memcmp(c.rgb.data(), g.rgb.data(), c.rgb.size() * sizeof(float)), 0);
}

// The CGAL bunny (75,408 triangles, the speed benchmark's scene).
TEST(LongPacketTraversal, BunnyEqualsOneRayTraversal) {
  if (ru::scene::find_demo_mesh("bunny").empty()) GTEST_SKIP() << "libcgal-demo not installed (scripts/install-deps.sh --long)";
  for (TriAlgo t : {TriAlgo::Robust, TriAlgo::MT}) check_scene<float>("bunny", "float", t);
  check_scene<double>("bunny", "double", TriAlgo::Robust);
}

// Boxes stored in a narrower format (RenderOptions::box_format, issue 16), rounded outward: every
// bound is a value of the box format, every stored vertex of a leaf lies inside its box and every
// child box inside its parent's. Counts the violations (0 expected).
namespace {
size_t box_violations(const Prepared<ru::num::Soft>& P, const ru::num::Format* box) {
  size_t bad = 0;
  auto d = [](const ru::num::Soft& x) { return x.to_double(); };
  auto inside = [&](const Vec3<ru::num::Soft>& p, const Vec3<ru::num::Soft>& lo, const Vec3<ru::num::Soft>& hi) {
    for (int c = 0; c < 3; ++c)
      if (!(d(lo[c]) <= d(p[c]) && d(p[c]) <= d(hi[c]))) return false;
    return true;
  };
  for (const auto& n : P.nodes) {
    if (box)
      for (int c = 0; c < 3; ++c)
        for (double v : {d(n.lo[c]), d(n.hi[c])})
          if (ru::num::to_double(*box, ru::num::from_double(*box, v).bits) != v) ++bad;  // not a box-format value
    if (n.left >= 0) {
      for (const int32_t k : {n.left, n.right})
        if (!inside(P.nodes[k].lo, n.lo, n.hi) || !inside(P.nodes[k].hi, n.lo, n.hi)) ++bad;
    } else {
      for (uint32_t i = n.first; i < n.first + n.count; ++i)
        for (const auto* p : {&P.tris[i].p0, &P.tris[i].p1, &P.tris[i].p2})
          if (!inside(*p, n.lo, n.hi)) ++bad;
    }
  }
  return bad;
}

void check_box_formats(const std::string& scene, const char* fmt, std::initializer_list<const char*> boxes) {
  const auto s = ru::scene::make_scene(scene);
  ru::num::SoftScope scope(ru::num::Format::parse(fmt));
  RenderOptions o = opts(fmt, 8);
  const Prepared<ru::num::Soft> exact = kernel::prepare<ru::num::Soft>(s, o, nullptr);
  EXPECT_EQ(box_violations(exact, nullptr), 0u) << scene << " " << fmt;
  for (const char* b : boxes) {
    SCOPED_TRACE(scene + " " + fmt + " boxes " + b);
    const ru::num::Format bf = ru::num::Format::parse(b);
    o.box_format = b;
    const Prepared<ru::num::Soft> P = kernel::prepare<ru::num::Soft>(s, o, nullptr);
    EXPECT_EQ(box_violations(P, &bf), 0u);
    // the planted error: the same bounds rounded to nearest instead of outward
    Prepared<ru::num::Soft> near = exact;
    size_t moved = 0;
    for (auto& n : near.nodes)
      for (int c = 0; c < 3; ++c)
        for (auto* x : {&n.lo[c], &n.hi[c]}) {
          const double v = ru::num::to_double(bf, ru::num::from_double(bf, x->to_double()).bits);
          moved += v != x->to_double();
          *x = ru::num::Soft::from_double(v);
        }
    ASSERT_GT(moved, 0u);
    EXPECT_GT(box_violations(near, &bf), 0u) << "nearest rounding must break containment";
  }
}
}  // namespace

TEST(BoxFormat, OutwardRoundedBoxesContainTheirGeometry) {
  check_box_formats("default", "e6m12", {"e5m8", "e4m3", "e6m8"});
  check_box_formats("default", "e8m23", {"e5m10", "e8m7"});
}

// The same on the CGAL bunny (issue 16 asks for it; the mesh is installed by --long).
TEST(BoxFormat, BunnyBoxesContainTheirGeometry) {
  if (ru::scene::find_demo_mesh("bunny").empty()) GTEST_SKIP() << "libcgal-demo not installed (scripts/install-deps.sh --long)";
  check_box_formats("bunny", "e6m12", {"e5m8", "e5m6"});
  check_box_formats("bunny", "e8m23", {"e5m10"});
}
