#pragma once
// A particle snapshot as the analyses read it back (the layout of io/snapshot.cpp: particles in
// global-id order, lab and tumbler-frame positions, provenance attributes), plus the few scene
// values the analyses need, taken from the resolved scene stored with it.
#include <cstdint>
#include <string>
#include <vector>

#include "base/particles.hpp"
#include "base/vec3.hpp"

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

  std::size_t size() const { return id.size(); }
  // The particles in the layout of the engine (positions, radii, species only), for the analyses
  // that take a Particles (concentration.hpp).
  Particles as_particles() const;
};

SnapshotData read_snapshot(const std::string& path);

// The snap_NNNNNN.h5 files of a directory, in order (empty if none).
std::vector<std::string> list_snapshots(const std::string& dir);

}  // namespace tumble::analysis
