// The cylinder of Rapaport 2007 in the engine: smooth end caps and rough curved wall, axial
// periodicity, leapfrog against velocity Verlet, the bed fill, and scene validation.
#include <gtest/gtest.h>

#include <cmath>

#include "base/error.hpp"
#include "dem_helpers.hpp"
#include "scene/fill_cylinder.hpp"

namespace tumble {
namespace {

using testing::make_particles;
using testing::Placed;

// A Rapaport-law cylinder in MD units (R = 10, L = 20), gravity off unless overridden.
Scene cylinder_scene(std::vector<std::string> extra = {}) {
  std::vector<std::string> o = {"tumbler.shape=cylinder",
                                "tumbler.radius=10",
                                "tumbler.length=20",
                                "particles.count=1",
                                "particles.d_small=1.122",
                                "particles.d_large=2.02",
                                "particles.density=1.9099",
                                "contact.law=rapaport2007",
                                "time.dt=5e-3",
                                "gravity.g=0",
                                "protocol.mode=rest",
                                "neighbor.skin=0.5",
                                "particles.large_fraction=0.5"};
  o.insert(o.end(), extra.begin(), extra.end());
  return parse_scene("", o, "test");
}

TEST(Cylinder, EndCapsExertNoTangentialForce) {
  const Scene s = cylinder_scene({"protocol.mode=single_axis", "protocol.axis=z",
                                  "protocol.omega=0.2", "protocol.duration=1"});
  const double r = 0.561;
  // Sliding and spinning against the z = -L/2 cap, 0.05 into it.
  Particles p = make_particles(s, {{{2, 0, -10 + r - 0.05}, {1, 0.5, 0}, {0, 3, 1}}});
  Simulation sim(s, p, geometry::Protocol::single_axis('z', 0.2));
  sim.compute_forces();
  const Particles& q = sim.particles();
  EXPECT_EQ(q.f[0].x, 0.0);
  EXPECT_EQ(q.f[0].y, 0.0);
  EXPECT_NEAR(q.f[0].z, 1000 * 0.05, 1e-9);  // f_v only: no normal velocity
  EXPECT_EQ(norm(q.t[0]), 0.0);
  // The same motion against the curved wall feels friction (the control).
  Particles w = make_particles(s, {{{10 - r + 0.05, 0, 0}, {0, 0.5, 1}, {0, 3, 1}}});
  Simulation sim2(s, w, geometry::Protocol::single_axis('z', 0.2));
  sim2.compute_forces();
  EXPECT_GT(std::hypot(sim2.particles().f[0].y, sim2.particles().f[0].z), 0.1);
  EXPECT_GT(norm(sim2.particles().t[0]), 0.0);
}

TEST(Cylinder, PeriodicAxisCouplesParticlesAcrossTheEnds) {
  const Scene s = cylinder_scene({"tumbler.periodic=on"});
  const double r = 0.561;
  // Centres 0.3 from each end: 0.6 apart through the boundary, overlap 2r - 0.6.
  Particles p = make_particles(s, {{{0, -5, 10 - 0.3}, {}, {}}, {{0, -5, -10 + 0.3}, {}, {}}});
  Simulation sim(s, p, geometry::Protocol::at_rest());
  sim.compute_forces();
  const std::size_t a = testing::index_of(sim, 0), b = testing::index_of(sim, 1);
  const double expect = 1000 * (2 * r - 0.6);
  EXPECT_NEAR(sim.particles().f[a].z, -expect, 1e-9) << "pushed towards -z, away from its image";
  EXPECT_NEAR(sim.particles().f[b].z, expect, 1e-9);
  // A particle moving through the end comes back at the other one.
  Particles m = make_particles(s, {{{0, -5, 10 - 0.01}, {0, 0, 2}, {}}});
  Simulation sim2(s, m, geometry::Protocol::at_rest());
  sim2.compute_forces();
  for (int k = 0; k < 200; ++k) sim2.step();
  sim2.request_rebuild();
  sim2.step();
  EXPECT_NEAR(sim2.particles().x[0].z, -10 - 0.01 + 201 * 5e-3 * 2, 1e-9);
  EXPECT_NO_THROW(sim2.check_health());
  // Without periodicity the caps hold it in (and the control: they really are there).
  const Scene capped = cylinder_scene();
  Simulation sim3(capped, make_particles(capped, {{{0, -5, 10 - 0.6}, {0, 0, 2}, {}}}),
                  geometry::Protocol::at_rest());
  sim3.compute_forces();
  for (int k = 0; k < 400; ++k) sim3.step();
  EXPECT_LT(sim3.particles().v[0].z, 0.0) << "bounced off the cap";
}

Particles small_bed(const Scene& s) { return make_cylinder_bed(s).particles; }

TEST(Cylinder, LeapfrogAndVelocityVerletTraceTheSamePositions) {
  const std::vector<std::string> common = {"particles.count=400", "gravity.g=5",
                                           "particles.size_spread=0.2"};
  Scene vv = cylinder_scene(common);
  std::vector<std::string> lf_o = common;
  lf_o.push_back("time.integrator=leapfrog");
  Scene lf = cylinder_scene(lf_o);
  const Particles bed = small_bed(vv);
  Simulation a(vv, bed, geometry::Protocol::single_axis('z', 0.2));
  Simulation b(lf, bed, geometry::Protocol::single_axis('z', 0.2));
  a.compute_forces();
  b.compute_forces();
  for (int k = 0; k < 600; ++k) {
    a.step();
    b.step();
  }
  double worst = 0;
  for (std::size_t i = 0; i < bed.size(); ++i) {
    const std::size_t j = testing::index_of(b, a.particles().id[i]);
    worst = std::max(worst, norm(a.particles().x[i] - b.particles().x[j]));
  }
  // Same algorithm, different rounding: the particles fall ~1.2 d in these 600 steps.
  EXPECT_LT(worst, 1e-9);
  // The velocities differ by half a kick: leapfrog reports v(t - dt/2).
  const std::size_t i = 0, j = testing::index_of(b, a.particles().id[0]);
  const Vec3 half_kick = a.particles().v[i] - b.particles().v[j];
  EXPECT_NEAR(half_kick.y, -0.5 * 5e-3 * 5, 0.05) << "about half a step of gravity";
}

TEST(Cylinder, FillPlacesEveryParticleInsideWithoutOverlap) {
  for (const char* start : {"mixed", "large_zneg"}) {
    const Scene s = cylinder_scene(
        {"particles.count=1500", "particles.size_spread=0.2", std::string("fill.start=") + start});
    const CylinderBed bed = make_cylinder_bed(s);
    const Particles& p = bed.particles;
    ASSERT_EQ(p.size(), 1500u);
    int large = 0;
    double z_large_max = -1e9, z_small_min = 1e9;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double r = p.radius[i], rs = r * bed.shrink;
      EXPECT_LE(std::hypot(p.x[i].x, p.x[i].y) + rs, 10 + 1e-12);
      EXPECT_LE(std::fabs(p.x[i].z) + rs, 10 + 1e-12);
      const double dn = p.species[i] == 1 ? 2.02 : 1.122;
      EXPECT_LE(2 * r, dn + 1e-12);
      EXPECT_GE(2 * r, dn - 0.2 - 1e-12);
      for (std::size_t j = i + 1; j < p.size(); ++j)
        ASSERT_GE(norm(p.x[i] - p.x[j]), (r + p.radius[j]) * bed.shrink - 1e-12);
      if (p.species[i] == 1) {
        ++large;
        z_large_max = std::max(z_large_max, p.x[i].z);
      } else {
        z_small_min = std::min(z_small_min, p.x[i].z);
      }
    }
    // Equal volumes by the nominal sizes: the number fraction of big particles is 1/(1 + 1.8^3).
    EXPECT_NEAR(large / 1500.0, 1 / (1 + std::pow(2.02 / 1.122, 3)), 1e-3);
    if (std::string(start) == "large_zneg") {
      EXPECT_LT(z_large_max, z_small_min);
    }
  }
}

TEST(Cylinder, SceneValidationNamesTheKey) {
  auto message = [](std::vector<std::string> o) {
    try {
      cylinder_scene(o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message({"particles.count=0"}).find("particles.count"), std::string::npos);
  EXPECT_NE(message({"protocol.mode=biaxial"}).find("protocol.mode"), std::string::npos);
  EXPECT_NE(message({"protocol.mode=single_axis", "protocol.axis=x", "protocol.duration=1"})
                .find("protocol.axis"),
            std::string::npos);
  EXPECT_NE(message({"particles.count=200000"}).find("does not fit"), std::string::npos);
  EXPECT_NE(message({"time.dt=0.05"}).find("stability bound"), std::string::npos);
  EXPECT_NE(message({"tumbler.length=3"}).find("tumbler.length"), std::string::npos);
  EXPECT_EQ(message({}), "accepted");
  // The Yu law tabulates two sizes: a size spread needs the Rapaport law.
  EXPECT_NE(message({"contact.law=yu2022", "particles.size_spread=0.1"}).find("size_spread"),
            std::string::npos);
}

}  // namespace
}  // namespace tumble
