#include "cm/island.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace tumble::cm {
namespace {

// The points of a closed curve, in their order along it, thinned to about `vertices` and turned
// counter-clockwise.
Polygon polygon_from_curve(const std::vector<Vec2>& curve, int vertices) {
  Polygon poly;
  const std::size_t stride = std::max<std::size_t>(1, curve.size() / std::max(vertices, 3));
  for (std::size_t k = 0; k < curve.size(); k += stride) poly.vertices.push_back(curve[k]);
  if (poly.signed_area() < 0) std::reverse(poly.vertices.begin(), poly.vertices.end());
  return poly;
}

double wrap_angle(double a) { return std::remainder(a, 2 * kPi); }  // into [-π, π]

// Rotation number (turns per iterate) of the orbit `pts` about the centre. Each increment of the
// angle is taken on the branch nearest the median increment: on a curve that is not star-shaped
// about the centre the increments vary around their mean, by less than half a turn. The average
// uses the weights exp(-1 / (t (1 - t))) of the weighted Birkhoff average (Das, Sander, Yorke),
// which converges faster than any power of 1/N on a quasi-periodic orbit.
double rotation_number(const CentreFrame& f, const std::vector<Vec2>& pts) {
  const std::size_t m = pts.size();
  std::vector<double> step(m - 1);
  for (std::size_t k = 0; k + 1 < m; ++k)
    step[k] = wrap_angle(f.angle(pts[k + 1]) - f.angle(pts[k]));
  std::vector<double> sorted = step;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double guess = sorted[sorted.size() / 2];
  double sum = 0, weights = 0;
  for (std::size_t k = 0; k < step.size(); ++k) {
    const double t = (k + 0.5) / step.size();
    const double w = std::exp(-1.0 / (t * (1 - t)));
    sum += w * (guess + wrap_angle(step[k] - guess));
    weights += w;
  }
  return sum / weights / (2 * kPi);
}

double convex_hull_perimeter(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  const auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Vec2> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {  // Andrew's monotone chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], p[i - 1]) <= 0) --k;
    hull[k++] = p[i - 1];
  }
  double len = 0;
  for (std::size_t i = 0; i + 1 < k; ++i) len += (hull[i + 1] - hull[i]).norm();
  return len;
}

// The circle test of IslandOptions::Order: orders `pts` by k ρ mod 1 (in place) if they form a
// curve winding once around the centre.
bool ordered_by_circle_coordinate(const CentreFrame& f, std::vector<Vec2>& pts,
                                  const IslandOptions& opt) {
  const std::size_t m = pts.size();
  const double rho = rotation_number(f, pts);
  std::vector<std::pair<double, std::size_t>> phase(m);
  for (std::size_t k = 0; k < m; ++k) {
    const double x = static_cast<double>(k) * rho;
    phase[k] = {x - std::floor(x), k};
  }
  std::sort(phase.begin(), phase.end());
  std::vector<Vec2> ordered(m);
  for (std::size_t i = 0; i < m; ++i) ordered[i] = pts[phase[i].second];
  double length = 0, longest = 0, turn = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const Vec2& a = ordered[i];
    const Vec2& b = ordered[(i + 1) % m];
    const double e = (b - a).norm();
    length += e;
    longest = std::max(longest, e);
    turn += wrap_angle(f.angle(b) - f.angle(a));
  }
  if (std::abs(std::abs(turn) - 2 * kPi) > 1e-6) return false;  // winds once around the centre
  if (length > opt.max_length_ratio * convex_hull_perimeter(pts)) return false;
  if (longest > opt.max_edge_ratio * length / m) return false;
  pts = std::move(ordered);
  return true;
}

