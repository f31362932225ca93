// Rotation, animation, image-error and profile studies (see render/studies.hpp).
#include "rayunits/render/studies.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rayunits/bvh/rotate.hpp"

namespace ru::render {
namespace {

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Cast {
  double seconds = 0, boxes_per_ray = 0;
};
Cast ray_cast(const scene::Scene& s, const bvh::Bvh& tree, int size) {
  RenderOptions o;
  o.width = o.height = size;
  o.format = "float";
  o.shadows = false;
  o.threads = 1;
  o.topology = &tree;
  RenderStats st;
  render(s, o, &st);
  return {st.render_seconds, double(st.box_tests) / double(std::max<uint64_t>(1, st.primary_rays))};
}

}  // namespace

RotationRow rotation_study(const scene::Scene& s, const RotationOptions& o) {
  RotationRow r;
  r.scene = s.name;
  r.triangles = s.tris.size();
  auto pb = bvh::triangle_boxes(s);
  bvh::BuildOptions bo;
  bo.max_leaf = o.leaf_size;
  auto t0 = std::chrono::steady_clock::now();
  bvh::Bvh none = bvh::build_sah(pb, bo);
  r.build_s = since(t0);
  bvh::Bvh hill = none, sa = none;
  if (o.progress) std::fprintf(stderr, "bvh %s: hill climbing\n", s.name.c_str());
  bvh::RotateStats hs = bvh::hill_climb(hill);
  if (o.progress) std::fprintf(stderr, "bvh %s: simulated annealing (%d iterations)\n", s.name.c_str(), o.sa_iterations);
  bvh::AnnealOptions ao;
  ao.iterations = o.sa_iterations;
  ao.heat = o.heat;
  ao.seed = o.seed;
  bvh::RotateStats as = bvh::anneal(sa, bvh::SahParams{}, ao);
  r.hill_s = hs.seconds;
  r.sa_s = as.seconds;
  r.cost_none = bvh::sah_cost(none);
  r.cost_hill = hs.cost_after;
  r.cost_sa = as.cost_after;
  r.hill_passes = hs.passes;
  r.sa_passes = as.passes;
  r.hill_rotations = hs.rotations;
  r.sa_rotations = as.rotations;
  r.sa_cost_per_pass = as.cost_per_pass;
  if (o.cast_size > 0) {
    if (o.progress) std::fprintf(stderr, "bvh %s: ray casting %dx%d with each tree\n", s.name.c_str(), o.cast_size, o.cast_size);
    Cast a = ray_cast(s, none, o.cast_size), b = ray_cast(s, hill, o.cast_size), c = ray_cast(s, sa, o.cast_size);
    r.cast_none = a.seconds;
    r.cast_hill = b.seconds;
    r.cast_sa = c.seconds;
    r.boxes_none = a.boxes_per_ray;
    r.boxes_hill = b.boxes_per_ray;
    r.boxes_sa = c.boxes_per_ray;
  }
  return r;
}

std::vector<AnimationFrame> animation_study(const std::string& name, int frames, int cast_size, bool progress) {
  std::vector<AnimationFrame> out;
  bvh::BuildOptions bo;
  bo.max_leaf = 1;  // §5.6: primitives whose motion may diverge go to separate leaves
  scene::Scene f0 = scene::make_animation_frame(name, 0, frames);
  bvh::Bvh refit_tree = bvh::build_sah(bvh::triangle_boxes(f0), bo), rot_tree = refit_tree;
  for (int f = 0; f < frames; ++f) {
    scene::Scene s = scene::make_animation_frame(name, f, frames);
    auto pb = bvh::triangle_boxes(s);
    AnimationFrame a;
    a.frame = f;
    auto t0 = std::chrono::steady_clock::now();
    bvh::refit(refit_tree, pb);
    a.update_refit_s = since(t0);
    t0 = std::chrono::steady_clock::now();
    a.rotations = bvh::refit_rotate(rot_tree, pb);
    a.update_rotate_s = since(t0);
    t0 = std::chrono::steady_clock::now();
    bvh::Bvh rebuilt = bvh::build_sah(pb, bo);
    a.rebuild_s = since(t0);
    a.cost_refit = bvh::sah_cost(refit_tree);
    a.cost_rotate = bvh::sah_cost(rot_tree);
    a.cost_rebuild = bvh::sah_cost(rebuilt);
    if (cast_size > 0) {
      a.render_refit_s = ray_cast(s, refit_tree, cast_size).seconds;
      a.render_rotate_s = ray_cast(s, rot_tree, cast_size).seconds;
      a.render_rebuild_s = ray_cast(s, rebuilt, cast_size).seconds;
    }
    if (progress)
      std::fprintf(stderr, "bvh anim %s: frame %d/%d  SAH refit %.1f  rotate %.1f  rebuild %.1f\n", name.c_str(), f + 1,
                   frames, a.cost_refit, a.cost_rotate, a.cost_rebuild);
    out.push_back(a);
  }
  return out;
}

std::vector<ImageStudyRow> image_study(const scene::Scene& s, const ImageStudyOptions& o) {
  RenderOptions base;
  base.width = o.width;
  base.height = o.height;
  base.bvh = o.bvh;
  base.box = o.box;
  base.noise = o.noise;
  base.threads = o.threads;
  RenderOptions ro = base;
  ro.format = "double";
  if (o.progress) std::fprintf(stderr, "study image %s: double reference\n", s.name.c_str());
  const Image ref = render(s, ro);
  if (!o.image_dir.empty()) write_png(o.image_dir + "/" + o.image_prefix + "reference_double.png", ref);
  std::vector<ImageStudyRow> rows;
  for (int e : o.exp_bits)
    for (int m : o.frac_bits) {
      std::vector<Image> imgs;
      for (TriAlgo a : o.algos) {
        RenderOptions r = base;
        r.format = "e" + std::to_string(e) + "m" + std::to_string(m);
        r.tri = a;
        RenderStats st;
        Image img = render(s, r, &st);
        ImageStudyRow row;
        row.exp_bits = e;
        row.frac_bits = m;
        row.algo = a;
        row.diff = compare(img, ref);
        row.seconds = st.render_seconds;
        row.overflows = st.soft.overflow;
        row.underflows = st.soft.underflow;
        row.invalids = st.soft.invalid;
        rows.push_back(row);
        if (o.progress)
          std::fprintf(stderr, "study image %s: %s %-6s errors %6llu  PSNR %6.1f dB  (%.1f s)\n", s.name.c_str(),
                       r.format.c_str(), tri_name(a), (unsigned long long)row.diff.errors, row.diff.psnr, row.seconds);
        if (!o.image_dir.empty())
          write_png(o.image_dir + "/" + o.image_prefix + r.format + "_" + tri_name(a) + ".png", img);
        imgs.push_back(std::move(img));
      }
      if (!o.image_dir.empty() && !imgs.empty()) {
        // Side by side: each algorithm's render and its error map, then the reference.
        std::vector<Image> maps;
        for (const Image& im : imgs) maps.push_back(error_map(im, ref));
        std::vector<const Image*> all;
        for (size_t i = 0; i < imgs.size(); ++i) {
          all.push_back(&imgs[i]);
          all.push_back(&maps[i]);
        }
        all.push_back(&ref);
        write_png(o.image_dir + "/" + o.image_prefix + "side_e" + std::to_string(e) + "m" + std::to_string(m) + ".png", hconcat(all));
      }
    }
  return rows;
}

Profile profile_scene(const scene::Scene& s, const ProfileOptions& o) {
  Profile p;
  p.scene = s.name;
  p.triangles = s.tris.size();
  RenderOptions ro;
  ro.width = o.width;
  ro.height = o.height;
  ro.tri = o.algo;
  ro.bvh = o.bvh;
  ro.threads = o.threads;
  ro.format = "probe";
  ro.profile_all = &p.all;
  ro.profile_inputs = &p.inputs;
  if (o.progress) std::fprintf(stderr, "profile %s: recording every value (double)\n", s.name.c_str());
  RenderStats st;
  render(s, ro, &st);
  p.noise_evals = st.noise_evals;
  // Exponent widths: overflow / underflow counts from the histogram of every computed value.
  for (int E = 2; E <= 11; ++E) {
    ExpWidthRow w;
    w.exp_bits = E;
    w.emax = (1 << (E - 1)) - 1;
    w.emin = 1 - w.emax;
    // Infinities in the double render are deliberate (t = +INF before a hit, 1/0 for an axis-
    // parallel direction component): only finite values beyond the range count as overflow.
    w.overflow = p.all.count_above(w.emax);
    w.subnormal = p.all.count_below(w.emin);
    p.widths.push_back(w);
    if (!p.recommended_exp && w.overflow == 0) p.recommended_exp = E;
  }
  // Exponent width: the smallest one without overflow, widened while even a wide fraction
  // (M = 40) misses the image target (then underflow of small values is what hurts);
  // fraction width: the smallest meeting the target at that exponent width.
  if (p.recommended_exp) {
    RenderOptions ref_o = ro;
    ref_o.format = "double";
    ref_o.profile_all = ref_o.profile_inputs = nullptr;
    const Image ref = render(s, ref_o);
    auto try_format = [&](int e, int m) {
      RenderOptions r = ref_o;
      r.format = "e" + std::to_string(e) + "m" + std::to_string(m);
      FracRow fr;
      fr.frac_bits = m;
      fr.diff = compare(render(s, r), ref);
      fr.meets = double(fr.diff.errors) <= o.max_error_fraction * double(fr.diff.pixels) && fr.diff.psnr >= o.min_psnr;
      if (o.progress)
        std::fprintf(stderr, "profile %s: %s errors %llu PSNR %.1f dB%s\n", s.name.c_str(), r.format.c_str(),
                     (unsigned long long)fr.diff.errors, fr.diff.psnr, fr.meets ? "  meets the target" : "");
      return fr;
    };
    p.no_overflow_exp = p.recommended_exp;
    while (p.recommended_exp <= 11) {
      FracRow wide = try_format(p.recommended_exp, 40);
      p.exp_checks.push_back({p.recommended_exp, wide});
      if (wide.meets) break;
      ++p.recommended_exp;
    }
    if (p.recommended_exp > 11) p.recommended_exp = 0;
    for (int m = o.min_frac; p.recommended_exp && m <= o.max_frac && 1 + p.recommended_exp + m <= 64; ++m) {
      FracRow fr = try_format(p.recommended_exp, m);
      p.fracs.push_back(fr);
      if (fr.meets) {
        p.recommended_frac = m;
        break;
      }
    }
    for (auto& w : p.widths) {  // below the smallest subnormal of (E, recommended M): flushed
      const int m = p.recommended_frac ? p.recommended_frac : 23;
      w.flushed = p.all.count_below(w.emin - m);
    }
  }
  p.units = {"ray_box", o.algo == TriAlgo::Robust ? "ray_tri_robust" : "ray_tri_mt", "fp_add", "fp_mul", "fp_div",
             "fp_sqrt", "fp_cmp"};
  if (p.noise_evals > 0) p.units.push_back("noise");
  return p;
}

std::string profile_text(const Profile& p, const ProfileOptions& o) {
  std::ostringstream os;
  char buf[256];
  os << "scene " << p.scene << ": " << p.triangles << " triangles, " << o.width << "x" << o.height << ", "
     << tri_name(o.algo) << " triangle test, " << bvh_name(o.bvh) << " BVH\n";
  std::snprintf(buf, sizeof buf, "values computed: %llu finite non-zero, %llu zero, %llu inf, %llu nan\n",
                (unsigned long long)p.all.finite_nonzero(), (unsigned long long)p.all.zeros,
                (unsigned long long)p.all.infs, (unsigned long long)p.all.nans);
  os << buf;
  std::snprintf(buf, sizeof buf, "  binary exponents %d .. %d, smallest |x| %.4g, largest %.4g\n", p.all.min_exp(),
                p.all.max_exp(), p.all.min_abs, p.all.max_abs);
  os << buf;
  std::snprintf(buf, sizeof buf,
                "unit operands (ray origins/directions, vertices; Fig. 3.5's population): exponents %d .. %d, "
                "smallest %.4g, largest %.4g\n",
                p.inputs.min_exp(), p.inputs.max_exp(), p.inputs.min_abs, p.inputs.max_abs);
  os << buf;
  os << "exponent histogram of all values (exponent: count):\n";
  const uint64_t total = std::max<uint64_t>(1, p.all.finite_nonzero());
  for (int e = p.all.min_exp(); e <= p.all.max_exp(); ++e) {
    uint64_t c = p.all.counts[e - ExpHistogram::kMinExp];
    if (!c) continue;
    int bar = static_cast<int>(std::lround(60.0 * double(c) / double(total) * 4));
    std::snprintf(buf, sizeof buf, "  %5d %12llu %s\n", e, (unsigned long long)c, std::string(std::min(bar, 60), '#').c_str());
    os << buf;
  }
  os << "exponent width: overflows / values below the smallest normal\n";
  for (const auto& w : p.widths) {
    std::snprintf(buf, sizeof buf, "  e%-2d (normal 2^%d .. 2^%d): overflow %llu, below normal %llu\n", w.exp_bits, w.emin,
                  w.emax, (unsigned long long)w.overflow, (unsigned long long)w.subnormal);
    os << buf;
  }
  if (p.recommended_exp) {
    os << "smallest exponent width without overflow: " << p.no_overflow_exp << " bits\n";
    for (const auto& [e, f] : p.exp_checks) {
      std::snprintf(buf, sizeof buf, "  e%dm40 errors %6llu  PSNR %6.1f dB%s\n", e, (unsigned long long)f.diff.errors,
                    f.diff.psnr, f.meets ? "  <- meets: range suffices" : "  (misses even with 40 fraction bits: underflow)");
      os << buf;
    }
    os << "recommended exponent width: " << p.recommended_exp << " bits\n";
    for (const auto& f : p.fracs) {
      std::snprintf(buf, sizeof buf, "  e%dm%-2d errors %6llu (%.3f%%)  PSNR %6.1f dB%s\n", p.recommended_exp, f.frac_bits,
                    (unsigned long long)f.diff.errors, 100.0 * f.diff.errors / double(f.diff.pixels), f.diff.psnr,
                    f.meets ? "  <- meets" : "");
      os << buf;
    }
    if (p.recommended_frac)
      std::snprintf(buf, sizeof buf, "recommended format: e%dm%d (target: <= %.2f%% pixels over 10%%, PSNR >= %.0f dB)\n",
                    p.recommended_exp, p.recommended_frac, 100 * o.max_error_fraction, o.min_psnr);
    else
      std::snprintf(buf, sizeof buf, "no fraction width up to %d meets the target\n", o.max_frac);
    os << buf;
  } else {
    os << "no exponent width up to 11 avoids overflow\n";
  }
  os << "units needed:";
  for (const auto& u : p.units) os << " " << u;
  os << (p.noise_evals ? "" : "  (no procedural materials: no noise unit)") << "\n";
  return os.str();
}

std::string profile_json(const Profile& p, const ProfileOptions& o) {
  using J = nlohmann::ordered_json;
  auto num = [](double v) -> J {  // JSON has no infinities: "inf"/"-inf"; NaN as null
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    if (std::isnan(v)) return nullptr;
    return v;
  };
  auto hist = [&](const ExpHistogram& h) {
    J counts = J::object();
    for (int e = h.min_exp(); e <= h.max_exp(); ++e)
      if (const uint64_t c = h.counts[e - ExpHistogram::kMinExp]) counts[std::to_string(e)] = c;
    return J{{"finite_nonzero", h.finite_nonzero()}, {"zeros", h.zeros},     {"infs", h.infs},
             {"nans", h.nans},                       {"min_exp", h.min_exp()}, {"max_exp", h.max_exp()},
             {"min_abs", num(h.min_abs)},            {"max_abs", num(h.max_abs)}, {"counts", counts}};
  };
  J j;
  j["scene"] = p.scene;
  j["triangles"] = p.triangles;
  j["width"] = o.width;
  j["height"] = o.height;
  j["tri"] = tri_name(o.algo);
  j["bvh"] = bvh_name(o.bvh);
  j["target"] = {{"max_error_fraction", num(o.max_error_fraction)}, {"min_psnr", num(o.min_psnr)}};
  j["values"] = hist(p.all);
  j["unit_operands"] = hist(p.inputs);
  j["exponent_widths"] = J::array();
  for (const auto& w : p.widths)
    j["exponent_widths"].push_back({{"exp_bits", w.exp_bits}, {"emin", w.emin}, {"emax", w.emax},
                                    {"overflow", w.overflow}, {"below_normal", w.subnormal}, {"flushed", w.flushed}});
  j["no_overflow_exp_bits"] = p.no_overflow_exp;
  j["recommended_exp_bits"] = p.recommended_exp;
  j["fraction_widths"] = J::array();
  for (const auto& f : p.fracs)
    j["fraction_widths"].push_back({{"frac_bits", f.frac_bits}, {"errors", f.diff.errors}, {"pixels", f.diff.pixels},
                                    {"psnr", num(f.diff.psnr)}, {"meets", f.meets}});
  j["recommended_frac_bits"] = p.recommended_frac;
  j["recommended_format"] = p.recommended_exp && p.recommended_frac
                                ? J("e" + std::to_string(p.recommended_exp) + "m" + std::to_string(p.recommended_frac))
                                : J(nullptr);
  j["noise_evaluations"] = p.noise_evals;
  j["units"] = p.units;
  return j.dump(2) + "\n";
}

}  // namespace ru::render
