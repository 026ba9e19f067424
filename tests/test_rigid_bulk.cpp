// fidelity.bulk = "rigid" (engine/rigid_bulk.cpp): with nothing frozen it is the dynamic engine
// bit for bit; a bed turning as a solid freezes below its surface and the frozen particles follow
// the wall's rotation exactly (also when read between rebuilds, which changes nothing); a bed
// tilted below its repose angle freezes and stays put (whole, surface included, below a still
// slope); one tilted above it thaws and flows as the dynamic bed does (also when it froze whole); a
// change of the protocol's segment thaws the bed; a restart continues bitwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <vector>

#include "bed_fixture.hpp"
#include "engine/simulation.hpp"
#include "io/checkpoint.hpp"
#include "run/realization.hpp"

using namespace tumble;
using namespace tumble::testing;

namespace {

Scene rigid_scene(std::vector<std::string> more = {}) {
  std::vector<std::string> o = {"protocol.mode=single_axis", "fidelity.bulk=rigid"};
  o.insert(o.end(), more.begin(), more.end());
  return tiny_scene(o);
}

// Frozen among the first `count` particles (a simulation's own: its ghosts follow them).
std::size_t count_frozen(const Particles& p, std::size_t count) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < count; ++i) n += p.bulk_state[i] < 0;
  return n;
}
std::size_t count_frozen(const Simulation& sim) {
  return count_frozen(sim.particles(), sim.local_count());
}
std::size_t count_frozen(const Particles& p) { return count_frozen(p, p.size()); }

// The settled tiny bed tilted by `deg` about z (positions only: it is at rest).
Particles tilted(Particles bed, double deg) {
  const Mat3 q = Mat3::rotation({0, 0, 1}, deg2rad(deg));
  for (auto& x : bed.x) x = q * x;
  return bed;
}

// Mean displacement over the particles, in small diameters, from positions by id.
double mean_displacement(const Particles& p, const std::vector<Vec3>& start, double d) {
  double mean = 0;
  for (std::size_t i = 0; i < p.size(); ++i) mean += norm(p.x[i] - start[p.id[i]]);
  return mean / static_cast<double>(p.size()) / d;
}

std::vector<Vec3> by_id(const Particles& p) {
  std::vector<Vec3> x(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) x[p.id[i]] = p.x[i];
  return x;
}

// How many of two lists of positions (by id, as by_id gives) differ in any bit.
std::size_t differing(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  EXPECT_EQ(a.size(), b.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    differ += a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z;
  return differ;
}

}  // namespace

TEST(RigidBulk, WithNothingFrozenItIsTheDynamicEngineBitForBit) {
  // A dwell longer than the run: no particle ever freezes, and the rigid path (its integrator,
  // its freeze/thaw passes and forced rebuilds) must give the dynamic trajectory. (The filtered
  // pair list is then not built; with frozen particles it is checked by the tests below and by
  // the rank tests.)
  const Scene dyn = tiny_scene({"protocol.mode=single_axis", "protocol.rpm=10"});
  const Scene rig = rigid_scene({"protocol.rpm=10", "fidelity.bulk_dwell=1000"});
  const Particles bed = tiny_settled_bed();
  Simulation a(dyn, bed, geometry::Protocol::single_axis('x', dyn.omega()));
  Simulation b(rig, bed, geometry::Protocol::single_axis('x', rig.omega()));
  ASSERT_FALSE(a.rigid_bulk());
  ASSERT_TRUE(b.rigid_bulk());
  a.compute_forces();
  b.compute_forces();
  for (int k = 0; k < 3000; ++k) {
    a.step();
    b.step();
  }
  EXPECT_GT(b.rebuilds(), 2u);
  EXPECT_EQ(count_frozen(b), 0u);
  const Particles &p = a.particles(), &q = b.particles();
  ASSERT_EQ(p.size(), q.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int d = 0; d < 3; ++d)
      differ += p.x[i][d] != q.x[i][d] || p.v[i][d] != q.v[i][d] || p.w[i][d] != q.w[i][d];
  EXPECT_EQ(differ, 0u);
  // The dynamic engine holds none of the rigid bulk's columns (field::kRigidOnly): exactly their
  // 52 bytes per particle less state than the rigid one's, and its checkpoint rows are as before.
  EXPECT_TRUE(p.bulk_state.empty() && p.bulk_anchor.empty() && p.bulk_gravity.empty());
  EXPECT_EQ(q.bulk_state.size(), q.size());
  EXPECT_EQ(b.memory().particles - a.memory().particles,
            p.size() * (sizeof(std::int32_t) + 2 * sizeof(Vec3)));
}

