#pragma once
// Non-mixing islands: the region around an elliptic periodic point bounded by its outermost
// closed invariant curve (a KAM curve; Yu 2022 Sec. I, Fig. 1). Found by launching orbits of
// P^n at increasing distance along a ray from the centre and keeping the farthest one that is a
// closed curve winding once around the centre (P^n keeps the cyclic order of its points), then
// refining that distance by bisection. The
// boundary is that orbit, ordered by angle about the centre, as a polygon in chart coordinates.
#include <cmath>
#include <optional>
#include <string>
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
  // where a thin chaotic layer or a resonance chain crosses it inside the outermost curve
  // (docs/cm.md: the outermost certified curve moves by ~1 % in area from ray to ray in the
  // sticky layer at the islands' edge; 16 rays make mirror-image islands agree to 0.1 %).
  int rays = 16;
  // How an orbit is certified as an invariant curve and ordered into a polygon:
  //  - angle: by its points' angle about the centre; P^n must keep their cyclic order. Holds
  //    only for curves that are star-shaped about the centre in the normal-form frame, which the
  //    outer curves of large islands are not (docs/cm.md).
  //  - circle (the default): by the circle coordinate k ρ mod 1 of the k-th iterate (ρ the rotation
  //  number of
  //    P^n on the curve, a weighted Birkhoff average of the angle increments). The ordered points
  //    must wind once around the centre, their polygon be no longer than `max_length_ratio` times
  //    their convex hull's perimeter, and no edge longer than `max_edge_ratio` times the mean
  //    edge. A chaotic orbit has no rotation number: ordered by a false one its polygon zigzags
  //    across the orbit and is many times longer than the hull.
  enum class Order { angle, circle };
  Order order = Order::circle;
  double max_length_ratio = 3;
  double max_edge_ratio = 25;
  // Secondary chains outside each island's boundary (resonances p/q of P^n about its centre with
  // q <= max_chain_q) get islands of their own (chain_islands); 0: none. At (90°, 90°) a 3/7
  // chain holds 1.4 % of the disc's regular orbits outside the primary islands (docs/cm.md).
  int max_chain_q = 12;
  // Rays per chain island (each of its n q members is scanned, the largest curve kept).
  int chain_rays = 8;
  // Where θz = θx, mirror-image orbits get congruent islands: the larger orbit's boundaries
  // mapped by the half-iteration symmetry onto the other's (docs/cm.md).
  bool mirror = true;
};

struct Island {
  int point = -1;  // index of the elliptic point in the periodic-point list
  int orbit = -1, period = 0;
  double r = 0;  // shell radius
  Vec2 center = Vec2::Zero();
  Polygon boundary;
  double extent = 0;           // distance from the centre to `launch`
  Vec2 launch = Vec2::Zero();  // the boundary orbit's starting point
  // A secondary chain's island: the orbit of the island it surrounds; -1 for a primary island.
  int parent_orbit = -1;
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
// holds the iterates in their order along the curve (opt.order says how it is found).
bool closed_curve_around(const SectionMap& map, const CentreFrame& f, const Vec2& v, int n,
                         int iterations, const IslandOptions& opt,
                         std::vector<Vec2>* curve = nullptr);

// The island around one elliptic point, or nothing if not even the first scan step is regular.
std::optional<Island> island_around(const SectionMap& map, const PeriodicPoint& centre,
                                    const IslandOptions& opt);

// The secondary island chains just outside `island` (around elliptic point `centre`): orbits of
// P^n launched along the rays beyond its boundary whose rotation number about the centre is a
// rational p/q (a resonance outside the last invariant circle: regular, but enclosed by no curve
// around the centre) lead, by Newton from the mean of every q-th iterate, to an elliptic orbit of
// period n q, whose islands are found as for any orbit. Chains get orbit indices from `orbit_id`
// on and parent_orbit = island.orbit.
// Seeds inside any island of `found` are skipped.
std::vector<Island> chain_islands(const SectionMap& map, const PeriodicPoint& centre,
                                  const Island& island, const std::vector<Island>& found,
                                  const IslandOptions& opt, int orbit_id);

// Islands around every elliptic point in `points` (indices refer to that list), skipping
// points inside an island already found (pass points sorted by period). The islands of one orbit
// are images of one boundary curve under P (island.cpp: orbit_islands).
// Progress counts elliptic points, weighted by their period.
std::vector<Island> find_islands(const SectionMap& map, const std::vector<PeriodicPoint>& points,
                                 const IslandOptions& opt, const Progress& progress = {});

// Bytes one island test holds at its peak, per iterate of the longer of `iterations` and
// `final_iterations`: the orbit (16 B) with its angles and orderings (20 B), or the orbit and
// the angle-sorted copy the polygon is drawn from (40 B); with the circle order, also the angle
// steps, phases, ordered copy and hull (112 B in all). The islands themselves (`vertices`
// points each) are small beside it.
double island_memory_bytes(const IslandOptions& opt);

// A short name of the options that shape a boundary ("circle8": circle order, 8 rays), for the
// names of cached island files: islands found another way are not reused silently.
std::string island_method_tag(const IslandOptions& opt);

// Fraction of the chart area (whole shell) covered by the islands (disjoint by construction).
double island_area_fraction(const ShellChart& chart, const std::vector<Island>& islands);
// Fraction of the bulk disc covered by the islands: what a view from below can see.
double island_bulk_area_fraction(const ShellChart& chart, const std::vector<Island>& islands);
// For each island, the primary island it belongs to: itself, or for a secondary chain's island
// the nearest island of its parent orbit (P^n maps the chain around that island onto itself).
std::vector<int> primary_island_of(const std::vector<Island>& islands);
// Index of the island containing chart point v, or -1.
int island_containing(const std::vector<Island>& islands, const Vec2& v);

}  // namespace tumble::cm
