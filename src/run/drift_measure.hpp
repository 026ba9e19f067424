#pragma once
// Measures the MCM's axial drift grid from a DEM run (Yu 2022 App. A): the axial velocity of large
// particles near the free surface of the flowing layer, sampled (every 0.1 s in the paper) while
// they flow downstream, averaged per cell of an n x n grid over the layer's footprint.
//
// Frames: the DEM's free surface is tilted by the repose angle β about the axis of the current
// rotation; untilting by β about Ω̂ and applying the continuum model's phase frame
// (cm/protocol.hpp: z phase (x, y, z); x phase (z, y, −x)) gives (streamwise, normal, axial)
// coordinates with the surface at normal = 0, which is the drift-grid convention of
// cm/drift_grid.hpp (lengths in R, velocities in ω R).
//
// Approximations, stated: "near the free surface" is a centre within d_L of the plane through
// the tumbler centre (the surface of a half-full bed); "flowing" is a positive streamwise
// velocity (the paper tracks a particle from its entry until the streamwise velocity reverses);
// only the "rotate" segments of the protocol are sampled (during the tilts the bed moves as a
// solid body).
#include <cstdint>
#include <string>
#include <vector>

#include "base/particles.hpp"
#include "cm/drift_grid.hpp"

namespace tumble::analysis {

class DriftGridMeter {
 public:
  DriftGridMeter(int n, double tumbler_radius, double repose_rad, double omega, double d_large);

  // Empty statistics of this grid, to sample into.
  cm::DriftStatistics zeros() const { return cm::DriftStatistics::zeros(n_); }
  // Samples the large particles (species 1) for the rotation with angular velocity `omega_vec`
  // (about x or z) into `into` (of this grid's size: CorruptInputError otherwise, e.g. the sums
  // of a damaged checkpoint). Returns the number of particles sampled.
  std::int64_t sample(const Particles& p, const Vec3& omega_vec, cm::DriftStatistics& into) const;
  // Mean and standard deviation per cell; cells never sampled get v = 0 and the mean σ of the
  // sampled cells (the MCM needs a σ everywhere in the footprint).
  cm::DriftGrid grid(const cm::DriftStatistics& statistics, const std::string& source) const;
  // Frame of a lab vector for the rotation `omega_vec` (exposed for tests).
  Vec3 to_layer_frame(const Vec3& lab, const Vec3& omega_vec) const;

 private:
  int n_;
  double R_, repose_, omega_, d_large_;
};

}  // namespace tumble::analysis
