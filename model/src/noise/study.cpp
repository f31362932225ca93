// The noise quality study; see rayunits/noise/study.hpp and docs/NOISE.md.
#include "rayunits/noise/study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "rayunits/util/process.hpp"
#include "rayunits/util/rng.hpp"

namespace ru::noise {

namespace {

// Maximizes f over [0,1]^3: grid, then a pattern search from the best grid points.
Bound maximize(const std::function<double(Vec3)>& f, int grid) {
  struct Cand {
    double v;
    Vec3 p;
  };
  std::vector<Cand> c;
  for (int i = 0; i <= grid; ++i)
    for (int j = 0; j <= grid; ++j)
      for (int k = 0; k <= grid; ++k) {
        Vec3 p{static_cast<double>(i) / grid, static_cast<double>(j) / grid, static_cast<double>(k) / grid};
        c.push_back({f(p), p});
      }
  std::partial_sort(c.begin(), c.begin() + std::min<size_t>(16, c.size()), c.end(),
                    [](const Cand& a, const Cand& b) { return a.v > b.v; });
  Bound best{c[0].v, c[0].p};
  for (size_t n = 0; n < std::min<size_t>(16, c.size()); ++n) {
    Vec3 p = c[n].p;
    double v = c[n].v, h = 1.0 / grid;
    while (h > 1e-9) {
      bool moved = false;
      for (int a = 0; a < 3; ++a)
        for (int sgn = -1; sgn <= 1; sgn += 2) {
          Vec3 q = p;
          double* qa = a == 0 ? &q.x : a == 1 ? &q.y : &q.z;
          *qa = std::clamp(*qa + sgn * h, 0.0, 1.0);
          double w = f(q);
          if (w > v) {
            v = w;
            p = q;
            moved = true;
          }
        }
      if (!moved) h /= 2;
    }
    if (v > best.value) best = {v, p};
  }
  return best;
}

double w_cell(double d) {  // the half-resolution kernel in cell units
  if (!(d < 1)) return 0;
  double t = 1 - d, t2 = t * t, t4 = t2 * t2;
  return 4 * t4 * t - 3 * t4;
}

double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

void progress(const StudyOptions& o, const std::string& s) {
  if (o.progress) std::fprintf(stderr, "noise study: %s\n", s.c_str());
}

}  // namespace

Bound bound_half_cell(int grid) {
  return maximize(
      [](Vec3 F) {
        double s = 0;
        for (int c = 0; c < 8; ++c) {
          Vec3 D{F.x - (c & 1), F.y - ((c >> 1) & 1), F.z - (c >> 2)};
          double d = dot(D, D);
          s += std::sqrt(d) * std::fabs(w_cell(d));
        }
        return s;
      },
      grid);
}

Bound bound_full(int grid) {
  return maximize(
      [](Vec3 F) {
        double s = 0;
        for (int k = -1; k <= 2; ++k)
          for (int j = -1; j <= 2; ++j)
            for (int i = -1; i <= 2; ++i) {
              Vec3 D{F.x - i, F.y - j, F.z - k};
              double d = dot(D, D);
              s += std::sqrt(d) * std::fabs(kensler_kernel(d));
            }
        return s;
      },
      grid);
}

Bound bound_perlin(int grid) {
  return maximize(
      [](Vec3 F) {
        double s = 0, f[3] = {fade(F.x), fade(F.y), fade(F.z)};
        for (int c = 0; c < 8; ++c) {
          int b[3] = {c & 1, (c >> 1) & 1, c >> 2};
          Vec3 D{F.x - b[0], F.y - b[1], F.z - b[2]};
          double wgt = 1;
          for (int a = 0; a < 3; ++a) wgt *= b[a] ? f[a] : 1 - f[a];
          s += std::sqrt(2.0) * std::sqrt(dot(D, D)) * wgt;
        }
        return s;
      },
      grid);
}

double bound_fixed(const FixedNoise& f) {
  const int B = f.config().frac_bits;
  if (B > 9) throw std::invalid_argument("bound_fixed: exhaustive bound needs frac_bits <= 9");
  const std::int64_t one = 1ll << B;
  std::int64_t g2max = 0;
  for (int h = 0; h < 64; ++h) {
    const auto& g = f.grad(h);
    g2max = std::max<std::int64_t>(g2max, std::int64_t{g[0]} * g[0] + std::int64_t{g[1]} * g[1] + std::int64_t{g[2]} * g[2]);
  }
  const bool trunc = f.config().datapath == NoiseDatapath::kTrunc;
  // |w| as a function of the (truncated) squared distance, exactly as the model computes it
  std::vector<std::int64_t> wabs(3 * one + 1);
  for (std::int64_t d = 0; d <= 3 * one; ++d) {
    if (trunc) {
      wabs[d] = std::llabs(f.trunc_weight(d));
    } else {
      std::int64_t t = d < one ? one - d : 0, t2 = (t * t) >> B, t4 = (t2 * t2) >> B, t5 = (t4 * t) >> B;
      wabs[d] = std::llabs(4 * t5 - 3 * t4);
    }
  }
  // |dot| <= (|p| + slack) / 2^R with p the exact sum (units 2^-(B + Gb)); kFull: the floor only
  const int r = B + f.grad_frac_bits() - f.dot_frac_bits();  // the dot product's shift (kFull: B; kTrunc: B - 3)
  const std::int64_t slack = trunc ? f.trunc_dot_slack() : (std::int64_t{1} << B) - 1;
  auto isqrt_ceil = [](std::uint64_t n) {
    std::uint64_t r = static_cast<std::uint64_t>(std::sqrt(static_cast<double>(n)));
    while (r * r > n) --r;
    while ((r + 1) * (r + 1) <= n) ++r;
    return r * r == n ? r : r + 1;
  };
  std::vector<std::int64_t> sq[2], a2[2];
  for (int b = 0; b < 2; ++b) {
    sq[b].resize(one);
    a2[b].resize(one);
    for (std::int64_t fr = 0; fr < one; ++fr) {
      std::int64_t a = b ? one - fr : fr;
      sq[b][fr] = (a * a) >> B;
      a2[b][fr] = a * a;
    }
  }
  std::int64_t best = 0;
  for (std::int64_t x = 0; x < one; ++x)
    for (std::int64_t y = 0; y < one; ++y)
      for (std::int64_t z = 0; z < one; ++z) {
        std::int64_t s = 0;
        for (int c = 0; c < 8; ++c) {
          int bx = c & 1, by = (c >> 1) & 1, bz = c >> 2;
          std::int64_t d = sq[bx][x] + sq[by][y] + sq[bz][z];
          if (wabs[d] == 0) continue;
          std::uint64_t A2 = static_cast<std::uint64_t>(a2[bx][x] + a2[by][y] + a2[bz][z]);
          std::int64_t pmax = static_cast<std::int64_t>(isqrt_ceil(A2 * static_cast<std::uint64_t>(g2max)));
          std::int64_t dmax = (pmax + slack) >> r;  // kFull: ceil(|p| / 2^B) >= |floor(p / 2^B)|
          s += wabs[d] * dmax;
        }
        best = std::max(best, s);
      }
  return std::ldexp(static_cast<double>(best), -(B + f.dot_frac_bits()));
}

std::vector<NoiseSpec> study_noises(const FixedNoise& fixed) {
  auto r256 = std::make_shared<NoiseRef>(builtin_tables(), 256);
  auto r64 = std::make_shared<NoiseRef>(builtin_tables(), 64);
  auto fx = std::make_shared<FixedNoise>(fixed);
  const Vec3 N = (1.0 / std::sqrt(3.0)) * Vec3{1, 1, 1};
  std::vector<NoiseSpec> v;
  v.push_back({"perlin_improved", "Perlin improved noise (2002): single-table hash, 12 edge gradients, separable quintic",
               Slice::kAxis, 1, [](double x, double y, double z) { return perlin_improved(x, y, z); }});
  v.push_back({"perlin_hash_256", "separable quintic, 256 relaxed gradients, Perlin's single-table hash P[P[P[i]+j]+k]",
               Slice::kAxis, 1, [r256](double x, double y, double z) { return r256->separable(x, y, z, Hash::kPerlin); }});
  v.push_back({"xor_hash_256", "separable quintic, 256 relaxed gradients, xor hash Px[i]^Py[j]^Pz[k] (sec. 4.5)",
               Slice::kAxis, 1, [r256](double x, double y, double z) { return r256->separable(x, y, z, Hash::kXor); }});
  v.push_back({"kensler_full", "Kensler: xor hash, 256 relaxed gradients, radial 4-point kernel (sec. 4.6), slice z = const",
               Slice::kAxis, 1, [r256](double x, double y, double z) { return r256->full(x, y, z); }});
  v.push_back({"kensler_full_diag", "Kensler full, slice normal to x = y = z (no projection; Fig. 4.8)", Slice::kDiagonal,
               1, [r256](double x, double y, double z) { return r256->full(x, y, z); }});
  v.push_back({"kensler_projected", "Kensler with projection onto the slice plane (sec. 4.7, Fig. 4.10/4.11)",
               Slice::kDiagonal, 1,
               [r256, N](double x, double y, double z) { return r256->projected(Vec3{x, y, z}, N); }});
  v.push_back({"half_res", "half-resolution grid (sec. 4.8), float, 64 relaxed gradients, cell units", Slice::kAxis, 1,
               [r64](double x, double y, double z) { return r64->half_cell(x, y, z); }});
  v.push_back({"fixed_b" + std::to_string(fixed.config().frac_bits),
               "fixed-point hardware model, " + fixed.config().describe() + ", cell units", Slice::kAxis, 1,
               [fx](double x, double y, double z) {
                 return fx->to_real(fx->eval(fx->quantize(x), fx->quantize(y), fx->quantize(z)));
               }});
  // the truncated datapath (ru_noise_trunc) at the same widths
  FixedConfig tc = fixed.config();
  tc.datapath = NoiseDatapath::kTrunc;
  if (tc.frac_bits >= 5) {
    auto tx = std::make_shared<FixedNoise>(tc);
    v.push_back({"fixed_trunc_b" + std::to_string(tc.frac_bits),
                 "fixed-point truncated datapath (ru_noise_trunc), " + tc.describe() + ", cell units", Slice::kAxis, 1,
                 [tx](double x, double y, double z) {
                   return tx->to_real(tx->eval(tx->quantize(x), tx->quantize(y), tx->quantize(z)));
                 }});
  }
  return v;
}

Image render_slice(const NoiseSpec& s, int n, double px_per_lattice) {
  Image img(n, n);
  const double step = s.lattice / px_per_lattice;
  const double z0 = 0.375 * s.lattice;
  const Vec3 e1 = (1.0 / std::sqrt(2.0)) * Vec3{1, -1, 0}, e2 = (1.0 / std::sqrt(6.0)) * Vec3{1, 1, -2};
  const Vec3 c = Vec3{z0, z0, z0};
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      if (s.slice == Slice::kAxis) {
        img.at(x, y) = s.eval(x * step, y * step, z0);
      } else {
        Vec3 p = c + (x * step) * e1 + (y * step) * e2;
        img.at(x, y) = s.eval(p.x, p.y, p.z);
      }
    }
  return img;
}