TEST(RigidBulk, TurningBedFreezesBelowItsSurfaceAndTheFrozenTurnWithTheWall) {
  // 3 rpm about x for 0.4 s (7 degrees: the bed still turns as a solid).
  const Scene s = rigid_scene();
  const geometry::Protocol turn = geometry::Protocol::single_axis('x', s.omega());
  Simulation sim(s, tiny_settled_bed(), turn);
  sim.compute_forces();
  // Dormant springs are turned at each freeze/thaw pass: end both runs of steps with one (a
  // forced rebuild), so that they are up to date when compared below.
  for (int k = 0; k < 20000; ++k) {
    if (k == 19999) sim.request_rebuild();
    sim.step();
  }
  const Particles& p = sim.particles();
  const std::size_t frozen = count_frozen(sim);
  // The bed is 5 d_large deep at its centre, the margin 2 d_large.
  EXPECT_GT(static_cast<double>(frozen), 0.2 * static_cast<double>(p.size()));
  EXPECT_NEAR(sim.frozen_fraction(), static_cast<double>(frozen) / p.size(), 0.02);
  // No frozen particle within the margin of the bed's top.
  double top = -1e300;
  for (std::size_t i = 0; i < p.size(); ++i) top = std::max(top, p.x[i].y + p.radius[i]);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.bulk_state[i] < 0) {
      ASSERT_LT(p.x[i].y + p.radius[i], top - s.bulk_margin * s.d_large);
    }

  // Particles frozen now and after 500 more steps (fewer than the dwell: a thawed one cannot
  // freeze again in between) moved exactly with the wall: x(t2) = Q(t2) Q(t1)^T x(t1).
  const double t1 = sim.time();
  std::vector<Vec3> x1(p.size());
  std::vector<int> was(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    x1[p.id[i]] = p.x[i];
    was[p.id[i]] = p.bulk_state[i] == -1;
  }
  neighbor::ContactHistory h1;
  sim.save_contacts(h1);
  for (int k = 0; k < 500; ++k) {
    if (k == 499) sim.request_rebuild();
    sim.step();
  }
  ASSERT_LT(500, s.bulk_dwell / s.time_step());
  const Mat3 q1 = turn.orientation(t1), q2 = turn.orientation(sim.time());
  const Vec3 omega = turn.omega(sim.time());
  std::size_t checked = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!was[p.id[i]] || p.bulk_state[i] != -1) continue;
    const Vec3 expect = q2 * q1.tmul(x1[p.id[i]]);
    ASSERT_LT(norm(p.x[i] - expect), 1e-15 * 500 * s.radius) << "particle " << p.id[i];
    ASSERT_LT(norm(p.v[i] - cross(omega, p.x[i])), 1e-15);
    ASSERT_EQ(p.w[i].x, omega.x);
    ++checked;
  }
  EXPECT_GT(checked, frozen / 2);
  // The dormant springs of pairs frozen throughout turned with the wall: the same in the
  // tumbler's frame, Q(t2)^T h(t2) = Q(t1)^T h(t1).
  neighbor::ContactHistory h2;
  sim.save_contacts(h2);
  std::vector<int> now(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) now[p.id[i]] = p.bulk_state[i] == -1;
  std::size_t springs = 0;
  for (const auto& r : h2.records()) {
    if (!was[r.lo] || !was[r.hi] || !now[r.lo] || !now[r.hi]) continue;
    const auto before = h1.lookup(r.lo, r.hi);
    const Vec3 a = q1.tmul({before[0], before[1], before[2]});
    const Vec3 b = q2.tmul({r.history[0], r.history[1], r.history[2]});
    ASSERT_LE(norm(a - b), 1e-12 * norm(a)) << "pair " << r.lo << ", " << r.hi;
    ++springs;
  }
  EXPECT_GT(springs, 100u);
}

