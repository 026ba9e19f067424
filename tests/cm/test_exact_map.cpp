// The exact per-phase CM map against the velocity field integrated with event location.
#include <gtest/gtest.h>

#include <random>

#include "cm/exact_map.hpp"
#include "cm/integrator.hpp"
#include "cm/protocol.hpp"
#include "cm_test_util.hpp"

namespace {
using namespace tumble::cm;
using tumble::cm::test::random_bed_point;
constexpr double kEps = 0.15;

// One phase (57 deg) and a whole revolution (several layer transits), from points anywhere in
// the bed, bulk and layer alike.
TEST(ExactMap, AgreesWithIntegratedFieldTo1e6) {
  std::mt19937_64 rng(11);
  long events = 0;
  for (double t : {57 * kPi / 180, 2 * kPi}) {
    for (int k = 0; k < 150; ++k) {
      const Vec3 p = random_bed_point(rng, 0.05, 0.999);
      IntegratorStats st;
      const Vec3 a = flow_z_exact(p, t, kEps);
      const Vec3 b = flow_z_integrated(p, t, kEps, {}, &st);
      events += st.events;
      EXPECT_LT((a - b).norm(), 1e-6) << "p = " << p.transpose() << ", t = " << t;
    }
  }
  EXPECT_GT(events, 100);  // the comparison really crossed the interface many times
}

TEST(ExactMap, WholeProtocolAgreesWithIntegratedField) {
  const Protocol exact = Protocol::degrees(57, 57);
  const Protocol integ = Protocol::degrees(57, 57, kEps, FlowModel::Integrated);
  std::mt19937_64 rng(12);
  for (int k = 0; k < 40; ++k) {
    const Vec3 p = random_bed_point(rng);
    EXPECT_LT((iterate(exact, p, 3) - iterate(integ, p, 3)).norm(), 1e-6);
  }
}

// Every layer transit lasts pi eps and ends on the bulk circle it started from (docs/cm.md).
TEST(ExactMap, LayerTransitLastsPiEpsAndRejoinsItsCircle) {
  for (double z : {0.0, 0.3, -0.7})
    for (double a : {0.05, 0.4, 0.9 * std::sqrt(1 - z * z)}) {
      const Vec3 entry = layer_point(a, 0, z, kEps);
      const Vec3 exit(a, -layer_depth(a, z, kEps), z);
      EXPECT_LT((flow_z_exact(entry, kPi * kEps, kEps) - exit).norm(), 1e-14);
      EXPECT_LT((flow_z_integrated(entry, kPi * kEps, kEps) - exit).norm(), 1e-8);
      EXPECT_TRUE(in_layer(flow_z_exact(entry, 0.999 * kPi * kEps, kEps), kEps));
      EXPECT_NEAR(std::hypot(entry.x(), entry.y()), std::hypot(exit.x(), exit.y()), 1e-15);
    }
}

TEST(ExactMap, InverseUndoesThePeriodMap) {
  for (FlowModel m : {FlowModel::Exact, FlowModel::Pwi}) {
    const Protocol pr = Protocol::degrees(57, 68, kEps, m);
    std::mt19937_64 rng(13);
    for (int k = 0; k < 200; ++k) {
      const Vec3 p = random_bed_point(rng);
      EXPECT_LT((inverse_period_map(pr, period_map(pr, p)) - p).norm(), 1e-12);
    }
  }
}

}  // namespace