// The angle test's order: the points sorted by their angle about the centre.
void order_by_angle(const CentreFrame& f, std::vector<Vec2>& pts) {
  std::vector<std::pair<double, Vec2>> polar;
  polar.reserve(pts.size());
  for (const Vec2& v : pts) polar.push_back({f.angle(v), v});
  std::sort(polar.begin(), polar.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t k = 0; k < pts.size(); ++k) pts[k] = polar[k].second;
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
  if (opt.order == IslandOptions::Order::circle) {
    if (!ordered_by_circle_coordinate(f, pts, opt)) return false;
    if (curve) *curve = std::move(pts);
    return true;
  }
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
  if (curve) {
    order_by_angle(f, pts);
    *curve = std::move(pts);
  }
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

// The chart steps per unit of the normal-form radius of `rays` rays from the centre, evenly
// spaced in the normal-form angle, the first towards the chart centre (which keeps it inside the
// chart).
std::vector<Vec2> ray_directions(const CentreFrame& f, int rays) {
  const Vec2 towards = f.c.norm() > 1e-9 ? Vec2(-f.c) : Vec2(1, 0);
  const Vec2 w0 = (f.W * towards).normalized();
  const Eigen::Matrix2d Winv = f.W.inverse();
  std::vector<Vec2> dirs;
  for (int k = 0; k < std::max(1, rays); ++k) {
    const double a = 2 * kPi * k / std::max(1, rays);
    dirs.push_back(Winv * Vec2(std::cos(a) * w0.x() - std::sin(a) * w0.y(),
                               std::sin(a) * w0.x() + std::cos(a) * w0.y()));
  }
  return dirs;
}

}  // namespace

std::optional<Island> island_around(const SectionMap& map, const PeriodicPoint& centre,
                                    const IslandOptions& opt) {
  const CentreFrame f = CentreFrame::of(centre);
  const Vec2 c = centre.v;
  const int n = centre.period;
  // Scan in the normal-form radius rho (invariant ellipses near c are circles rho = const of
  // area pi rho^2). Invariant curves around c are nested, so the largest certified one is the
  // outermost found.
  std::vector<Vec2> curve;
  std::optional<Vec2> launch;
  double best_area = -1;
  for (const Vec2& dir : ray_directions(f, opt.rays)) {
    std::vector<Vec2> pts;
    const auto l = scan_ray(map, f, dir, n, opt, pts);
    if (!l) continue;
    const double area = polygon_from_curve(pts, opt.vertices).area();
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
  isl.boundary = polygon_from_curve(curve, opt.vertices);
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

// The islands of an orbit from one certified island `best` of member `first`: its polygon and
// launch mapped by P onto the next members in turn (P preserves orientation, so the order along
// the curve is kept); centres[k] and point_of[k] are member k's. Empty if an image does not hold
// its member's centre (not this orbit's curve after all).
// Where an image edge's chord strays from the image curve by more than this (chart units), the
// image of the edge's midpoint is inserted (up to kChordDepth halvings).
constexpr double kChordTol = 1e-6;
constexpr int kChordDepth = 12;

// Appends to `out` the images of the points of the edge a-b between A = P(a) and B = P(b)
// (exclusive) that the image curve needs for its chords to keep within kChordTol of it.
void refine_image_edge(const SectionMap& map, const Vec2& a, const Vec2& A, const Vec2& b,
                       const Vec2& B, int depth, std::vector<Vec2>& out) {
  const Vec2 m = 0.5 * (a + b), M = map(m, 1);
  if (depth >= kChordDepth || (M - 0.5 * (A + B)).norm() <= kChordTol) return;
  refine_image_edge(map, a, A, m, M, depth + 1, out);
  out.push_back(M);
  refine_image_edge(map, m, M, b, B, depth + 1, out);
}

// The image under P of a polygon whose vertices lie on an invariant curve: the vertices' images,
// and between them the images of edge points where the image is curved. In the layer's thin ring
// the chart bends P's image of a straight edge, and the images' chords alone cut an island short:
// at (45°, 45°) the member in the ring came out 3.4% smaller than its two images (0.02677 of the
// chart against 0.0277), and points inside it left it under P^3.
Polygon image_polygon(const SectionMap& map, const Polygon& poly) {
  const std::vector<Vec2>& v = poly.vertices;
  std::vector<Vec2> images(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) images[k] = map(v[k], 1);
  Polygon out;
  out.vertices.reserve(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) {
    const std::size_t next = (k + 1) % v.size();
    out.vertices.push_back(images[k]);
    refine_image_edge(map, v[k], images[k], v[next], images[next], 0, out.vertices);
  }
  return out;
}

std::vector<Island> map_around_orbit(const SectionMap& map, const Island& best, int first,
                                     const std::vector<Vec2>& centres,
                                     const std::vector<int>& point_of) {
  const int n = static_cast<int>(centres.size());
  std::vector<Island> out(n);
  Polygon boundary = best.boundary;
  Vec2 launch = best.launch;
  for (int step = 0; step < n; ++step) {
    const int k = (first + step) % n;
    Island& isl = out[k];
    isl = best;
    isl.point = point_of[k];
    isl.center = centres[k];
    isl.launch = launch;
    isl.extent = (launch - centres[k]).norm();
    isl.boundary = boundary;
    if (!isl.boundary.contains(centres[k])) return {};
    launch = map(launch, 1);
    boundary = image_polygon(map, boundary);
  }
  return out;
}

// The islands of one orbit. P maps each island onto the next, so their boundaries are images
// of one curve. Each member's own scan gives a candidate. Circle order: the largest candidate
// wins and its polygon is mapped onto the other members. Angle order: the largest candidate
// whose images are closed curves around every other member wins, and the others are drawn from
// its images (the angle test depends on the member's frame, so images are re-tested). Either way
// the islands of an orbit are congruent under P.
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
  if (opt.order == IslandOptions::Order::circle && !by_area.empty()) {
    // Every candidate is an orbit certified at its own member. Its images under P are the same
    // orbit moved on, so they need no second test (which could only fail on the test's geometric
    // margins, not on the dynamics: a sticky orbit that passed the long test at one member would
    // pass or fail alike at all). The largest candidate's polygon is mapped vertex by vertex to
    // the other members; the order along the curve is kept (P preserves orientation).
    std::vector<Vec2> centres;
    for (int m : members) centres.push_back(points[m].v);
    Island best = candidates[by_area.front()];
    best.point = members[owner[by_area.front()]];
    return map_around_orbit(map, best, owner[by_area.front()], centres, members);
  }
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
      isl.boundary = polygon_from_curve(curve, opt.vertices);
      launch = map(launch, 1);
    }
    if (ok) return out;
  }
  return {};
}

