#pragma once
// A particle snapshot as the analyses read it back (the layout of io/snapshot.cpp: particles in
// global-id order, lab and tumbler-frame positions, provenance attributes), plus the few scene
// values the analyses need, taken from the resolved scene stored with it.
#include <cstdint>
#include <string>
#include <vector>

#include "base/particles.hpp"
#include "base/vec3.hpp"
#include "scene/mixture.hpp"

namespace tumble::analysis {

struct SnapshotData {
  std::string path;
  std::vector<std::int64_t> id;  // ascending
  std::vector<std::int32_t> species;
  std::vector<double> radius;
  std::vector<Vec3> x, x_tumbler;  // lab frame, tumbler frame [m]
  double time = 0, iteration = 0;
  std::string scene_text;  // the resolved scene (provenance)
  // From the scene: tumbler radius, protocol angles [deg], density ratio rho_large / rho_small.
  double R = 0, theta_z = 0, theta_x = 0, density_ratio = 1;
  // tumbler.shape and protocol.mode as the scene file writes them: the maps of the sphere and the
  // islands of the biaxial protocol are not those of a cylinder or of another protocol.
  std::string shape = "sphere", mode = "biaxial";
  // Which species is which (the scene's mixture): the analyses count its mapped species, the
  // large one of a size-bidisperse bed and the light one of a density-bidisperse bed.
  Mixture mixture;

  std::size_t size() const { return id.size(); }
  // The particles in the layout of the engine (positions, radii, species only), for the analyses
  // that take a Particles (concentration.hpp).
  Particles as_particles() const;
};

SnapshotData read_snapshot(const std::string& path);

// The snap_NNNNNN.h5 files of a directory, in order (empty if none).
std::vector<std::string> list_snapshots(const std::string& dir);

// A snapshot "at iteration N" lies near N, not on it: within half a time step (run/
// snapshot_observer.hpp: snapshot_step), or, in runs written before 2026-11-28, drifting by
// ~1e-4 after 35 iterations (35.0000014, 34.99994); whole iterations are compared with this slack.
inline constexpr double kIterationSlack = 1e-3;

// Whether a snapshot at iteration n belongs to the window first <= N <= last (both ends in).
inline bool in_iteration_window(double n, double first, double last) {
  return n >= first - kIterationSlack && n <= last + kIterationSlack;
}

// Per snapshot (iterations ascending): whether it repeats its predecessor's configuration. A run
// that ends a few steps after a periodic snapshot writes its end as well (34.99994 and 35.0 in
// older runs; now only when the run's length is not a whole number of intervals); a
// snapshot closer to the one before than 1% of the list's median spacing is such a repeat, so
// stroboscopic analyses count each configuration once (the first).
std::vector<bool> repeated_snapshots(const std::vector<double>& iterations);

}  // namespace tumble::analysis
