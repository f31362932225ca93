// rayunits study exact-path: how often ray_tri_exact's exact (slow) side path decides, on the
// ray/triangle tests of a trace (e.g. `render --trace-out` of a real render), and how often its
// decision differs from ray_tri_robust's (units/ray_tri_exact.hpp).
#include <cstdio>
#include <mutex>
#include <string>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/num/fp.hpp"
#include "rayunits/units/ray_tri.hpp"
#include "rayunits/units/ray_tri_exact.hpp"
#include "rayunits/units/trace.hpp"
#include "rayunits/util/parallel.hpp"

namespace ru::cli {
namespace {

using namespace ru::units;
using ru::num::Format;

struct Counts {
  uint64_t tests = 0, slow = 0, slow_edge = 0, slow_interval = 0, edges_slow = 0;
  uint64_t hits_exact = 0, hits_robust = 0, differ = 0;
  void add(const Counts& o) {
    tests += o.tests, slow += o.slow, slow_edge += o.slow_edge, slow_interval += o.slow_interval;
    edges_slow += o.edges_slow, hits_exact += o.hits_exact, hits_robust += o.hits_robust, differ += o.differ;
  }
};

template <class T>
void run_one(const TriRecord& r, const ExactTriOptions& o, Counts& c) {
  const auto a = vcast<T>(r.a), d = vcast<T>(r.d), p0 = vcast<T>(r.p0), p1 = vcast<T>(r.p1), p2 = vcast<T>(r.p2);
  const T tmin = ru::num::fp_cast<T>(r.t_min), tmax = ru::num::fp_cast<T>(r.t_max);
  const auto e = ray_tri_exact(a, d, p0, p1, p2, tmin, tmax, o);
  const auto b = ray_tri_robust(a, d, p0, p1, p2, tmin, tmax);
  ++c.tests;
  c.slow += e.path.slow();
  c.slow_edge += e.path.slow_edges != 0;
  c.edges_slow += e.path.slow_edges;
  c.slow_interval += e.path.slow_interval;
  c.hits_exact += e.hit;
  c.hits_robust += b.hit;
  c.differ += e.hit != b.hit;
}

bool in_format(const Format& f, double x) {
  if (std::isnan(x) || std::isinf(x)) return true;
  const auto res = ru::num::from_double(f, x);
  return ru::num::to_double(f, res.bits) == x;
}

int run_cmd(int argc, char** argv) {
  CLI::App app{
      "Cost of ray_tri_exact's exact side path on the ray/triangle records of a trace (render --trace-out): "
      "the share of tests the fast (filtered) path decides alone, and the tests whose decision differs from "
      "ray_tri_robust. The last line is 'tests=N slow=S fast_percent=P'.",
      "rayunits study exact-path"};
  std::string trace_file, format = "e8m23", filter = "permanent-format";
  int threads = 2;
  app.add_option("--trace", trace_file, "binary trace (docs/UNITS.md); its tri records are used")->required();
  app.add_option("--format", format, "the format the trace was rendered in (every value must be in it)")
      ->capture_default_str();
  app.add_option("--filter", filter,
                 "the fast path's error bound: permanent (2^K times the permanent, computed beside the volume), "
                 "permanent-format (the same, the interval's error evaluated in the format with directed rounding "
                 "as ru_ray_tri_exact does; the default) or exponent (from the factors' largest exponents; cheap hardware, looser)")
      ->capture_default_str()
      ->check(CLI::IsMember({"permanent", "permanent-format", "exponent"}));
  app.add_option("--threads", threads, "worker threads")->capture_default_str()->check(CLI::Range(1, 64));
  if (!parse_args(app, argc, argv)) return 0;
  const Format f = Format::parse(format);
  const Trace tr = read_trace(trace_file);
  if (tr.tris.empty()) throw UsageError("trace " + trace_file + " has no ray-triangle records");
  for (size_t i = 0; i < tr.tris.size(); ++i) {
    const TriRecord& r = tr.tris[i];
    for (const Vec3d* v : {&r.a, &r.d, &r.p0, &r.p1, &r.p2})
      for (int k = 0; k < 3; ++k)
        if (!in_format(f, (*v)[k]))
          throw UsageError("trace " + trace_file + ": tri record " + std::to_string(i) + " has a value (" +
                           std::to_string((*v)[k]) + ") that is not in " + f.name() + " (give the render's --format)");
  }
  const Format f32{8, 23, true, ru::num::Round::RNE}, f64{11, 52, true, ru::num::Round::RNE};
  const int mode = f == f32 ? 1 : f == f64 ? 2 : 0;
  ExactTriOptions opt;
  opt.filter = filter == "exponent"           ? ExactFilter::Exponent
               : filter == "permanent-format" ? ExactFilter::PermanentFormat
                                              : ExactFilter::Permanent;
  Counts all;
  std::mutex mu;
  const size_t block = 4096, nblocks = (tr.tris.size() + block - 1) / block;
  ru::util::parallel_for(nblocks, threads, [&](size_t b) {
    ru::num::SoftScope scope(f);
    Counts c;
    for (size_t i = b * block; i < std::min(tr.tris.size(), (b + 1) * block); ++i) {
      if (mode == 1) run_one<float>(tr.tris[i], opt, c);
      else if (mode == 2) run_one<double>(tr.tris[i], opt, c);
      else run_one<ru::num::Soft>(tr.tris[i], opt, c);
    }
    std::lock_guard<std::mutex> lock(mu);
    all.add(c);
  });
  auto pct = [](uint64_t n, uint64_t d) { return d ? 100.0 * static_cast<double>(n) / static_cast<double>(d) : 0.0; };
  std::printf("trace %s: %llu ray-triangle tests, format %s, filter %s\n", trace_file.c_str(),
              static_cast<unsigned long long>(all.tests), f.name().c_str(), filter.c_str());
  std::printf("exact path taken: %llu tests (%.4f %%): %llu for edge signs (%llu edges), %llu for the interval\n",
              static_cast<unsigned long long>(all.slow), pct(all.slow, all.tests),
              static_cast<unsigned long long>(all.slow_edge), static_cast<unsigned long long>(all.edges_slow),
              static_cast<unsigned long long>(all.slow_interval));
  std::printf("hits: ray_tri_exact %llu, ray_tri_robust %llu; decisions that differ: %llu\n",
              static_cast<unsigned long long>(all.hits_exact), static_cast<unsigned long long>(all.hits_robust),
              static_cast<unsigned long long>(all.differ));
  std::printf("tests=%llu slow=%llu fast_percent=%.4f\n", static_cast<unsigned long long>(all.tests),
              static_cast<unsigned long long>(all.slow), 100.0 - pct(all.slow, all.tests));
  return 0;
}

}  // namespace

RU_COMMAND("study exact-path", "share of ray_tri_exact tests its exact side path decides, on a trace", run_cmd);

}  // namespace ru::cli
