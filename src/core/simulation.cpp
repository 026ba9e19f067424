#include "core/simulation.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace tumble {

Simulation::Simulation(const Scene& s, Particles particles, geometry::Protocol protocol,
                       double time, std::int64_t step)
    : p_(std::move(particles)),
      protocol_(std::move(protocol)),
      gravity_{0, -s.g, 0},
      dt_(s.time_step()),
      time_(time),
      step_(step) {
  wall_.radius = s.radius;
  const double m[2] = {s.mass_small(), s.mass_large()};
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b)
      pair_[a][b] = contact::yu2022_pair(s.restitution, s.collision_time, s.tangential_damping,
                                         s.friction, m[a] * m[b] / (m[a] + m[b]));
    wall_pair_[a] = contact::yu2022_pair(s.restitution, s.collision_time, s.tangential_damping,
                                         s.wall_friction, m[a]);
  }
  // Chosen once per scene: frictionless scenes compile without the tangential spring.
  if (s.friction > 0)
    pair_kernel_ = &Simulation::pair_forces<true>;
  else
    pair_kernel_ = &Simulation::pair_forces<false>;
  if (s.wall_friction > 0)
    wall_kernel_ = &Simulation::wall_forces<true>;
  else
    wall_kernel_ = &Simulation::wall_forces<false>;

  // Cells cover the tumbler's bounding cube; side >= largest cutoff.
  double rmax = 0;
  for (double r : p_.radius) rmax = std::max(rmax, r);
  const double skin = s.skin * s.d_small;
  const double R = s.radius + skin;
  list_ = neighbor::VerletList(neighbor::CellGrid({-R, -R, -R}, {R, R, R}, 2 * rmax + skin), skin);
}

void Simulation::rebuild_lists(const neighbor::ContactHistory* history) {
  list_.rebuild(p_, history);
  // Only particles within one skin of the wall can touch it before the next rebuild (no particle
  // moves more than skin/2 in between).
  wall_candidates_.clear();
  const double skin = list_.skin();
  for (std::size_t i = 0; i < p_.size(); ++i) {
    const double reach = wall_.radius - p_.radius[i] - skin;
    if (reach <= 0 || norm2(p_.x[i]) > reach * reach)
      wall_candidates_.push_back(static_cast<std::uint32_t>(i));
  }
}

void Simulation::compute_forces() {
  rebuild_lists(nullptr);
  last_build_step_ = step_;
  for (std::size_t i = 0; i < p_.size(); ++i) p_.f[i] = p_.t[i] = Vec3{};
  (this->*pair_kernel_)();
  (this->*wall_kernel_)();
}

void Simulation::restore(const neighbor::ContactHistory& history) {
  rebuild_lists(&history);
  last_build_step_ = step_;
}

void Simulation::maybe_rebuild(double max_displacement2) {
  const double half = 0.5 * list_.skin();
  if (force_rebuild_ || max_displacement2 > half * half) {
    if (!force_rebuild_ && step_ - last_build_step_ < 10) ++fast_rebuilds_;
    rebuild_lists(nullptr);
    last_build_step_ = step_;
    force_rebuild_ = false;
  }
}

void Simulation::step() {
  const std::size_t n = p_.size();
  const double h = 0.5 * dt_;
  Vec3* __restrict x = p_.x.data();
  Vec3* __restrict v = p_.v.data();
  Vec3* __restrict w = p_.w.data();
  Vec3* __restrict f = p_.f.data();
  Vec3* __restrict t = p_.t.data();
  const double* __restrict im = p_.inv_mass.data();
  const double* __restrict ii = p_.inv_inertia.data();
  // First half kick and drift; the accumulators are cleared and the largest displacement since
  // the last neighbour rebuild found in the same pass.
  const Vec3* __restrict x_ref = list_.reference_positions().data();
  const bool have_ref = list_.reference_positions().size() == n;
  double max_d2 = have_ref ? 0.0 : 1e300;
  for (std::size_t i = 0; i < n; ++i) {
    v[i] += h * (im[i] * f[i] + gravity_);
    w[i] += (h * ii[i]) * t[i];
    x[i] += dt_ * v[i];
    f[i] = t[i] = Vec3{};
    if (have_ref) max_d2 = std::max(max_d2, norm2(x[i] - x_ref[i]));
  }
  time_ += dt_;
  ++step_;
  maybe_rebuild(max_d2);  // may permute particles: reload the pointers below
  (this->*pair_kernel_)();
  (this->*wall_kernel_)();
  // Second half kick.
  v = p_.v.data();
  w = p_.w.data();
  f = p_.f.data();
  t = p_.t.data();
  im = p_.inv_mass.data();
  ii = p_.inv_inertia.data();
  for (std::size_t i = 0; i < n; ++i) {
    v[i] += h * (im[i] * f[i] + gravity_);
    w[i] += (h * ii[i]) * t[i];
  }
}

