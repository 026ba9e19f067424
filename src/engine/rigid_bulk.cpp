// fidelity.bulk = "rigid": the calm bulk of a rolling bed turns with the wall as a solid.
//
// A particle is *frozen* (bulk_state -1) when, at a neighbour rebuild, it and every particle of
// its neighbour list within reach have stayed put in the tumbler's frame (within
// bulk_calm_distance d_large of where their stay began) for bulk_dwell seconds, and its top lies
// more than bulk_margin d_large below the free surface of its column. A frozen particle is carried
// exactly by the wall's rotation (positions by the protocol's orientation, v = Ω × r, w = Ω), feels
// no wall, and its pairs with other frozen particles are left out of the neighbour list: no force
// loop runs them and no rebuild filters them; their springs wait by ids (dormant, turned with the
// wall) and restart from there when one of the pair thaws (neighbor/verlet_list.hpp). Pairs with a
// moving particle are computed as for any pair (the frozen one acts as a rough wall grain). It
// thaws at the next rebuild when a neighbour moves (leaves its calm distance) or the surface comes
// within the margin, at the first rebuild of a new protocol segment (unless bulk_segment_thaw is
// off; with omega, only of a segment whose Ω differs from the last one's), at a rebuild when
// gravity, seen from the tumbler, has changed by more than bulk_thaw_gravity g since it froze (off
// at the default 2), and at the very next step when its moving neighbours push it harder than
// bulk_thaw_force times its weight (checked in kick_drift_rigid below). With bulk_still_slope set,
// the margin holds only while the free surface is inclined at least that much: below it (a tilt
// under the repose angle, a bed at rest) the surface layer freezes like the bulk, and it thaws at
// the first pass that finds the surface steeper.
//
// A frozen particle's place is a function of time alone: turn(t_b -> t) x_b, from its position
// x_b at the last rebuild (time t_b), so every rank computes the same bits for it, owner or ghost
// holder, whenever it asks. The step computes it only for the frozen particles that are in a pair
// with a moving one; the others wait for the next rebuild or reader (sync_frozen), and frozen
// ghosts are not refreshed. A step then costs nothing for a frozen particle no moving one touches.
//
// States change only at rebuilds, which every rank passes at the same step, and every decision is
// a comparison of values that serial and decomposed runs compute alike (displacements from
// refreshed ghost positions and the anchors of the last pass, integer flags, maxima): the ghosts
// learn the new states from the exchange of the rebuild that follows.
#include <algorithm>
#include <cmath>

#include "engine/simulation.hpp"

