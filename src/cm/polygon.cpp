#include "cm/polygon.hpp"

#include <cmath>

namespace tumble::cm {

double Polygon::signed_area() const {
  double s = 0;
  const std::size_t n = vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = vertices[i];
    const Vec2& b = vertices[(i + 1) % n];
    s += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * s;
}

double Polygon::area() const { return std::abs(signed_area()); }

bool Polygon::contains(const Vec2& q) const {
  bool in = false;
  const std::size_t n = vertices.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = vertices[i];
    const Vec2& b = vertices[j];
    if ((a.y() > q.y()) != (b.y() > q.y()) &&
        q.x() < (b.x() - a.x()) * (q.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

Vec2 Polygon::centroid() const {
  Vec2 c = Vec2::Zero();
  double a2 = 0;
  const std::size_t n = vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = vertices[i];
    const Vec2& b = vertices[(i + 1) % n];
    const double w = a.x() * b.y() - b.x() * a.y();
    c += w * (a + b);
    a2 += w;
  }
  return a2 != 0 ? Vec2(c / (3 * a2)) : c;
}

Polygon clip_to_disc(const Polygon& poly, double radius, int sides) {
  std::vector<Vec2> out = poly.vertices;
  for (int e = 0; e < sides && !out.empty(); ++e) {
    // Clip against the half-plane n . v <= h of the e-th edge of the inscribed polygon.
    const double mid = 2 * kPi * (e + 0.5) / sides;
    const Vec2 nrm(std::cos(mid), std::sin(mid));
    const double h = radius * std::cos(kPi / sides);
    std::vector<Vec2> in;
    in.reserve(out.size() + 1);
    for (std::size_t i = 0; i < out.size(); ++i) {
      const Vec2& a = out[i];
      const Vec2& b = out[(i + 1) % out.size()];
      const double da = nrm.dot(a) - h, db = nrm.dot(b) - h;
      if (da <= 0) in.push_back(a);
      if ((da <= 0) != (db <= 0)) in.push_back(a + (b - a) * (da / (da - db)));
    }
    out.swap(in);
  }
  return {out};
}

}  // namespace tumble::cm
