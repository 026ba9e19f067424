// The Yu 2022 kernel on its own: coefficients from (e, t_c), the Coulomb cap, and the spring kept
// in the tangent plane.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/yu2022.hpp"

using namespace tumble;
using namespace tumble::contact;

TEST(Yu2022Law, CoefficientsMatchTheBenchmarkParameterFile) {
  // the LIGGGHTS reference bed's contact table (docs/performance.md): small-small m_eff
  // = 5.235988e-06 kg, kn = 207.114697 N/m, kt = 59.175628 N/m, 2 γ_n = 557.048269 1/s.
  const Yu2022Pair p = yu2022_pair(0.87, 5e-4, 0.0, 0.6, 5.235988e-06);
  EXPECT_NEAR(p.kn, 207.114697, 1e-5);
  EXPECT_NEAR(p.kt, 59.175628, 1e-5);
  EXPECT_NEAR(p.dn / 5.235988e-06, 557.048269, 1e-5);
  EXPECT_EQ(p.dt, 0.0);
}

TEST(Yu2022Law, TangentialForceIsCappedAtMuFn) {
  const Yu2022Pair p = yu2022_pair(0.87, 5e-4, 10.0, 0.6, 1e-5);
  const Vec3 n{0, 1, 0};
  Vec3 spring{}, ft;
  const double overlap = 1e-5;
  const Vec3 vrel{3.0, 0, 0};  // fast sliding
  const Vec3 f = yu2022_force<true>(p, n, overlap, vrel, spring, 1e-5, ft);
  const double fn = dot(f, n);
  EXPECT_NEAR(norm(ft), 0.6 * fn, 1e-12 * fn);
  EXPECT_LT(ft.x, 0.0);  // opposes sliding
  // The stored spring is the one that reproduces the capped force.
  const Vec3 again = -(p.kt * spring + p.dt * vrel);
  EXPECT_NEAR(again.x, ft.x, 1e-12 * std::fabs(ft.x));
}

TEST(Yu2022Law, SpringIsProjectedIntoTheTangentPlane) {
  const Yu2022Pair p = yu2022_pair(0.87, 5e-4, 0.0, 100.0, 1e-5);
  const double a = 0.3;
  const Vec3 n{std::sin(a), std::cos(a), 0};
  Vec3 spring{1e-6, 0, 0}, ft;
  yu2022_force<true>(p, n, 1e-5, Vec3{}, spring, 1e-5, ft);
  EXPECT_NEAR(dot(spring, n), 0.0, 1e-20);
  EXPECT_NEAR(norm(spring), 1e-6 * std::cos(a), 1e-18);  // projection, as LAMMPS/LIGGGHTS
}

TEST(Yu2022Law, FrictionlessKernelHasNoTangentialForce) {
  const Yu2022Pair p = yu2022_pair(0.87, 5e-4, 0.0, 0.6, 1e-5);
  Vec3 spring{}, ft;
  const Vec3 f = yu2022_force<false>(p, {0, 1, 0}, 1e-5, {1, -0.1, 0}, spring, 1e-5, ft);
  EXPECT_EQ(f.x, 0.0);
  EXPECT_EQ(norm(ft), 0.0);
  EXPECT_NEAR(f.y, p.kn * 1e-5 + p.dn * 0.1, 1e-15);
}
