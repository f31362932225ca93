// Studies built on the renderer: BVH rotations on static scenes (Table 5.1 shape) and on
// animations (§5.6, Table 5.2 shape), the image-error study (Tables 3.5/3.6), scene profiles
// (Fig. 3.5 and the "model only what a scene requires" recommendation), the render benchmark.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "rayunits/render/render.hpp"

namespace ru::render {

// ---------------------------------------------------------------- tree rotations, static
struct RotationOptions {
  int leaf_size = 4;
  int sa_iterations = 1250;  // §5.4: N = 1250, f = 50
  double heat = 0.15;        // h (see bvh/rotate.hpp)
  uint64_t seed = 1;
  int cast_size = 256;        // ray-casting image (primary rays only, float, one thread)
  bool progress = false;
};
struct RotationRow {
  std::string scene;
  size_t triangles = 0;
  double build_s = 0, hill_s = 0, sa_s = 0;
  double cost_none = 0, cost_hill = 0, cost_sa = 0;
  double cast_none = 0, cast_hill = 0, cast_sa = 0;     // ray-casting seconds
  double boxes_none = 0, boxes_hill = 0, boxes_sa = 0;  // ray-box tests per primary ray
  int hill_passes = 0, sa_passes = 0;
  uint64_t hill_rotations = 0, sa_rotations = 0;
  std::vector<double> sa_cost_per_pass;  // Fig. 5.4
};
RotationRow rotation_study(const scene::Scene& s, const RotationOptions& o);

// ---------------------------------------------------------------- tree rotations, animation
struct AnimationFrame {
  int frame = 0;
  double cost_refit = 0, cost_rotate = 0, cost_rebuild = 0;
  uint64_t rotations = 0;
  double update_refit_s = 0, update_rotate_s = 0, rebuild_s = 0;
  double render_refit_s = 0, render_rotate_s = 0, render_rebuild_s = 0;
};
std::vector<AnimationFrame> animation_study(const std::string& name, int frames, int cast_size, bool progress);

// ---------------------------------------------------------------- image-error study
struct ImageStudyOptions {
  int width = 256, height = 256;
  std::vector<int> exp_bits{7};
  std::vector<int> frac_bits{8, 10, 12, 14, 16, 18, 20, 22};
  std::vector<TriAlgo> algos{TriAlgo::Robust, TriAlgo::MT};
  BvhKind bvh = BvhKind::Median;  // what the dissertation's reduced-precision renders used
  units::BoxMode box = units::BoxMode::Plain;
  NoiseMode noise = NoiseMode::Float;
  int threads = 2;
  std::string image_dir;  // non-empty: write reference, per-point images and side-by-sides
  std::string image_prefix;  // prepended to every image file name
  bool progress = false;
};
struct ImageStudyRow {
  int exp_bits = 0, frac_bits = 0;
  TriAlgo algo = TriAlgo::Robust;
  ImageDiff diff;
  double seconds = 0;
  uint64_t overflows = 0, underflows = 0, invalids = 0;
};
std::vector<ImageStudyRow> image_study(const scene::Scene& s, const ImageStudyOptions& o);

// ---------------------------------------------------------------- scene profile
struct ProfileOptions {
  int width = 128, height = 128;
  TriAlgo algo = TriAlgo::Robust;
  BvhKind bvh = BvhKind::Median;
  double max_error_fraction = 0.001;  // <= 0.1 % of the pixels more than 10 % off
  double min_psnr = 40.0;
  int min_frac = 4, max_frac = 30;
  int threads = 2;
  bool progress = false;
};
struct ExpWidthRow {
  int exp_bits = 0;
  int emin = 0, emax = 0;
  uint64_t overflow = 0;   // values with exponent > emax
  uint64_t subnormal = 0;  // values below the smallest normal (gradual underflow)
  uint64_t flushed = 0;    // values below the smallest subnormal at the recommended fraction
};
struct FracRow {
  int frac_bits = 0;
  ImageDiff diff;
  bool meets = false;
};
struct Profile {
  std::string scene;
  size_t triangles = 0;
  ExpHistogram all, inputs;
  std::vector<ExpWidthRow> widths;
  int no_overflow_exp = 0;   // smallest E without overflow (0: none up to 11)
  // E >= no_overflow_exp checked with 40 fraction bits; recommended_exp is the first meeting
  // the target (0: none up to 11)
  std::vector<std::pair<int, FracRow>> exp_checks;
  int recommended_exp = 0;
  std::vector<FracRow> fracs;
  int recommended_frac = 0;  // smallest M meeting the target at recommended_exp (0: none)
  std::vector<std::string> units;
  uint64_t noise_evals = 0;
};
Profile profile_scene(const scene::Scene& s, const ProfileOptions& o);
std::string profile_json(const Profile& p, const ProfileOptions& o);
std::string profile_text(const Profile& p, const ProfileOptions& o);

}  // namespace ru::render
