// The Rapaport 2007 contact law on its own: the ratchet, the caps of f_s and f_g, the normal part.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/rapaport2007.hpp"

namespace tumble {
namespace {

contact::Rapaport2007Pair paper_pair() {
  contact::Rapaport2007Pair p;
  p.kn = 1000;
  p.gn = 5;
  p.gs = 2;
  p.mu = 0.1;  // the paper's small-small value: 0.5 * 2 / 10
  p.kg = 500;
  p.ratchet = 0.1;
  return p;
}

const Vec3 kN{0, 0, 1};

TEST(RapaportLaw, NormalForceIsSpringPlusDashpot) {
  const auto p = paper_pair();
  Vec3 u{}, ft;
  const Vec3 f = contact::rapaport2007_force<true>(p, kN, 0.02, {0, 0, -0.3}, u, 5e-3, ft);
  EXPECT_NEAR(f.z, 1000 * 0.02 + 5 * 0.3, 1e-12);
  EXPECT_EQ(ft.x, 0.0);
  EXPECT_EQ(ft.y, 0.0);
}

TEST(RapaportLaw, RatchetResetsDisplacementBeyondTheLimit) {
  auto p = paper_pair();
  p.mu = 1e9;  // no cap: see u itself through f_g
  p.gs = 0;
  const double dt = 5e-3, vs = 1.5;  // |u| grows by 7.5e-3 per step
  Vec3 u{}, ft;
  int resets = 0;
  double prev = 0;
  for (int k = 1; k <= 40; ++k) {
    contact::rapaport2007_force<true>(p, kN, 0.01, {vs, 0, 0}, u, dt, ft);
    ASSERT_LE(norm(u), 0.1) << "step " << k;
    EXPECT_NEAR(ft.x, -p.kg * u.x, 1e-9);
    if (norm(u) < prev) {
      ++resets;
      EXPECT_EQ(norm(u), 0.0) << "a reset sets u to zero";
      // 0.1 / 7.5e-3 = 13.3: the 14th accumulation exceeds the limit.
      EXPECT_EQ(k % 14, 0) << "reset at step " << k;
    }
    prev = norm(u);
  }
  EXPECT_EQ(resets, 2);
}

TEST(RapaportLaw, FrictionalDampingIsCappedByCoulomb) {
  auto p = paper_pair();
  p.kg = 0;
  const double overlap = 0.01, fn = 1000 * overlap;  // vn = 0
  for (double vs : {0.01, 0.1, 0.4, 1.0, 10.0}) {
    Vec3 u{}, ft;
    contact::rapaport2007_force<true>(p, kN, overlap, {0, vs, 0}, u, 5e-3, ft);
    const double expect = std::min(p.gs * vs, p.mu * fn);
    EXPECT_NEAR(norm(ft), expect, 1e-12) << "v_s = " << vs;
    EXPECT_LT(ft.y, 0.0) << "opposes sliding";
  }
}

TEST(RapaportLaw, RestoringForceIsCappedByCoulomb) {
  auto p = paper_pair();
  p.gs = 0;
  const double overlap = 0.01, fn = 1000 * overlap;
  for (double ux : {1e-4, 1e-3, 0.05}) {
    Vec3 u{ux, 0, 0}, ft;
    contact::rapaport2007_force<true>(p, kN, overlap, {0, 0, 0}, u, 5e-3, ft);
    EXPECT_NEAR(norm(ft), std::min(p.kg * ux, p.mu * fn), 1e-12) << "u = " << ux;
    EXPECT_LE(norm(ft), p.mu * fn * (1 + 1e-12));
  }
}

TEST(RapaportLaw, EachTransverseTermIsCappedSeparately) {
  // The paper caps f_s and f_g each at μ|f_n|: together they may reach 2 μ|f_n|.
  const auto p = paper_pair();
  const double overlap = 0.01, fn = 1000 * overlap;
  Vec3 u{0.05, 0, 0}, ft;
  contact::rapaport2007_force<true>(p, kN, overlap, {1.0, 0, 0}, u, 5e-3, ft);
  EXPECT_NEAR(norm(ft), 2 * p.mu * fn, 1e-9);
}

TEST(RapaportLaw, FrictionlessInstanceHasNoTransverseForce) {
  const auto p = paper_pair();
  Vec3 u{}, ft;
  const Vec3 f = contact::rapaport2007_force<false>(p, kN, 0.01, {1, 1, -0.1}, u, 5e-3, ft);
  EXPECT_EQ(f.x, 0.0);
  EXPECT_EQ(f.y, 0.0);
  EXPECT_EQ(norm(u), 0.0);
}

}  // namespace
}  // namespace tumble