TEST(RigidBulk, ReadingTheStateBetweenRebuildsChangesNothing) {
  // A frozen particle that no moving one touches is turned with the wall only when something
  // reads the state (or at the next rebuild), from where it was at the last rebuild. Two runs of
  // the same turning bed, one read at every step, one never: bitwise the same at the end, and
  // whenever read, the frozen particles are where the wall's rotation has carried them.
  const Scene s = rigid_scene();
  const geometry::Protocol turn = geometry::Protocol::single_axis('x', s.omega());
  Simulation read(s, tiny_settled_bed(), turn), quiet(s, tiny_settled_bed(), turn);
  read.compute_forces();
  quiet.compute_forces();
  std::vector<Vec3> last;
  double last_time = 0;
  std::size_t checked = 0;
  for (int k = 0; k < 8000; ++k) {
    read.step();
    quiet.step();
    const Particles& p = read.particles();
    // Every 97th step, against the positions read 97 steps before (of the particles frozen at
    // both reads; fewer steps than the dwell, so frozen at both means frozen throughout).
    if (k % 97 != 0) continue;
    ASSERT_LT(97, s.bulk_dwell / s.time_step());
    std::vector<Vec3> now(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      now[p.id[i]] = p.bulk_state[i] < 0 ? p.x[i] : Vec3{1e300, 0, 0};
    if (!last.empty()) {
      const Mat3 q1 = turn.orientation(last_time), q2 = turn.orientation(read.time());
      for (std::size_t id = 0; id < now.size(); ++id) {
        if (now[id].x == 1e300 || last[id].x == 1e300) continue;
        ASSERT_LT(norm(now[id] - q2 * q1.tmul(last[id])), 1e-13 * s.radius) << "id " << id;
        ++checked;
      }
    }
    last = now;
    last_time = read.time();
  }
  EXPECT_GT(checked, 10000u);
  EXPECT_GT(read.frozen_fraction(), 0.2);
  const Particles &p = read.particles(), &q = quiet.particles();
  ASSERT_EQ(p.size(), q.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_EQ(p.id[i], q.id[i]);
    ASSERT_EQ(p.bulk_state[i], q.bulk_state[i]) << "particle " << p.id[i];
    for (const auto& [a, b] : {std::pair{p.x[i], q.x[i]}, {p.v[i], q.v[i]}, {p.w[i], q.w[i]}}) {
      ASSERT_EQ(a.x, b.x) << "particle " << p.id[i];
      ASSERT_EQ(a.y, b.y) << "particle " << p.id[i];
      ASSERT_EQ(a.z, b.z) << "particle " << p.id[i];
    }
  }
}

TEST(RigidBulk, GravitysTurnThawsTheFrozenAndTheyRefreeze) {
  // 3 rpm about x for 0.4 s (7.2 degrees, the bed turning as a solid). The first particles freeze
  // after the dwell (0.9 degrees); with bulk_thaw_gravity = 0.05 (a turn of 2.9 degrees since
  // freezing) they thaw near 3.8 degrees and refreeze a dwell later; without the rule (default)
  // they stay frozen while gravity, seen from the tumbler, turns by 6 degrees (0.11 g).
  auto run = [](const std::vector<std::string>& more, double& worst, std::size_t& frozen) {
    const Scene s = rigid_scene(more);
    const geometry::Protocol turn = geometry::Protocol::single_axis('x', s.omega());
    Simulation sim(s, tiny_settled_bed(), turn);
    sim.compute_forces();
    for (int k = 0; k < 20000; ++k) {
      if (k == 19999) sim.request_rebuild();  // end on a freeze/thaw pass
      sim.step();
    }
    const Vec3 g_now = turn.orientation(sim.time()).tmul({0, -1, 0});
    const Particles& p = sim.particles();
    worst = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.bulk_state[i] < 0) worst = std::max(worst, norm(g_now - p.bulk_gravity[i]));
    frozen = count_frozen(sim);
    return sim.gravity_thaws();
  };
  double worst_off = 0, worst_on = 0;
  std::size_t frozen_off = 0, frozen_on = 0;
  EXPECT_EQ(run({}, worst_off, frozen_off), 0u);
  EXPECT_GT(worst_off, 0.1);  // the rule, on, would have thawed them
  const std::uint64_t thawed = run({"fidelity.bulk_thaw_gravity=0.05"}, worst_on, frozen_on);
  EXPECT_GT(static_cast<double>(thawed), 0.5 * static_cast<double>(frozen_off));
  EXPECT_LE(worst_on, 0.05);
  std::cout << "gravity's turn: rule off: frozen " << frozen_off << ", largest change " << worst_off
            << " g; rule at 0.05 g: " << thawed << " thawed, frozen " << frozen_on
            << ", largest change " << worst_on << " g\n";
  EXPECT_GT(static_cast<double>(frozen_on), 0.5 * static_cast<double>(frozen_off));  // refrozen
}

