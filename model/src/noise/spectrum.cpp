// Power spectra and spectral measures of the noise study; see rayunits/noise/spectrum.hpp.
#include "rayunits/noise/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace ru::noise {

namespace {
bool pow2(int n) { return n > 0 && (n & (n - 1)) == 0; }
}  // namespace

void fft(std::vector<std::complex<double>>& a, bool inverse) {
  const size_t n = a.size();
  if (!pow2(static_cast<int>(n))) throw std::invalid_argument("fft: size must be a power of two");
  for (size_t i = 1, j = 0; i < n; ++i) {  // bit reversal
    size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (size_t len = 2; len <= n; len <<= 1) {
    const double ang = 2 * M_PI / static_cast<double>(len) * (inverse ? 1 : -1);
    for (size_t i = 0; i < n; i += len) {
      for (size_t k = 0; k < len / 2; ++k) {
        // twiddle computed directly (no recurrence) so the error stays at rounding level
        std::complex<double> w(std::cos(ang * static_cast<double>(k)), std::sin(ang * static_cast<double>(k)));
        std::complex<double> u = a[i + k], v = a[i + k + len / 2] * w;
        a[i + k] = u + v;
        a[i + k + len / 2] = u - v;
      }
    }
  }
}

void fft2(std::vector<std::complex<double>>& a, int w, int h) {
  if (!pow2(w) || !pow2(h) || a.size() != static_cast<size_t>(w) * h)
    throw std::invalid_argument("fft2: sizes must be powers of two");
  std::vector<std::complex<double>> line;
  for (int y = 0; y < h; ++y) {
    line.assign(a.begin() + static_cast<long>(y) * w, a.begin() + static_cast<long>(y + 1) * w);
    fft(line);
    std::copy(line.begin(), line.end(), a.begin() + static_cast<long>(y) * w);
  }
  line.resize(h);
  for (int x = 0; x < w; ++x) {
    for (int y = 0; y < h; ++y) line[y] = a[static_cast<size_t>(y) * w + x];
    fft(line);
    for (int y = 0; y < h; ++y) a[static_cast<size_t>(y) * w + x] = line[y];
  }
}

Image power_spectrum(const Image& img, bool hann) {
  double mean = 0;
  for (double v : img.v) mean += v;
  mean /= static_cast<double>(img.v.size());
  std::vector<std::complex<double>> a(img.v.size());
  for (int y = 0; y < img.h; ++y) {
    double wy = hann ? 0.5 - 0.5 * std::cos(2 * M_PI * y / img.h) : 1.0;
    for (int x = 0; x < img.w; ++x) {
      double wx = hann ? 0.5 - 0.5 * std::cos(2 * M_PI * x / img.w) : 1.0;
      a[static_cast<size_t>(y) * img.w + x] = (img.at(x, y) - mean) * wx * wy;
    }
  }
  fft2(a, img.w, img.h);
  Image p(img.w, img.h);
  for (size_t i = 0; i < a.size(); ++i) p.v[i] = std::norm(a[i]);
  return p;
}

namespace {
int signed_bin(int k, int n) { return k < n / 2 ? k : k - n; }
}  // namespace

std::vector<double> radial_profile(const Image& P) {
  int rmax = static_cast<int>(std::ceil(std::hypot(P.w / 2, P.h / 2))) + 1;
  std::vector<double> sum(rmax + 1, 0.0), cnt(rmax + 1, 0.0);
  for (int y = 0; y < P.h; ++y)
    for (int x = 0; x < P.w; ++x) {
      int r = static_cast<int>(std::lround(std::hypot(signed_bin(x, P.w), signed_bin(y, P.h))));
      sum[r] += P.at(x, y);
      cnt[r] += 1;
    }
  for (int r = 0; r <= rmax; ++r) sum[r] = cnt[r] > 0 ? sum[r] / cnt[r] : 0;
  return sum;
}

SpectrumStats spectrum_stats(const Image& P, const SpectrumParams& p) {
  SpectrumStats s;
  const int W = P.w, H = P.h;
  // frequency of bin (kx, ky) in cycles per lattice spacing
  auto fx = [&](int kx) { return bin_freq(kx, W, p.px_per_lattice); };
  auto fy = [&](int ky) { return bin_freq(ky, H, p.px_per_lattice); };
  double total = 0, low = 0, high = 0;
  std::vector<double> ang_sum(p.angle_bins, 0.0), ang_cnt(p.angle_bins, 0.0);
  for (int ky = 0; ky < H; ++ky)
    for (int kx = 0; kx < W; ++kx) {
      if (kx == 0 && ky == 0) continue;
      double f = std::hypot(fx(kx), fy(ky));
      double v = P.at(kx, ky);
      total += v;
      if (f < p.f_low) low += v;
      if (f > p.f_high) high += v;
      if (f >= p.f_low && f <= p.f_high) {
        double a = std::atan2(fy(ky), fx(kx));
        if (a < 0) a += M_PI;  // real image: P(k) = P(-k)
        int b = std::min(p.angle_bins - 1, static_cast<int>(a / M_PI * p.angle_bins));
        ang_sum[b] += v;
        ang_cnt[b] += 1;
      }
    }
  {
    // power quantiles along the radius (ring sums, ring = bins with round(|k|) = r)
    std::vector<double> ring;
    for (int ky = 0; ky < H; ++ky)
      for (int kx = 0; kx < W; ++kx) {
        if (kx == 0 && ky == 0) continue;
        size_t r = static_cast<size_t>(std::lround(std::hypot(signed_bin(kx, W), signed_bin(ky, H))));
        if (ring.size() <= r) ring.resize(r + 1, 0.0);
        ring[r] += P.at(kx, ky);
      }
    const double bin = p.px_per_lattice / std::max(W, H);
    double cum = 0, q[3] = {0.1, 0.5, 0.9}, *out[3] = {&s.q10, &s.q50, &s.q90};
    int qi = 0;
    for (size_t r = 0; r < ring.size() && qi < 3; ++r) {
      cum += ring[r];
      while (qi < 3 && cum >= q[qi] * total) *out[qi++] = static_cast<double>(r) * bin;
    }
    s.octaves = s.q10 > 0 ? std::log2(s.q90 / s.q10) : 0;
  }
  s.low_frac = total > 0 ? low / total : 0;
  s.high_frac = total > 0 ? high / total : 0;
  s.band_frac = 1 - s.low_frac - s.high_frac;
  {
    double m = 0, m2 = 0;
    int n = 0;
    for (int b = 0; b < p.angle_bins; ++b) {
      if (ang_cnt[b] == 0) continue;
      double v = ang_sum[b] / ang_cnt[b];
      m += v;
      m2 += v * v;
      ++n;
    }
    m /= n;
    s.anisotropy = m > 0 ? std::sqrt(std::max(0.0, m2 / n - m * m)) / m : 0;
  }
  // Striation: normalize by the radial mean, then compare the means of whole lines.
  std::vector<double> R = radial_profile(P);
  {
    size_t best = 1;
    for (size_t r = 1; r < R.size(); ++r)
      if (R[r] > R[best]) best = r;
    s.peak_freq = static_cast<double>(best) * p.px_per_lattice / std::max(W, H);
  }
  auto line_index = [&](bool horizontal) {
    // horizontal: lines of constant ky (mean over kx); else lines of constant kx
    const int nlines = horizontal ? H : W, nalong = horizontal ? W : H;
    std::vector<double> means;
    double nbins = 0;
    for (int l = 0; l < nlines; ++l) {
      double sum = 0;
      int cnt = 0;
      for (int a = 0; a < nalong; ++a) {
        int kx = horizontal ? a : l, ky = horizontal ? l : a;
        double f = std::hypot(fx(kx), fy(ky));
        if (f < p.stria_f_min || f > p.stria_f_max) continue;
        int r = static_cast<int>(std::lround(std::hypot(signed_bin(kx, W), signed_bin(ky, H))));
        if (R[r] <= 0) continue;
        sum += P.at(kx, ky) / R[r];
        ++cnt;
      }
      if (cnt < 16) continue;
      means.push_back(sum / cnt);
      nbins += cnt;
    }
    if (means.size() < 2) return 0.0;
    double m = 0, m2 = 0;
    for (double v : means) {
      m += v;
      m2 += v * v;
    }
    const double n = static_cast<double>(means.size());
    m /= n;
    double cv = std::sqrt(std::max(0.0, m2 / n - m * m)) / m;
    return cv * std::sqrt(nbins / n);  // ~1 for independent bins, >> 1 for striated lines
  };
  s.striation_y = line_index(true);
  s.striation_x = line_index(false);
  return s;
}

std::vector<unsigned char> gray_linear(const Image& img, double m) {
  std::vector<unsigned char> px(img.v.size());
  for (size_t i = 0; i < img.v.size(); ++i) {
    double t = (img.v[i] / m + 1) * 0.5 * 255.0;
    px[i] = static_cast<unsigned char>(std::clamp(std::lround(t), 0l, 255l));
  }
  return px;
}

std::vector<unsigned char> spectrum_view(const Image& P, int crop, double decades) {
  if (crop > P.w || crop > P.h) throw std::invalid_argument("spectrum_view: crop larger than the spectrum");
  double mx = 0;
  for (size_t i = 1; i < P.v.size(); ++i) mx = std::max(mx, P.v[i]);
  const double top = std::log10(mx > 0 ? mx : 1);
  std::vector<unsigned char> px(static_cast<size_t>(crop) * crop);
  for (int y = 0; y < crop; ++y)
    for (int x = 0; x < crop; ++x) {
      int kx = ((x - crop / 2) % P.w + P.w) % P.w, ky = ((y - crop / 2) % P.h + P.h) % P.h;
      double v = P.at(kx, ky);
      double t = v > 0 ? (std::log10(v) - (top - decades)) / decades : 0;
      px[static_cast<size_t>(y) * crop + x] = static_cast<unsigned char>(std::clamp(std::lround(t * 255), 0l, 255l));
    }
  return px;
}

void write_png_gray(const std::string& path, int w, int h, const std::vector<unsigned char>& px) {
  if (px.size() != static_cast<size_t>(w) * h) throw std::invalid_argument("write_png_gray: size mismatch");
  if (!stbi_write_png(path.c_str(), w, h, 1, px.data(), w))
    throw std::runtime_error("cannot write " + path);
}

}  // namespace ru::noise
