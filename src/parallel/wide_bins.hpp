#pragma once
// The wide particles of a size mixture that the other ranks sent at a rebuild (centre and radius,
// Domain::thin_halo), binned by cell per source rank, so that the thin halo's test "is one of
// rank r's wide particles within r_i + r_w + skin of this thin particle?" looks at the few in the
// neighbouring cells, not at all of them (the scan grows as border area squared: fine at 2 ranks
// of a small bed, ~10 tests per particle-step for 10^6 particles a rank with many large ones).
#include <cstdint>
#include <vector>

#include "base/vec3.hpp"

namespace tumble::parallel {

class WideBins {
 public:
  // from_rank[r]: 4 doubles per particle (x, y, z, radius). `ri_skin_max`: the largest r_i +
  // skin a query will ask with; the cells are at least that plus the largest r_w, so that the 27
  // cells around a point hold every particle within reach (and coarser when the particles are
  // spread far apart, so that a grid never has many more cells than particles). A row with a
  // position that is not finite is left out (the health check reports such a particle).
  // `period_z` > 0: positions are periodic in z with that period.
  void assign(const std::vector<std::vector<double>>& from_rank, double ri_skin_max,
              double period_z);
  // Whether a wide particle of rank r lies within (r_i + r_w + skin) * margin of x (the nearest
  // image in z when periodic); `ri_skin` = r_i + skin.
  bool any_within(int r, const Vec3& x, double ri_skin, double margin) const;

 private:
  struct Grid {  // one source rank's particles, counting-sorted by cell (CSR)
    Vec3 lo;
    double cell = 1;
    int n[3] = {0, 0, 0};
    std::vector<std::uint32_t> start;  // per cell, into `rows`
    std::vector<double> rows;          // 4 doubles per particle, in cell order
  };
  bool any_in_cells(const Grid& g, const Vec3& x, double ri_skin, double margin) const;
  std::vector<Grid> grids_;
  double period_z_ = 0;
};

}  // namespace tumble::parallel
