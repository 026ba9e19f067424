#pragma once
// Collision fixtures shared by the contact-law tests (tests/test_binary_collisions.cpp and
// tests/test_oblique_impact.cpp for the Yu law, tests/test_hertz_mindlin.cpp): binary head-on
// collisions of two particles or of a particle with the wall, and oblique impacts on the wall,
// run through the engine with whichever law the scene selects.
#include <algorithm>
#include <cmath>
#include <vector>

#include "dem_helpers.hpp"

namespace tumble::testing {

// Head-on collisions (pair_collision, wall_collision): the measured normal restitution and the
// contact duration, measured between the linearly interpolated zero crossings of the overlap (a
// step count alone resolves only one time step).
struct Outcome {
  double restitution = 0, duration = 0;
};

// Two particles approaching head-on along x with relative speed u.
inline Outcome pair_collision(int sa, int sb, double u, const Scene& s) {
  const double ra = 0.5 * (sa ? s.d_large : s.d_small), rb = 0.5 * (sb ? s.d_large : s.d_small);
  const double gap = 0.1 * s.d_small;
  Simulation sim(s,
                 make_particles(s, {{{-ra - gap / 2, 0, 0}, {u / 2, 0, 0}, {}, sa},
                                    {{rb + gap / 2, 0, 0}, {-u / 2, 0, 0}, {}, sb}}),
                 geometry::Protocol::at_rest());
  sim.compute_forces();
  auto overlap = [&]() {
    const auto& p = sim.particles();
    return p.radius[0] + p.radius[1] - norm(p.x[0] - p.x[1]);
  };
  double prev = overlap(), t_start = -1, t_end = -1;
  for (int k = 0; k < 100000 && t_end < 0; ++k) {
    sim.step();
    const double ov = overlap();
    if (t_start < 0 && prev <= 0 && ov > 0) t_start = sim.time() - sim.dt() * ov / (ov - prev);
    if (t_start >= 0 && prev > 0 && ov <= 0) t_end = sim.time() - sim.dt() * ov / (ov - prev);
    prev = ov;
  }
  const auto& p = sim.particles();
  const std::size_t a = index_of(sim, 0), b = index_of(sim, 1);
  const double v_after = p.v[b].x - p.v[a].x;  // separating: b moves +x relative to a
  return {v_after / u, t_end - t_start};
}

// A particle moving radially onto the (resting) tumbler wall with speed u.
inline Outcome wall_collision(int sp, double u, const Scene& s) {
  const double r = 0.5 * (sp ? s.d_large : s.d_small);
  const double y0 = -(s.radius - r - 0.05 * s.d_small);
  Simulation sim(s, make_particles(s, {{{0, y0, 0}, {0, -u, 0}, {}, sp}}),
                 geometry::Protocol::at_rest());
  sim.compute_forces();
  auto overlap = [&]() { return norm(sim.particles().x[0]) + r - s.radius; };
  double prev = overlap(), t_start = -1, t_end = -1;
  for (int k = 0; k < 100000 && t_end < 0; ++k) {
    sim.step();
    const double ov = overlap();
    if (t_start < 0 && prev <= 0 && ov > 0) t_start = sim.time() - sim.dt() * ov / (ov - prev);
    if (t_start >= 0 && prev > 0 && ov <= 0) t_end = sim.time() - sim.dt() * ov / (ov - prev);
    prev = ov;
  }
  return {sim.particles().v[0].y / u, t_end - t_start};
}

// Oblique impact on the wall at `angle_deg` from the normal (the tumbler of test_scene, radius
// 0.1 m, is nearly flat at the particle's scale), speed 0.5: contact-point tangential velocity and
// kinetic energy before and after, impulses, and how many steps of the contact's core were at the
// Coulomb cap.
struct Impact {
  double vt_contact_before = 0, vt_contact_after = 0;
  double energy_before = 0, energy_after = 0;
  double impulse_n = 0, impulse_t = 0;
  int core_steps = 0, capped_core_steps = 0;  // steps with both overlaps > 20% of the peak
  double worst_cap_ratio_error = 0;           // max | |F_t|/(μ|F_n|) − 1 | over capped steps
};

inline Impact impact(double angle_deg, const Scene& s, int species = 0) {
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
  const double mu = s.wall_friction;  // the wall contact's Coulomb coefficient
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
      steps.push_back({ov_prev, ov, norm(ft) / (mu * std::fabs(fn))});
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

}  // namespace tumble::testing
