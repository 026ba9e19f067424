#pragma once
// Yu 2022 Fig. 5: particles in a plane through the bed that cuts two non-mixing regions. The
// KAM tubes are cone-like, with their apex towards the tumbler centre (Fig. 1(b)), so the plane
// through the centre and the two island centres cuts both tubes along their axes. Particles whose
// centres lie within a slab about the plane are binned on an n x n grid of in-plane coordinates
// (s1, s2) in [-1, 1]^2 (units of R); c_L of a bin is the large share of the binned solid volume.
// The tube boundaries are where the circles r = const of the plane enter or leave the islands of
// the CM's KAM shells.
#include <utility>
#include <vector>

#include "analysis/snapshot_data.hpp"
#include "base/vec3.hpp"
#include "cm/island.hpp"

namespace tumble::analysis {

struct SectionPlane {
  Vec3 e1, e2;  // orthonormal, in the plane; e1 towards the first direction
  Vec3 normal;
};

// The plane through the origin and directions a and b (not parallel).
SectionPlane plane_through(const Vec3& a, const Vec3& b);

// Fig. 5's default pair among the islands of one shell: the two of different orbits whose
// centres lie farthest apart on the Lambert disc; {-1, -1} when no two orbits are present.
std::pair<int, int> farthest_island_pair(const std::vector<cm::Island>& shell);

// The plane through the tumbler centre and the centres of two islands (Lambert disc points).
SectionPlane plane_through_islands(const cm::Island& a, const cm::Island& b);

// The same plane with its in-plane axes turned so that e2 points up (+y projected on the plane)
// and the bed lies at the bottom of a picture; unchanged if the plane is horizontal.
SectionPlane upright(const SectionPlane& p);

class SectionMap {
 public:
  explicit SectionMap(int n = 40) : large(n * n, 0.0), small(n * n, 0.0), n_(n) {}
  int n() const { return n_; }
  // Bins the particles of one configuration (lab frame) with |distance to the plane| <= half
  // width [m]; cell (i, j): s1 in [-1 + 2i/n, -1 + 2(i+1)/n], s2 likewise, flat i n + j.
  void add(const SnapshotData& s, const SectionPlane& plane, double half_width);
  std::vector<double> c_large() const;  // NaN where nothing was binned

  // Solid volume per bin, summed over configurations: `large` holds the mixture's mapped species
  // (the large one of a size-bidisperse bed, the light one of a density-bidisperse bed, as the
  // maps), `small` the other.
  std::vector<double> large, small;
  int samples = 0;

 private:
  int n_;
};

struct TubeCrossing {
  double r = 0;           // shell radius (units of R)
  double s1 = 0, s2 = 0;  // in-plane coordinates of the boundary point
  int island = -1;        // index in the islands list passed in
};

// Boundary points of the islands (any shells) on the plane: along each shell's circle in the
// plane, sampled at `samples` angles, the points where island membership changes.
std::vector<TubeCrossing> tube_crossings(const std::vector<cm::Island>& islands,
                                         const SectionPlane& plane, int samples = 4096);

}  // namespace tumble::analysis
