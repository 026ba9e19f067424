// Oblique impacts of a sphere on the tumbler wall (radius 0.1 m, nearly flat at the particle's
// scale) with friction μ = 0.6 and γ_t = 0:
//  - small incidence angle: the contact sticks; with k_t = 2/7 k_n the tangential oscillation of
//    a solid sphere has the normal frequency, so the contact-point tangential velocity reverses;
//  - large incidence angle (tan θ > 7/2 μ (1+e)): the contact slides throughout, |F_t| = μ|F_n| at
//  every step and the
//    tangential impulse is μ times the normal impulse;
//  - at every angle up to grazing, the kinetic energy (translation + rotation) never grows.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "collision_fixtures.hpp"

using namespace tumble;
using namespace tumble::testing;

TEST(ObliqueImpact, SmallAngleSticksAndReversesTangentialVelocity) {
  const Scene s = test_scene();
  const Impact o = impact(5.0, s);
  // Sticking: a sliding contact can only slow the contact point, never reverse it.
  EXPECT_LT(o.vt_contact_after, 0.0);
  EXPECT_GT(-o.vt_contact_after / o.vt_contact_before, 0.5);
  EXPECT_LT(o.capped_core_steps, o.core_steps / 10);
}

TEST(ObliqueImpact, LargeAngleSlidesAtTheCoulombLimit) {
  const Scene s = test_scene();
  for (int sp : {0, 1}) {
    // Gross sliding throughout needs tan θ > (7/2) μ (1 + e) = 3.9 (θ > 76°) for a solid sphere.
    const Impact o = impact(85.0, s, sp);
    // Sliding throughout: every step of the contact is at the cap, and the tangential impulse is μ
    // times the normal impulse.
    EXPECT_GT(o.core_steps, 30) << "species " << sp;
    EXPECT_EQ(o.capped_core_steps, o.core_steps) << "species " << sp;
    EXPECT_NEAR(o.impulse_t / o.impulse_n, 0.6, 0.006) << "species " << sp;
    EXPECT_GT(o.vt_contact_after, 0.0) << "a sliding contact keeps its direction";
    EXPECT_LT(o.worst_cap_ratio_error, 1e-4) << "the cap is never exceeded";
  }
}

TEST(ObliqueImpact, NoEnergyGainAtAnyAngleUpToGrazing) {
  for (const char* mu : {"0.1", "0.6", "2"}) {
    const Scene s = test_scene({std::string("contact.wall_friction=") + mu});
    for (double angle : {1.0, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 88.0, 89.5, 89.9}) {
      const Impact o = impact(angle, s);
      EXPECT_LE(o.energy_after, o.energy_before * (1 + 1e-12)) << "mu " << mu << " angle " << angle;
    }
  }
}

TEST(ObliqueImpact, ParticlePairGrazingDoesNotGainEnergy) {
  // Two spheres brushing past each other with a small normal component.
  const Scene s = test_scene();
  for (double b_frac : {0.9, 0.99, 0.999}) {
    const double d = s.d_small;
    const double b = b_frac * d;  // impact parameter
    Simulation sim(s,
                   make_particles(s, {{{-2 * d, b / 2, 0}, {0.5, 0, 0}, {}, 0},
                                      {{2 * d, -b / 2, 0}, {-0.5, 0, 0}, {}, 0}}),
                   geometry::Protocol::at_rest());
    sim.compute_forces();
    const double e0 = sim.energy().kinetic;
    for (int k = 0; k < 20000; ++k) sim.step();
    EXPECT_LE(sim.energy().kinetic, e0 * (1 + 1e-12)) << "impact parameter " << b_frac;
  }
}
