// Stability at the extremes of the allowed parameter ranges (issue 8): the engine runs a loose bed
// collapsing under gravity, or a bed turned by the protocol, at the edge of each range and must
// stay finite, keep every particle inside the tumbler, and (at rest, where nothing drives the bed)
// never gain mechanical energy. Above the time-step bound a scene is refused, not run.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "dem_helpers.hpp"
#include "scene/fill.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {

// A 12 mm tumbler with 1 and 2 mm beads, t_c = 1e-3 s: a few thousand particles, so each extreme
// costs about a second.
Scene extreme_scene(const std::vector<std::string>& extra) {
  std::vector<std::string> o = {"tumbler.radius=0.012",        "particles.d_small=0.001",
                                "particles.d_large=0.002",     "particles.fill_level=0.3",
                                "contact.collision_time=1e-3", "protocol.mode=rest"};
  o.insert(o.end(), extra.begin(), extra.end());
  return parse_scene("", o, "extreme");
}

struct Outcome {
  double energy_gain = 0;  // max over samples of (E - E0) / (M g R)
  double max_speed = 0;    // m/s
  std::size_t n = 0;
};

// Runs `steps` from the loose start lattice; health checked every 100 steps (throws RunError).
Outcome run(const Scene& s, int steps, const geometry::Protocol& protocol) {
  Simulation sim(s, make_bed(s), protocol);
  sim.compute_forces();
  double mass = 0;
  for (double im : sim.particles().inv_mass) mass += 1 / im;
  const double scale = std::max(mass * s.g * s.radius, 1e-30);
  const double e0 = sim.energy().total();
  Outcome out;
  out.n = sim.particles().size();
  for (int k = 1; k <= steps; ++k) {
    sim.step();
    if (k % 100 == 0) {
      sim.check_health();
      out.energy_gain = std::max(out.energy_gain, (sim.energy().total() - e0) / scale);
      for (const Vec3& v : sim.particles().v) out.max_speed = std::max(out.max_speed, norm(v));
    }
  }
  return out;
}

// At rest: finite, inside, no energy gain beyond 0.1% of M g R (the loose lattice releases about
// 0.3 M g R as it collapses).
void expect_stable_at_rest(const std::vector<std::string>& extra, int steps = 3000) {
  const Scene s = extreme_scene(extra);
  Outcome o;
  std::string what;
  for (const auto& e : extra) what += e + " ";
  ASSERT_NO_THROW(o = run(s, steps, geometry::Protocol::at_rest())) << what;
  EXPECT_LT(o.energy_gain, 1e-3) << what;
  EXPECT_LT(o.max_speed, 1.0) << what;
}

double bound_of(const std::vector<std::string>& extra) {
  return time_step_bound(extreme_scene(extra));
}

}  // namespace

TEST(Extremes, TimeStepAtAndJustBelowTheBound) {
  for (const char* e : {"contact.restitution=1", "contact.restitution=0.05"}) {
    const double b = bound_of({e});
    char at[64], below[64];
    std::snprintf(at, sizeof at, "time.dt=%.17g", b);
    std::snprintf(below, sizeof below, "time.dt=%.17g", 0.9 * b);
    expect_stable_at_rest({e, at});
    expect_stable_at_rest({e, below});
    // Just above: refused before any work, naming the key and the bound.
    char above[64];
    std::snprintf(above, sizeof above, "time.dt=%.17g", 1.001 * b);
    try {
      (void)extreme_scene({e, above});
      ADD_FAILURE() << "dt above the bound accepted";
    } catch (const InputError& err) {
      EXPECT_NE(std::string(err.what()).find("time.dt"), std::string::npos);
      EXPECT_NE(std::string(err.what()).find("stability bound"), std::string::npos);
    }
  }
}

TEST(Extremes, RestitutionAndFriction) {
  expect_stable_at_rest({"contact.restitution=0.05"});
  expect_stable_at_rest({"contact.restitution=1"});
  expect_stable_at_rest({"contact.friction=0", "contact.wall_friction=0"});
  expect_stable_at_rest({"contact.friction=2", "contact.wall_friction=2"});
  expect_stable_at_rest({"contact.restitution=1", "contact.friction=0", "contact.wall_friction=0"});
}

