#include "cm/island.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace tumble::cm {
namespace {

struct Polar {
  double angle;
  Vec2 v;
};

// The points of a closed curve around the centre, ordered by angle and thinned to about
// `vertices`.
Polygon polygon_from_curve(const CentreFrame& f, const std::vector<Vec2>& pts, int vertices) {
  std::vector<Polar> polar;
  polar.reserve(pts.size());
  for (const Vec2& v : pts) polar.push_back({f.angle(v), v});
  std::sort(polar.begin(), polar.end(),
            [](const Polar& a, const Polar& b) { return a.angle < b.angle; });
  Polygon poly;
  const std::size_t stride = std::max<std::size_t>(1, polar.size() / std::max(vertices, 3));
  for (std::size_t k = 0; k < polar.size(); k += stride) poly.vertices.push_back(polar[k].v);
  return poly;
}

}  // namespace

CentreFrame CentreFrame::of(const PeriodicPoint& pt) {
  CentreFrame f;
  f.c = pt.v;
  if (pt.type != Stability::Elliptic) return f;
  // J = cos(phi) I + sin(phi) K with K^2 = -I, det K = 1; Q = +-Omega K, Omega = [[0,1],[-1,0]],
  // is symmetric, has det 1 and J^T Q J = Q. With Q = W^T W, W J W^-1 is a rotation.
  const Eigen::Matrix2d K =
      (pt.jacobian - std::cos(pt.rotation) * Eigen::Matrix2d::Identity()) / std::sin(pt.rotation);
  Eigen::Matrix2d Q;
  Q << K(1, 0), -K(0, 0), -K(0, 0), -K(0, 1);
  if (Q(0, 0) < 0) Q = -Q;
  const double w00 = std::sqrt(Q(0, 0)), w01 = Q(0, 1) / w00;
  const double w11 = std::sqrt(std::max(Q(1, 1) - w01 * w01, 1e-300));
  f.W << w00, w01, 0, w11;
  return f;
}

bool closed_curve_around(const SectionMap& map, const CentreFrame& f, const Vec2& v0, int n,
                         int iterations, const IslandOptions& opt, std::vector<Vec2>* curve) {
  const Vec2& c = f.c;
  std::vector<Vec2> pts;
  pts.reserve(iterations);
  Vec2 v = v0;
  for (int k = 0; k < iterations; ++k) {
    v = map(v, n);
    if ((v - c).norm() > opt.max_radius) return false;
    pts.push_back(v);
  }
  const int m = static_cast<int>(pts.size());
  if (m < 3) return false;
  std::vector<int> order(m);
  for (int k = 0; k < m; ++k) order[k] = k;
  std::vector<double> angle(m);
  for (int k = 0; k < m; ++k) angle[k] = f.angle(pts[k]);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return angle[a] < angle[b]; });
  // Winding once around c: no large angular gap, including the wrap-around one.
  double gap = angle[order.front()] + 2 * kPi - angle[order.back()];
  for (int k = 1; k < m; ++k) gap = std::max(gap, angle[order[k]] - angle[order[k - 1]]);
  if (gap > opt.max_gap) return false;
  // On an invariant circle P^n acts as an orientation-preserving circle homeomorphism, so it
  // keeps the cyclic order of points: walking the iterates in angular order, their images are
  // met in angular order too, with one wrap-around. Chaotic orbits, sticky ones near the last
  // curve included, break the order somewhere.
  std::vector<int> rank(m);
  for (int k = 0; k < m; ++k) rank[order[k]] = k;
  std::vector<int> image_rank;
  image_rank.reserve(m);
  for (int k = 0; k < m; ++k)
    if (order[k] + 1 < m) image_rank.push_back(rank[order[k] + 1]);
  int descents = image_rank.front() < image_rank.back() ? 1 : 0;
  for (std::size_t k = 1; k < image_rank.size(); ++k)
    if (image_rank[k] < image_rank[k - 1]) ++descents;
  if (descents > 1 + opt.order_defects) return false;
  if (curve) *curve = std::move(pts);
  return true;
}

