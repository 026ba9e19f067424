#pragma once
// Non-mixing islands: the region around an elliptic periodic point bounded by its outermost
// closed invariant curve (a KAM curve; Yu 2022 Sec. I, Fig. 1). Found by launching orbits of
// P^n at increasing distance along a ray from the centre and keeping the farthest one that is a
// closed curve winding once around the centre (P^n keeps the cyclic order of its points), then
// refining that distance by bisection. The
// boundary is that orbit, ordered by angle about the centre, as a polygon in chart coordinates.
#include <cmath>
#include <optional>
#include <vector>

#include "cm/periodic.hpp"
#include "cm/polygon.hpp"
#include "cm/progress.hpp"

namespace tumble::cm {

struct IslandOptions {
  int iterations = 1000;         // iterates of P^n per test orbit
  int final_iterations = 10000;  // iterates certifying the boundary orbit (and its polygon)
  double step = 0.004;           // scan step in the normal-form radius (sqrt(area / pi) units)
  double max_radius = 0.45;      // largest distance from the centre (chart units)
  int bisections = 8;
  double max_gap = kPi / 3;  // largest angular gap an orbit may leave around the centre
  int order_defects = 0;     // iterates allowed to break the cyclic order (see island.cpp)
  int vertices = 256;        // polygon vertices kept (subsampled from the orbit)
  // Rays scanned from the centre, evenly spaced in the normal-form angle; the boundary is the
  // largest certified curve of all of them. One ray (towards the chart centre) can stop short
  // where a thin chaotic layer or a resonance chain crosses it inside the outermost curve.
  int rays = 1;
};

struct Island {
  int point = -1;  // index of the elliptic point in the periodic-point list
  int orbit = -1, period = 0;
  double r = 0;  // shell radius
  Vec2 center = Vec2::Zero();
  Polygon boundary;
  double extent = 0;           // distance from the centre to `launch`
  Vec2 launch = Vec2::Zero();  // the boundary orbit's starting point
};

// Coordinates around an elliptic point in which P^n is a rotation to first order,
// w = W (v - c) (Birkhoff normal form of the linear part; det W = 1). Angles about the centre are
// taken in w, so elongated islands are handled like round ones.
struct CentreFrame {
  Vec2 c = Vec2::Zero();
  Eigen::Matrix2d W = Eigen::Matrix2d::Identity();
  static CentreFrame of(const PeriodicPoint& pt);
  double angle(const Vec2& v) const {
    const Vec2 w = W * (v - c);
    return std::atan2(w.y(), w.x());
  }
};

// Is the orbit of P^n from v a closed curve winding once around the centre? On success `curve`
// holds the iterates (unordered).
bool closed_curve_around(const SectionMap& map, const CentreFrame& f, const Vec2& v, int n,
                         int iterations, const IslandOptions& opt,
                         std::vector<Vec2>* curve = nullptr);

// The island around one elliptic point, or nothing if not even the first scan step is regular.
std::optional<Island> island_around(const SectionMap& map, const PeriodicPoint& centre,
                                    const IslandOptions& opt);

// Islands around every elliptic point in `points` (indices refer to that list), skipping
// points inside an island already found (pass points sorted by period). The islands of one orbit
// are images of one boundary curve under P (island.cpp: orbit_islands).
// Progress counts elliptic points, weighted by their period.
std::vector<Island> find_islands(const SectionMap& map, const std::vector<PeriodicPoint>& points,
                                 const IslandOptions& opt, const Progress& progress = {});

// Bytes one island test holds at its peak, per iterate of the longer of `iterations` and
// `final_iterations`: the orbit (16 B) with its angles and orderings (20 B), or the orbit and
// the angle-sorted copy the polygon is drawn from (40 B). The islands themselves (`vertices`
// points each) are small beside it.
double island_memory_bytes(const IslandOptions& opt);

// Fraction of the chart area (whole shell) covered by the islands (disjoint by construction).
double island_area_fraction(const ShellChart& chart, const std::vector<Island>& islands);
// Fraction of the bulk disc covered by the islands: what a view from below can see.
double island_bulk_area_fraction(const ShellChart& chart, const std::vector<Island>& islands);
// Index of the island containing chart point v, or -1.
int island_containing(const std::vector<Island>& islands, const Vec2& v);

}  // namespace tumble::cm