TEST(RigidBulk, BedTiltedBelowReposeFreezesAndStaysPut) {
  // The tumbler at rest (Ω = 0: the frozen particles do not move at all), the bed tilted 18°,
  // below its ~27° repose angle, for 0.5 s: most of the bed below the surface layer freezes, and
  // the bed moves no more than the dynamic one does (Tumbler.BedAtRestStaysAtRest...: < 0.25 d).
  // A margin of 2 d_large: this bed is only ~6 d_large deep, and with the default 3 less than a
  // quarter of it lies below the margin (472 of 2,085 froze).
  const Scene s = rigid_scene({"fidelity.bulk_margin=2"});
  const Particles bed = tilted(tiny_settled_bed(), 18);
  const std::vector<Vec3> start = by_id(bed);
  Simulation sim(s, bed, geometry::Protocol::at_rest());
  sim.compute_forces();
  for (int k = 0; k < 25000; ++k) sim.step();
  const Particles& p = sim.particles();
  EXPECT_GT(static_cast<double>(count_frozen(sim)), 0.25 * static_cast<double>(p.size()));
  EXPECT_LT(mean_displacement(p, start, s.d_small), 0.25);
  EXPECT_LT(sim.rms_speed(), 1e-3);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.bulk_state[i] == -1) {
      ASSERT_EQ(norm(p.v[i]), 0.0);  // carried by a wall at rest
    }
}

TEST(RigidBulk, BelowTheStillSlopeTheWholeBedFreezesAndAboveItTheSurfaceStaysMoving) {
  // fidelity.bulk_still_slope: the bed tilted 18° at rest (below its ~27° repose angle; its
  // surface then lies at ~12°, the settled tiny bed's own being ~6° the other way) with a still
  // slope of 25° freezes whole, surface layer included (the bed tilted just below the
  // repose angle: all frozen, nothing moves relative to the wall), and stays put. With 10°,
  // below the surface's slope, the key changes nothing: the same run bit for bit as without it.
  const Particles bed = tilted(tiny_settled_bed(), 18);
  const std::vector<Vec3> start = by_id(bed);
  auto run = [&](std::vector<std::string> keys) {
    Simulation sim(rigid_scene(keys), bed, geometry::Protocol::at_rest());
    sim.compute_forces();
    for (int k = 0; k < 25000; ++k) sim.step();
    return sim.particles();
  };
  const Particles still = run({"fidelity.bulk_still_slope=25"});
  EXPECT_EQ(count_frozen(still), still.size());
  EXPECT_LT(mean_displacement(still, start, tiny_scene().d_small), 0.25);
  const Particles margin = run({}), steeper = run({"fidelity.bulk_still_slope=10"});
  EXPECT_LT(count_frozen(margin), still.size() / 2);  // the default margin of 3 d_large holds
  EXPECT_EQ(count_frozen(steeper), count_frozen(margin));
  EXPECT_EQ(differing(by_id(steeper), by_id(margin)), 0u);
  std::printf("tilted 18 deg at rest: frozen %zu of %zu (still slope 25), %zu (10 and none)\n",
              count_frozen(still), still.size(), count_frozen(margin));
}

