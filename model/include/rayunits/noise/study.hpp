// rayunits noise: the quality study behind `rayunits noise study` (docs/NOISE.md): output-range
// bounds, 2D slices and their spectra, and the fixed-point error against the float reference.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rayunits/noise/fixed.hpp"
#include "rayunits/noise/reference.hpp"
#include "rayunits/noise/spectrum.hpp"

namespace ru::noise {

// ---- output-range bounds ----------------------------------------------------------------------
// A bound M with |noise| <= M everywhere, from the Cauchy-Schwarz inequality per lattice point
// (|D . G| <= |D| |G|): M = max over the cell of sum |D| |G|max |kernel|, maximized on a grid of
// (grid+1)^3 points of the cell and refined by a local pattern search (docs/NOISE.md).
struct Bound {
  double value = 0;
  Vec3 at;  // where (fractional position in the cell)
};
Bound bound_half_cell(int grid = 48);  // NoiseRef::half_cell, |G| = 1
Bound bound_full(int grid = 24);       // NoiseRef::full / projected without falloff, |G| = 1
Bound bound_perlin(int grid = 48);     // perlin_improved, |g| = sqrt(2)
// Rigorous bound of |FixedNoise::eval| (before saturation) in units of N: exhaustive over
// every fractional input of one cell (2^(3B) points; frac_bits <= 9), with
// |dot| <= ceil(sqrt(|a|^2 |g|max^2) / 2^B) per corner. Returns value / 2^(2B).
double bound_fixed(const FixedNoise& f);

// ---- slices -----------------------------------------------------------------------------------
enum class Slice { kAxis, kDiagonal };  // z = const, or the plane normal to x = y = z

struct NoiseSpec {
  std::string name;         // file-name stem, e.g. "perlin_improved"
  std::string title;        // one line
  Slice slice = Slice::kAxis;
  double lattice = 1;       // lattice spacing in the function's own units
  // value at the point p (function units)
  std::function<double(double, double, double)> eval;
};

// The study's set of noises (built from the checked-in tables).
std::vector<NoiseSpec> study_noises(const FixedNoise& fixed);

// Samples an n x n slice with `px_per_lattice` pixels per lattice spacing.
Image render_slice(const NoiseSpec& s, int n, double px_per_lattice);

// ---- fixed-point error -------------------------------------------------------------------------
struct ErrorRow {
  int frac_bits = 0, out_w = 0;
  long samples = 0;
  double max_abs = 0, rms = 0, mean = 0;  // fixed - float, in units of N (cell units)
  double psnr_db = 0;                     // 8-bit images, [-bound, bound] -> 0..255
  long saturated = 0;
};
ErrorRow fixed_error(const FixedConfig& c, long samples, std::uint64_t seed, double bound, int psnr_size);

// ---- the study --------------------------------------------------------------------------------
struct StudyOptions {
  std::string out_dir;
  std::string command;          // the command line (recorded in the summary)
  int spectrum_size = 1024;     // pixels per side of the spectral images (power of two)
  int view_size = 512;          // pixels per side of the slice views
  double view_px_per_lattice = 32;
  long error_samples = 200000;  // per fraction width
  long range_samples = 1000000; // output-range samples per noise (>= 10^7 with --long)
  int min_bits = 4, max_bits = 12;
  std::uint64_t seed = 1;
  bool plot = true;             // run scripts/plot_noise.py for the PNG curve
  bool progress = true;         // progress lines on stderr
};
struct StudyResult {
  std::vector<ErrorRow> errors;  // the fixed-point error rows (noise_error_vs_bits.csv)
  std::string summary_md;        // the Markdown written to noise_summary.md
};
// Writes noise_*.csv, noise_*.png and noise_summary.md into out_dir (`rayunits noise study`;
// the report's noise section calls it too).
StudyResult run_study_result(const StudyOptions& o);
int run_study(const StudyOptions& o);  // run_study_result; returns 0

}  // namespace ru::noise