namespace {

// The outermost closed curve around the centre found along one ray of chart step `dir` per unit
// of the normal-form radius, certified with the long orbit; its iterates in `curve`.
std::optional<Vec2> scan_ray(const SectionMap& map, const CentreFrame& f, const Vec2& dir, int n,
                             const IslandOptions& opt, std::vector<Vec2>& curve) {
  const Vec2 c = f.c;
  double best = -1;
  for (double d = opt.step; d * dir.norm() <= opt.max_radius; d += opt.step) {
    if (!map.chart().inside(c + d * dir)) break;
    // Keep scanning past failures: a chain of secondary islands inside the island breaks
    // the ray into several regular stretches, and the boundary is the outermost curve.
    if (closed_curve_around(map, f, c + d * dir, n, opt.iterations, opt)) best = d;
  }
  if (best < 0) return std::nullopt;
  double lo = best, hi = best + opt.step;
  for (int b = 0; b < opt.bisections; ++b) {
    const double mid = 0.5 * (lo + hi);
    if (closed_curve_around(map, f, c + mid * dir, n, opt.iterations, opt))
      lo = mid;
    else
      hi = mid;
  }
  // The polygon orbit is longer; a sticky orbit that passed the short test can fail it, so step
  // back inwards until it holds.
  while (!closed_curve_around(map, f, c + lo * dir, n, opt.final_iterations, opt, &curve)) {
    lo -= 0.25 * opt.step;
    if (lo <= 0) return std::nullopt;
  }
  return c + lo * dir;
}

}  // namespace

std::optional<Island> island_around(const SectionMap& map, const PeriodicPoint& centre,
                                    const IslandOptions& opt) {
  const CentreFrame f = CentreFrame::of(centre);
  const Vec2 c = centre.v;
  const int n = centre.period;
  // Scan in the normal-form radius rho (invariant ellipses near c are circles rho = const of
  // area pi rho^2). The first ray points towards the chart centre, which keeps it inside the
  // chart; the others turn from it by equal normal-form angles. Invariant curves around c are
  // nested, so the largest certified one is the outermost found.
  const Vec2 towards = c.norm() > 1e-9 ? Vec2(-c) : Vec2(1, 0);
  const Vec2 w0 = (f.W * towards).normalized();
  const Eigen::Matrix2d Winv = f.W.inverse();
  std::vector<Vec2> curve;
  std::optional<Vec2> launch;
  double best_area = -1;
  for (int k = 0; k < std::max(1, opt.rays); ++k) {
    const double a = 2 * kPi * k / std::max(1, opt.rays);
    const Vec2 w(std::cos(a) * w0.x() - std::sin(a) * w0.y(),
                 std::sin(a) * w0.x() + std::cos(a) * w0.y());
    const Vec2 dir = Winv * w;  // chart step per unit rho
    std::vector<Vec2> pts;
    const auto l = scan_ray(map, f, dir, n, opt, pts);
    if (!l) continue;
    const double area = polygon_from_curve(f, pts, opt.vertices).area();
    if (area > best_area) {
      best_area = area;
      launch = l;
      curve = std::move(pts);
    }
  }
  if (!launch) return std::nullopt;
  Island isl;
  isl.period = n;
  isl.orbit = centre.orbit;
  isl.r = map.chart().r();
  isl.center = c;
  isl.launch = *launch;
  isl.extent = (isl.launch - c).norm();
  isl.boundary = polygon_from_curve(f, curve, opt.vertices);
  return isl;
}

