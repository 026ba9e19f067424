#pragma once
// Closed polygons in a chart (island boundaries in Lambert coordinates): area and point
// membership, so DEM analyses can ask "is this particle inside an island" with the same shape
// that is drawn in the overlays.
#include <vector>

#include "cm/flow_field.hpp"

namespace tumble::cm {

struct Polygon {
  std::vector<Vec2> vertices;  // in order, last vertex joined to the first

  // Shoelace area (positive for counter-clockwise order).
  double signed_area() const;
  double area() const;
  // Even-odd (crossing number) rule; points on an edge may go either way.
  bool contains(const Vec2& q) const;
  Vec2 centroid() const;
};

// The part of `poly` inside the disc |v| <= radius (Sutherland-Hodgman against the inscribed
// regular polygon with `sides` edges; relative area error O(1 / sides^2)).
Polygon clip_to_disc(const Polygon& poly, double radius, int sides = 2048);

}  // namespace tumble::cm
