// rayunits units: synthetic ray-triangle and ray-box workloads (deterministic for a seed on
// every host: xoshiro256** generator of util/rng.hpp, IEEE-exact double arithmetic and sqrt only).
//
// Triangles (modelled on the dissertation's benchmark, §3.5): random triangles about the
// origin (centre uniform in [-1,1]^3, vertices = centre + uniform [-1/2,1/2]^3), each tested
// by a packet of rays from one origin on the sphere of radius 5. Each ray is aimed at
// p0 + u (p1 - p0) + v (p2 - p0) with u, v uniform in [1 - sqrt(2), 1]: that point is in the
// triangle with probability exactly 1/4, so about 25 % of the pairs hit (measured and printed
// by the tools with the exact test). d is normalised, t_min = 0, t_max = +INF. All
// coordinates are multiplied by `scale` (extremes: 1e-6 and 1e+6), optionally times a random
// power of two per packet (log2_spread).
//
// Boxes: random boxes about the origin (centre uniform in [-1,1]^3, half extents uniform in
// [0.05, 0.5]), packets of rays from an origin on the radius-5 sphere aimed at uniform points
// of the box grown by 1.6x per axis (roughly half hit), plus special rays: a fraction with one
// or two direction components exactly zero (inv = +-INF), of which some start exactly on a
// slab plane of the box (0*INF); some rays start inside the box; some have a finite t_max.
//
// Adversarial boxes for one format (AdversarialBoxGen, adversarial_box): every value is
// representable in the format; tiny and huge boxes (scale 2^-4 .. 2^4), rays aimed exactly at a
// corner, an edge point or a face point of the box from a random direction (the slab intervals
// touch within an ulp), a quarter of them grazing (one direction component +0 or -0), some with
// a finite t_min / t_max.
#pragma once

#include <cstdint>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/units/trace.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::units {

// xoshiro256** seeded with splitmix64 (util/rng.hpp): next(), uniform() ([0, 1), 53 random
// bits), uniform(lo, hi).
class Rng : public util::Xoshiro256ss {
 public:
  using util::Xoshiro256ss::Xoshiro256ss;
  uint64_t below(uint64_t n);         // [0, n), n > 0 (modulo with rejection)
  Vec3d unit_vector();                // uniform on the unit sphere (rejection sampling)
};

struct SynthTriOptions {
  uint64_t seed = 1;
  size_t triangles = 256;
  size_t rays_per_packet = 16;
  double scale = 1.0;
  // Each packet (triangle and its rays) is scaled by scale * 2^u, u uniform in [-spread,
  // spread]: values then span many binades, like the dissertation's scenes (Fig. 3.5:
  // exponents -33..18), so narrow exponents overflow/underflow.
  double log2_spread = 0.0;
};
std::vector<TriRecord> synth_tri(const SynthTriOptions& o);

struct SynthBoxOptions {
  uint64_t seed = 1;
  size_t boxes = 256;
  size_t rays_per_packet = 16;
  double scale = 1.0;
  double axis_parallel_fraction = 0.10;  // rays with zero direction components
  double on_plane_fraction = 0.5;        // of those, origin exactly on a slab plane (0*INF)
  double inside_fraction = 0.05;         // rays starting inside the box
  double finite_tmax_fraction = 0.25;    // rays with a finite t_max
};
std::vector<BoxRecord> synth_box(const SynthBoxOptions& o);

// Adversarial ray-box pairs for format f, one at a time (a long run needs no vector):
// next() draws box, target on the box (corner, edge or face point), direction, origin and
// t range from the generator's own stream; inv_k = 1/d_k rounded into f (+-INF where 1/d_k
// overflows, d_k = +-0 gives +-INF). The records are exact in f (rounding them into f changes
// nothing). No SoftScope is needed (and the thread's Soft statistics are not touched).
class AdversarialBoxGen {
 public:
  AdversarialBoxGen(const ru::num::Format& f, uint64_t seed);
  BoxRecord next();

 private:
  double q(double x) const;  // x rounded into f_ (RNE)
  ru::num::Format f_;
  Rng rng_;
  double maxf_;
};
// The first n records of AdversarialBoxGen(f, seed).
std::vector<BoxRecord> adversarial_box(const ru::num::Format& f, uint64_t seed, size_t n);

}  // namespace ru::units