namespace {

// Indices of the elliptic points of one orbit in dynamical order: members[k] is P^k of
// members[0]. Empty if an image is not in the list.
std::vector<int> orbit_members(const SectionMap& map, const std::vector<PeriodicPoint>& points,
                               int first) {
  std::vector<int> members{first};
  Vec3 q = points[first].p;
  for (int k = 1; k < points[first].period; ++k) {
    q = period_map(map.protocol(), q);
    const Vec2 v = map.chart().to_chart(q);
    int found = -1;
    for (std::size_t j = 0; j < points.size(); ++j)
      if (points[j].period == points[first].period && (points[j].v - v).norm() < 1e-6)
        found = static_cast<int>(j);
    if (found < 0) return {};
    members.push_back(found);
  }
  return members;
}

// The islands of one orbit. P maps each island onto the next, so their boundaries are images
// of one curve. Each member's own scan gives a candidate; the largest candidate whose images
// are closed curves around every other member wins, and the others are drawn from its images.
// This keeps the islands of an orbit congruent under P and rejects a sticky chaotic orbit that
// happened to pass the test at one member.
std::vector<Island> orbit_islands(const SectionMap& map, const std::vector<PeriodicPoint>& points,
                                  const std::vector<int>& members, const IslandOptions& opt) {
  const int n = static_cast<int>(members.size());
  std::vector<Island> candidates;
  std::vector<int> owner;
  for (int k = 0; k < n; ++k)
    if (auto isl = island_around(map, points[members[k]], opt)) {
      candidates.push_back(*isl);
      owner.push_back(k);
    }
  std::vector<int> by_area(candidates.size());
  for (std::size_t i = 0; i < by_area.size(); ++i) by_area[i] = static_cast<int>(i);
  std::sort(by_area.begin(), by_area.end(), [&](int a, int b) {
    return candidates[a].boundary.area() > candidates[b].boundary.area();
  });
  for (int ci : by_area) {
    std::vector<Island> out(n);
    bool ok = true;
    Vec2 launch = candidates[ci].launch;
    for (int step = 0; step < n && ok; ++step) {
      const int k = (owner[ci] + step) % n;
      const PeriodicPoint& centre = points[members[k]];
      const CentreFrame f = CentreFrame::of(centre);
      std::vector<Vec2> curve;
      ok = closed_curve_around(map, f, launch, n, opt.final_iterations, opt, &curve);
      if (!ok) break;
      Island& isl = out[k];
      isl.point = members[k];
      isl.period = n;
      isl.orbit = centre.orbit;
      isl.r = map.chart().r();
      isl.center = centre.v;
      isl.launch = launch;
      isl.extent = (launch - centre.v).norm();
      isl.boundary = polygon_from_curve(f, curve, opt.vertices);
      launch = map(launch, 1);
    }
    if (ok) return out;
  }
  return {};
}

}  // namespace

std::vector<Island> find_islands(const SectionMap& map, const std::vector<PeriodicPoint>& points,
                                 const IslandOptions& opt, const Progress& progress) {
  std::vector<Island> out;
  std::vector<bool> done(points.size(), false);
  double work = 0, work_done = 0;
  for (const auto& p : points)
    if (p.type == Stability::Elliptic) work += p.period;
  const auto count_done = [&](std::size_t k) {
    if (done[k] || points[k].type != Stability::Elliptic) return;
    done[k] = true;
    work_done += points[k].period;
    report(progress, work_done / work);
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (done[i] || points[i].type != Stability::Elliptic) continue;
    // Satellites (higher-period elliptic points inside a found island) are part of that island.
    if (island_containing(out, points[i].v) >= 0) {
      count_done(i);
      continue;
    }
    auto members = orbit_members(map, points, static_cast<int>(i));
    if (members.empty()) {  // orbit not complete in the list: this point alone
      if (auto isl = island_around(map, points[i], opt)) {
        isl->point = static_cast<int>(i);
        out.push_back(std::move(*isl));
      }
      count_done(i);
      continue;
    }
    auto islands = orbit_islands(map, points, members, opt);
    for (int m : members) count_done(m);
    for (auto& isl : islands) out.push_back(std::move(isl));
  }
  report(progress, 1.0);
  return out;
}

double island_memory_bytes(const IslandOptions& opt) {
  return 40.0 * std::max(opt.iterations, opt.final_iterations);
}

double island_area_fraction(const ShellChart& chart, const std::vector<Island>& islands) {
  double a = 0;
  for (const auto& isl : islands) a += isl.boundary.area();
  return a / chart.area();
}

double island_bulk_area_fraction(const ShellChart& chart, const std::vector<Island>& islands) {
  double a = 0;
  for (const auto& isl : islands) a += clip_to_disc(isl.boundary, chart.rim()).area();
  return a / chart.bulk_area();
}

int island_containing(const std::vector<Island>& islands, const Vec2& v) {
  for (std::size_t i = 0; i < islands.size(); ++i)
    if (islands[i].boundary.contains(v)) return static_cast<int>(i);
  return -1;
}

}  // namespace tumble::cm
