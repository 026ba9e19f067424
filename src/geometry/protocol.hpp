#pragma once
// The tumbler's rotation as a function of time. The tumbler never moves in space; its wall moves
// with velocity Ω(t) × r. The protocol is a list of segments of constant Ω; the orientation
// (tumbler frame -> lab frame) is composed exactly segment by segment, so analyses can express
// particles in the tumbler frame without integration error.
#include <cstdint>
#include <string>
#include <vector>

#include "base/vec3.hpp"

namespace tumble::geometry {

struct Segment {
  Vec3 axis;               // unit axis (lab frame)
  double omega = 0;        // signed angular speed about `axis` [rad/s]
  double duration = 0;     // [s]
  const char* label = "";  // "tilt", "rotate", "tilt back", "spin"
};

class Protocol {
 public:
  // No rotation at all (settling, benchmarks of a bed at rest).
  static Protocol at_rest();
  // Biaxial spherical tumbler (Yu 2022 Sec. II): about z by θz, then about x by θx; each rotation
  // is tilt by the repose angle β, rotate θ, tilt back β, all at angular speed ω. Angles in
  // radians.
  static Protocol biaxial(double theta_z, double theta_x, double repose, double omega);
  // Constant Ω about a single horizontal axis ('x' or 'z').
  static Protocol single_axis(char axis, double omega);

  // Angular velocity of the tumbler at time t.
  Vec3 omega(double t) const;
  // Orientation: maps tumbler-frame coordinates to the lab frame at time t.
  Mat3 orientation(double t) const;
  // Duration of one protocol iteration (period); 0 when not periodic.
  double period() const { return period_; }
  // Protocol iteration (periods completed, fractional) at time t.
  double iteration(double t) const { return period_ > 0 ? t / period_ : 0.0; }
  bool periodic() const { return period_ > 0; }
  // Segment label at time t (for progress output).
  const char* phase(double t) const;
  // The axis of the segment of time t (unit, lab frame; as listed, whatever Ω's sense), and the
  // angle in radians the wall has turned since that segment began (for a constant Ω: since t = 0;
  // at rest: a zero axis and 0). The flowing layer of a biaxial run is measured about the first.
  Vec3 segment_axis(double t) const;
  double segment_turn(double t) const;
  // Which segment of the whole run time t lies in (periods completed x segments per period +
  // segment): two times share it exactly when Ω is constant between them. 0 for a constant Ω.
  std::int64_t segment_count(double t) const;
  // Ω of the segment numbered `count` as segment_count numbers them (for a constant Ω: that Ω).
  // Two segments in a row with the same Ω are one motion with two names (a tilt by β and the
  // rotation after it turn about the same axis at the same speed).
  Vec3 segment_omega(std::int64_t count) const;

 private:
  // Segment of time t within its period, and the time `into` it has run.
  std::size_t segment_at(double t, double& into) const;
  void locate(double t, std::size_t& seg, double& tau, Mat3& start) const;
  std::vector<Segment> segments_;
  std::vector<Mat3> start_orientation_;  // orientation at each segment's start (first period)
  Mat3 period_rotation_;                 // net rotation of one period
  double period_ = 0;
  Vec3 constant_omega_;
  bool constant_ = true;
};

}  // namespace tumble::geometry