ErrorRow fixed_error(const FixedConfig& cfg, long samples, std::uint64_t seed, double bound, int psnr_size) {
  FixedNoise f(cfg);
  NoiseRef r64(builtin_tables(), 64);
  ErrorRow row;
  row.frac_bits = cfg.frac_bits;
  row.out_w = cfg.out_w;
  row.samples = samples;
  const std::int64_t one = 1ll << cfg.frac_bits;
  const std::int64_t vmax = (1ll << (cfg.out_w - 1)) - 1, vmin = -(1ll << (cfg.out_w - 1));
  std::uint64_t s = seed ^ (0x9e37ull * static_cast<std::uint64_t>(cfg.frac_bits));
  double se = 0, sum = 0;
  for (long i = 0; i < samples; ++i) {
    std::int64_t w[3];
    for (int a = 0; a < 3; ++a) {
      std::int64_t cell = static_cast<std::int64_t>(util::splitmix64(s) % 256) - 128;
      std::int64_t fr = static_cast<std::int64_t>(util::splitmix64(s) % static_cast<std::uint64_t>(one));
      w[a] = cell * one + fr;
    }
    std::int64_t v = f.eval(w[0], w[1], w[2]);
    if (v == vmax || v == vmin) ++row.saturated;
    double e = f.to_real(v) - r64.half_cell(f.input_real(w[0]), f.input_real(w[1]), f.input_real(w[2]));
    row.max_abs = std::max(row.max_abs, std::fabs(e));
    se += e * e;
    sum += e;
  }
  row.rms = std::sqrt(se / static_cast<double>(samples));
  row.mean = sum / static_cast<double>(samples);
  // PSNR of an 8-bit image: psnr_size^2 pixels, 16 pixels per cell, slice z = 0.375.
  auto q8 = [bound](double v) { return static_cast<double>(std::clamp(std::lround((v / bound + 1) * 0.5 * 255), 0l, 255l)); };
  double mse = 0;
  for (int y = 0; y < psnr_size; ++y)
    for (int x = 0; x < psnr_size; ++x) {
      double u = x / 16.0, v = y / 16.0, z = 0.375;
      double ref = r64.half_cell(u, v, z);
      double fv = f.to_real(f.eval(f.quantize(u), f.quantize(v), f.quantize(z)));
      double d = q8(fv) - q8(ref);
      mse += d * d;
    }
  mse /= static_cast<double>(psnr_size) * psnr_size;
  row.psnr_db = mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : INFINITY;
  return row;
}

