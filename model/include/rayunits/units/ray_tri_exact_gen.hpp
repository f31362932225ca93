// rayunits units: the operand generator of the exactly-once unit's tests (ru_ray_tri_exact and
// its side path ru_exact_path): records weighted towards the cases the filter cannot decide --
// coordinates on a small grid (exact zeros of edge volumes, rays through vertices and along
// edges, directions in the triangle's plane), extremes (largest finite, smallest subnormal,
// smallest normal), and t_min / t_max equal to the exact hit distance. One generator, the
// project's RNG (util::Xoshiro256ss); used by the unit registry (models::ray_tri_exact_inputs)
// and by tb/exact.
#pragma once

#include <cstdint>

#include "rayunits/num/format.hpp"
#include "rayunits/units/vec.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::units {

// One record: op (0..2 edge k, 3 the interval: the side-path request a test of ru_exact_path
// makes; ru_ray_tri_exact ignores it) and 17 operand bit patterns (a, d, p0, p1, p2 as x, y, z;
// t_min, t_max). Formats of at most 32 bits.
struct ExactTriRecord {
  int op = 0;
  uint32_t bits[17] = {};
};

// The value of a bit pattern as the units read it (flush-to-zero: a subnormal reads as zero).
double exact_gen_value(const num::Format& f, uint32_t b);
Vec3d exact_gen_vec3(const num::Format& f, const uint32_t* b);

class ExactTriGen {
 public:
  ExactTriGen(const num::Format& f, uint64_t seed);
  // Record i of the stream: i % 5 picks the kind (0 random finite, 1 grid, 2 grid through a
  // vertex, 3 grid with d = +-edge (V = 0), 4 extremes).
  ExactTriRecord next(int i);

 private:
  uint32_t random_finite();
  uint32_t extreme();
  uint32_t grid(int scale);
  uint32_t enc(double x) const;
  void through_vertex(ExactTriRecord& r);
  void bounds(ExactTriRecord& r);
  double exact_t(const ExactTriRecord& r) const;
  uint64_t below(uint64_t n) { return util::bounded_lemire(rng_, n); }

  num::Format f_;
  util::Xoshiro256ss rng_;
  int scale_ = 0;
};

}  // namespace ru::units
