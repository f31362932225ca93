// rayunits render: one image of a scene in a chosen arithmetic format.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "rayunits/report/report.hpp"
#include "rayunits/synth/process.hpp"
#include "render_common.hpp"

namespace ru::render {
std::string report_render_section(ru::report::Context& ctx);  // model/src/render/report_render.cpp
}

namespace ru::cli {
namespace {

}  // namespace

bool parse_render_command(int argc, char** argv, RenderCommand& c) {
  CLI::App app{"Render a scene (Mirth-style: primary rays, hard shadows, Lambert + ambient, noise materials)"};
  c.sa.add(app);
  std::string size = "512x512";
  uint64_t trace_limit = 0;
  int threads = 2, leaf = 4;
  bool no_shadows = false, quiet = false;
  app.add_option("--format", c.format, "double | float | eXmY[-ftz] (emulated format)");
  app.add_option("--tri", c.tri, "ray-triangle unit: robust | mt");
  app.add_option("--box", c.box, "ray-box unit: plain | conservative");
  app.add_option("--bvh", c.bvh, "BVH build: sah (binned SAH) | median (Mirth)");
  app.add_option("--leaf", leaf, "max triangles per leaf (median: a node with fewer becomes a leaf)");
  app.add_option("--noise", c.noise, "noise model of procedural materials: float | fixed (hardware unit ru_noise) | fixed-trunc (ru_noise_trunc)");
  app.add_option("--texture", c.texture,
                 "procedural materials: shader (octave sums in the format around the noise model) | unit (the "
                 "texture unit ru_texture, needs --noise fixed-trunc or fixed)");
  app.add_option("--box-format", c.opt.box_format,
                 "BVH node boxes stored in this narrower format eXmY, rounded outward (default: the --format's own boxes)");
  app.add_flag("--fma", c.opt.fma,
               "the shading's multiply-adds as fused multiply-adds, one rounding each (ru_fp_fma; std::fma natively)");
  app.add_option("--size", size, "image size WxH (or N)");
  app.add_option("--threads", threads, "render threads")->check(CLI::Range(1, 64));
  app.add_flag("--no-shadows", no_shadows, "primary rays only");
  app.add_option("--out", c.out, "output PNG")->required();
  app.add_option("--trace-out", c.trace_out, "write the tested ray/box and ray/tri pairs (trace format of docs/UNITS.md)");
  app.add_option("--trace-limit", trace_limit, "stop the trace after this many records (0: all)");
  app.add_flag("--compare", c.compare, "also render in double and print errors / PSNR against it");
  app.add_option("--diff-out", c.diff_out, "with --compare: write the error map PNG here");
  app.add_option("--compare-noise", c.compare_noise,
                 "with --compare: the reference's noise model (default: as --noise), e.g. float to measure a noise unit");
  app.add_option("--json", c.json_out, "also write the run as one JSON line (stats; with --compare its errors vs double)");
  app.add_flag("--quiet", quiet, "no progress lines");
  if (!parse_args(app, argc, argv)) return false;

  render::RenderOptions& opt = c.opt;
  parse_size(size, &opt.width, &opt.height);
  opt.format = c.format;
  opt.tri = parse_or_usage([&] { return render::parse_tri(c.tri); });
  opt.box = parse_or_usage([&] { return render::parse_box(c.box); });
  opt.bvh = parse_or_usage([&] { return render::parse_bvh(c.bvh); });
  opt.noise = parse_or_usage([&] { return render::parse_noise(c.noise); });
  opt.texture = parse_or_usage([&] { return render::parse_texture(c.texture); });
  if (opt.texture == render::TextureImpl::Unit && opt.noise == render::NoiseMode::Float)
    throw UsageError("--texture unit needs a fixed noise model (--noise fixed-trunc or fixed)");
  c.ref_noise = c.compare_noise.empty() ? opt.noise : parse_or_usage([&] { return render::parse_noise(c.compare_noise); });
  if (!c.compare_noise.empty() && !c.compare) throw UsageError("--compare-noise needs --compare");
  opt.leaf_size = leaf;
  opt.threads = threads;
  opt.shadows = !no_shadows;
  opt.progress = !quiet;
  opt.trace_path = c.trace_out;
  opt.trace_limit = trace_limit;
  if (leaf < 1 || leaf > 64) throw UsageError("--leaf must be 1..64");
  if (c.format != "double" && c.format != "float") ru::num::Format::parse(c.format);  // early one-line error
  parse_or_usage([&] {
    render::check_box_format(opt.box_format, c.format);
    return 0;
  });
  c.sa.check();
  return true;
}

namespace {

int run_render(int argc, char** argv) {
  RenderCommand c;
  if (!parse_render_command(argc, argv, c)) return 0;
  const SceneArgs& sa = c.sa;
  const render::RenderOptions& opt = c.opt;
  const std::string &format = c.format, &tri = c.tri, &box = c.box, &noise = c.noise, &out = c.out,
                    &trace_out = c.trace_out, &diff_out = c.diff_out, &json_out = c.json_out;
  const bool compare = c.compare;
  const int threads = opt.threads;
  const scene::Scene s = sa.load();
  render::RenderStats st;
  const render::Image img = render::render(s, opt, &st);
  render::write_png(out, img);
  const double rays = double(st.primary_rays + st.shadow_rays);
  std::printf("scene %s: %zu triangles, %zu BVH nodes (%s, SAH cost %.2f)\n", s.name.c_str(), s.tris.size(),
              st.bvh_nodes, render::bvh_name(opt.bvh), st.sah_cost);
  std::printf("format %s, tri %s, box %s, %dx%d, %d thread(s): build %.3f s, render %.3f s (%.2f frames/s, %.2f Mrays/s; CPU %.3f s)\n",
              format.c_str(), tri.c_str(), box.c_str(), opt.width, opt.height, trace_out.empty() ? threads : 1,
              st.build_seconds, st.render_seconds, 1.0 / st.render_seconds, rays / st.render_seconds / 1e6,
              st.render_cpu_seconds);
  std::printf("rays: %llu primary, %llu shadow; tests: %llu ray-box, %llu ray-tri; noise evaluations: %llu\n",
              (unsigned long long)st.primary_rays, (unsigned long long)st.shadow_rays,
              (unsigned long long)st.box_tests, (unsigned long long)st.tri_tests, (unsigned long long)st.noise_evals);
  if (st.soft.ops)
    std::printf("emulated ops: %llu (overflow %llu, underflow %llu, invalid %llu, divzero %llu)\n",
                (unsigned long long)st.soft.ops, (unsigned long long)st.soft.overflow,
                (unsigned long long)st.soft.underflow, (unsigned long long)st.soft.invalid,
                (unsigned long long)st.soft.divzero);
  if (!trace_out.empty())
    std::printf("trace %s: %llu ray-box, %llu ray-tri records%s\n", trace_out.c_str(),
                (unsigned long long)st.trace_boxes, (unsigned long long)st.trace_tris,
                st.trace_truncated ? " (truncated at --trace-limit)" : "");
  std::printf("wrote %s\n", out.c_str());
  nlohmann::json vs_double;
  if (compare) {
    render::RenderOptions ro = opt;
    ro.format = "double";
    ro.fma = false;  // the reference is the plain double render, with or without --fma
    ro.noise = c.ref_noise;
    // a float-noise reference sums its octaves in the shader (the texture unit is fixed point)
    if (ro.noise == render::NoiseMode::Float) ro.texture = render::TextureImpl::Shader;
    ro.trace_path.clear();
    const render::Image ref = render::render(s, ro);
    const render::ImageDiff d = render::compare(img, ref);
    const std::string ref_noise = c.compare_noise.empty() ? noise : c.compare_noise;
    const char* ref_texture = ro.texture == render::TextureImpl::Unit ? "unit" : "shader";
    std::printf("vs double (noise %s, texture %s): %llu pixels more than 10%% different (%.3f%%), PSNR %.1f dB\n",
                ref_noise.c_str(), ref_texture, (unsigned long long)d.errors, 100.0 * d.errors / d.pixels, d.psnr);
    vs_double = render::to_json(d);
    vs_double["noise"] = ref_noise;
    vs_double["texture"] = ref_texture;
    if (!diff_out.empty()) {
      render::write_png(diff_out, render::error_map(img, ref));
      std::printf("wrote %s\n", diff_out.c_str());
    }
  }
  if (!json_out.empty()) {
    nlohmann::json j = render::to_json(st);
    j["scene"] = s.name;
    j["triangles"] = s.tris.size();
    j["tri"] = tri;
    j["box"] = box;
    j["bvh"] = render::bvh_name(opt.bvh);
    j["noise"] = noise;
    j["texture"] = c.texture;
    j["width"] = opt.width;
    j["height"] = opt.height;
    j["shadows"] = opt.shadows;
    j["fma"] = opt.fma;
    j["png"] = out;
    if (compare) j["vs_double"] = vs_double;
    synth::write_file_atomic(json_out, j.dump() + "\n");
  }
  return 0;
}

}  // namespace

RU_COMMAND("render", "render a scene in a chosen format (double, float, eXmY) to PNG", run_render);

// Report section (here because registrations must be linked straight into the executable).
// Params: --param render.scene=NAME, render.size=N, render.sa_iters=N.
RU_REPORT_SECTION("render", "Reduced-precision renders, scene profile and BVH rotations", 600,
                  &ru::render::report_render_section, true, true);

}  // namespace ru::cli
