// The Mirth-style renderer, one template over the arithmetic type (double, float, Soft, Probe).
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "rayunits/bvh/median.hpp"
#include "rayunits/noise/fixed.hpp"
#include "rayunits/noise/reference.hpp"
#include "rayunits/render/render.hpp"
#include "rayunits/render/tracer.hpp"
#include "rayunits/units/ray_box.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/trace.hpp"
#include "rayunits/util/parallel.hpp"

namespace ru::render {

using num::fp_abs;
using num::fp_cast;
using num::fp_max;
using num::fp_min;
using num::fp_to_double;
using units::Vec3;

void parse_size(const std::string& s, int* w, int* h) {
  char* end = nullptr;
  const long a = std::strtol(s.c_str(), &end, 10);
  long b = a;
  if (end && *end == 'x') {
    const char* p = end + 1;
    b = std::strtol(p, &end, 10);
    if (end == p) end = nullptr;
  }
  if (!end || *end != '\0' || a < 1 || b < 1 || a > 16384 || b > 16384)
    throw std::invalid_argument("bad --size '" + s + "' (expected WxH or N, 1..16384, e.g. 512x512)");
  *w = static_cast<int>(a);
  *h = static_cast<int>(b);
}

TriAlgo parse_tri(const std::string& s) {
  if (s == "robust") return TriAlgo::Robust;
  if (s == "mt") return TriAlgo::MT;
  throw std::invalid_argument("unknown triangle test '" + s + "' (accepted: robust, mt)");
}
void check_box_format(const std::string& box, const std::string& format) {
  if (box.empty()) return;
  const std::string accepted = "(accepted: an eXmY format, without -ftz, no wider than the render format " + format + ")";
  num::Format b;
  try {
    b = num::Format::parse(box);
    b.validate();
  } catch (const std::exception& e) {
    throw std::invalid_argument("bad box format '" + box + "': " + e.what() + " " + accepted);
  }
  if (!b.subnormals) throw std::invalid_argument("box format '" + box + "' flushes to zero: outward rounding needs its subnormals " + accepted);
  const num::Format f = format == "double" ? num::Format{11, 52}
                        : format == "float" ? num::Format{8, 23}
                                            : num::Format::parse(format);
  if (b.exp_bits > f.exp_bits || b.frac_bits > f.frac_bits || (!f.subnormals && b.exp_bits == f.exp_bits))
    throw std::invalid_argument("box format '" + box + "' has values the render format " + format +
                                " does not hold " + accepted);
}

double round_box_bound(const num::Format& box, double x, bool up) {
  num::Format f = box;
  f.round = up ? num::Round::RUP : num::Round::RDN;
  return num::to_double(f, num::from_double(f, x).bits);
}

BvhKind parse_bvh(const std::string& s) {
  if (s == "sah") return BvhKind::Sah;
  if (s == "median") return BvhKind::Median;
  throw std::invalid_argument("unknown BVH build '" + s + "' (accepted: sah, median)");
}
NoiseMode parse_noise(const std::string& s) {
  if (s == "float") return NoiseMode::Float;
  if (s == "fixed") return NoiseMode::Fixed;
  if (s == "fixed-trunc") return NoiseMode::FixedTrunc;
  throw std::invalid_argument("unknown noise model '" + s + "' (accepted: float, fixed, fixed-trunc)");
}

TextureImpl parse_texture(const std::string& s) {
  if (s == "shader") return TextureImpl::Shader;
  if (s == "unit") return TextureImpl::Unit;
  throw std::invalid_argument("unknown texture implementation '" + s + "' (accepted: shader, unit)");
}

noise::TextureConfig texture_config(NoiseMode m) {
  noise::TextureConfig c;
  c.noise = noise::default_config(m == NoiseMode::Fixed ? noise::NoiseDatapath::kFull : noise::NoiseDatapath::kTrunc);
  return c;  // the defaults: 8 octaves, lacunarity 2, gain 1/2, 12 output fraction bits
}
units::BoxMode parse_box(const std::string& s) {
  if (s == "plain") return units::BoxMode::Plain;
  if (s == "conservative") return units::BoxMode::Conservative;
  throw std::invalid_argument("unknown box test '" + s + "' (accepted: plain, conservative)");
}
const char* tri_name(TriAlgo a) { return a == TriAlgo::Robust ? "robust" : "mt"; }
const char* bvh_name(BvhKind k) { return k == BvhKind::Sah ? "sah" : "median"; }

namespace {

// Prepared, Tracer, prepare(): rayunits/render/tracer.hpp (shared with the TRaX model).
using kernel::Counters;
using kernel::prepare;
using kernel::Prepared;
using kernel::TraceSink;
using kernel::Tracer;

double process_cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// Per-thread environment of the arithmetic type: the Soft format scope, the Probe sink.
template <class T>
struct ThreadEnv {
  explicit ThreadEnv(const num::Format&) {}
  void finish(RenderStats&, std::mutex&) {}
};
template <>
struct ThreadEnv<num::Soft> {
  num::SoftScope scope;
  explicit ThreadEnv(const num::Format& f) : scope(f) {}
  void finish(RenderStats& st, std::mutex& m) {
    std::lock_guard<std::mutex> g(m);
    st.soft.add(num::soft_stats());
  }
};
template <>
struct ThreadEnv<Probe> {
  detail::ProbeSink sink;
  detail::ProbeSink* saved;
  explicit ThreadEnv(const num::Format&) : saved(detail::probe_sink) { detail::probe_sink = &sink; }
  ~ThreadEnv() { detail::probe_sink = saved; }
  ExpHistogram* all = nullptr;
  ExpHistogram* inputs = nullptr;
  void finish(RenderStats&, std::mutex& m) {
    std::lock_guard<std::mutex> g(m);
    if (all) all->merge(sink.all);
    if (inputs) inputs->merge(sink.inputs);
  }
};

template <class T>
Image render_t(const scene::Scene& s, const RenderOptions& opt, const num::Format& fmt, RenderStats& st) {
  auto t0 = std::chrono::steady_clock::now();
  std::mutex mtx;
  Prepared<T> P;
  {
    ThreadEnv<T> env(fmt);
    if constexpr (std::is_same_v<T, Probe>) {
      env.all = opt.profile_all;
      env.inputs = opt.profile_inputs;
    }
    P = prepare<T>(s, opt, &st);
    env.finish(st, mtx);
  }
  auto t1 = std::chrono::steady_clock::now();
  const double cpu1 = process_cpu_seconds();
  st.build_seconds = std::chrono::duration<double>(t1 - t0).count();

  Image img;
  img.width = opt.width;
  img.height = opt.height;
  img.rgb.assign(static_cast<size_t>(opt.width) * opt.height * 3, 0.0f);
  constexpr int kTile = 16;
  const int tx = (opt.width + kTile - 1) / kTile, ty = (opt.height + kTile - 1) / kTile;
  const int ntiles = tx * ty;

  std::unique_ptr<units::TraceWriter> writer;
  TraceSink sink;
  if (!opt.trace_path.empty()) {
    writer = std::make_unique<units::TraceWriter>(opt.trace_path);
    sink.w = writer.get();
    sink.limit = opt.trace_limit;
  }
  // A trace is written in tile order by one thread, so that it is the same on every run.
  const int threads = writer ? 1 : std::max(1, opt.threads);

  // Tiles are handed out one at a time (util::parallel_workers); each thread keeps its own
  // arithmetic environment and tracer.
  auto worker = [&](const util::TakeIndex& take) {
    ThreadEnv<T> env(fmt);
    if constexpr (std::is_same_v<T, Probe>) {
      env.all = opt.profile_all;
      env.inputs = opt.profile_inputs;
    }
    Tracer<T> tr(P, opt);
    if (writer) tr.trace = &sink;
    for (size_t next; take(next);) {
      const int tile = static_cast<int>(next);
      const int x0 = (tile % tx) * kTile, y0 = (tile / tx) * kTile;
      const int x1 = std::min(x0 + kTile, opt.width), y1 = std::min(y0 + kTile, opt.height);
      if constexpr (kernel::kNative<T>) {
        // 2x2 pixel quads traced as packets (Tracer::shade_quad: each pixel's colour is the
        // one shade_pixel gives it).
        for (int y = y0; y < y1; y += 2)
          for (int x = x0; x < x1; x += 2) {
            Vec3<T> d[4], c[4];
            unsigned lanes = 0;
            for (int j = 0; j < 4; ++j) {
              const int qx = x + (j & 1), qy = y + (j >> 1);
              if (qx >= x1 || qy >= y1) continue;
              lanes |= 1u << j;
              d[j] = tr.primary_dir(fp_cast<T>(qx + 0.5), fp_cast<T>(qy + 0.5));
            }
            tr.shade_quad(d, lanes, c);
            for (int j = 0; j < 4; ++j)
              if (lanes >> j & 1u) {
                float* out = img.at(x + (j & 1), y + (j >> 1));
                for (int k = 0; k < 3; ++k) out[k] = kernel::pixel_value(fp_to_double(c[j][k]));
              }
          }
      } else {
        for (int y = y0; y < y1; ++y) {
          const T py = fp_cast<T>(y + 0.5);
          for (int x = x0; x < x1; ++x) {
            const T px = fp_cast<T>(x + 0.5);
            const Vec3<T> d = tr.primary_dir(px, py);
            const Vec3<T> c = tr.shade_pixel(d);
            float* out = img.at(x, y);
            for (int k = 0; k < 3; ++k) out[k] = kernel::pixel_value(fp_to_double(c[k]));
          }
        }
      }
    }
    env.finish(st, mtx);
    std::lock_guard<std::mutex> g(mtx);
    st.primary_rays += tr.cnt.primary;
    st.shadow_rays += tr.cnt.shadow;
    st.box_tests += tr.cnt.box;
    st.tri_tests += tr.cnt.tri;
    st.noise_evals += tr.cnt.noise;
    st.texture_evals += tr.cnt.texture;
    st.shading_samples += tr.cnt.shading;
  };
  util::ParallelOptions po;
  if (opt.progress)
    po.progress = [&](size_t done, size_t) {
      const int d = static_cast<int>(done);
      std::fprintf(stderr, "render %s: %3d%% (%d/%d tiles) %.1f s\n", st.format.c_str(), 100 * d / ntiles, d,
                   ntiles, std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count());
    };
  util::parallel_workers(static_cast<size_t>(ntiles), threads, worker, po);
  if (writer) {
    writer->close();
    st.trace_boxes = writer->box_count();
    st.trace_tris = writer->tri_count();
    st.trace_truncated = sink.truncated;
  }
  st.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  st.render_cpu_seconds = process_cpu_seconds() - cpu1;
  return img;
}

}  // namespace

Image render(const scene::Scene& s, const RenderOptions& opt, RenderStats* stats) {
  if (opt.width < 1 || opt.height < 1 || opt.width > 16384 || opt.height > 16384)
    throw std::invalid_argument("image size must be between 1x1 and 16384x16384");
  if (opt.leaf_size < 1 || opt.leaf_size > 64) throw std::invalid_argument("leaf size must be 1..64");
  RenderStats local;
  RenderStats& st = stats ? *stats : local;
  st = RenderStats{};
  st.format = opt.format;
  if (opt.format != "probe") check_box_format(opt.box_format, opt.format);
  else if (!opt.box_format.empty()) throw std::invalid_argument("a box format is not accepted with format probe");
  if (opt.format == "double") return render_t<double>(s, opt, num::Format{11, 52}, st);
  if (opt.format == "float") return render_t<float>(s, opt, num::Format{8, 23}, st);
  if (opt.format == "probe") return render_t<Probe>(s, opt, num::Format{11, 52}, st);
  const num::Format f = num::Format::parse(opt.format);  // FormatError on a bad name
  return render_t<num::Soft>(s, opt, f, st);
}

}  // namespace ru::render
