#pragma once
// When a case samples its fields: sample j is taken at the time step nearest to iteration j / n
// (n = collect.samples_per_iteration; n = 1 is stroboscopic, at the end of every iteration). The
// series uses every sample of the run; the maps use the samples of the window [from, to]; Δψ
// pairs samples m = k n apart, both inside the window, for each lag k listed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "campaign/campaign_spec.hpp"
#include "scene/mixture.hpp"
#include "scene/scene.hpp"

namespace tumble::campaign {

struct CollectPlan {
  CollectSpec spec;
  double radius = 0;               // tumbler radius R
  Mixture mixture;                 // the species' roles (which one the maps show)
  double shell_inner = 0.9;        // the concentration shell, resolved (spec.shell_one_diameter)
  double steps_per_iteration = 0;  // period / dt (not an integer in general)
  std::int64_t total_steps = 0;
  std::int64_t last_sample = 0;                    // largest j inside the run
  std::int64_t window_first = 0, window_last = 0;  // sample indices of the window
  // m per lag (in the order of collect.displacement_periods): Δψ pairs samples j - m and j.
  std::vector<std::int64_t> lags;
  std::int64_t max_lag() const {
    return lags.empty() ? 0 : *std::max_element(lags.begin(), lags.end());
  }
  std::int64_t min_lag() const {
    return lags.empty() ? 0 : *std::min_element(lags.begin(), lags.end());
  }
  // Step of sample j (the last one is clamped onto the run's final step).
  std::int64_t sample_step(std::int64_t j) const {
    return std::min(total_steps, static_cast<std::int64_t>(std::llround(
                                     j * steps_per_iteration / spec.samples_per_iteration)));
  }
  bool in_window(std::int64_t j) const { return j >= window_first && j <= window_last; }
};

// Throws InputError naming the collect.* key that does not fit the scene.
CollectPlan make_collect_plan(const CollectSpec& spec, const Scene& scene);

}  // namespace tumble::campaign