// The resonance p/q of P^n about the centre that the orbit `pts` follows, if it is one: its
// rotation number, as the weighted Birkhoff averages of both halves (which agree to round-off on a
// regular orbit and wander on a chaotic one), within `tol` of p/q for the smallest q in
// [2, max_q]. Zero if there is none.
int resonance_of(const CentreFrame& f, const std::vector<Vec2>& pts, int max_q, double tol) {
  const std::size_t half = pts.size() / 2;
  const double a = rotation_number(f, std::vector<Vec2>(pts.begin(), pts.begin() + half));
  const double b = rotation_number(f, std::vector<Vec2>(pts.begin() + half, pts.end()));
  if (std::abs(a - b) > tol) return 0;
  for (int q = 2; q <= max_q; ++q) {
    const double p = std::round(a * q);
    // p/q in lowest terms, p not a multiple of q: an orbit circling a neighbouring island (or
    // nothing) has rotation number 0 about this centre.
    if (std::abs(a * q - p) < q * tol) return std::gcd(static_cast<long>(p), long{q}) == 1 ? q : 0;
  }
  return 0;
}

// The islands of one secondary chain: the elliptic orbit of period n q of P whose point nearest
// `guess` is refined by Newton, with its n q islands (orbit_islands). Empty if Newton fails, the
// point is not elliptic, or its period is lower.
std::vector<Island> chain_from(const SectionMap& map, const Vec2& guess, int period,
                               const IslandOptions& opt, int orbit_id) {
  PeriodicSearch search;
  Vec2 v;
  if (!newton_periodic(map, guess, period, search, v)) return {};
  std::vector<PeriodicPoint> pts(period);
  Vec2 w = v;
  for (int k = 0; k < period; ++k) {
    if (k > 0 && (w - v).norm() < 1e-8) return {};  // a lower period
    pts[k].v = w;
    pts[k].period = period;
    pts[k].orbit = orbit_id;
    classify(map, pts[k], search);
    if (pts[k].type != Stability::Elliptic) return {};
    w = map(w, 1);
  }
  // As orbit_islands does in circle order: every member is scanned (the outermost certified
  // curve varies from member to member in the sticky layer at the edge) and the largest
  // candidate is mapped onto the others. A member's island cannot reach past half the distance
  // to its nearest sibling.
  std::optional<Island> first;
  int first_k = 0;
  for (int k = 0; k < period; ++k) {
    IslandOptions own = opt;
    own.rays = std::min(opt.rays, opt.chain_rays);
    for (int j = 0; j < period; ++j)
      if (j != k) own.max_radius = std::min(own.max_radius, 0.5 * (pts[j].v - pts[k].v).norm());
    auto cand = island_around(map, pts[k], own);
    if (cand && (!first || cand->boundary.area() > first->boundary.area())) {
      first = std::move(cand);
      first_k = k;
    }
  }
  if (!first) return {};
  std::vector<Vec2> centres;
  for (const auto& pt : pts) centres.push_back(pt.v);
  return map_around_orbit(map, *first, first_k, centres, std::vector<int>(period, -1));
}