namespace {
// Freeze the level bed at rest (with `keys`), then tilt it (frozen states and all) by 50°, and run
// it rigid and dynamic from that tilt: what must flow must thaw and flow as the dynamic bed does.
void expect_tilted_bed_thaws_and_flows(const std::vector<std::string>& keys,
                                       double frozen_share_before) {
  const Scene s = rigid_scene(keys);
  Simulation level(s, tiny_settled_bed(), geometry::Protocol::at_rest());
  level.compute_forces();
  for (int k = 0; k < 20000; ++k) level.step();
  const std::size_t frozen_before = count_frozen(level);
  ASSERT_GT(static_cast<double>(frozen_before),
            frozen_share_before * static_cast<double>(level.local_count()));
  const Particles bed = tilted(level.particles(), 50);
  const std::vector<Vec3> start = by_id(bed);
  std::vector<int> was_frozen(bed.size(), 0);
  for (std::size_t i = 0; i < bed.size(); ++i) was_frozen[bed.id[i]] = bed.bulk_state[i] < 0;

  Simulation rigid(s, bed, geometry::Protocol::at_rest());
  Particles plain = bed;
  for (auto& st : plain.bulk_state) st = 0;
  Simulation dynamic(tiny_scene(), plain, geometry::Protocol::at_rest());
  rigid.compute_forces();
  dynamic.compute_forces();
  std::size_t fewest_frozen = frozen_before;
  for (int k = 0; k < 25000; ++k) {
    rigid.step();
    dynamic.step();
    fewest_frozen = std::min(fewest_frozen, count_frozen(rigid));
  }
  const Particles& p = rigid.particles();
  const double moved = mean_displacement(p, start, s.d_small);
  const double moved_dynamic = mean_displacement(dynamic.particles(), start, s.d_small);
  // Measured: the dynamic bed moves ~2 d on average; the rigid one must flow as far (within 25%).
  EXPECT_GT(moved_dynamic, 1.0);
  EXPECT_NEAR(moved, moved_dynamic, 0.25 * moved_dynamic);
  // The particles frozen before the tilt thawed and moved as the same particles of the dynamic
  // bed did (mean displacement within 25%).
  auto mean_of_frozen = [&](const Particles& q) {
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < q.size(); ++i)
      if (was_frozen[q.id[i]]) {
        sum += norm(q.x[i] - start[q.id[i]]);
        ++count;
      }
    return sum / static_cast<double>(count) / s.d_small;
  };
  const double deep = mean_of_frozen(p), deep_dynamic = mean_of_frozen(dynamic.particles());
  EXPECT_GT(deep_dynamic, 0.2);
  EXPECT_NEAR(deep, deep_dynamic, 0.25 * deep_dynamic);
  // Most thawed during the slide (the slumped bed at rest freezes again afterwards).
  EXPECT_LT(fewest_frozen, frozen_before / 4);
  std::printf(
      "tilted 50 deg: frozen before %zu, after %zu; mean displacement rigid %.3f d, "
      "dynamic %.3f d; of the particles frozen before: %.3f d, %.3f d; fewest frozen %zu\n",
      frozen_before, count_frozen(rigid), moved, moved_dynamic, deep, deep_dynamic, fewest_frozen);
}
}  // namespace

TEST(RigidBulk, BedTiltedAboveReposeThawsAndFlowsAsTheDynamicBed) {
  expect_tilted_bed_thaws_and_flows({}, 0.2);
}

TEST(RigidBulk, AWholeFrozenBedTiltedAboveItsStillSlopeThawsAndFlowsAsTheDynamicBed) {
  // With a still slope of 20° the level bed freezes whole, surface included; tilted 50° it finds
  // the surface steeper at its first pass, and the surface layer thaws, then what it uncovers.
  expect_tilted_bed_thaws_and_flows({"fidelity.bulk_still_slope=20"}, 0.95);
}

