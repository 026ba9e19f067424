// With e = 1 and μ = 0 the Yu law is a conservative linear spring, and velocity Verlet is
// symplectic: the total energy (kinetic + gravitational + spring) of a dense, agitated bed must not
// drift. Measured over 1e5 steps of a settled ~2,000-particle bed whose particles were given random
// velocities of 5 cm/s, with the gravitational energy counted from the tumbler's bottom.
#include <gtest/gtest.h>

#include <cmath>

#include "bed_fixture.hpp"
#include "engine/simulation.hpp"
#include "scene/fill.hpp"

using namespace tumble;
using namespace tumble::testing;

TEST(EnergyConservation, ElasticFrictionlessDenseBedOver1e5Steps) {
  const Scene s =
      tiny_scene({"contact.restitution=1", "contact.friction=0", "contact.wall_friction=0"});
  Particles bed = tiny_settled_bed();
  Rng rng(3);
  for (auto& v : bed.v)
    v = {0.05 * (2 * rng.uniform() - 1), 0.05 * (2 * rng.uniform() - 1),
         0.05 * (2 * rng.uniform() - 1)};
  double mass = 0;
  for (double im : bed.inv_mass) mass += 1.0 / im;
  Simulation sim(s, std::move(bed), geometry::Protocol::at_rest());
  sim.compute_forces();
  // Gravitational energy measured from the bottom of the tumbler (y = -R).
  auto energy = [&]() { return sim.energy().total() + mass * s.g * s.radius; };
  const EnergyBreakdown e0 = sim.energy();
  const double free0 = e0.kinetic + e0.elastic;
  // Block averages over 1000 steps (sampled every 10) remove Verlet's bounded O((ω δt)²)
  // oscillation of the energy of each contact, leaving the drift.
  std::vector<double> block_mean;
  double worst_instant = 0;
  const double first = energy();
  for (int block = 0; block < 100; ++block) {
    double sum = 0;
    for (int k = 0; k < 1000; ++k) {
      sim.step();
      if (k % 10 == 0) {
        const double e = energy();
        sum += e;
        worst_instant = std::max(worst_instant, std::fabs(e - first));
      }
    }
    block_mean.push_back(sum / 100);
  }
  sim.check_health();
  const double drift = std::fabs(block_mean.back() - block_mean.front()) / block_mean.front();
  const double drift_free = std::fabs(block_mean.back() - block_mean.front()) / free0;
  std::printf(
      "energy drift over 1e5 steps: %.3e of the total, %.3e of (KE0 + elastic0); "
      "largest instantaneous deviation %.3e of (KE0 + elastic0)\n",
      drift, drift_free, worst_instant / free0);
  EXPECT_LT(drift, 1e-4);
  EXPECT_LT(worst_instant / free0, 1e-2);  // bounded: no blow-up at the contact onsets
}
