#pragma once
// Helpers shared by the MPI tests: ranks, a scratch directory, the tiny rotating scene with its
// settled bed (settled once by world rank 0), and the distance between two runs.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/protocol.hpp"
#include "run/realization.hpp"
#include "scene/scene.hpp"

namespace tumble::testing {

inline int rank_of(MPI_Comm c) {
  int r = 0;
  MPI_Comm_rank(c, &r);
  return r;
}
inline int size_of(MPI_Comm c) {
  int n = 1;
  MPI_Comm_size(c, &n);
  return n;
}
inline int world_rank() { return rank_of(MPI_COMM_WORLD); }

// TUMBLE_TEST_SCRATCH/name, created by world rank 0 (collective over the world).
inline std::string scratch(const std::string& name) {
  const auto d = std::filesystem::path(TUMBLE_TEST_SCRATCH) / name;
  if (world_rank() == 0) std::filesystem::create_directories(d);
  MPI_Barrier(MPI_COMM_WORLD);
  return d.string();
}

// bst_tiny-like bed (2,085 particles) rotating biaxially at 15 rpm.
inline Scene tiny(std::vector<std::string> o = {}) {
  std::vector<std::string> all = {"tumbler.radius=0.02", "contact.collision_time=1e-3",
                                  "fill.bed_cache=" + scratch("beds"), "protocol.mode=biaxial",
                                  "protocol.rpm=15"};
  all.insert(all.end(), o.begin(), o.end());
  return parse_scene("", all, "tiny");
}

// The settled bed of `s`: settled once by world rank 0 (cached), then read by every rank
// (collective over the world).
inline Particles tiny_bed(const Scene& s) {
  if (world_rank() == 0) settled_bed(s, nullptr);
  MPI_Barrier(MPI_COMM_WORLD);
  return settled_bed(s, nullptr);
}

inline geometry::Protocol biaxial(const Scene& s) {
  return geometry::Protocol::biaxial(deg2rad(s.theta_z), deg2rad(s.theta_x), deg2rad(s.repose.deg),
                                     s.omega());
}

// Largest distance between the particles of two beds, matched by id (ids 0..N-1); nearest image
// along z when periodic with `period_z`.
inline double max_deviation(const Particles& a, const Particles& b, double period_z = 0) {
  std::vector<Vec3> by_id(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) by_id[a.id[i]] = a.x[i];
  double worst = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    Vec3 d = b.x[i] - by_id[b.id[i]];
    if (period_z > 0) d.z -= period_z * std::nearbyint(d.z / period_z);
    worst = std::max(worst, norm(d));
  }
  return worst;
}

}  // namespace tumble::testing