template <bool kFriction>
void Simulation::pair_forces() {
  const std::size_t n = p_.size();
  const Vec3* __restrict x = p_.x.data();
  const Vec3* __restrict v = p_.v.data();
  const Vec3* __restrict w = p_.w.data();
  const double* __restrict rad = p_.radius.data();
  const std::int32_t* __restrict sp = p_.species.data();
  Vec3* __restrict f = p_.f.data();
  Vec3* __restrict t = p_.t.data();
  const std::uint32_t* __restrict start = list_.start.data();
  const std::uint32_t* __restrict nbr = list_.nbr.data();
  Vec3* __restrict spring = list_.spring.data();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 xi = x[i];
    const double ri = rad[i];
    Vec3 fi{}, ti{};
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
      const std::uint32_t j = nbr[k];
      const Vec3 d = xi - x[j];
      const double rsum = ri + rad[j];
      const double d2 = norm2(d);
      if (d2 >= rsum * rsum) {
        if constexpr (kFriction)  // contact over: the history starts afresh
          if (spring[k].x != 0.0 || spring[k].y != 0.0 || spring[k].z != 0.0) spring[k] = Vec3{};
        continue;
      }
      const double dist = std::sqrt(d2);
      const Vec3 nrm = (1.0 / dist) * d;
      const Vec3 vrel = v[i] - v[j] - cross(ri * w[i] + rad[j] * w[j], nrm);
      Vec3 ft;
      const Vec3 fc = contact::yu2022_force<kFriction>(pair_[sp[i]][sp[j]], nrm, rsum - dist, vrel,
                                                       spring[k], dt_, ft);
      fi += fc;
      f[j] -= fc;
      if constexpr (kFriction) {
        const Vec3 tq = cross(ft, nrm);  // = -n x F_t: torque per unit lever arm on both
        ti += ri * tq;
        t[j] += rad[j] * tq;
      }
    }
    f[i] += fi;
    t[i] += ti;
  }
}

template <bool kFriction>
void Simulation::wall_forces() {
  const Vec3 omega = protocol_.omega(time_);
  for (const std::uint32_t i : wall_candidates_) {
    Vec3 nrm, point;
    const double ri = p_.radius[i];
    const double overlap = wall_.overlap(p_.x[i], ri, nrm, point);
    if (overlap <= 0) {
      if constexpr (kFriction) p_.wall_spring[i] = Vec3{};
      continue;
    }
    const Vec3 vrel = p_.v[i] - cross(ri * p_.w[i], nrm) - cross(omega, point);
    Vec3 ft;
    const Vec3 fc = contact::yu2022_force<kFriction>(wall_pair_[p_.species[i]], nrm, overlap, vrel,
                                                     p_.wall_spring[i], dt_, ft);
    p_.f[i] += fc;
    if constexpr (kFriction) p_.t[i] += ri * cross(ft, nrm);
  }
}

void Simulation::check_health() const {
  for (std::size_t i = 0; i < p_.size(); ++i) {
    const Vec3& x = p_.x[i];
    const Vec3& v = p_.v[i];
    if (!std::isfinite(x.x + x.y + x.z + v.x + v.y + v.z)) {
      std::ostringstream os;
      os << "non-finite state of particle " << p_.id[i] << " at t = " << time_ << " s (step "
         << step_ << "): the time step may be too large for the contact stiffness";
      throw RunError(os.str());
    }
    if (wall_.escaped(x)) {
      std::ostringstream os;
      os << "particle " << p_.id[i] << " left the tumbler at t = " << time_ << " s (step " << step_
         << "), |x| = " << norm(x) << " m > R = " << wall_.radius << " m";
      throw RunError(os.str());
    }
  }
}

EnergyBreakdown Simulation::energy() const {
  EnergyBreakdown e;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    const double m = 1.0 / p_.inv_mass[i];
    e.kinetic += 0.5 * m * norm2(p_.v[i]) + 0.5 / p_.inv_inertia[i] * norm2(p_.w[i]);
    e.potential -= m * dot(gravity_, p_.x[i]);
    Vec3 nrm, point;
    const double ov = wall_.overlap(p_.x[i], p_.radius[i], nrm, point);
    if (ov > 0) {
      const auto& c = wall_pair_[p_.species[i]];
      e.elastic += 0.5 * c.kn * ov * ov + 0.5 * c.kt * norm2(p_.wall_spring[i]);
    }
    for (std::uint32_t k = list_.start[i]; k < list_.start[i + 1]; ++k) {
      const std::uint32_t j = list_.nbr[k];
      const double ovp = p_.radius[i] + p_.radius[j] - norm(p_.x[i] - p_.x[j]);
      if (ovp > 0) {
        const auto& c = pair_[p_.species[i]][p_.species[j]];
        e.elastic += 0.5 * c.kn * ovp * ovp + 0.5 * c.kt * norm2(list_.spring[k]);
      }
    }
  }
  return e;
}

double Simulation::rms_speed() const {
  if (p_.size() == 0) return 0;
  double s = 0;
  for (const auto& v : p_.v) s += norm2(v);
  return std::sqrt(s / p_.size());
}

template void Simulation::pair_forces<true>();
template void Simulation::pair_forces<false>();
template void Simulation::wall_forces<true>();
template void Simulation::wall_forces<false>();

}  // namespace tumble
