// rayunits noise: images, 2D power spectra and the spectral quality numbers of the noise study
// (definitions in docs/NOISE.md, "Spectral measures").
#pragma once

#include <complex>
#include <string>
#include <vector>

namespace ru::noise {

// A real image, row-major: v[y * w + x].
struct Image {
  int w = 0, h = 0;
  std::vector<double> v;
  Image() = default;
  Image(int w_, int h_) : w(w_), h(h_), v(static_cast<size_t>(w_) * h_, 0.0) {}
  double& at(int x, int y) { return v[static_cast<size_t>(y) * w + x]; }
  double at(int x, int y) const { return v[static_cast<size_t>(y) * w + x]; }
};

// In-place radix-2 FFT (n a power of two), forward: X[k] = sum x[j] e^{-2 pi i jk/n}.
void fft(std::vector<std::complex<double>>& a, bool inverse = false);
// Forward 2D FFT of a w x h complex array (both powers of two), row-major.
void fft2(std::vector<std::complex<double>>& a, int w, int h);

// Power spectrum |F|^2 of the image after removing its mean and (optionally) applying a
// separable Hann window; returned unshifted (index ky * w + kx, frequency 0 at index 0).
Image power_spectrum(const Image& img, bool hann = true);

// Frequency in cycles per lattice spacing of spectrum bin k (signed, -n/2 .. n/2-1) for an image
// of n pixels with `px_per_lattice` pixels per lattice spacing.
inline double bin_freq(int k, int n, double px_per_lattice) {
  int s = k < n / 2 ? k : k - n;
  return static_cast<double>(s) * px_per_lattice / n;
}

struct SpectrumStats {
  double low_frac = 0;      // power at 0 < f < f_low, over the total (DC excluded)
  double high_frac = 0;     // power at f > f_high, over the total
  double band_frac = 0;     // power at f_low <= f <= f_high
  double q10 = 0, q50 = 0, q90 = 0;  // frequencies below which 10 / 50 / 90 % of the power lie
  double octaves = 0;       // log2(q90 / q10): width of the band holding the central 80 %
  double anisotropy = 0;    // coefficient of variation of the mean power over angle bins, f_low..f_high
  double striation_x = 0;   // line-to-line variation index of lines of constant kx (vertical lines)
  double striation_y = 0;   // ... of lines of constant ky (horizontal lines)
  double peak_freq = 0;     // frequency of the largest radial mean power (cycles per lattice)
};

struct SpectrumParams {
  double px_per_lattice = 4;  // pixels per lattice spacing of the noise being measured
  double f_low = 0.25;        // cycles per lattice spacing (half the lattice Nyquist frequency)
  double f_high = 1.0;        // cycles per lattice spacing (the lattice's sampling frequency)
  int angle_bins = 32;        // over [0, pi)
  double stria_f_min = 0.125, stria_f_max = 1.0;  // annulus of the striation index
};

SpectrumStats spectrum_stats(const Image& power, const SpectrumParams& p = {});

// Radial mean power profile: element r is the mean over bins with round(|k|) == r (k in bins).
std::vector<double> radial_profile(const Image& power);

// 8-bit images. gray_linear maps [-m, m] to 0..255 (clamped); spectrum_view shows
// log10(power) over `decades` decades below the maximum, DC centred, cropped to `crop` x `crop`
// bins around DC (crop <= w, h).
std::vector<unsigned char> gray_linear(const Image& img, double m);
std::vector<unsigned char> spectrum_view(const Image& power, int crop, double decades = 6);
// Writes an 8-bit grayscale PNG; throws std::runtime_error on failure.
void write_png_gray(const std::string& path, int w, int h, const std::vector<unsigned char>& px);

}  // namespace ru::noise
