// The optimised pair loop (engine/contact_lanes.hpp: touching pairs scanned four at a time, forces
// on AVX2 lanes) against the plain loop, kept as the reference (TUMBLE_PLAIN_KERNELS=1). Each lane
// does the plain kernel's operations in its order, without fused multiply-adds, so on a generic
// build the two agree bitwise, step after step; a -march=native build lets the compiler fuse
// multiply-adds differently in the two, so there they must agree to round-off in one force
// evaluation. The Yu and Rapaport laws have lane kernels; Hertz-Mindlin runs the plain loop, and
// the test checks that it says so.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>

#include "dem_helpers.hpp"
#include "scene/fill.hpp"
#include "scene/fill_cylinder.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {

// A dense bed filled as a loose lattice, dropped and stirred: every particle gets a random
// velocity and spin, so that contacts open, close and slide during the run.
Scene bed_scene(const std::vector<std::string>& extra) { return rotating_bed_scene(extra, 0.35); }

// Speeds of up to 5% of a diameter per collision time (0.05 m/s for the SI beds, 0.5 for the
// MD-unit cylinder), spins of the same surface speed.
Particles agitated(const Scene& s) {
  Particles p = s.cylinder() ? make_cylinder_bed(s).particles : make_bed(s);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const double speed = s.law == "rapaport2007" ? 0.5 : 0.05, spin = speed / (0.5 * s.d_small);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.v[i] = {speed * u(rng), speed * u(rng), speed * u(rng)};
    p.w[i] = {spin * u(rng), spin * u(rng), spin * u(rng)};
  }
  return p;
}

struct Run {
  Particles state;
  std::string kernel;
};

// `steps` steps from the stirred bed with the plain or the optimised loop.
Run run(const Scene& s, bool plain, int steps) {
  if (plain)
    setenv("TUMBLE_PLAIN_KERNELS", "1", 1);
  else
    unsetenv("TUMBLE_PLAIN_KERNELS");
  Simulation sim(s, agitated(s), geometry::Protocol::single_axis('z', s.omega()));
  unsetenv("TUMBLE_PLAIN_KERNELS");
  sim.compute_forces();
  for (int k = 0; k < steps; ++k) sim.step();
  return {sim.particles(), sim.pair_kernel_name()};
}

bool cpu_has_lanes() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

#ifdef __FMA__
constexpr bool kFusedMultiplyAdd = true;  // -march=native on a CPU with FMA
#else
constexpr bool kFusedMultiplyAdd = false;
#endif

// Largest difference of a Vec3 field relative to the field's largest magnitude.
double relative_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, norm(a[i] - b[i]));
    scale = std::max(scale, norm(a[i]));
  }
  return scale > 0 ? diff / scale : diff;
}

void expect_lanes_equal_plain(const Scene& s) {
  const Run plain = run(s, true, 0);
  ASSERT_STREQ(plain.kernel.c_str(), "plain");
  const Run lanes0 = run(s, false, 0);
  if (!cpu_has_lanes()) {  // nothing else to run on this CPU
    EXPECT_STREQ(lanes0.kernel.c_str(), "plain");
    return;
  }
  ASSERT_STREQ(lanes0.kernel.c_str(), "avx2 lanes");
  // One force evaluation of the stirred bed (both sort the particles the same way).
  ASSERT_EQ(plain.state.id, lanes0.state.id);
  EXPECT_LE(relative_difference(plain.state.f, lanes0.state.f), 1e-13);
  EXPECT_LE(relative_difference(plain.state.t, lanes0.state.t), 1e-13);
  if (kFusedMultiplyAdd) return;  // beyond one evaluation, round-off differences grow
  // Generic build: bitwise, including 2,000 steps of opening, closing and sliding contacts.
  const Run a = run(s, true, 2000), b = run(s, false, 2000);
  ASSERT_EQ(a.state.id, b.state.id);
  for (std::size_t i = 0; i < a.state.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      ASSERT_EQ(a.state.x[i][d], b.state.x[i][d]) << "particle " << a.state.id[i];
      ASSERT_EQ(a.state.v[i][d], b.state.v[i][d]) << "particle " << a.state.id[i];
      ASSERT_EQ(a.state.w[i][d], b.state.w[i][d]) << "particle " << a.state.id[i];
      ASSERT_EQ(a.state.f[i][d], b.state.f[i][d]) << "particle " << a.state.id[i];
      ASSERT_EQ(a.state.t[i][d], b.state.t[i][d]) << "particle " << a.state.id[i];
    }
}

}  // namespace

TEST(LaneKernels, YuWithFrictionTwoSpecies) { expect_lanes_equal_plain(bed_scene({})); }

TEST(LaneKernels, YuWithFrictionOneSpecies) {
  expect_lanes_equal_plain(bed_scene({"particles.large_fraction=0"}));
}

TEST(LaneKernels, YuFrictionless) {
  expect_lanes_equal_plain(bed_scene({"contact.friction=0", "contact.wall_friction=0"}));
}

TEST(LaneKernels,
     YuSlidingEverywhere) {  // a low friction coefficient: the Coulomb cap on most lanes
  expect_lanes_equal_plain(bed_scene({"contact.friction=0.05"}));
}

TEST(LaneKernels, YuInAnAxiallyPeriodicCylinder) {  // nearest images across the period
  expect_lanes_equal_plain(
      bed_scene({"tumbler.shape=cylinder", "tumbler.length=0.012", "tumbler.periodic=on",
                 "protocol.axis=z", "particles.count=600"}));
}

// The Rapaport cylinder's law in MD units (tests/test_cylinder.cpp's scene, filled and stirred).
Scene rapaport_scene(const std::vector<std::string>& extra) {
  std::vector<std::string> o = {"tumbler.shape=cylinder",
                                "tumbler.radius=9",
                                "tumbler.length=12",
                                "particles.count=500",
                                "particles.d_small=1.122",
                                "particles.d_large=2.02",
                                "particles.density=1.9099",
                                "contact.law=rapaport2007",
                                "time.dt=5e-3",
                                "gravity.g=5",
                                "protocol.mode=single_axis",
                                "protocol.axis=z",
                                "protocol.omega=0.2",
                                "protocol.duration=100",
                                "neighbor.skin=0.5",
                                "particles.large_fraction=0.5"};
  o.insert(o.end(), extra.begin(), extra.end());
  return parse_scene("", o, "lanes_rapaport");
}

TEST(LaneKernels, RapaportWithFriction) {  // frictional damping and the restoring spring k_g
  expect_lanes_equal_plain(rapaport_scene({"contact.kg=500"}));
}

TEST(LaneKernels, RapaportRatchetAndCapsActive) {  // a small ratchet resets u on many lanes
  expect_lanes_equal_plain(rapaport_scene({"contact.kg=5000", "contact.ratchet=0.002"}));
}

TEST(LaneKernels, RapaportPeriodicWithoutRestoringSpring) {
  expect_lanes_equal_plain(rapaport_scene({"tumbler.periodic=on", "contact.kg=0"}));
}

TEST(LaneKernels, RapaportFrictionless) {
  expect_lanes_equal_plain(rapaport_scene({"contact.mu_max=0"}));
}

TEST(LaneKernels, OtherLawsRunThePlainLoop) {
  const Scene s = bed_scene({"contact.law=hertz_mindlin", "time.dt=1e-6"});
  EXPECT_STREQ(run(s, false, 0).kernel.c_str(), "plain");
}