namespace tumble {
namespace {
// The wall's rotation from time `from` to time `to`: Q(to) Q(from)^T, column by column (exact
// across a change of the protocol's segment).
Mat3 turn_between(const geometry::Protocol& protocol, double from, double to) {
  const Mat3 a = protocol.orientation(from), b = protocol.orientation(to);
  Mat3 turn;
  for (int c = 0; c < 3; ++c) {
    const Vec3 e{c == 0 ? 1.0 : 0.0, c == 1 ? 1.0 : 0.0, c == 2 ? 1.0 : 0.0};
    const Vec3 col = b * a.tmul(e);
    turn.a[0][c] = col.x;
    turn.a[1][c] = col.y;
    turn.a[2][c] = col.z;
  }
  return turn;
}
}  // namespace

// The tangent of the free surface's inclination: the plane y = a x + c z + d fitted by least
// squares to the tops of the columns within the bulk's slope reach (HUGE_VAL where fewer than
// three columns or no plane fits). Columns are d_large wide, so each top is the surface to within
// a particle: over a bed tens of particles wide the fit's slope is that of the surface's plane.
double Simulation::surface_slope_tan() const {
  const RigidBulk& b = bulk_;
  double n = 0, sx = 0, sz = 0, sy = 0, sxx = 0, szz = 0, sxz = 0, sxy = 0, szy = 0;
  for (int cx = 0; cx < b.nx; ++cx)
    for (int cz = 0; cz < b.nz; ++cz) {
      const double y = b.top[static_cast<std::size_t>(cx) * b.nz + cz];
      if (y < -1e299) continue;  // an empty column
      const double x = b.x0 + (cx + 0.5) * b.bin, z = b.z0 + (cz + 0.5) * b.bin;
      if (x * x + (b.slope_z ? z * z : 0.0) > b.slope_reach2) continue;
      n += 1;
      sx += x;
      sz += z;
      sy += y;
      sxx += x * x;
      szz += z * z;
      sxz += x * z;
      sxy += x * y;
      szy += z * y;
    }
  if (n < 3) return HUGE_VAL;
  // Centred sums: the 2 x 2 normal equations of (a, c).
  const double cxx = sxx - sx * sx / n, czz = szz - sz * sz / n, cxz = sxz - sx * sz / n;
  const double cxy = sxy - sx * sy / n, czy = szy - sz * sy / n;
  const double det = cxx * czz - cxz * cxz;
  if (!(det > 1e-12 * (cxx * czz))) return HUGE_VAL;
  const double a = (cxy * czz - czy * cxz) / det, c = (czy * cxx - cxy * cxz) / det;
  return std::sqrt(a * a + c * c);
}

void Simulation::update_bulk_states() {
  const std::size_t n = n_local_, all = p_.size();
  RigidBulk& b = bulk_;
  // The dormant springs (pairs frozen since the last pass) and the wall springs of frozen
  // particles turned with the wall in the meantime: turn them too, so that a thawed contact
  // restarts from its spring as seen in the tumbler's frame; and the dormant records' anchors,
  // which follow their row particle (a migration routes the records by them). Springs are
  // lab-frame vectors in every law of today (width 3); another history would need its own rule.
  {
    const Mat3 turn = turn_between(protocol_, b.last_update_time, time_);
    if (list_.history_layout().width == 3)
      for (std::size_t i = 0; i < n; ++i)
        if (p_.bulk_state[i] < 0) p_.wall_spring[i] = turn * p_.wall_spring[i];
    const bool spring = list_.history_layout().width == 3;
    b.dormant.update([&](neighbor::HistoryValues& h, Vec3& anchor) {
      if (spring) {
        const Vec3 v = turn * Vec3{h[0], h[1], h[2]};
        h[0] = v.x;
        h[1] = v.y;
        h[2] = v.z;
      }
      anchor = turn * anchor;
    });
  }
  // Calm: within calm_distance of its anchor, the tumbler-frame position where its present stay
  // began. A displacement, not a speed: the bulk of a rolling bed rattles (deep particles move at
  // ~0.1 omega R and spin at ~4 omega relative to the wall at any instant) while it stays put to
  // a few thousandths of d_large per degree of rotation (docs/accuracy.md, "Rigid bulk"). Ghosts
  // too: their positions are refreshed every step and their anchors are their owners' as of the
  // last pass (sent with the ghost copies of the rebuild that followed it), which is what the
  // owner's own test below reads, so serial and decomposed runs decide alike.
  // (The periodic cylinder turns about z: a particle wrapped across the period, or a ghost image
  // of it, has not moved.)
  const Mat3 q = protocol_.orientation(time_);
  const double calm2 = b.calm_distance * b.calm_distance;
  b.calm.assign(all, 0);
  for (std::size_t i = 0; i < all; ++i)
    b.calm[i] = norm2(cylinder_.nearest_image(q.tmul(p_.x[i]) - p_.bulk_anchor[i])) < calm2;
  // Unsettled: itself or a neighbour within reach not calm. Each pair of the (half) list marks
  // both ends; a pair across a rank border is in the list of both ranks.
  b.unsettled.assign(all, 0);
  const double skin = list_.skin();
  for (std::size_t i = 0; i < n; ++i) {
    b.unsettled[i] |= !b.calm[i];
    for (std::uint32_t k = list_.start[i]; k < list_.start[i + 1]; ++k) {
      const std::uint32_t j = list_.nbr[k];
      const Vec3 d = cylinder_.nearest_image(p_.x[i] - p_.x[j]);
      const double reach = p_.radius[i] + p_.radius[j] + skin;
      if (norm2(d) >= reach * reach) continue;
      if (!b.calm[j]) b.unsettled[i] = 1;
      if (!b.calm[i]) b.unsettled[j] = 1;
    }
  }
  // The free surface: the highest particle top per column, over every rank.
  const std::size_t columns = static_cast<std::size_t>(b.nx) * static_cast<std::size_t>(b.nz);
  b.top.assign(columns, -1e300);
  auto column_of = [&](const Vec3& x, int& cx, int& cz) {
    cx = std::clamp(static_cast<int>(std::floor((x.x - b.x0) / b.bin)), 0, b.nx - 1);
    cz = std::clamp(static_cast<int>(std::floor((x.z - b.z0) / b.bin)), 0, b.nz - 1);
  };
  for (std::size_t i = 0; i < n; ++i) {
    int cx, cz;
    column_of(p_.x[i], cx, cz);
    double& t = b.top[static_cast<std::size_t>(cx) * b.nz + cz];
    t = std::max(t, p_.x[i].y + p_.radius[i]);
  }
  if (dom_)
    MPI_Allreduce(MPI_IN_PLACE, b.top.data(), static_cast<int>(columns), MPI_DOUBLE, MPI_MAX,
                  dom_->comm());
  // The still surface: inclined less than bulk_still_slope, the bed's surface layer turns with
  // the wall too (a tilt below the repose angle; a bed at rest), and may freeze like the bulk.
  // The slope comes from the columns' tops, which every rank holds alike.
  b.still = b.still_slope_tan > 0 && surface_slope_tan() < b.still_slope_tan;
  // Freeze after the dwell, thaw at once. The depth is taken below the top of the particle's own
  // column, one d_large wide: on a surface at the repose angle the column's highest top lies at
  // most ~tan(30 deg) d_large above the surface over the particle. (Against the lowest of the
  // 3 x 3 columns around it, a bed at the repose angle 5 d_large deep never froze: the columns'
  // tops differ by as much as the margin.)
  // A change of the protocol's segment (a new axis or speed, a tilt) thaws everything: the bed
  // re-forms its free surface and flowing layer about the new axis, and whatever stays put
  // refreezes one dwell later. With bulk_segment_thaw off it thaws nothing by itself: the bulk
  // below the surface goes on turning with the wall, and what the new motion sets moving thaws by
  // the other rules (its surface, a moving neighbour, the push, gravity's turn). That saves the
  // refreezing dwell after each of an iteration's six segment changes, and changes what the bed
  // does, so `on` stays the default until its errors are measured (docs/accuracy.md). Between
  // the two, `omega` thaws where Ω changes (the tilt's start, the tilt back) and not where the
  // tilt by β becomes the rotation about the same axis: there the whole-bed thaw of `on` made
  // the surface speed step up for a few degrees (bst_small, docs/accuracy.md).
  // Gravity's turn: a frozen particle's held contacts carried its weight when it froze, and still
  // do so as they were; gravity, seen from the tumbler, has since turned with the wall. Released,
  // it would accelerate relative to the wall by about g |ĝ_T(now) - ĝ_T(freeze)| (its moving
  // neighbours' push aside, which the thaw force covers): past bulk_thaw_gravity g it thaws.
  const Vec3 g_now = q.tmul(gravity_ * (1 / std::sqrt(norm2(gravity_))));
  const double thaw_g2 = b.thaw_gravity * b.thaw_gravity;
  const bool gravity_rule = b.thaw_gravity < 2;  // |ĝ - ĝ'| <= 2: at 2 the rule never fires
  const std::int64_t elapsed = step_ - b.last_update;
  const std::int64_t segment = protocol_.segment_count(time_);
  // (omega: Ω compared exactly, both from the protocol's one list of segments.)
  bool new_segment = false;
  if (segment != b.segment) {
    if (b.segment_thaw == SegmentThaw::on) new_segment = true;
    if (b.segment_thaw == SegmentThaw::omega) {
      const Vec3 was = protocol_.segment_omega(b.segment), now = protocol_.segment_omega(segment);
      new_segment = was.x != now.x || was.y != now.y || was.z != now.z;
    }
  }
  b.segment = segment;
  std::int64_t frozen = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!b.calm[i]) p_.bulk_anchor[i] = q.tmul(p_.x[i]);  // it moved: a new stay begins here
    int cx, cz;
    column_of(p_.x[i], cx, cz);
    const double surface = b.top[static_cast<std::size_t>(cx) * b.nz + cz];
    const bool deep = b.still || surface - (p_.x[i].y + p_.radius[i]) > b.margin;
    const bool eligible = deep && !b.unsettled[i] && !new_segment;
    std::int32_t& s = p_.bulk_state[i];
    Vec3& g_frozen = p_.bulk_gravity[i];
    if (s < 0) {
      // (A checkpoint from before the field has no direction: it counts from the restart.)
      if (norm2(g_frozen) == 0) g_frozen = g_now;
      const bool turned = gravity_rule && norm2(g_now - g_frozen) > thaw_g2;
      if (s == -2 || !eligible || turned) s = 0;
      gravity_thaws_ += turned;
    } else if (!eligible) {
      s = 0;
    } else {
      const std::int64_t calm = std::min<std::int64_t>(s + elapsed, std::int64_t{1} << 30);
      s = calm >= b.dwell_steps ? -1 : static_cast<std::int32_t>(calm);
      if (s < 0) g_frozen = g_now;
    }
    frozen += s < 0;
  }
  b.last_update = step_;
  b.last_update_time = time_;
  frozen_fraction_ = sum(static_cast<double>(frozen)) / sum(static_cast<double>(n));
}

