#include "parallel/wide_bins.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::parallel {

void WideBins::assign(const std::vector<std::vector<double>>& from_rank, double ri_skin_max,
                      double period_z) {
  period_z_ = period_z;
  grids_.assign(from_rank.size(), Grid{});
  for (std::size_t r = 0; r < from_rank.size(); ++r) {
    std::vector<double> w;  // the rows with finite numbers
    for (std::size_t k = 0; k + 4 <= from_rank[r].size(); k += 4) {
      const double* row = &from_rank[r][k];
      if (std::isfinite(row[0]) && std::isfinite(row[1]) && std::isfinite(row[2]) &&
          std::isfinite(row[3]))
        w.insert(w.end(), row, row + 4);
    }
    const std::size_t m = w.size() / 4;
    if (m == 0) continue;
    Grid& g = grids_[r];
    Vec3 lo{w[0], w[1], w[2]}, hi = lo;
    double rw_max = 0;
    for (std::size_t k = 0; k < m; ++k) {
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], w[4 * k + d]);
        hi[d] = std::max(hi[d], w[4 * k + d]);
      }
      rw_max = std::max(rw_max, w[4 * k + 3]);
    }
    g.lo = lo;
    // (1e-6: the queries' margin of 1e-9 stays inside a cell.)
    g.cell = (ri_skin_max + rw_max) * (1 + 1e-6);
    auto count = [&] {
      double cells = 1;
      for (int d = 0; d < 3; ++d) cells *= std::floor((hi[d] - lo[d]) / g.cell) + 1;
      return cells;
    };
    while (count() > 8.0 * static_cast<double>(m) + 64) g.cell *= 2;
    std::size_t cells = 1;
    for (int d = 0; d < 3; ++d) {
      g.n[d] = static_cast<int>((hi[d] - lo[d]) / g.cell) + 1;
      cells *= static_cast<std::size_t>(g.n[d]);
    }
    auto cell_of = [&](const double* x) {
      int c[3];
      for (int d = 0; d < 3; ++d)
        c[d] = std::min(g.n[d] - 1, static_cast<int>((x[d] - g.lo[d]) / g.cell));
      return (static_cast<std::size_t>(c[0]) * g.n[1] + c[1]) * g.n[2] + c[2];
    };
    g.start.assign(cells + 1, 0);
    for (std::size_t k = 0; k < m; ++k) ++g.start[cell_of(&w[4 * k]) + 1];
    for (std::size_t c = 0; c < cells; ++c) g.start[c + 1] += g.start[c];
    std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
    g.rows.resize(4 * m);
    for (std::size_t k = 0; k < m; ++k)
      std::copy_n(&w[4 * k], 4, &g.rows[4 * fill[cell_of(&w[4 * k])]++]);
  }
}

bool WideBins::any_in_cells(const Grid& g, const Vec3& x, double ri_skin, double margin) const {
  int c[3];
  for (int d = 0; d < 3; ++d) {
    const double at = std::floor((x[d] - g.lo[d]) / g.cell);
    if (!(at >= -1 && at <= g.n[d])) return false;  // farther than a cell from all (or NaN)
    c[d] = static_cast<int>(at);
  }
  for (int i = std::max(0, c[0] - 1); i <= std::min(g.n[0] - 1, c[0] + 1); ++i)
    for (int j = std::max(0, c[1] - 1); j <= std::min(g.n[1] - 1, c[1] + 1); ++j)
      for (int k = std::max(0, c[2] - 1); k <= std::min(g.n[2] - 1, c[2] + 1); ++k) {
        const std::size_t cell = (static_cast<std::size_t>(i) * g.n[1] + j) * g.n[2] + k;
        for (std::uint32_t q = g.start[cell]; q < g.start[cell + 1]; ++q) {
          const double* w = &g.rows[4 * q];
          const double dx = x[0] - w[0], dy = x[1] - w[1], dz = x[2] - w[2];
          const double cut = (ri_skin + w[3]) * margin;
          if (dx * dx + dy * dy + dz * dz <= cut * cut) return true;
        }
      }
  return false;
}

bool WideBins::any_within(int r, const Vec3& x, double ri_skin, double margin) const {
  const Grid& g = grids_[static_cast<std::size_t>(r)];
  if (g.start.empty()) return false;
  if (any_in_cells(g, x, ri_skin, margin)) return true;
  if (period_z_ <= 0) return false;
  // Across the periodic ends: the nearest image is one of the two shifted ones.
  return any_in_cells(g, x + Vec3{0, 0, period_z_}, ri_skin, margin) ||
         any_in_cells(g, x - Vec3{0, 0, period_z_}, ri_skin, margin);
}

}  // namespace tumble::parallel
