// rayunits study image: Tables 3.5 / 3.6 on our scenes — pixels more than 10 % different from
// the double render, and PSNR, per exponent/fraction width and triangle algorithm.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_util.hpp"
#include "rayunits/render/studies.hpp"
#include "rayunits/report/report.hpp"
#include "rayunits/util/process.hpp"
#include "render_common.hpp"

namespace ru::cli {
namespace {

std::vector<int> parse_range(const std::string& s, const char* what) {
  // "8:22:2" (first:last:step), "8:22" (step 1), "7" or "7,8".
  std::vector<int> out;
  std::stringstream ss(s);
  std::string part;
  while (std::getline(ss, part, ',')) {
    int a, b, c = 1;
    char x;
    std::stringstream ps(part);
    if (!(ps >> a)) throw UsageError(std::string("bad ") + what + " '" + s + "' (expected N, A:B or A:B:STEP)");
    b = a;
    if (ps >> x) {
      if (x != ':' || !(ps >> b)) throw UsageError(std::string("bad ") + what + " '" + s + "'");
      if (ps >> x) {
        if (x != ':' || !(ps >> c) || c < 1) throw UsageError(std::string("bad ") + what + " '" + s + "'");
      }
    }
    if (b < a) throw UsageError(std::string("bad ") + what + " '" + s + "' (empty range)");
    for (int v = a; v <= b; v += c) out.push_back(v);
  }
  if (out.empty()) throw UsageError(std::string("empty ") + what);
  return out;
}

int run_study_image(int argc, char** argv) {
  CLI::App app{"Image-error study (Tables 3.5/3.6): renders in eXmY vs the double reference, robust vs Moller-Trumbore"};
  SceneArgs sa;
  sa.add(app, "default");
  std::string exp = "7", frac = "8:22:2", tris = "robust,mt", size = "256x256", out = "study_image", bvh = "median",
              box = "plain", noise = "float";
  int threads = 2;
  bool no_plot = false;
  app.add_option("--exp", exp, "exponent widths: N, A:B or A:B:STEP, comma lists");
  app.add_option("--frac", frac, "fraction widths, e.g. 8:22:2");
  app.add_option("--tri", tris, "ray-triangle algorithms: robust,mt");
  app.add_option("--size", size, "image size WxH");
  app.add_option("--bvh", bvh, "BVH build: median (Mirth, as in the dissertation; built in the format) | sah");
  app.add_option("--box", box, "ray-box test: plain | conservative");
  app.add_option("--noise", noise, "noise model: float | fixed");
  app.add_option("--threads", threads, "render threads")->check(CLI::Range(1, 64));
  app.add_option("--out", out, "output directory (CSV, images, plot)");
  app.add_flag("--no-plot", no_plot, "skip the matplotlib plot");
  if (!parse_args(app, argc, argv)) return 0;
  render::ImageStudyOptions o;
  parse_size(size, &o.width, &o.height);
  o.exp_bits = parse_range(exp, "--exp");
  o.frac_bits = parse_range(frac, "--frac");
  for (int e : o.exp_bits)
    for (int m : o.frac_bits) ru::num::Format{e, m}.validate();  // one-line FormatError
  o.algos.clear();
  std::stringstream ts(tris);
  std::string t;
  while (std::getline(ts, t, ',')) o.algos.push_back(parse_or_usage([&] { return render::parse_tri(t); }));
  if (o.algos.empty()) throw UsageError("no --tri algorithm");
  o.bvh = parse_or_usage([&] { return render::parse_bvh(bvh); });
  o.box = parse_or_usage([&] { return render::parse_box(box); });
  o.noise = parse_or_usage([&] { return render::parse_noise(noise); });
  o.threads = threads;
  o.progress = true;
  const scene::Scene s = sa.load();
  std::filesystem::create_directories(out);
  o.image_dir = out;
  auto rows = render::image_study(s, o);
  const std::string csv = out + "/image_errors.csv";
  std::ofstream f(csv);
  if (!f) throw UsageError("cannot write '" + csv + "'");
  f << "# rayunits study image --scene " << s.name << " " << o.width << "x" << o.height << " bvh " << bvh << " box "
    << box << "; errors = pixels with some channel more than 10% of full scale from the double render\n";
  f << "scene,exp_bits,frac_bits,algorithm,errors,pixels,psnr,seconds,overflow_ops,underflow_ops,invalid_ops\n";
  std::printf("scene %s, %dx%d, %s BVH, %s box test: pixels > 10%% off the double render, PSNR (dB)\n", s.name.c_str(),
              o.width, o.height, bvh.c_str(), box.c_str());
  std::printf("%6s %6s | %10s %8s | %10s %8s\n", "format", "", "MT errors", "PSNR", "robust err", "PSNR");
  for (const auto& r : rows) {
    char psnr[32];
    std::snprintf(psnr, sizeof psnr, "%.2f", r.diff.psnr);
    f << s.name << "," << r.exp_bits << "," << r.frac_bits << "," << render::tri_name(r.algo) << "," << r.diff.errors
      << "," << r.diff.pixels << "," << (std::isinf(r.diff.psnr) ? std::string("inf") : std::string(psnr)) << ","
      << r.seconds << "," << r.overflows << "," << r.underflows << "," << r.invalids << "\n";
  }
  for (int e : o.exp_bits)
    for (int m : o.frac_bits) {
      const render::ImageStudyRow *mt = nullptr, *rb = nullptr;
      for (const auto& r : rows)
        if (r.exp_bits == e && r.frac_bits == m) (r.algo == render::TriAlgo::MT ? mt : rb) = &r;
      std::printf("e%dm%-3d        | %10s %8s | %10s %8s\n", e, m,
                  mt ? std::to_string(mt->diff.errors).c_str() : "-", mt ? (std::isinf(mt->diff.psnr) ? "inf" : std::to_string(mt->diff.psnr).substr(0, 5).c_str()) : "-",
                  rb ? std::to_string(rb->diff.errors).c_str() : "-", rb ? (std::isinf(rb->diff.psnr) ? "inf" : std::to_string(rb->diff.psnr).substr(0, 5).c_str()) : "-");
    }
  f.close();
  std::printf("wrote %s and the images in %s/\n", csv.c_str(), out.c_str());
  if (!no_plot) {
    const std::string py = ru::report::find_python();
    const std::string script = (ru::report::scripts_dir() / "plot_render_study.py").string();
    const std::string cmd = py + " '" + script + "' '" + csv + "' '" + out + "/image_errors.png'";
    if (util::run_foreground({py, script, csv, out + "/image_errors.png"}) != 0)
      throw UsageError("plot failed: " + cmd);
    std::printf("wrote %s/image_errors.png\n", out.c_str());
  }
  return 0;
}

}  // namespace

RU_COMMAND("study image", "image error vs format width, robust vs MT (Tables 3.5/3.6 on our scenes)", run_study_image);

}  // namespace ru::cli