namespace {
// The biaxial protocol's segments at 10 rpm, short: tilt 3 deg, rotate 6 deg about z, ... The bed
// turning with the wall freezes below its surface during the tilt. Counted: the frozen at the
// tilt's end, the fewest up to the first pass after it (a quarter of the dwell at most) and the
// frozen four dwells later; the positions at the tilt's end, by id.
struct SegmentChange {
  std::size_t before = 0, fewest = 0, after = 0, particles = 0;
  std::vector<Vec3> x_at_change;
};

// The change looked at is the tilt's end (3 deg: the tilt becomes the rotation, Ω the same) or,
// with change_deg = 9, the rotation's end (the tilt back: Ω reversed).
SegmentChange through_segment_change(const std::string& segment_thaw, double change_deg = 3) {
  const Scene s = tiny_scene({"protocol.mode=biaxial", "protocol.rpm=10", "fidelity.bulk=rigid",
                              "fidelity.bulk_dwell=0.004", segment_thaw});
  const auto proto = geometry::Protocol::biaxial(deg2rad(6), deg2rad(6), deg2rad(3), s.omega());
  Simulation sim(s, tiny_settled_bed(), proto);
  sim.compute_forces();
  const double tilt_end = deg2rad(change_deg) / s.omega();
  while (sim.time() + sim.dt() < tilt_end) sim.step();
  SegmentChange c;
  c.particles = sim.local_count();
  c.before = c.fewest = count_frozen(sim);
  c.x_at_change = by_id(sim.particles());
  const double quarter_dwell = 0.25 * 0.004 + 10 * sim.dt();
  while (sim.time() < tilt_end + quarter_dwell + sim.dt()) {
    sim.step();
    c.fewest = std::min(c.fewest, count_frozen(sim));
  }
  while (sim.time() < tilt_end + 4 * 0.004) sim.step();
  c.after = count_frozen(sim);
  return c;
}
}  // namespace

TEST(RigidBulk, AChangeOfSegmentThawsTheBedAndItRefreezes) {
  // With the default segment thaw nothing is frozen at the first pass after the tilt ends; one
  // dwell later the bulk is frozen again.
  const SegmentChange c = through_segment_change("fidelity.bulk_segment_thaw=on");
  EXPECT_GT(static_cast<double>(c.before), 0.1 * static_cast<double>(c.particles));
  EXPECT_EQ(c.fewest, 0u);
  EXPECT_GT(static_cast<double>(c.after), 0.1 * static_cast<double>(c.particles));
  std::printf("segment change: frozen %zu before, %zu fewest after, %zu four dwells later\n",
              c.before, c.fewest, c.after);
}

TEST(RigidBulk, WithoutTheSegmentThawTheBulkStaysFrozenAcrossTheChange) {
  // With fidelity.bulk_segment_thaw = off the bulk frozen at the tilt's end stays frozen through
  // the change (it thaws only by the other rules: the surface, which the bed's new motion lifts
  // slowly at 10 rpm, a moving neighbour, a push). Up to the change the run is the default one bit
  // for bit.
  const SegmentChange on = through_segment_change("fidelity.bulk_segment_thaw=on");
  const SegmentChange off = through_segment_change("fidelity.bulk_segment_thaw=off");
  EXPECT_EQ(differing(on.x_at_change, off.x_at_change), 0u);
  EXPECT_EQ(on.before, off.before);
  EXPECT_EQ(on.fewest, 0u);
  EXPECT_GT(static_cast<double>(off.fewest), 0.8 * static_cast<double>(off.before));
  std::printf("segment change without its thaw: frozen %zu before, %zu fewest after (with it: 0)\n",
              off.before, off.fewest);
}

TEST(RigidBulk, TheOmegaSegmentThawSkipsTheTiltsEndAndThawsWhereOmegaChanges) {
  // fidelity.bulk_segment_thaw = omega: where the tilt becomes the rotation (Ω the same) it is the
  // run without the segment thaw, bit for bit through the change; where the rotation becomes the
  // tilt back (Ω reversed) it thaws the whole bed as the default does.
  const SegmentChange off = through_segment_change("fidelity.bulk_segment_thaw=off");
  const SegmentChange omega = through_segment_change("fidelity.bulk_segment_thaw=omega");
  EXPECT_EQ(differing(off.x_at_change, omega.x_at_change), 0u);
  EXPECT_EQ(omega.before, off.before);
  EXPECT_EQ(omega.fewest, off.fewest);
  EXPECT_EQ(omega.after, off.after);
  EXPECT_GT(static_cast<double>(omega.fewest), 0.8 * static_cast<double>(omega.before));
  const SegmentChange back_off = through_segment_change("fidelity.bulk_segment_thaw=off", 9);
  const SegmentChange back = through_segment_change("fidelity.bulk_segment_thaw=omega", 9);
  EXPECT_GT(static_cast<double>(back.before), 0.1 * static_cast<double>(back.particles));
  EXPECT_EQ(back.fewest, 0u);
  EXPECT_GT(static_cast<double>(back.after), 0.1 * static_cast<double>(back.particles));
  EXPECT_GT(static_cast<double>(back_off.fewest), 0.8 * static_cast<double>(back_off.before));
  std::printf(
      "omega segment thaw: at the tilt's end frozen %zu before, %zu fewest after (as off);"
      " at the tilt back %zu before, %zu fewest (off: %zu of %zu), %zu four dwells later\n",
      omega.before, omega.fewest, back.before, back.fewest, back_off.fewest, back_off.before,
      back.after);
}

