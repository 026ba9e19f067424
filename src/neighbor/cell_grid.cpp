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
                    std::vector<std::uint32_t>* moving_end, const std::uint8_t* border) const {
  const std::size_t n = x.size();
  // Keys: the layer cell (the cell, or with `border` the cell plus cell_count() for a flagged
  // particle), or (with the states) twice that plus one for a frozen particle.
  const std::size_t cells = (border ? 2 : 1) * cell_count();
  const std::size_t per = state ? 2 : 1, keys = per * cells;
  std::vector<std::uint32_t> key(n), key_start(keys + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t cell = cell_of(x[i]) + (border && border[i] ? cell_count() : 0);
    key[i] = static_cast<std::uint32_t>(per * cell + (state && state[i] < 0 ? 1 : 0));
    ++key_start[key[i] + 1];
  }
  for (std::size_t c = 0; c < keys; ++c) key_start[c + 1] += key_start[c];
  std::vector<std::uint32_t> fill(key_start.begin(), key_start.end() - 1);
  perm.resize(n);
  for (std::size_t i = 0; i < n; ++i) perm[fill[key[i]]++] = static_cast<std::uint32_t>(i);
  if (!state) {
    cell_start = std::move(key_start);
    return;
  }
  cell_start.resize(cells + 1);
  moving_end->resize(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    cell_start[c] = key_start[2 * c];
    (*moving_end)[c] = key_start[2 * c + 1];
  }
  cell_start[cells] = key_start[keys];
}

}  // namespace tumble::neighbor