void Simulation::set_pair_view() {
  RigidBulk& b = bulk_;
  const std::size_t n = n_local_, all = p_.size();
  const std::int32_t* state = p_.bulk_state.data();
  // The force loops run the whole list: with the rigid bulk it holds no pair of two frozen
  // particles (they are dormant).
  pairs_ = {list_.start.data(), list_.nbr.data(), list_.row.data(), list_.history.data(),
            list_.nbr.size()};
  // Nothing frozen here (ghosts included): every particle moves (the rigid path then costs only
  // its pass at each rebuild; a dynamic run keeps no list of them).
  b.any_frozen = rigid_ && std::any_of(p_.bulk_state.begin(), p_.bulk_state.end(),
                                       [](std::int32_t s) { return s < 0; });
  b.moving.clear();
  b.exposed.clear();
  b.exposed_ghosts.clear();
  if (!b.any_frozen) {
    b.x_build.clear();
    return;
  }
  // The frozen ends of the pairs (each has a moving one) are the frozen particles the step must
  // turn.
  b.touched.assign(all, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const bool frozen_i = state[i] < 0;
    for (std::uint32_t k = list_.start[i]; k < list_.start[i + 1]; ++k) {
      b.touched[i] |= frozen_i;
      b.touched[list_.nbr[k]] |= state[list_.nbr[k]] < 0;
    }
  }
  // Who the step moves, and where the frozen are now (their origin until the next rebuild). A
  // frozen particle outside every pair keeps no force or torque: none reaches it until it is in a
  // pair again (the thaw-force check reads it then).
  b.frozen_reach2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::uint32_t>(i);
    if (state[i] >= 0) {
      // (A run of consecutive rows: one per border class after a sort, more after a restore.)
      if (b.moving.empty() || b.moving.back().last != k)
        b.moving.push_back({k, k + 1});
      else
        ++b.moving.back().last;
      continue;
    }
    b.frozen_reach2 = std::max(b.frozen_reach2, norm2(p_.x[i]));
    if (b.touched[i]) {
      b.exposed.push_back(k);
    } else {
      p_.f[i] = p_.t[i] = Vec3{};
    }
  }
  for (std::size_t g = n; g < all; ++g)
    if (state[g] < 0 && b.touched[g]) b.exposed_ghosts.push_back(static_cast<std::uint32_t>(g));
  b.x_build.assign(p_.x.begin(), p_.x.end());
  b.build_time = b.synced_time = time_;
}