// The half-iteration symmetry of a protocol with θz = θx (docs/cm.md, Sec. 1): F = (S F_z)² with
// S the mirror x <-> z, so G = S F_z commutes with F and maps an orbit's islands onto its mirror
// orbit's, invariant curves onto invariant curves.
Vec2 half_iteration_mirror(const SectionMap& map, const Vec2& v) {
  const Vec3 h = phase_map(map.protocol(), Axis::Z, map.chart().from_chart(v));
  return map.chart().to_chart(Vec3(h.z(), h.y(), h.x()));
}

// Where θz = θx, each pair of mirror-image orbits gets the larger orbit's islands twice: the
// smaller one's boundaries are replaced by the images of the larger one's under G. Boundaries of
// thin curved islands (the (45°, 45°) fingers) depend on whether a ray happens to run along
// them, so one orbit of a pair can come out far smaller than its mirror image.
void impose_mirror_symmetry(const SectionMap& map, const std::vector<PeriodicPoint>& points,
                            const IslandOptions& opt, std::vector<Island>& islands) {
  const Protocol& pr = map.protocol();
  if (std::abs(pr.theta_z - pr.theta_x) > 1e-12) return;
  const std::size_t n = islands.size();
  std::vector<int> image(n, -1);  // the island whose centre is G of this one's
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 g = half_iteration_mirror(map, islands[i].center);
    for (std::size_t j = 0; j < n; ++j)
      if ((islands[j].center - g).norm() < 1e-6) image[i] = static_cast<int>(j);
  }
  std::map<int, double> area;  // per orbit
  for (const auto& isl : islands) area[isl.orbit] += isl.boundary.area();
  std::vector<bool> replaced(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    const int j = image[i];
    if (j < 0 || islands[j].orbit == islands[i].orbit || replaced[i]) continue;
    if (area[islands[i].orbit] <= area[islands[j].orbit]) continue;
    Island& b = islands[j];
    b.launch = half_iteration_mirror(map, islands[i].launch);
    b.extent = (b.launch - b.center).norm();
    replaced[j] = true;
    // The image of the launch lies on the mirror island's boundary curve: its own orbit draws
    // the polygon, sampled along the curve like any other boundary (the images of the polygon's
    // vertices are on the curve too, but spaced as G stretches it). They are the fallback.
    std::vector<Vec2> curve;
    if (b.point >= 0 && closed_curve_around(map, CentreFrame::of(points[b.point]), b.launch,
                                            b.period, opt.final_iterations, opt, &curve)) {
      b.boundary = polygon_from_curve(curve, opt.vertices);
      continue;
    }
    b.boundary = islands[i].boundary;
    for (Vec2& v : b.boundary.vertices) v = half_iteration_mirror(map, v);
    if (b.boundary.signed_area() < 0)  // S is a reflection
      std::reverse(b.boundary.vertices.begin(), b.boundary.vertices.end());
  }
}

}  // namespace

std::vector<Island> chain_islands(const SectionMap& map, const PeriodicPoint& centre,
                                  const Island& island, const std::vector<Island>& found,
                                  const IslandOptions& opt, int orbit_id) {
  const CentreFrame f = CentreFrame::of(centre);
  const Vec2 c = centre.v;
  const int n = centre.period;
  std::vector<Island> chains;
  for (const Vec2& dir : ray_directions(f, opt.rays)) {
    for (double d = opt.step; d * dir.norm() <= opt.max_radius; d += opt.step) {
      const Vec2 seed = c + d * dir;
      if (!map.chart().inside(seed)) break;
      if (island_containing(found, seed) >= 0 || island_containing(chains, seed) >= 0) continue;
      std::vector<Vec2> pts;
      pts.reserve(opt.iterations);
      Vec2 v = seed;
      bool escaped = false;
      for (int k = 0; k < opt.iterations && !escaped; ++k) {
        v = map(v, n);
        escaped = (v - c).norm() > opt.max_radius;
        pts.push_back(v);
      }
      if (escaped) continue;  // chaotic: it left the island's neighbourhood
      const int q = resonance_of(f, pts, opt.max_chain_q, 1e-7);
      if (q == 0) continue;
      // Every q-th iterate stays in the seed's own island of the chain, circling its centre.
      Vec2 mean = Vec2::Zero();
      int count = 0;
      for (std::size_t k = q - 1; k < pts.size(); k += q, ++count) mean += pts[k];
      auto chain = chain_from(map, mean / count, n * q, opt, orbit_id);
      // A new chain: its centres lie in no island found so far. (The seed itself may lie just
      // outside the certified curves, in the chain's sticky layer.)
      if (chain.empty() || island_containing(chains, chain.front().center) >= 0 ||
          island_containing(found, chain.front().center) >= 0)
        continue;
      for (auto& isl : chain) {
        isl.point = -1;
        isl.parent_orbit = island.orbit;
        chains.push_back(std::move(isl));
      }
      ++orbit_id;
    }
  }
  return chains;
}

