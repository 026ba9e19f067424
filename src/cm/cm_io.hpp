#pragma once
// HDF5 files of the continuum model (layouts in docs/cm.md). Every file is written atomically
// (io::AtomicH5Writer) and carries the protocol, the model, the sign convention and the Tumble
// version as attributes of "/" (file_protocol.hpp). Tables read back are checked for consistent
// lengths before use (a damaged file: CorruptInputError, exit 3).
#include <string>
#include <vector>

#include "cm/island.hpp"
#include "cm/manifold.hpp"
#include "cm/mcm_summary.hpp"
#include "cm/poincare.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::cm {

void write_poincare(const std::string& path, const Protocol& pr, const PoincareOptions& opt,
                    const std::vector<PoincareSet>& sets);

// Periodic points found on shell r, and islands (shell r and any KAM-tube shells) in one flat
// table: /islands/vertices [V][2] with /islands/offsets [K+1], one row per island in the others.
void write_orbits(const std::string& path, const Protocol& pr, double r,
                  const std::vector<PeriodicPoint>& points, const std::vector<Island>& islands);
std::vector<PeriodicPoint> read_periodic_points(const std::string& path);
std::vector<Island> read_islands(const std::string& path);
// The islands of one shell radius from an orbits file (|r - island.r| < 1e-9).
std::vector<Island> islands_on_shell(const std::vector<Island>& all, double r);

// The manifolds file, written one manifold at a time as each is traced, so that a run holds
// only the manifold being traced (manifold_memory_bytes), however many hyperbolic orbits it has.
class ManifoldsWriter {
 public:
  ManifoldsWriter(const std::string& path, const Protocol& pr, double r,
                  const std::vector<PeriodicPoint>& points);
  void add(const Manifold& m);  // as /manifolds/<k>, k = 0, 1, ... in call order
  void commit();                // renames the finished file into place

 private:
  io::AtomicH5Writer writer_;
  std::vector<int> periods_;  // of `points`, for each manifold's "period" attribute
  int next_ = 0;
};
void write_manifolds(const std::string& path, const Protocol& pr, double r,
                     const std::vector<PeriodicPoint>& points, const std::vector<Manifold>& ms);

void write_mcm(const std::string& path, const Protocol& pr, const McmOptions& opt,
               const DriftGrid& grid, const McmResult& res, const McmSummary& summary);

}  // namespace tumble::cm
