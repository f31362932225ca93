// Mirth-style renderer (dissertation §2.1) over a selectable arithmetic type: primary rays,
// hard shadows, Lambert + ambient shading, procedural noise materials (§4.1).
//
// --format double | float | eXmY[-ftz]: with eXmY every arithmetic operation of ray
// generation, traversal (the ray-box unit model, units/ray_box.hpp), intersection (the
// ray-triangle unit models, units/ray_tri.hpp) and shading is one operation of the emulated
// format (ru::num::Soft). The BVH's boxes are recomputed in the format from the triangles
// rounded into it (min/max: exact); the Mirth median-split build runs entirely in the format,
// the binned-SAH build chooses its split planes in double (see docs/RENDER.md).
#pragma once
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "rayunits/bvh/bvh.hpp"
#include "rayunits/num/fp.hpp"
#include "rayunits/render/arith.hpp"
#include "rayunits/scene/scene.hpp"
#include "rayunits/noise/texture.hpp"
#include "rayunits/units/ray_box.hpp"

namespace ru::render {

enum class TriAlgo : uint8_t { Robust, MT };
enum class BvhKind : uint8_t { Sah, Median };
// NoiseRef::half in double, FixedNoise of ru_noise (Kensler's datapath) or of ru_noise_trunc
// (the truncated datapath, docs/NOISE.md)
enum class NoiseMode : uint8_t { Float, Fixed, FixedTrunc };

TriAlgo parse_tri(const std::string& s);      // "robust" | "mt"; throws std::invalid_argument
BvhKind parse_bvh(const std::string& s);      // "sah" | "median"
NoiseMode parse_noise(const std::string& s);  // "float" | "fixed" | "fixed-trunc"
// How the procedural materials sum octaves and apply their transfer functions: in the shader
// (the format's arithmetic around one noise evaluation per octave) or on the texture unit
// (noise::FixedTexture = rtl/ru_texture.sv, one evaluation per material sample; needs a fixed
// noise model, whose datapath its noise units use).
enum class TextureImpl : uint8_t { Shader, Unit };
TextureImpl parse_texture(const std::string& s);  // "shader" | "unit"
// The texture unit of the renderer and the chip: default widths, 8 octaves at most (the
// Octaves parameter; the scenes' materials use 1..8), the noise datapath of `noise`.
noise::TextureConfig texture_config(NoiseMode noise);
units::BoxMode parse_box(const std::string& s);  // "plain" | "conservative"
// "512x384" or "256" (square), each side 1..16384; throws std::invalid_argument
// "bad --size 'x' (expected WxH or N, 1..16384, e.g. 512x512)".
void parse_size(const std::string& s, int* w, int* h);
const char* tri_name(TriAlgo a);
// Throws std::invalid_argument (one line: what is wrong, what is accepted) unless box is "" or a
// format eXmY whose every value is one of `format`'s (double/float: e11m52/e8m23), without -ftz.
void check_box_format(const std::string& box, const std::string& format);
// x rounded outward into the box format: down (lo) or up (hi); +-INF beyond its range.
double round_box_bound(const num::Format& box, double x, bool up);
const char* bvh_name(BvhKind k);

struct RenderOptions {
  int width = 512, height = 512;
  std::string format = "float";  // double | float | eXmY[-ftz] (validated by render())
  TriAlgo tri = TriAlgo::Robust;
  units::BoxMode box = units::BoxMode::Plain;
  BvhKind bvh = BvhKind::Sah;
  int leaf_size = 4;  // SAH: max triangles per leaf; median: Mirth's max_tris_per_leaf
  // BVH node boxes stored in a narrower format eXmY (no -ftz; exponent and fraction no wider than
  // the render format's), each bound rounded outward (lo down, hi up) from the exact box of the
  // rounded triangles, so the stored box still contains its geometry; "" = the render format's
  // boxes (exact: min/max of stored vertices). check_box_format validates it.
  std::string box_format;
  NoiseMode noise = NoiseMode::Float;
  // The shading's multiply-adds (ray points o + d t, colour blends, dot and cross products,
  // octave sums, the camera's ray directions) as fused multiply-adds, one rounding each
  // (ru_fp_fma; std::fma in float/double); false: a product and a sum, each rounded.
  bool fma = false;
  TextureImpl texture = TextureImpl::Shader;
  bool shadows = true;
  int threads = 2;
  bool progress = false;        // progress lines on stderr
  std::string trace_path;       // non-empty: write the tested ray/box and ray/tri pairs
  uint64_t trace_limit = 0;     // stop recording after this many records (0: no limit)
  const bvh::Bvh* topology = nullptr;  // use this tree's structure instead of building one
  ExpHistogram* profile_all = nullptr;     // format "probe": every computed value
  ExpHistogram* profile_inputs = nullptr;  // format "probe": the units' operands
};

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // linear colour, clamped to [0, 1], row-major from the top
  float* at(int x, int y) { return &rgb[3 * (static_cast<size_t>(y) * width + x)]; }
  const float* at(int x, int y) const { return &rgb[3 * (static_cast<size_t>(y) * width + x)]; }
};

struct RenderStats {
  std::string format;
  double build_seconds = 0, render_seconds = 0;
  double render_cpu_seconds = 0;  // process CPU time of the render phase (all threads)
  uint64_t primary_rays = 0, shadow_rays = 0, box_tests = 0, tri_tests = 0, noise_evals = 0;
  uint64_t texture_evals = 0, shading_samples = 0;  // texture-unit requests; procedural samples
  uint64_t trace_boxes = 0, trace_tris = 0;
  bool trace_truncated = false;
  size_t bvh_nodes = 0;
  double sah_cost = 0;
  num::SoftStats soft;  // flag counts of the emulated arithmetic (eXmY only)
};

// Renders the scene. format "probe" runs in double and fills opt.profile_* (scene profile).
// Throws ru::num::FormatError for a bad format name, std::invalid_argument for bad sizes,
// units::TraceError when the trace file cannot be written.
Image render(const scene::Scene& s, const RenderOptions& opt, RenderStats* stats = nullptr);

// Image comparison as in Tables 3.5/3.6: a pixel is an error when some colour channel differs
// from the reference by more than 10 % of full scale; PSNR over all channels, peak 1.
struct ImageDiff {
  uint64_t pixels = 0, errors = 0;  // errors: pixels more than 10 % different
  double mse = 0, psnr = 0;         // psnr = +inf for identical images
  double max_abs = 0;
};
ImageDiff compare(const Image& test, const Image& ref, double threshold = 0.1);

// The typed rows of a render (`rayunits render --json`, sweep results): every RenderStats field
// (rays, tests, BVH, seconds, the emulated arithmetic's flag counts) and an ImageDiff's errors,
// error fraction and PSNR (null for identical images).
nlohmann::json to_json(const RenderStats& s);
nlohmann::json to_json(const ImageDiff& d);

// PNG output (stb_image_write): 8 bits per channel, value*255 rounded.
void write_png(const std::string& path, const Image& img);  // throws std::runtime_error
// Images side by side (same height) with a 4-pixel grey gap.
Image hconcat(const std::vector<const Image*>& images);
// Error map: black where the pixel is within the threshold, the test pixel elsewhere tinted red.
Image error_map(const Image& test, const Image& ref, double threshold = 0.1);

}  // namespace ru::render