StudyResult run_study_result(const StudyOptions& o) {
  namespace fs = std::filesystem;
  StudyResult res;
  if (o.out_dir.empty()) throw std::invalid_argument("noise study: --out DIR is required");
  if (o.spectrum_size < 64 || (o.spectrum_size & (o.spectrum_size - 1)))
    throw std::invalid_argument("noise study: --size must be a power of two >= 64, got " + std::to_string(o.spectrum_size));
  if (o.min_bits < 4 || o.max_bits > 16 || o.min_bits > o.max_bits)
    throw std::invalid_argument("noise study: fraction bits must lie in 4..16");
  fs::create_directories(o.out_dir);
  const fs::path out(o.out_dir);
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  std::ostringstream md;
  md << "# Noise study\n\nCommand: `" << o.command << "`  \nTables: seed 0x" << std::hex << builtin_tables().seed
     << std::dec << "; sampling seed " << o.seed << ". Definitions: docs/NOISE.md.\n\n";

  // ---- bounds ----
  progress(o, "output-range bounds");
  const FixedConfig fcfg{8, 8, 15};  // default datapath, output wide enough to be exact
  FixedNoise fixed(fcfg);
  const Bound bh = bound_half_cell(), bf = bound_full(), bp = bound_perlin();
  const double bfx = bound_fixed(fixed);
  FixedConfig tcfg = fcfg;
  tcfg.datapath = NoiseDatapath::kTrunc;
  FixedNoise fixed_trunc(tcfg);
  const double bft = bound_fixed(fixed_trunc);

  // ---- spectra ----
  std::ofstream sp(out / "noise_spectra.csv");
  sp << "noise,slice,size,px_per_lattice,window,low_frac,band_frac,high_frac,q10,q50,q90,octaves,anisotropy,"
        "striation_x,striation_y,peak_freq,title\n";
  const bool one_period = o.spectrum_size == 1024;
  md << "## Slices and power spectra\n\n" << o.spectrum_size << "x" << o.spectrum_size
     << " samples, 4 per lattice spacing, mean removed; "
     << (one_period ? "axis slices span exactly one table period (256 lattice spacings) and are transformed without "
                      "a window, diagonal slices with a Hann window"
                    : "Hann window")
     << ". Frequencies f in cycles per lattice spacing: low = power fraction at f < 0.25, high at f > 1; q10/q50/q90 "
        "= power quantiles along f; octaves = log2(q90/q10). `white_noise` (i.i.d. Gaussian pixels) gives the "
        "sampling floor of the anisotropy and striation measures at this size.\n\n"
     << "| noise | slice | low | high | q10 | q50 | q90 | octaves | anisotropy | striation x | striation y |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  SpectrumParams spp;
  spp.px_per_lattice = 4;
  std::vector<NoiseSpec> specs = study_noises(fixed);
  {
    auto st = std::make_shared<std::uint64_t>(o.seed * 0x9E3779B97F4A7C15ull + 3);
    specs.push_back({"white_noise", "i.i.d. Gaussian pixels (floor of the anisotropy and striation measures)",
                     Slice::kAxis, 1, [st](double, double, double) {
                       // Box-Muller from two splitmix64 uniforms
                       double u1 = (static_cast<double>(util::splitmix64(*st) >> 11) + 1) * 0x1p-53;
                       double u2 = util::unit_double(util::splitmix64(*st));
                       return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
                     }});
  }
  for (const NoiseSpec& s : specs) {
    progress(o, "spectrum of " + s.name + " (" + fmt("%.1f", elapsed()) + " s)");
    Image img = render_slice(s, o.spectrum_size, 4);
    const bool hann = !(one_period && s.slice == Slice::kAxis);
    Image P = power_spectrum(img, hann);
    SpectrumStats st = spectrum_stats(P, spp);
    write_png_gray((out / ("noise_" + s.name + "_spectrum.png")).string(), o.spectrum_size / 2, o.spectrum_size / 2,
                   spectrum_view(P, o.spectrum_size / 2));
    Image view = render_slice(s, o.view_size, o.view_px_per_lattice);
    double m = 0;
    for (double v : view.v) m = std::max(m, std::fabs(v));
    write_png_gray((out / ("noise_" + s.name + "_slice.png")).string(), o.view_size, o.view_size,
                   gray_linear(view, m > 0 ? m : 1));
    const char* sl = s.slice == Slice::kAxis ? "axis" : "diagonal";
    sp << s.name << "," << sl << "," << o.spectrum_size << ",4," << (hann ? "hann" : "none") << ","
       << fmt("%.6g", st.low_frac) << "," << fmt("%.6g", st.band_frac) << "," << fmt("%.6g", st.high_frac) << ","
       << fmt("%.6g", st.q10) << "," << fmt("%.6g", st.q50) << "," << fmt("%.6g", st.q90) << ","
       << fmt("%.6g", st.octaves) << "," << fmt("%.6g", st.anisotropy) << "," << fmt("%.6g", st.striation_x) << ","
       << fmt("%.6g", st.striation_y) << "," << fmt("%.6g", st.peak_freq) << ",\"" << s.title << "\"\n";
    md << "| " << s.name << " | " << sl << " | " << fmt("%.4f", st.low_frac) << " | " << fmt("%.4f", st.high_frac)
       << " | " << fmt("%.3f", st.q10) << " | " << fmt("%.3f", st.q50) << " | " << fmt("%.3f", st.q90) << " | "
       << fmt("%.2f", st.octaves) << " | " << fmt("%.3f", st.anisotropy) << " | " << fmt("%.2f", st.striation_x)
       << " | " << fmt("%.2f", st.striation_y) << " |\n";
  }
  md << "\nImages: `noise_<name>_slice.png` (" << o.view_size << " px, " << o.view_px_per_lattice
     << " px per lattice spacing, gray = 0, scaled to the image's max |value|) and `noise_<name>_spectrum.png` "
        "(log10 power over 6 decades, DC centred, |f| <= 1 cycle per lattice spacing).\n\n";

  // ---- fixed-point error vs fraction bits ----
  std::ofstream er(out / "noise_error_vs_bits.csv");
  er << "frac_bits,out_w,samples,max_abs,rms,mean,psnr_db,at_output_limit,datapath\n";
  md << "## Fixed-point model vs float half-resolution reference\n\n"
     << o.error_samples << " random inputs per row (cells -128..127, every fraction equally likely), error in units "
        "of N (cell units, |N| <= " << fmt("%.5f", bh.value)
     << "); PSNR of a 512x512 8-bit image ([-bound, bound] -> 0..255). out_w = 2B-1 keeps the sum exact; the last "
        "row is the unit's default output width.\n\n"
     << "Datapath `full` is ru_noise (Kensler's), `trunc` ru_noise_trunc (docs/NOISE.md).\n\n"
     << "| datapath | frac bits | out_w | max abs | RMS | mean | PSNR dB |\n|---|---|---|---|---|---|---|\n";
  std::vector<FixedConfig> cfgs;
  for (const NoiseDatapath dp : {NoiseDatapath::kFull, NoiseDatapath::kTrunc}) {
    for (int b = o.min_bits; b <= o.max_bits; ++b)
      if (dp == NoiseDatapath::kFull || b >= 5) cfgs.push_back({b, 8, 2 * b - 1, dp});
    cfgs.push_back(FixedConfig{8, 8, 10, dp});
  }
  for (const FixedConfig& c : cfgs) {
    progress(o, "fixed-point error " + c.describe() + " (" + fmt("%.1f", elapsed()) + " s)");
    ErrorRow r = fixed_error(c, o.error_samples, o.seed, bh.value, 512);
    const char* dp_name = c.datapath == NoiseDatapath::kTrunc ? "trunc" : "full";
    res.errors.push_back(r);
    er << r.frac_bits << "," << r.out_w << "," << r.samples << "," << fmt("%.6g", r.max_abs) << ","
       << fmt("%.6g", r.rms) << "," << fmt("%.6g", r.mean) << "," << fmt("%.4f", r.psnr_db) << "," << r.saturated
       << "," << dp_name << "\n";
    md << "| " << dp_name << " | " << r.frac_bits << " | " << r.out_w << " | " << fmt("%.5f", r.max_abs) << " | " << fmt("%.6f", r.rms)
       << " | " << fmt("%.2e", r.mean) << " | " << fmt("%.2f", r.psnr_db) << " |\n";
  }

  // ---- output range ----
  std::ofstream rg(out / "noise_range.csv");
  rg << "noise,samples,min,max,bound,bound_where\n";
  md << "\n## Output range\n\n" << o.range_samples
     << " random points per noise (coordinates uniform in [-128, 128)) against the derived bound.\n\n"
     << "| noise | samples | min | max | bound |\n|---|---|---|---|---|\n";
  NoiseRef r256(builtin_tables(), 256), r64(builtin_tables(), 64);
  struct RangeCase {
    const char* name;
    std::function<double(double, double, double)> f;
    double bound;
    Vec3 at;
  };
  const RangeCase rc[] = {
      {"perlin_improved", [](double x, double y, double z) { return perlin_improved(x, y, z); }, bp.value, bp.at},
      {"kensler_full", [&](double x, double y, double z) { return r256.full(x, y, z); }, bf.value, bf.at},
      {"half_res", [&](double x, double y, double z) { return r64.half_cell(x, y, z); }, bh.value, bh.at},
      {"fixed_b8",
       [&](double x, double y, double z) {
         return fixed.to_real(fixed.eval(fixed.quantize(x), fixed.quantize(y), fixed.quantize(z)));
       },
       bfx, Vec3{}},
      {"fixed_trunc_b8",
       [&](double x, double y, double z) {
         return fixed_trunc.to_real(fixed_trunc.eval(fixed_trunc.quantize(x), fixed_trunc.quantize(y), fixed_trunc.quantize(z)));
       },
       bft, Vec3{}},
  };
  for (const RangeCase& c : rc) {
    progress(o, std::string("output range of ") + c.name + " (" + fmt("%.1f", elapsed()) + " s)");
    std::uint64_t s = o.seed * 0x2545F4914F6CDD1Dull + 7;
    double lo = INFINITY, hi = -INFINITY;
    for (long i = 0; i < o.range_samples; ++i) {
      double p[3];
      for (double& q : p) q = util::unit_double(util::splitmix64(s)) * 256 - 128;
      double v = c.f(p[0], p[1], p[2]);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    std::string where = std::string(c.name).rfind("fixed_", 0) == 0
                            ? "exhaustive over one cell (rigorous)"
                            : "at (" + fmt("%.4f", c.at.x) + " " + fmt("%.4f", c.at.y) + " " + fmt("%.4f", c.at.z) + ")";
    rg << c.name << "," << o.range_samples << "," << fmt("%.9g", lo) << "," << fmt("%.9g", hi) << ","
       << fmt("%.9g", c.bound) << ",\"" << where << "\"\n";
    md << "| " << c.name << " | " << o.range_samples << " | " << fmt("%.5f", lo) << " | " << fmt("%.5f", hi) << " | "
       << fmt("%.5f", c.bound) << " |\n";
  }
  md << "\nBounds: Cauchy-Schwarz per lattice point maximized over the cell (float noises), exhaustive over "
        "every input fraction of a cell for the fixed-point model (B=8). Total time "
     << fmt("%.1f", elapsed()) << " s.\n";
  std::ofstream(out / "noise_summary.md") << md.str();
  sp.close();
  er.close();
  rg.close();
  if (!sp || !er || !rg) throw std::runtime_error("noise study: cannot write the CSV files in " + o.out_dir);

  if (o.plot) {
    std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    std::string script = std::string(RU_SOURCE_DIR) + "/scripts/plot_noise.py";
    std::string cmd = py + " '" + script + "' '" + o.out_dir + "'";
    progress(o, "plot: " + cmd);
    if (util::run_foreground({py, script, o.out_dir}) != 0)
      std::fprintf(stderr, "noise study: warning: plotting failed (%s); the CSV files are complete\n", cmd.c_str());
  }
  progress(o, "done in " + fmt("%.1f", elapsed()) + " s: " + o.out_dir);
  res.summary_md = md.str();
  return res;
}

int run_study(const StudyOptions& o) {
  run_study_result(o);
  return 0;
}

}  // namespace ru::noise
