#include "cm/periodic.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <optional>

namespace tumble::cm {

const char* to_string(Stability s) {
  switch (s) {
    case Stability::Elliptic:
      return "elliptic";
    case Stability::Hyperbolic:
      return "hyperbolic";
    case Stability::Parabolic:
      return "parabolic";
  }
  return "?";
}

bool section_jacobian(const SectionMap& map, const Vec2& v, int n, double h, Eigen::Matrix2d& J) {
  for (int k = 0; k < 2; ++k) {
    Vec2 d = Vec2::Zero();
    d[k] = h;
    if (!map.chart().inside(v + d) || !map.chart().inside(v - d)) return false;
    J.col(k) = (map(v + d, n) - map(v - d, n)) / (2 * h);
  }
  return true;
}

bool newton_periodic(const SectionMap& map, Vec2 v, int n, const PeriodicSearch& opt, Vec2& out) {
  auto residual = [&](const Vec2& w) -> std::optional<Vec2> {
    if (!map.chart().inside(w)) return std::nullopt;
    return Vec2(map(w, n) - w);
  };
  auto g = residual(v);
  if (!g) return false;
  for (int it = 0; it < opt.max_newton; ++it) {
    if (g->norm() < opt.tol) {
      out = v;
      return true;
    }
    Eigen::Matrix2d J;
    if (!section_jacobian(map, v, n, opt.fd_step, J)) return false;
    J -= Eigen::Matrix2d::Identity();
    if (std::abs(J.determinant()) < 1e-14) return false;
    Vec2 step = -J.inverse() * *g;
    // Damped Newton: the map is only piecewise smooth, so a full step can land on another
    // branch; halve until the residual drops.
    bool improved = false;
    for (int half = 0; half < 12 && !improved; ++half, step *= 0.5) {
      const auto g2 = residual(v + step);
      if (g2 && g2->norm() < g->norm()) {
        v += step;
        g = g2;
        improved = true;
      }
    }
    if (!improved) return false;
  }
  if (g->norm() < opt.tol) {
    out = v;
    return true;
  }
  return false;
}

void classify(const SectionMap& map, PeriodicPoint& pt, const PeriodicSearch& opt) {
  pt.p = map.chart().from_chart(pt.v);
  if (!section_jacobian(map, pt.v, pt.period, opt.fd_step, pt.jacobian)) return;
  const Eigen::Matrix2d& J = pt.jacobian;
  pt.trace = J.trace();
  pt.det = J.determinant();
  const double tr = pt.trace;
  if (std::abs(std::abs(tr) - 2) < opt.parabolic) {
    pt.type = Stability::Parabolic;
  } else if (std::abs(tr) < 2) {
    pt.type = Stability::Elliptic;
    pt.rotation = std::acos(tr / 2);
  } else {
    pt.type = Stability::Hyperbolic;
    const double disc = std::sqrt(tr * tr - 4 * pt.det);
    const double l1 = (tr + (tr > 0 ? disc : -disc)) / 2;  // |l1| > 1
    const double l2 = pt.det / l1;
    pt.lambda = l1;
    auto eigvec = [&J](double l) {
      // (J - l I) e = 0: either row gives e; take the better conditioned one.
      const Vec2 a(J(0, 1), l - J(0, 0)), b(l - J(1, 1), J(1, 0));
      return (a.norm() > b.norm() ? a : b).normalized();
    };
    pt.unstable = eigvec(l1);
    pt.stable = eigvec(l2);
  }
}

namespace {

// True if p returns to itself after fewer than n periods (then it is found at that period).
bool has_lower_period(const Protocol& pr, const Vec3& p, int n) {
  Vec3 q = p;
  for (int d = 1; d < n; ++d) {
    q = period_map(pr, q);
    if (n % d == 0 && (q - p).norm() < 1e-8) return true;
  }
  return false;
}

// Groups the points into orbits (P maps each member to the next) and completes each orbit: a
// member that no start of the grid converged to (one in the layer's ring, or between starts) is
// the image of one that was found, added and classified where its Jacobian agrees on the kind.
// Before, orbits were listed with members missing: at (57°,57°) on grid 40, 7 of 24 hyperbolic
// orbits (a period-2 orbit of 1 point), at (45°,45°) on grid 20 an elliptic period-3 orbit of 2,
// so one of its islands was never traced.
void group_orbits(const SectionMap& map, std::vector<PeriodicPoint>& pts,
                  const PeriodicSearch& opt) {
  int next = 0;
  const std::size_t found = pts.size();
  for (std::size_t i = 0; i < found; ++i) {
    if (pts[i].orbit >= 0) continue;
    pts[i].orbit = next;
    const int period = pts[i].period;
    const Stability type = pts[i].type;
    Vec3 q = pts[i].p;
    for (int k = 1; k < period; ++k) {
      q = period_map(map.protocol(), q);
      const Vec2 v = map.chart().to_chart(q);
      bool member = false;
      for (auto& other : pts)
        if (other.period == period && (other.v - v).norm() < 10 * opt.merge) {
          if (other.orbit < 0) other.orbit = next;
          member = member || other.orbit == next;
        }
      if (member || !map.chart().inside(v)) continue;
      PeriodicPoint pt;
      pt.v = v;
      pt.period = period;
      classify(map, pt, opt);
      if (pt.type != type) continue;  // (a Jacobian across the chart's edge: not trusted)
      pt.orbit = next;
      pts.push_back(pt);
    }
    ++next;
  }
}

}  // namespace

std::vector<PeriodicPoint> find_periodic_points(const SectionMap& map, const PeriodicSearch& opt,
                                                const Progress& progress) {
  std::vector<PeriodicPoint> found;
  const double rim = map.chart().outer();
  const double starts = static_cast<double>(opt.grid) * opt.grid;
  const double work = starts * opt.max_period * (opt.max_period + 1) / 2.0;
  for (int n = 1; n <= opt.max_period; ++n) {
    const double before = starts * n * (n - 1) / 2.0;  // work of periods 1 .. n-1
    for (int i = 0; i < opt.grid; ++i) {
      report(progress, (before + static_cast<double>(n) * i * opt.grid) / work);
      for (int j = 0; j < opt.grid; ++j) {
        const Vec2 guess(rim * (-1 + (2 * i + 1.0) / opt.grid),
                         rim * (-1 + (2 * j + 1.0) / opt.grid));
        if (!map.chart().inside(guess)) continue;
        Vec2 v;
        if (!newton_periodic(map, guess, n, opt, v)) continue;
        const bool seen = std::any_of(found.begin(), found.end(), [&](const PeriodicPoint& q) {
          return (q.v - v).norm() < opt.merge;
        });
        if (seen) continue;
        PeriodicPoint pt;
        pt.v = v;
        pt.period = n;
        pt.p = map.chart().from_chart(v);
        if (has_lower_period(map.protocol(), pt.p, n)) continue;
        classify(map, pt, opt);
        found.push_back(pt);
      }
    }
  }
  report(progress, 1.0);
  std::stable_sort(found.begin(), found.end(), [](const PeriodicPoint& a, const PeriodicPoint& b) {
    return a.period < b.period;
  });
  group_orbits(map, found, opt);
  std::stable_sort(found.begin(), found.end(), [](const PeriodicPoint& a, const PeriodicPoint& b) {
    return a.period != b.period ? a.period < b.period : a.orbit < b.orbit;
  });
  return found;
}

double periodic_search_memory_bytes(const PeriodicSearch& opt) {
  const double most_points = static_cast<double>(opt.grid) * opt.grid * opt.max_period;
  return most_points * (sizeof(PeriodicPoint) + 164);
}

}  // namespace tumble::cm
