// rayunits profile: the scene's value profile (Fig. 3.5 shape) and the smallest format and the
// units it needs ("model only what a scene requires").
#include <cstdio>
#include <fstream>

#include "cli_util.hpp"
#include "rayunits/render/studies.hpp"
#include "render_common.hpp"

namespace ru::cli {
namespace {

int run_profile(int argc, char** argv) {
  CLI::App app{"Scene profile: exponent histogram of every value the render computes, overflow/underflow per "
               "exponent width, the smallest format meeting an image-error target, the units needed"};
  SceneArgs sa;
  sa.add(app, "default");
  std::string size = "128x128", tri = "robust", bvh = "median", json;
  render::ProfileOptions o;
  app.add_option("--size", size, "image size WxH of the profile and of the error renders");
  app.add_option("--tri", tri, "ray-triangle algorithm: robust | mt");
  app.add_option("--bvh", bvh, "BVH build: median | sah");
  app.add_option("--max-errors", o.max_error_fraction, "target: largest fraction of pixels more than 10% off")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--min-psnr", o.min_psnr, "target: smallest PSNR in dB");
  app.add_option("--min-frac", o.min_frac, "first fraction width tried")->check(CLI::Range(1, 52));
  app.add_option("--max-frac", o.max_frac, "last fraction width tried")->check(CLI::Range(1, 52));
  app.add_option("--threads", o.threads, "render threads")->check(CLI::Range(1, 64));
  app.add_option("--json", json, "also write the profile as JSON here");
  if (!parse_args(app, argc, argv)) return 0;
  parse_size(size, &o.width, &o.height);
  o.algo = parse_or_usage([&] { return render::parse_tri(tri); });
  o.bvh = parse_or_usage([&] { return render::parse_bvh(bvh); });
  if (o.min_frac > o.max_frac) throw UsageError("--min-frac is larger than --max-frac");
  o.progress = true;
  const scene::Scene s = sa.load();
  const render::Profile p = render::profile_scene(s, o);
  std::fputs(render::profile_text(p, o).c_str(), stdout);
  if (!json.empty()) {
    std::ofstream f(json);
    if (!f) throw UsageError("cannot write '" + json + "'");
    f << render::profile_json(p, o);
    std::printf("wrote %s\n", json.c_str());
  }
  return 0;
}

}  // namespace

RU_COMMAND("profile", "scene value profile, smallest sufficient format and the units a scene needs", run_profile);

}  // namespace ru::cli
