#include "islands/cross_section.hpp"

#include <cmath>
#include <limits>
#include <set>

#include "projection/lambert.hpp"

namespace tumble::analysis {

SectionPlane plane_through(const Vec3& a, const Vec3& b) {
  SectionPlane p;
  p.e1 = a * (1.0 / norm(a));
  const Vec3 w = b - dot(b, p.e1) * p.e1;  // Gram-Schmidt: e2 points towards b
  p.e2 = w * (1.0 / norm(w));
  p.normal = cross(p.e1, p.e2);
  return p;
}

std::pair<int, int> farthest_island_pair(const std::vector<cm::Island>& shell) {
  std::pair<int, int> best{-1, -1};
  double dmax = -1;
  for (std::size_t i = 0; i < shell.size(); ++i)
    for (std::size_t j = i + 1; j < shell.size(); ++j) {
      const double d = (shell[i].center - shell[j].center).norm();
      // Primary islands only: a secondary chain's islands hug their parent's edge.
      if (shell[i].parent_orbit >= 0 || shell[j].parent_orbit >= 0) continue;
      if (shell[i].orbit != shell[j].orbit && d > dmax) {
        dmax = d;
        best = {static_cast<int>(i), static_cast<int>(j)};
      }
    }
  return best;
}

SectionPlane plane_through_islands(const cm::Island& a, const cm::Island& b) {
  auto dir = [](const cm::Island& is) {
    const auto u = lambert_inverse({is.center.x(), is.center.y()});
    return Vec3{u[0], u[1], u[2]};
  };
  return plane_through(dir(a), dir(b));
}

SectionPlane upright(const SectionPlane& p) {
  const Vec3 up{0, 1, 0};
  const Vec3 w = up - dot(up, p.normal) * p.normal;  // +y projected on the plane
  if (norm(w) < 1e-9) return p;
  SectionPlane q;
  q.e2 = w * (1.0 / norm(w));
  q.e1 = cross(q.e2, p.normal);  // (e1, e2, normal) right-handed, as before
  q.normal = p.normal;
  return q;
}

void SectionMap::add(const SnapshotData& s, const SectionPlane& plane, double half_width) {
  const int mapped = s.mixture.mapped;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (std::abs(dot(s.x[i], plane.normal)) > half_width) continue;
    const double s1 = dot(s.x[i], plane.e1) / s.R, s2 = dot(s.x[i], plane.e2) / s.R;
    const int a = static_cast<int>(std::floor((s1 + 1) * 0.5 * n_));
    const int b = static_cast<int>(std::floor((s2 + 1) * 0.5 * n_));
    if (a < 0 || a >= n_ || b < 0 || b >= n_) continue;
    const double r = s.radius[i];
    (s.species[i] == mapped ? large : small)[a * n_ + b] += 4.0 / 3.0 * kPi * r * r * r;
  }
  ++samples;
}

std::vector<double> SectionMap::c_large() const {
  std::vector<double> c(large.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < c.size(); ++k)
    if (large[k] + small[k] > 0) c[k] = large[k] / (large[k] + small[k]);
  return c;
}

std::vector<TubeCrossing> tube_crossings(const std::vector<cm::Island>& islands,
                                         const SectionPlane& plane, int samples) {
  std::set<double> shells;
  for (const auto& is : islands) shells.insert(is.r);
  std::vector<TubeCrossing> out;
  for (double r : shells) {
    // Membership along the circle of radius r in the plane; only the bulk (lower) part of the
    // shell is charted by the Lambert projection, so the upper half counts as outside.
    auto member = [&](double phi) {
      const Vec3 u = std::cos(phi) * plane.e1 + std::sin(phi) * plane.e2;
      if (u.y > 0) return -1;
      const DiscPoint d = lambert_from_below(u.x, u.y, u.z);
      for (std::size_t k = 0; k < islands.size(); ++k)
        if (islands[k].r == r && islands[k].boundary.contains(cm::Vec2(d.X, d.Z)))
          return static_cast<int>(k);
      return -1;
    };
    const double dphi = 2 * kPi / samples;
    int prev = member(0);
    for (int k = 1; k <= samples; ++k) {
      const int cur = member(k * dphi);
      if (cur != prev) {
        const double phi = (k - 0.5) * dphi;
        out.push_back({r, r * std::cos(phi), r * std::sin(phi), cur >= 0 ? cur : prev});
      }
      prev = cur;
    }
  }
  return out;
}

}  // namespace tumble::analysis
