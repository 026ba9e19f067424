#include "campaign/collect_plan.hpp"

#include "base/error.hpp"

namespace tumble::campaign {

CollectPlan make_collect_plan(const CollectSpec& spec, const Scene& scene) {
  auto fail = [](const std::string& key, const std::string& what) {
    throw InputError("key '" + key + "' " + what);
  };
  CollectPlan p;
  p.spec = spec;
  p.radius = scene.radius;
  p.mixture = mixture_of(scene);
  p.shell_inner = spec.shell_inner;
  if (spec.shell_one_diameter) {
    p.shell_inner = 1 - p.mixture.diameter[p.mixture.mapped] / scene.radius;
    if (!(p.shell_inner > 0))
      fail("collect.shell_inner",
           "= 'one_diameter' leaves no shell: the mapped species' diameter "
           "is not smaller than the tumbler radius");
  }
  if (spec.cylinder != scene.cylinder())
    fail("tumbler.shape",
         "differs between the campaign's template and a case (sweeps and "
         "overrides may not change the tumbler's shape)");
  if (scene.cylinder()) {  // the run samples S_a, S_r every output.analysis_interval itself
    if (!(scene.analysis_interval > 0))
      fail("output.analysis_interval", "must be > 0 in a cylinder campaign (it sets the series)");
    p.total_steps = scene.protocol_steps();
    return p;
  }
  if (scene.mode != Mode::biaxial)
    fail("collect.fields",
         "needs protocol.mode = 'biaxial' (samples are placed by protocol "
         "iteration), not '" +
             std::string(name_of(scene.mode)) + "'");
  const double dt = scene.time_step();
  const double period = scene.iterations > 0 ? scene.run_time() / scene.iterations : 0;
  if (!(period > 0)) fail("protocol.iterations", "must be > 0 for a campaign case");
  p.steps_per_iteration = period / dt;
  p.total_steps = scene.protocol_steps();
  const int n = spec.samples_per_iteration;
  if (p.steps_per_iteration / n < 1)
    fail("collect.samples_per_iteration",
         "= " + std::to_string(n) + " asks for samples closer than one time step (" +
             display_number(p.steps_per_iteration) + " steps per iteration)");
  p.last_sample = static_cast<std::int64_t>(std::floor(scene.iterations * n + 1e-9));
  const double to = spec.to < 0 ? scene.iterations : spec.to;
  if (to > scene.iterations * (1 + 1e-12) + 1e-12)
    fail("collect.iterations",
         "ends at iteration " + display_number(to) +
             ", after the run (protocol.iterations = " + display_number(scene.iterations) + ")");
  p.window_first = std::llround(spec.from * n);
  p.window_last = std::min<std::int64_t>(std::llround(to * n), p.last_sample);
  if (p.window_last < p.window_first)
    fail("collect.iterations", "holds no sample: widen it or raise collect.samples_per_iteration");
  for (const double k : spec.displacement_periods) {
    p.lags.push_back(std::llround(k * n));
    if (spec.displacement && p.window_first + p.lags.back() > p.window_last)
      fail("collect.displacement_periods",
           "= " + display_number(k) + " periods do not fit in the window " +
               "collect.iterations = [" + display_number(spec.from) + ", " + display_number(to) +
               "]: lengthen the run or the window, or drop this lag");
  }
  return p;
}

}  // namespace tumble::campaign