TEST(RigidBulk, RestartContinuesBitwise) {
  const std::string base = test_dir("rigid_restart");
  std::filesystem::remove_all(base);
  auto scene = [&](const std::string& out) {
    // A short dwell so that particles freeze and thaw within the 3,000 steps; a checkpoint every
    // 1,000 steps. The gravity rule at its finest (0.01: a turn of 0.57 degrees since freezing,
    // of the run's 1.1 degrees) thaws the first frozen particles in the run's second half, so the
    // restart must carry each frozen particle's gravity direction.
    return rigid_scene({"fidelity.bulk_dwell=0.004", "fidelity.bulk_calm_distance=0.1",
                        "fidelity.bulk_thaw_gravity=0.01", "protocol.duration=1",
                        "scene.output_dir=" + base + "/" + out, "output.checkpoint_interval=0.02",
                        "output.snapshot_interval=0.02"});
  };
  RunOptions full;
  full.max_steps = 3000;
  std::ostringstream full_log;
  full.log = &full_log;
  run_realization(scene("full"), full);
  // "[run] rigid bulk: ... N particles thawed by gravity's turn": the rule fired.
  const std::string text = full_log.str();
  const std::size_t at = text.find(" particles thawed by gravity");
  ASSERT_NE(at, std::string::npos) << text;
  const std::size_t from = text.rfind(' ', at - 1) + 1;
  EXPECT_GT(std::stoul(text.substr(from, at - from)), 0u) << "the gravity rule never fired";
  RunOptions first;
  first.max_steps = 2000;
  run_realization(scene("split"), first);
  RunOptions second;
  second.resume = true;
  second.max_steps = 1000;
  run_realization(scene("split"), second);

  const io::CheckpointData a = io::read_checkpoint(base + "/full/checkpoint.h5");
  const io::CheckpointData b = io::read_checkpoint(base + "/split/checkpoint.h5");
  ASSERT_EQ(a.step, 3000);
  ASSERT_EQ(b.step, 3000);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  EXPECT_EQ(state_differences(a.particles, b.particles), 0u);
  std::size_t frozen = 0;
  for (std::int32_t state : a.particles.bulk_state) frozen += state < 0;
  EXPECT_GT(frozen, 50u) << "nothing frozen at the end: the test would pass without the bulk";
  ASSERT_EQ(a.history.records().size(), b.history.records().size());
  for (std::size_t k = 0; k < a.history.records().size(); ++k) {
    const auto& r = a.history.records()[k];
    const auto& t = b.history.records()[k];
    EXPECT_TRUE(r.lo == t.lo && r.hi == t.hi && r.history == t.history);
  }
  ASSERT_EQ(a.series.frozen_fraction.size(), b.series.frozen_fraction.size());
  EXPECT_EQ(a.series.frozen_fraction, b.series.frozen_fraction);
}

// The run of `scene` resumed from its checkpoint for `steps` more steps (with the bulk option
// `scene` names), and its checkpoint then.
io::CheckpointData resumed(const Scene& scene, std::int64_t steps) {
  RunOptions more;
  more.resume = true;
  more.max_steps = steps;
  run_realization(scene, more);
  return io::read_checkpoint(scene.output_dir + "/checkpoint.h5");
}

