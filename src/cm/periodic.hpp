#pragma once
// Periodic points of the section map (Yu 2022 App. B): solve P^n(v) = v by Newton's method in
// the shell chart with a finite-difference Jacobian, from a grid of starting points; keep each
// point once, at its minimal period; classify by the 2x2 Jacobian of P^n (det = 1 for bulk ->
// bulk): |tr| < 2 elliptic (island centre) with rotation angle phi = acos(tr/2), |tr| > 2
// hyperbolic with eigenvalues lambda, 1/lambda. The 3D Jacobian of App. B has a third eigenvalue
// 1 along the shell normal (the invariant R), which the chart removes.
#include <Eigen/Core>
#include <vector>

#include "cm/progress.hpp"
#include "cm/section_map.hpp"

namespace tumble::cm {

enum class Stability { Elliptic = 0, Hyperbolic = 1, Parabolic = 2 };
const char* to_string(Stability s);

struct PeriodicPoint {
  Vec2 v = Vec2::Zero();  // chart (Lambert) coordinates
  Vec3 p = Vec3::Zero();  // position at the start of a period
  int period = 0;
  Eigen::Matrix2d jacobian = Eigen::Matrix2d::Identity();
  double trace = 2, det = 1;
  Stability type = Stability::Parabolic;
  double rotation = 0;  // elliptic: phi = acos(tr/2) in (0, pi)
  double lambda = 1;    // hyperbolic: the eigenvalue with |lambda| > 1
  Vec2 unstable = Vec2::Zero(), stable = Vec2::Zero();  // hyperbolic: unit eigenvectors
  int orbit = -1;  // index of the orbit (points mapped into each other by P)
};

struct PeriodicSearch {
  int max_period = 6;
  int grid = 40;            // starting points: grid x grid over the chart's bounding square
  double tol = 1e-11;       // Newton residual |P^n(v) - v|
  double fd_step = 1e-6;    // central-difference step for the Jacobian
  double merge = 1e-6;      // points closer than this are the same point
  double parabolic = 1e-6;  // | |tr| - 2 | below this: parabolic
  int max_newton = 40;
};

// Central-difference Jacobian of P^n at v; false if a stencil point leaves the chart.
bool section_jacobian(const SectionMap& map, const Vec2& v, int n, double h, Eigen::Matrix2d& J);
// Newton from `guess` for a point of period n (not necessarily minimal).
bool newton_periodic(const SectionMap& map, Vec2 guess, int n, const PeriodicSearch& opt,
                     Vec2& out);
// Jacobian, trace, type, rotation angle or eigen-directions of a found point.
void classify(const SectionMap& map, PeriodicPoint& pt, const PeriodicSearch& opt);
// All periodic points of minimal period 1..max_period found from the grid, classified and
// grouped into orbits (sorted by period, then orbit). Progress counts Newton starts, weighted by
// their period (a start of period n maps n periods per Newton step).
std::vector<PeriodicPoint> find_periodic_points(const SectionMap& map, const PeriodicSearch& opt,
                                                const Progress& progress = {});

// Bytes find_periodic_points and write_orbits may hold for the points found: at most one new
// point per Newton start and period (grid^2 x max_period; far fewer in practice), each kept as a
// PeriodicPoint and copied once more into the writer's columns (~164 B). An upper bound, so that
// a search that cannot fit is refused before it starts.
double periodic_search_memory_bytes(const PeriodicSearch& opt);

}  // namespace tumble::cm
