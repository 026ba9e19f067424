#include "neighbor/cell_grid.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::neighbor {

CellGrid::CellGrid(const Vec3& lo, const Vec3& hi, double min_cell) : lo_(lo) {
  for (int d = 0; d < 3; ++d)
    n_[d] = std::max(1, static_cast<int>(std::floor((hi[d] - lo[d]) / min_cell)));
  // Each direction divided into a whole number of cells (a periodic direction must be).
  for (int d = 0; d < 3; ++d) inv_cell_[d] = n_[d] / (hi[d] - lo[d]);
}

std::uint32_t CellGrid::cell_of(const Vec3& p) const {
  int c[3];
  for (int d = 0; d < 3; ++d) {
    c[d] = static_cast<int>(std::floor((p[d] - lo_[d]) * inv_cell_[d]));
    c[d] = std::min(std::max(c[d], 0), n_[d] - 1);
  }
  return index(c[0], c[1], c[2]);
}

void CellGrid::sort(const std::vector<Vec3>& x, std::vector<std::uint32_t>& perm,
                    std::vector<std::uint32_t>& cell_start, const std::int32_t* state,
                    const std::uint8_t* border) const {
  const std::size_t n = x.size(), cells = cell_count();
  const std::size_t per_class = state ? 2 : 1;
  const std::size_t keys = static_cast<std::size_t>(layer_count(border, state)) * cells;
  std::vector<std::uint32_t> key(n);
  cell_start.assign(keys + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t layer =
        per_class * (border && border[i] ? 1 : 0) + (state && state[i] < 0 ? 1 : 0);
    key[i] = static_cast<std::uint32_t>(layer * cells + cell_of(x[i]));
    ++cell_start[key[i] + 1];
  }
  for (std::size_t c = 0; c < keys; ++c) cell_start[c + 1] += cell_start[c];
  std::vector<std::uint32_t> fill(cell_start.begin(), cell_start.end() - 1);
  perm.resize(n);
  for (std::size_t i = 0; i < n; ++i) perm[fill[key[i]]++] = static_cast<std::uint32_t>(i);
}

}  // namespace tumble::neighbor
