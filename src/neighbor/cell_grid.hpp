#pragma once
// A uniform grid of box-shaped cells over a fixed box. Used to sort particles spatially (cache
// locality for the force loop) and to find neighbour candidates in the 27 surrounding cells.
#include <cstdint>
#include <vector>

#include "base/vec3.hpp"

namespace tumble::neighbor {

class CellGrid {
 public:
  CellGrid() = default;
  // Box [lo, hi], cells of every side >= min_cell, a whole number of cells in each direction.
  CellGrid(const Vec3& lo, const Vec3& hi, double min_cell);

  int nx() const { return n_[0]; }
  int ny() const { return n_[1]; }
  int nz() const { return n_[2]; }
  std::size_t cell_count() const { return static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]; }
  // Cell of a point (clamped into the box, so a stray particle still lands somewhere).
  std::uint32_t cell_of(const Vec3& p) const;
  std::uint32_t index(int i, int j, int k) const {
    return static_cast<std::uint32_t>((i * n_[1] + j) * n_[2] + k);
  }
  void coords(std::uint32_t c, int& i, int& j, int& k) const {
    k = static_cast<int>(c % n_[2]);
    j = static_cast<int>((c / n_[2]) % n_[1]);
    i = static_cast<int>(c / (static_cast<std::uint32_t>(n_[1]) * n_[2]));
  }

  // Stable counting sort of particles by layer, then cell: fills `perm` (new order -> old index)
  // and `cell_start` (layers x cell_count() + 1 entries: the particles of cell c of layer L are
  // [cell_start[L cell_count() + c], cell_start[L cell_count() + c + 1]) after permuting).
  // Without flags one layer: the order is by cell alone. With `border` (one flag per particle,
  // more than one rank) every particle with border[i] == 0 comes first, then the flagged ones.
  // With `state` (the rigid bulk: bulk_state) each of those splits in two, its moving particles
  // (state >= 0) first, then its frozen ones: layer L = (state ? 2 : 1) border[i] + frozen. The
  // frozen thus follow every moving particle of their border class, which keeps a moving row's
  // frozen partners above it in the list's half order and the moving rows in one or two runs.
  static int layer_count(bool border, bool state) { return (border ? 2 : 1) * (state ? 2 : 1); }
  void sort(const std::vector<Vec3>& x, std::vector<std::uint32_t>& perm,
            std::vector<std::uint32_t>& cell_start, const std::int32_t* state = nullptr,
            const std::uint8_t* border = nullptr) const;

 private:
  Vec3 lo_;
  double inv_cell_[3] = {1, 1, 1};
  int n_[3] = {1, 1, 1};
};

}  // namespace tumble::neighbor
