#pragma once
// Particle snapshots (one HDF5 file each, particles in global-id order) and the XDMF sidecar that
// lets ParaView open the whole sequence as a time series.
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "scene/scene.hpp"

namespace tumble::io {

struct SnapshotEntry {
  std::string file;  // relative to the output directory
  double time = 0;
  std::size_t count = 0;
};

// Writes datasets id, species, radius, x (lab), x_tumbler, v, w and provenance attributes.
void write_snapshot(const std::string& path, const Simulation& sim, const Scene& scene);
// (Re)writes `dir/snapshots.xdmf` listing every entry as a temporal collection.
void write_xdmf(const std::string& dir, const std::vector<SnapshotEntry>& entries);
// Provenance attributes on the root group: version, git hash, resolved scene, seed, date.
void write_provenance(class H5File& f, const Scene& scene);

}  // namespace tumble::io