TEST(Extremes, DensityAndSizeRatios) {
  expect_stable_at_rest({"particles.density_ratio=10"});
  expect_stable_at_rest({"particles.density_ratio=0.1"});
  expect_stable_at_rest({"particles.d_large=0.001"});  // size ratio 1
  expect_stable_at_rest({"particles.d_large=0.003"});  // size ratio 3 (4 needs R >= 16 mm: below)
  expect_stable_at_rest({"particles.d_large=0.004", "tumbler.radius=0.016"}, 2000);
}

TEST(Extremes, LargeFractionZeroAndOne) {
  expect_stable_at_rest({"particles.large_fraction=0"});
  expect_stable_at_rest({"particles.large_fraction=1"});
}

TEST(Extremes, VerySoftAndVeryStiff) {
  // The softest contact allowed: the bed's weight presses the bottom particles together by just
  // under the 25% of d_small that validation permits (overlap ∝ t_c²).
  const double ov = weight_overlap_fraction(extreme_scene({}));
  const double soft = 1e-3 * std::sqrt(0.95 * 0.25 / ov);
  EXPECT_GT(soft, 3e-3);
  expect_stable_at_rest({"contact.collision_time=" + std::to_string(soft)}, 3000);
  expect_stable_at_rest({"contact.collision_time=1e-6"}, 2000);  // δt = 2e-8 s
  // Softer than that: refused with the key and the largest allowed t_c named.
  try {
    (void)extreme_scene({"contact.collision_time=1e-2"});
    ADD_FAILURE() << "t_c = 1e-2 s accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("contact.collision_time <="), std::string::npos)
        << e.what();
  }
}

TEST(Extremes, ProtocolAnglesZero180And360) {
  for (const std::vector<double>& th :
       std::vector<std::vector<double>>{{0, 57}, {57, 0}, {180, 180}, {360, 360}, {360, 0}}) {
    const Scene s = extreme_scene({"protocol.mode=biaxial", "protocol.rpm=60",
                                   "protocol.theta_z=" + std::to_string(th[0]),
                                   "protocol.theta_x=" + std::to_string(th[1])});
    const auto protocol = geometry::Protocol::biaxial(deg2rad(s.theta_z), deg2rad(s.theta_x),
                                                      deg2rad(s.repose.deg), s.omega());
    Outcome o;
    ASSERT_NO_THROW(o = run(s, 3000, protocol)) << th[0] << ", " << th[1];
    // Driven: energy may grow, speeds stay of order ωR + sqrt(2 g R) (0.08 + 0.49 m/s).
    EXPECT_LT(o.max_speed, 1.0) << th[0] << ", " << th[1];
  }
  // Both angles zero would never move: refused.
  EXPECT_THROW(extreme_scene({"protocol.mode=biaxial", "protocol.theta_z=0", "protocol.theta_x=0"}),
               InputError);
}

TEST(Extremes, SingleParticleAndEmptyBed) {
  const Scene s = extreme_scene({});
  // One particle dropped in the tumbler bounces and comes to rest at the bottom.
  Simulation one(s, make_particles(s, {{{0.003, 0.0, 0.002}, {0.1, 0, 0}, {}, 1}}),
                 geometry::Protocol::single_axis('z', s.omega()));
  one.compute_forces();
  for (int k = 0; k < 20000; ++k) one.step();
  EXPECT_NO_THROW(one.check_health());
  EXPECT_LT(norm(one.particles().x[0]), s.radius);
  // No particle at all: every loop runs empty.
  Simulation none(s, make_particles(s, {}), geometry::Protocol::single_axis('z', s.omega()));
  none.compute_forces();
  for (int k = 0; k < 100; ++k) none.step();
  EXPECT_NO_THROW(none.check_health());
  EXPECT_EQ(none.energy().total(), 0.0);
  EXPECT_EQ(none.rms_speed(), 0.0);
}
