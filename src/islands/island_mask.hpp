#pragma once
// The continuum model's non-mixing islands as the DEM analyses see them: closed polygons in the
// Lambert chart of the lower hemisphere viewed from below (lambert.hpp). On the bulk part of a
// CM shell the chart is exactly that projection of the direction (cm/shell_chart.hpp), so a
// particle is "in an island" when the Lambert image of its lab-frame direction lies inside one
// of the polygons: the same test that draws the red curves of Yu 2022 Figs. 4 and 8.
#include <vector>

#include "base/vec3.hpp"
#include "cm/polygon.hpp"
#include "projection/lambert.hpp"

namespace tumble::analysis {

class IslandMask {
 public:
  IslandMask() = default;
  // `group`: for each polygon, the island index it counts as (a secondary chain's islands count
  // as the primary island they surround: cm::primary_island_of); empty: its own index.
  explicit IslandMask(std::vector<cm::Polygon> islands, std::vector<int> group = {})
      : islands_(std::move(islands)), group_(std::move(group)) {}

  int size() const { return static_cast<int>(islands_.size()); }
  const cm::Polygon& polygon(int k) const { return islands_[k]; }

  // Index of the island containing the disc point (its group), or -1 (islands do not overlap).
  int island_of(DiscPoint p) const;
  // Same for a direction (need not be unit); -1 on the upper hemisphere (u_y > 0), which the
  // view from below does not show.
  int island_of_direction(const Vec3& u) const;
  // Share of the unit disc (the whole view from below) the islands cover.
  double area_fraction() const;
  // Share of each grid cell's area inside an island, from sub x sub sample points per cell.
  // The Shirley-Chiu map has a constant Jacobian, so points evenly spaced in the square are
  // evenly spaced in area, and the share is exact up to O(1/sub) at the island edges.
  std::vector<double> cell_coverage(const LambertGrid& grid, int sub = 8) const;

 private:
  std::vector<cm::Polygon> islands_;
  std::vector<int> group_;
};

}  // namespace tumble::analysis
