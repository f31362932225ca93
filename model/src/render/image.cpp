// Image comparison (Tables 3.5/3.6 metrics), PNG output, side-by-side and error images.
#define STB_IMAGE_WRITE_STATIC  // private copy: other files may include stb_image_write too
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <cmath>
#include <nlohmann/json.hpp>
#include <limits>
#include <stdexcept>

#include "rayunits/render/render.hpp"

namespace ru::render {

nlohmann::json to_json(const RenderStats& s) {
  return {{"format", s.format},
          {"build_seconds", s.build_seconds},
          {"render_seconds", s.render_seconds},
          {"render_cpu_seconds", s.render_cpu_seconds},
          {"primary_rays", s.primary_rays},
          {"shadow_rays", s.shadow_rays},
          {"box_tests", s.box_tests},
          {"tri_tests", s.tri_tests},
          {"noise_evals", s.noise_evals},
          {"texture_evals", s.texture_evals},
          {"shading_samples", s.shading_samples},
          {"bvh_nodes", s.bvh_nodes},
          {"sah_cost", s.sah_cost},
          {"trace_boxes", s.trace_boxes},
          {"trace_tris", s.trace_tris},
          {"trace_truncated", s.trace_truncated},
          {"soft", {{"ops", s.soft.ops},
                    {"invalid", s.soft.invalid},
                    {"divzero", s.soft.divzero},
                    {"overflow", s.soft.overflow},
                    {"underflow", s.soft.underflow},
                    {"inexact", s.soft.inexact}}}};
}

nlohmann::json to_json(const ImageDiff& d) {
  nlohmann::json j = {{"pixels", d.pixels},
                      {"errors", d.errors},
                      {"error_fraction", d.pixels ? double(d.errors) / double(d.pixels) : 0.0},
                      {"mse", d.mse},
                      {"max_abs", d.max_abs}};
  j["psnr_db"] = std::isfinite(d.psnr) ? nlohmann::json(d.psnr) : nlohmann::json();
  return j;
}

ImageDiff compare(const Image& test, const Image& ref, double threshold) {
  if (test.width != ref.width || test.height != ref.height)
    throw std::invalid_argument("images differ in size");
  ImageDiff d;
  d.pixels = static_cast<uint64_t>(ref.width) * ref.height;
  double sum = 0;
  for (uint64_t i = 0; i < d.pixels; ++i) {
    double worst = 0;
    for (int k = 0; k < 3; ++k) {
      const double e = std::fabs(double(test.rgb[3 * i + k]) - double(ref.rgb[3 * i + k]));
      sum += e * e;
      worst = std::max(worst, e);
    }
    d.max_abs = std::max(d.max_abs, worst);
    if (worst > threshold) ++d.errors;
  }
  d.mse = d.pixels ? sum / (3.0 * d.pixels) : 0.0;
  d.psnr = d.mse > 0 ? 10.0 * std::log10(1.0 / d.mse) : std::numeric_limits<double>::infinity();
  return d;
}

void write_png(const std::string& path, const Image& img) {
  std::vector<unsigned char> px(img.rgb.size());
  for (size_t i = 0; i < px.size(); ++i) {
    const double v = std::min(1.0, std::max(0.0, double(img.rgb[i])));
    px[i] = static_cast<unsigned char>(std::lround(v * 255.0));
  }
  if (!stbi_write_png(path.c_str(), img.width, img.height, 3, px.data(), img.width * 3))
    throw std::runtime_error("cannot write PNG '" + path + "'");
}

Image hconcat(const std::vector<const Image*>& images) {
  Image out;
  const int gap = 4;
  for (const Image* im : images) {
    out.height = std::max(out.height, im->height);
    out.width += im->width;
  }
  if (!images.empty()) out.width += gap * static_cast<int>(images.size() - 1);
  out.rgb.assign(static_cast<size_t>(out.width) * out.height * 3, 0.5f);
  int x0 = 0;
  for (const Image* im : images) {
    for (int y = 0; y < im->height; ++y)
      for (int x = 0; x < im->width; ++x)
        for (int k = 0; k < 3; ++k) out.at(x0 + x, y)[k] = im->at(x, y)[k];
    x0 += im->width + gap;
  }
  return out;
}

Image error_map(const Image& test, const Image& ref, double threshold) {
  if (test.width != ref.width || test.height != ref.height)
    throw std::invalid_argument("images differ in size");
  Image out = ref;
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) {
      double worst = 0;
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(double(test.at(x, y)[k]) - ref.at(x, y)[k]));
      float* o = out.at(x, y);
      if (worst > threshold) {
        o[0] = 1.0f;
        o[1] = o[2] = 0.0f;
      } else {  // dimmed reference for context
        for (int k = 0; k < 3; ++k) o[k] *= 0.3f;
      }
    }
  return out;
}

}  // namespace ru::render