std::vector<Island> find_islands(const SectionMap& map, const std::vector<PeriodicPoint>& points,
                                 const IslandOptions& opt, const Progress& progress) {
  std::vector<Island> out;
  std::vector<bool> done(points.size(), false);
  double work = 0, work_done = 0;
  // The chain search takes about as long as the primary islands (docs/cm.md: 5 s and 14 s at
  // (90°, 90°)); the progress line gives each half.
  const double primary_share = opt.max_chain_q > 0 ? 0.5 : 1.0;
  for (const auto& p : points)
    if (p.type == Stability::Elliptic) work += p.period;
  const auto count_done = [&](std::size_t k) {
    if (done[k] || points[k].type != Stability::Elliptic) return;
    done[k] = true;
    work_done += points[k].period;
    report(progress, primary_share * work_done / work);
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
  if (opt.mirror) impose_mirror_symmetry(map, points, opt, out);
  if (opt.max_chain_q > 0) {
    // After every primary island, so that a chain is not searched inside another orbit's island.
    int next_orbit = 0;
    for (const auto& p : points) next_orbit = std::max(next_orbit, p.orbit + 1);
    const std::size_t primaries = out.size();
    std::vector<bool> searched(next_orbit, false);
    for (std::size_t i = 0; i < primaries; ++i) {
      const Island isl = out[i];
      if (isl.orbit < 0 || isl.point < 0 || searched[isl.orbit]) continue;
      searched[isl.orbit] = true;  // P maps a chain around one member onto the others'
      auto chains = chain_islands(map, points[isl.point], isl, out, opt, next_orbit);
      for (auto& c : chains) {
        next_orbit = std::max(next_orbit, c.orbit + 1);
        out.push_back(std::move(c));
      }
      report(progress, primary_share + (1 - primary_share) * (i + 1) / primaries);
    }
  }
  report(progress, 1.0);
  return out;
}

double island_memory_bytes(const IslandOptions& opt) {
  // The circle order also holds the angle steps, the phases, the ordered copy and the hull.
  const double per_iterate = opt.order == IslandOptions::Order::circle ? 112.0 : 40.0;
  return per_iterate * std::max(opt.iterations, opt.final_iterations);
}

std::string island_method_tag(const IslandOptions& opt) {
  return (opt.order == IslandOptions::Order::circle ? "circle" : "angle") +
         std::to_string(opt.rays) +
         (opt.max_chain_q > 0 ? "c" + std::to_string(opt.max_chain_q) : std::string()) +
         (opt.mirror ? "m" : "");
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

std::vector<int> primary_island_of(const std::vector<Island>& islands) {
  std::vector<int> primary(islands.size());
  for (std::size_t k = 0; k < islands.size(); ++k) {
    primary[k] = static_cast<int>(k);
    if (islands[k].parent_orbit < 0) continue;
    double nearest = INFINITY;
    for (std::size_t j = 0; j < islands.size(); ++j) {
      const double d = (islands[j].center - islands[k].center).norm();
      if (islands[j].orbit == islands[k].parent_orbit && islands[j].parent_orbit < 0 &&
          d < nearest) {
        nearest = d;
        primary[k] = static_cast<int>(j);
      }
    }
  }
  return primary;
}

int island_containing(const std::vector<Island>& islands, const Vec2& v) {
  for (std::size_t i = 0; i < islands.size(); ++i)
    if (islands[i].boundary.contains(v)) return static_cast<int>(i);
  return -1;
}

}  // namespace tumble::cm
