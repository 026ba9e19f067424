#include "geometry/protocol.hpp"

#include <cmath>

namespace tumble::geometry {

// Sign convention, shared with the continuum model (docs/cm.md, docs/architecture.md, "Continuum
// model notes"): a "rotation about z" turns the tumbler with Ω = −ω ẑ, so the bulk moves with u =
// (y, −x, 0) (y up); a "rotation about x" is that motion conjugated by a quarter turn about the
// vertical axis, Ω = +ω x̂. With the opposite x sense the DEM would be the mirror image (x → −x) of
// the continuum model's islands.
namespace {
const Vec3 kZ{0, 0, 1}, kX{1, 0, 0};
}

Protocol Protocol::at_rest() { return Protocol{}; }

Protocol Protocol::single_axis(char axis, double omega) {
  Protocol p;
  p.constant_ = true;
  p.constant_omega_ = axis == 'z' ? kZ * (-omega) : kX * omega;
  return p;
}

Protocol Protocol::biaxial(double theta_z, double theta_x, double repose, double omega) {
  Protocol p;
  p.constant_ = false;
  for (int k = 0; k < 2; ++k) {
    const Vec3 axis = k == 0 ? kZ : kX;
    const double sense = k == 0 ? -1.0 : 1.0;  // see the convention above
    const double theta = k == 0 ? theta_z : theta_x;
    if (repose > 0) p.segments_.push_back({axis, sense * omega, repose / omega, "tilt"});
    if (theta > 0) p.segments_.push_back({axis, sense * omega, theta / omega, "rotate"});
    if (repose > 0) p.segments_.push_back({axis, -sense * omega, repose / omega, "tilt back"});
  }
  Mat3 q = Mat3::identity();
  for (const auto& s : p.segments_) {
    p.start_orientation_.push_back(q);
    p.period_ += s.duration;
    q = Mat3::rotation(s.axis, s.omega * s.duration) * q;
  }
  p.period_rotation_ = q;
  if (p.segments_.empty()) p.constant_ = true;  // θ = 0 and β = 0: nothing moves
  return p;
}

std::size_t Protocol::segment_at(double t, double& into) const {
  double rem = t - std::floor(t / period_) * period_;
  if (rem < 0) rem = 0;
  std::size_t seg = 0;
  while (seg + 1 < segments_.size() && rem >= segments_[seg].duration) {
    rem -= segments_[seg].duration;
    ++seg;
  }
  into = rem;
  return seg;
}

void Protocol::locate(double t, std::size_t& seg, double& tau, Mat3& start) const {
  // Whole periods first: repeated products of orthogonal matrices stay orthogonal to round-off.
  const long k = static_cast<long>(std::floor(t / period_));
  Mat3 base = Mat3::identity();
  for (long i = 0; i < k; ++i) base = period_rotation_ * base;
  seg = segment_at(t, tau);
  start = start_orientation_[seg] * base;
}

Vec3 Protocol::omega(double t) const {
  if (constant_) return constant_omega_;
  double into;
  const auto& s = segments_[segment_at(t, into)];
  return s.axis * s.omega;
}

Mat3 Protocol::orientation(double t) const {
  if (constant_) {
    const double w = norm(constant_omega_);
    if (w == 0) return Mat3::identity();
    return Mat3::rotation(constant_omega_ * (1.0 / w), w * t);
  }
  std::size_t seg;
  double tau;
  Mat3 start;
  locate(t, seg, tau, start);
  const auto& s = segments_[seg];
  return Mat3::rotation(s.axis, s.omega * tau) * start;
}

const char* Protocol::phase(double t) const {
  if (constant_) return norm(constant_omega_) > 0 ? "spin" : "rest";
  double into;
  return segments_[segment_at(t, into)].label;
}

Vec3 Protocol::segment_axis(double t) const {
  if (constant_) {
    const double w = norm(constant_omega_);
    return w > 0 ? constant_omega_ * (1.0 / w) : Vec3{};
  }
  double into;
  return segments_[segment_at(t, into)].axis;
}

double Protocol::segment_turn(double t) const {
  if (constant_) return norm(constant_omega_) * t;
  double into;
  const auto& s = segments_[segment_at(t, into)];
  return std::abs(s.omega) * into;
}

std::int64_t Protocol::segment_count(double t) const {
  if (constant_) return 0;
  double into;
  const auto seg = static_cast<std::int64_t>(segment_at(t, into));
  const auto periods = static_cast<std::int64_t>(std::floor(t / period_));
  return periods * static_cast<std::int64_t>(segments_.size()) + seg;
}

Vec3 Protocol::segment_omega(std::int64_t count) const {
  if (constant_) return constant_omega_;
  const auto n = static_cast<std::int64_t>(segments_.size());
  const auto& s = segments_[static_cast<std::size_t>(((count % n) + n) % n)];
  return s.axis * s.omega;
}

}  // namespace tumble::geometry