// The first kick and drift with the rigid bulk: the moving particles as kick_drift does (in their
// order), then the frozen ones in a pair with a moving one, turned with the wall from where they
// were at the last rebuild, with the wall's velocity and spin at the step's end. Their force,
// still the last step's (their moving neighbours' alone: no frozen pairs, no wall), is checked
// first: pushed harder than bulk_thaw_force times its weight, a particle thaws at this step's
// rebuild (it still turns this step). The frozen particles' displacement since the rebuild, a
// rotation, is at most |turn - 1| |x_b|: that bound stands for theirs in the rebuild criterion.
template <bool kRotation>
double Simulation::kick_drift_rigid(double kick) {
  RigidBulk& b = bulk_;
  // Nothing frozen (a segment's first dwell): every owned particle moves, as in a dynamic run.
  if (!b.any_frozen) return kick_drift<kRotation>(kick);
  // (Each pass clears the ghosts' accumulators too; with no moving particle, a pass of no rows.)
  double max_d2 = b.moving.empty() ? kick_drift_rows<kRotation>(Rows{0, 0}, kick) : 0.0;
  for (const Rows& rows : b.moving)
    max_d2 = std::max(max_d2, kick_drift_range<kRotation>(rows, kick));
  Vec3* __restrict x = p_.x.data();
  Vec3* __restrict v = p_.v.data();
  Vec3* __restrict w = p_.w.data();
  Vec3* __restrict f = p_.f.data();
  Vec3* __restrict t = p_.t.data();
  const double* __restrict im = p_.inv_mass.data();
  const Mat3 turn = turn_between(protocol_, b.build_time, time_ + dt_);
  const Vec3 omega = protocol_.omega(time_ + dt_);
  const Vec3* __restrict xb = b.x_build.data();
  const double thaw2 = b.thaw_acceleration * b.thaw_acceleration;
  std::int32_t* __restrict state = p_.bulk_state.data();
  bool thawing = false;
  for (const std::uint32_t i : b.exposed) {
    if (state[i] == -1 && norm2(f[i]) * (im[i] * im[i]) > thaw2) {
      state[i] = -2;
      thawing = true;
    }
    x[i] = turn * xb[i];
    v[i] = cross(omega, x[i]);
    if constexpr (kRotation) {
      w[i] = omega;
      t[i] = Vec3{};
    }
    f[i] = Vec3{};
  }
  for (const std::uint32_t g : b.exposed_ghosts) {
    x[g] = turn * xb[g];
    v[g] = cross(omega, x[g]);
    if constexpr (kRotation) w[g] = omega;
  }
  double off2 = 0;  // |turn - 1|^2, Frobenius
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const double e = turn.a[r][c] - (r == c ? 1.0 : 0.0);
      off2 += e * e;
    }
  if (thawing) force_rebuild_ = thaw_pending_ = true;
  return std::max(max_d2, off2 * b.frozen_reach2);
}

template <bool kRotation>
void Simulation::half_kick_rigid() {
  if (!bulk_.any_frozen) {
    half_kick<kRotation>();
    return;
  }
  // The frozen are at the wall's velocity already.
  for (const Rows& rows : bulk_.moving) half_kick_range<kRotation>(rows);
}

template double Simulation::kick_drift_rigid<true>(double);
template double Simulation::kick_drift_rigid<false>(double);
template void Simulation::half_kick_rigid<true>();
template void Simulation::half_kick_rigid<false>();

void Simulation::sync_frozen() const {
  const RigidBulk& b = bulk_;
  if (!b.any_frozen || b.synced_time == time_) return;
  // The same operations on the same values as kick_drift_rigid's at this time: the particles it
  // turned come out unchanged.
  const Mat3 turn = turn_between(protocol_, b.build_time, time_);
  const Vec3 omega = protocol_.omega(time_);
  for (std::size_t i = 0; i < p_.size(); ++i) {
    if (p_.bulk_state[i] >= 0) continue;
    p_.x[i] = turn * b.x_build[i];
    p_.v[i] = cross(omega, p_.x[i]);
    if (rotation_) p_.w[i] = omega;
  }
  b.synced_time = time_;
}

}  // namespace tumble
