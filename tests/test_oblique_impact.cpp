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

#include "dem_helpers.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {
struct Impact {
  double vt_contact_before = 0, vt_contact_after = 0;
  double energy_before = 0, energy_after = 0;
  double impulse_n = 0, impulse_t = 0;
  int core_steps = 0, capped_core_steps = 0;  // steps with both overlaps > 20% of the peak
  double worst_cap_ratio_error = 0;           // max | |F_t|/(μ|F_n|) − 1 | over capped steps
};

Impact impact(double angle_deg, const Scene& s, int species = 0) {
  const double r = 0.5 * (species ? s.d_large : s.d_small);
  const double u = 0.5;  // impact speed
  const double a = angle_deg * kPi / 180.0;
  // Approaching the wall at the bottom (-y) with tangential velocity along +x.
  const double y0 = -(s.radius - r - 1e-6);
  Simulation sim(
      s, make_particles(s, {{{0, y0, 0}, {u * std::sin(a), -u * std::cos(a), 0}, {}, species}}),
      geometry::Protocol::at_rest());
  sim.compute_forces();
  Impact out;
  const auto& p = sim.particles();
  auto contact_vt = [&]() {
    const Vec3 n = -(1.0 / norm(p.x[0])) * p.x[0];  // wall -> particle
    const Vec3 vc = p.v[0] - cross(r * p.w[0], n);
    return vc - dot(vc, n) * n;
  };
  auto energy = [&]() { return sim.energy().kinetic; };
  out.vt_contact_before = contact_vt().x;
  out.energy_before = energy();
  const double m = 1.0 / p.inv_mass[0];
  const auto& wp = sim.wall_pair(species);
  // Per contact step: overlaps before and after, and |F_t|/(μ|F_n|) of the force measured from
  // the velocity change (gravity is off: all of it is contact force).
  struct StepRecord {
    double ov_before, ov_after, ratio;
  };
  std::vector<StepRecord> steps;
  bool was_in = false;
  double ov_prev = 0, peak = 0;
  for (int k = 0; k < 200000; ++k) {
    const Vec3 v_old = p.v[0];
    sim.step();
    Vec3 n, point;
    const double ov = sim.wall().overlap(p.x[0], r, n, point);
    if (ov > 0) {
      was_in = true;
      const Vec3 force = (m / sim.dt()) * (p.v[0] - v_old);
      const double fn = dot(force, n);
      const Vec3 ft = force - fn * n;
      out.impulse_n += fn * sim.dt();
      out.impulse_t += norm(ft) * sim.dt();
      steps.push_back({ov_prev, ov, norm(ft) / (wp.mu * std::fabs(fn))});
      peak = std::max(peak, ov);
    } else if (was_in) {
      break;
    }
    ov_prev = ov;
  }
  // A velocity change averages two force evaluations. Near the ends of the contact the dashpot
  // makes the normal force tensile in one of them, so the averaged normal parts cancel while the
  // tangential parts add: those steps say nothing about the cap. Elsewhere the ratio is exact up
  // to the turn of the curved wall's normal within a step (~v_t δt / R: ~5e-5).
  for (const auto& st : steps) {
    if (st.ov_before < 0.2 * peak || st.ov_after < 0.2 * peak) continue;
    ++out.core_steps;
    if (st.ratio > 1 - 1e-4) {
      ++out.capped_core_steps;
      out.worst_cap_ratio_error = std::max(out.worst_cap_ratio_error, std::fabs(st.ratio - 1));
    }
  }
  out.vt_contact_after = contact_vt().x;
  out.energy_after = energy();
  return out;
}
}  // namespace

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