TEST(RigidBulk, ARigidCheckpointContinuesDynamic) {
  // The rigid run's state is the dynamic engine's (its frozen particles at the wall's velocity,
  // their springs in the contact records): a restart with fidelity.bulk = dynamic (refused before)
  // thaws them all and runs on (its frozen particles were pushed by their moving neighbours alone
  // at the checkpoint: one half kick without their frozen pairs' forces).
  const std::string base = test_dir("rigid_to_dynamic");
  std::filesystem::remove_all(base);
  // (A series sample every 100 steps: some of them in the dynamic part.)
  auto scene = [&](const std::string& bulk) {
    return rigid_scene({"fidelity.bulk=" + bulk, "protocol.duration=1", "scene.output_dir=" + base,
                        "output.checkpoint_interval=0.02", "output.analysis_interval=0.002"});
  };
  RunOptions first;
  first.max_steps = 4000;
  run_realization(scene("rigid"), first);
  const io::CheckpointData a = io::read_checkpoint(base + "/checkpoint.h5");
  std::size_t frozen = 0;
  for (std::int32_t state : a.particles.bulk_state) frozen += state < 0;
  ASSERT_GT(frozen, 300u) << "nothing frozen at the checkpoint: the test would show nothing";
  const io::CheckpointData b = resumed(scene("dynamic"), 500);
  ASSERT_EQ(b.step, 4500);
  EXPECT_EQ(parse_scene(b.scene_text, {}, "checkpoint").bulk, Bulk::dynamic);
  std::size_t still = 0;
  for (std::int32_t state : b.particles.bulk_state) still += state != 0;
  EXPECT_EQ(still, 0u);
  // The frozen share stays one value per sample: the dynamic part's read 0 (nothing frozen).
  ASSERT_EQ(b.series.frozen_fraction.size(), b.series.time.size());
  ASSERT_GT(b.series.time.size(), a.series.time.size());
  EXPECT_GT(a.series.frozen_fraction.back(), 0.1);
  for (std::size_t k = a.series.time.size(); k < b.series.time.size(); ++k)
    EXPECT_EQ(b.series.frozen_fraction[k], 0.0) << "sample " << k;
  // 500 steps (0.01 s, 0.18 degrees) of a bed turning as a solid: the particles frozen at the
  // checkpoint stay with the wall as a dynamic bulk does (largest move relative to it 0.0054
  // d_small, measured; asserted < 0.02 d_small: a blow-up of the restart, not a subtle error).
  const Scene s = scene("dynamic");
  const geometry::Protocol turn = geometry::Protocol::single_axis('x', s.omega());
  const Mat3 q1 = turn.orientation(a.time), q2 = turn.orientation(b.time);
  std::vector<Vec3> before(a.particles.size());
  std::vector<int> was(a.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    before[a.particles.id[i]] = a.particles.x[i];
    was[a.particles.id[i]] = a.particles.bulk_state[i] < 0;
  }
  double largest = 0;
  for (std::size_t i = 0; i < b.particles.size(); ++i)
    if (was[b.particles.id[i]])
      largest = std::max(largest, norm(b.particles.x[i] - q2 * q1.tmul(before[b.particles.id[i]])));
  EXPECT_LT(largest, 0.02 * s.d_small);
}

TEST(RigidBulk, ADynamicCheckpointContinuesRigidWithItsSeriesAligned) {
  // A dynamic run resumed rigid: the frozen share, one value per sample of the run, reads 0 for
  // the dynamic part (nothing frozen) and the rigid engine's share after it.
  const std::string base = test_dir("dynamic_to_rigid");
  std::filesystem::remove_all(base);
  auto scene = [&](const std::string& bulk) {
    return rigid_scene({"fidelity.bulk=" + bulk, "fidelity.bulk_dwell=0.004", "protocol.duration=1",
                        "scene.output_dir=" + base, "output.checkpoint_interval=0.02",
                        "output.analysis_interval=0.002"});
  };
  RunOptions first;
  first.max_steps = 1000;
  run_realization(scene("dynamic"), first);
  const io::CheckpointData a = io::read_checkpoint(base + "/checkpoint.h5");
  ASSERT_GT(a.series.time.size(), 0u);
  EXPECT_TRUE(a.series.frozen_fraction.empty()) << "a dynamic run keeps no frozen share";
  const io::CheckpointData b = resumed(scene("rigid"), 1500);
  ASSERT_EQ(b.step, 2500);
  ASSERT_EQ(b.series.frozen_fraction.size(), b.series.time.size());
  ASSERT_GT(b.series.time.size(), a.series.time.size());
  for (std::size_t k = 0; k < a.series.time.size(); ++k)
    EXPECT_EQ(b.series.frozen_fraction[k], 0.0) << "sample " << k;
  EXPECT_GT(b.series.frozen_fraction.back(), 0.1) << "nothing froze: the test shows nothing";
}
