#include "islands/island_mask.hpp"

#include <cmath>

namespace tumble::analysis {

int IslandMask::island_of(DiscPoint p) const {
  const cm::Vec2 q(p.X, p.Z);
  for (int k = 0; k < size(); ++k)
    if (islands_[k].contains(q)) return group_.empty() ? k : group_[k];
  return -1;
}

int IslandMask::island_of_direction(const Vec3& u) const {
  const double n = norm(u);
  if (n == 0 || u.y > 0) return -1;
  return island_of(lambert_from_below(u.x / n, u.y / n, u.z / n));
}

double IslandMask::area_fraction() const {
  double a = 0;
  for (const auto& poly : islands_) a += cm::clip_to_disc(poly, 1.0).area();
  return a / kPi;
}

std::vector<double> IslandMask::cell_coverage(const LambertGrid& grid, int sub) const {
  const int n = grid.n();
  std::vector<double> cover(grid.cells(), 0.0);
  if (islands_.empty()) return cover;
  const double h = 2.0 / n, hs = h / sub;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      int in = 0;
      for (int si = 0; si < sub; ++si)
        for (int sj = 0; sj < sub; ++sj) {
          const double a = -1 + i * h + (si + 0.5) * hs;
          const double b = -1 + j * h + (sj + 0.5) * hs;
          if (island_of(square_to_disc(a, b)) >= 0) ++in;
        }
      cover[grid.flat(i, j)] = static_cast<double>(in) / (sub * sub);
    }
  return cover;
}

}  // namespace tumble::analysis
