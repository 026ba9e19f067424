#include "scene/fidelity.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "base/error.hpp"
#include "base/vec3.hpp"

namespace tumble {

const std::vector<std::string>& fidelity_tiers() {
  static const std::vector<std::string> t = {"standard", "reference", "fast", "preview"};
  return t;
}

namespace {
std::string num(double v) {
  std::ostringstream os;
  os.precision(12);
  os << v;
  return os.str();
}

struct Preset {
  double tc_factor, dt_fraction, skin, max_r_over_dl, min_froude, max_iterations;
};
}  // namespace

std::map<std::string, std::string> tier_values(Tier tier, const Scene& s) {
  std::map<std::string, std::string> v;
  if (tier == Tier::standard) return v;
  if (s.cylinder())
    throw InputError("scene error: key 'fidelity.tier' = '" + std::string(name_of(tier)) +
                     "': the tiers are defined for sphere scenes (Yu 2022); use 'standard' "
                     "for cylinders");
  Preset p{};
  switch (tier) {
    case Tier::reference:
      p = {0.5, std::min(s.dt_fraction, 0.01), s.skin, 0, 0, 0};
      break;
    case Tier::fast:
      p = {2, 1.0 / 30, 0.2, 8.75, 3e-3, 10};
      break;
    case Tier::preview:
      p = {4, 1.0 / 20, 0.3, 5, 1e-2, 3};
      break;
    case Tier::standard:
      break;
  }
  v["contact.collision_time"] = num(p.tc_factor * s.collision_time);
  v["time.dt_fraction"] = num(p.dt_fraction);
  v["time.dt"] = "0";  // δt from the fraction
  v["neighbor.skin"] = num(p.skin);
  // Softer contacts ring and creep for longer: a bed settles in about the same number of
  // collision times, so the settling allowance grows with t_c (a preview bed of bst_tiny
  // needed 2.2 s against the scene's 2 s).
  if (p.tc_factor > 1) v["fill.settle_max_time"] = num(p.tc_factor * s.settle_max_time);
  if (p.max_r_over_dl > 0 && s.radius / s.d_large > p.max_r_over_dl) {
    const double grow = s.radius / s.d_large / p.max_r_over_dl;
    v["particles.d_large"] = num(s.d_large * grow);
    v["particles.d_small"] = num(s.d_small * grow);
  }
  if (p.min_froude > 0 && s.mode != Mode::rest) {
    const double omega_min = std::sqrt(p.min_froude * s.g / s.radius);
    const double rpm_min = omega_min * 60 / (2 * kPi);
    if (s.rpm < rpm_min) v["protocol.rpm"] = num(rpm_min);
  }
  if (p.max_iterations > 0 && s.iterations > p.max_iterations)
    v["protocol.iterations"] = num(p.max_iterations);
  return v;
}

}  // namespace tumble
