// fidelity.bulk = "rigid": the calm bulk of a rolling bed turns with the wall as a solid.
//
// A particle is *frozen* (bulk_state -1) when, at a neighbour rebuild, it and every particle of
// its neighbour list within reach have stayed put in the tumbler's frame (within
// bulk_calm_distance d_large of where their stay began) for bulk_dwell seconds, and its top lies
// more than bulk_margin d_large below the free surface of its column. A frozen particle is carried
// exactly by the wall's rotation (positions by the protocol's orientation, v = Ω × r, w = Ω), feels
// no wall, and its pairs with other frozen particles are left out of the force loops: their springs
// stay in the whole list (dormant) and restart from there. Pairs with a moving particle are
// computed as for any pair (the frozen one acts as a rough wall grain). It thaws at the next
// rebuild when a neighbour moves (leaves its calm distance) or the surface comes within the
// margin, at the first rebuild of a new protocol segment, at a rebuild when gravity, seen from the
// tumbler, has changed by more than bulk_thaw_gravity g since it froze (off at the default 2), and
// at the very next step when its moving neighbours push it harder than bulk_thaw_force times its
// weight (checked in kick_drift, simulation.cpp). Frozen ghosts are turned by every rank itself,
// not refreshed.
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

void Simulation::update_bulk_states() {
  const std::size_t n = n_local_, all = p_.size();
  RigidBulk& b = bulk_;
  // The dormant springs (pairs frozen since the last pass) and the wall springs of frozen
  // particles turned with the wall in the meantime: turn them too, so that a thawed contact
  // restarts from its spring as seen in the tumbler's frame. Springs are lab-frame vectors in
  // every law of today (width 3); another history would need its own rule.
  if (list_.history_layout().width == 3) {
    const Mat3 turn = turn_between(protocol_, b.last_update_time, time_);
    double* h = list_.history.data();
    for (std::size_t i = 0; i < n; ++i) {
      if (p_.bulk_state[i] >= 0) continue;
      p_.wall_spring[i] = turn * p_.wall_spring[i];
      for (std::uint32_t k = list_.start[i]; k < list_.start[i + 1]; ++k) {
        if (p_.bulk_state[list_.nbr[k]] >= 0) continue;
        const Vec3 v = turn * Vec3{h[3 * k], h[3 * k + 1], h[3 * k + 2]};
        h[3 * k] = v.x;
        h[3 * k + 1] = v.y;
        h[3 * k + 2] = v.z;
      }
    }
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
  // Freeze after the dwell, thaw at once. The depth is taken below the top of the particle's own
  // column, one d_large wide: on a surface at the repose angle the column's highest top lies at
  // most ~tan(30 deg) d_large above the surface over the particle. (Against the lowest of the
  // 3 x 3 columns around it, a bed at the repose angle 5 d_large deep never froze: the columns'
  // tops differ by as much as the margin.)
  // A change of the protocol's segment (a new axis or speed, a tilt) thaws everything: the bed
  // re-forms its free surface and flowing layer about the new axis, and whatever stays put
  // refreezes one dwell later.
  // Gravity's turn: a frozen particle's held contacts carried its weight when it froze, and still
  // do so as they were; gravity, seen from the tumbler, has since turned with the wall. Released,
  // it would accelerate relative to the wall by about g |ĝ_T(now) - ĝ_T(freeze)| (its moving
  // neighbours' push aside, which the thaw force covers): past bulk_thaw_gravity g it thaws.
  const Vec3 g_now = q.tmul(gravity_ * (1 / std::sqrt(norm2(gravity_))));
  const double thaw_g2 = b.thaw_gravity * b.thaw_gravity;
  const bool gravity_rule = b.thaw_gravity < 2;  // |ĝ - ĝ'| <= 2: at 2 the rule never fires
  const std::int64_t elapsed = step_ - b.last_update;
  const std::int64_t segment = protocol_.segment_count(time_);
  const bool new_segment = segment != b.segment;
  b.segment = segment;
  std::int64_t frozen = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!b.calm[i]) p_.bulk_anchor[i] = q.tmul(p_.x[i]);  // it moved: a new stay begins here
    int cx, cz;
    column_of(p_.x[i], cx, cz);
    const double surface = b.top[static_cast<std::size_t>(cx) * b.nz + cz];
    const bool deep = surface - (p_.x[i].y + p_.radius[i]) > b.margin;
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
  // Nothing frozen here (ghosts included): the whole list, without a copy (the rigid path then
  // costs only its pass at each rebuild).
  const bool any_frozen = rigid_ && std::any_of(p_.bulk_state.begin(), p_.bulk_state.end(),
                                                [](std::int32_t s) { return s < 0; });
  if (!any_frozen) {
    bulk_.full.clear();
    pairs_ = {list_.start.data(), list_.nbr.data(), list_.row.data(), list_.history.data(),
              list_.nbr.size()};
    return;
  }
  // The pairs with at least one moving particle, in list order, with copies of their springs.
  RigidBulk& b = bulk_;
  const std::size_t n = n_local_;
  const std::size_t w = static_cast<std::size_t>(list_.history_layout().width);
  const std::int32_t* state = p_.bulk_state.data();
  b.start.resize(n + 1);
  b.nbr.resize(list_.nbr.size());
  b.full.resize(list_.nbr.size());
  b.history.resize(w * list_.nbr.size());
  std::uint32_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    b.start[i] = count;
    const bool frozen_i = state[i] < 0;
    for (std::uint32_t k = list_.start[i]; k < list_.start[i + 1]; ++k) {
      const std::uint32_t j = list_.nbr[k];
      if (frozen_i && state[j] < 0) continue;
      b.nbr[count] = j;
      b.full[count] = k;
      for (std::size_t d = 0; d < w; ++d) b.history[w * count + d] = list_.history[w * k + d];
      ++count;
    }
  }
  b.start[n] = count;
  b.nbr.resize(count);
  b.full.resize(count);
  b.history.resize(w * count);
  b.row.resize(count);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = b.start[i]; k < b.start[i + 1]; ++k)
      b.row[k] = static_cast<std::uint32_t>(i);
  pairs_ = {b.start.data(), b.nbr.data(), b.row.data(), b.history.data(), count};
}

void Simulation::sync_dormant() const {
  if (!rigid_) return;
  const RigidBulk& b = bulk_;
  const std::size_t w = static_cast<std::size_t>(list_.history_layout().width);
  for (std::size_t c = 0; c < b.full.size(); ++c)
    for (std::size_t d = 0; d < w; ++d) list_.history[w * b.full[c] + d] = b.history[w * c + d];
}

Mat3 Simulation::wall_turn_over_step() const { return turn_between(protocol_, time_, time_ + dt_); }

}  // namespace tumble
