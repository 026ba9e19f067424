#include "cm/manifold.hpp"

#include <cmath>
#include <stdexcept>

namespace tumble::cm {

Manifold trace_manifold(const SectionMap& map, const PeriodicPoint& h, bool unstable,
                        const ManifoldOptions& opt) {
  if (h.type != Stability::Hyperbolic)
    throw std::invalid_argument("trace_manifold: the point is not hyperbolic");
  const ShellChart& chart = map.chart();
  const Vec2 e = unstable ? h.unstable : h.stable;
  // Chart units per unit of 3D length along e, so the segment has the requested 3D length.
  const double dh = 1e-6;
  const double scale =
      (chart.from_chart(h.v + dh * e) - chart.from_chart(h.v - dh * e)).norm() / (2 * dh);
  const double half = 0.5 * opt.length / scale;
  const auto seed = [&](double s) { return chart.from_chart(h.v + s * half * e); };  // s in [-1,1]
  const auto step = [&](const Vec3& p) {
    return unstable ? period_map(map.protocol(), p) : inverse_period_map(map.protocol(), p);
  };
  const auto advance = [&](double s, int k) {
    Vec3 p = seed(s);
    for (int i = 0; i < k; ++i) p = step(p);
    return p;
  };

  Manifold m;
  m.unstable = unstable;
  std::vector<double> s(opt.initial_points);
  std::vector<Vec3> x(opt.initial_points);
  for (int i = 0; i < opt.initial_points; ++i) {
    s[i] = -1 + 2.0 * i / (opt.initial_points - 1);
    x[i] = seed(s[i]);
  }
  const auto record = [&](int k) {
    for (std::size_t i = 0; i < x.size(); ++i) {
      m.xyz.push_back(x[i]);
      m.chart.push_back(chart.to_chart(x[i]));
      m.iteration.push_back(k);
      m.param.push_back(s[i]);
    }
  };
  record(0);
  for (int k = 1; k <= opt.iterations; ++k) {
    for (auto& p : x) p = step(p);
    // Re-insert until neighbours are within `spacing` (new points can themselves be far apart).
    std::vector<double> s2;
    std::vector<Vec3> x2;
    for (std::size_t i = 0; i + 1 < x.size() && !m.truncated; ++i) {
      s2.push_back(s[i]);
      x2.push_back(x[i]);
      // Depth-first refinement of the gap (s[i], s[i+1]).
      std::vector<std::pair<double, Vec3>> stack{{s[i + 1], x[i + 1]}};
      double sl = s[i];
      Vec3 xl = x[i];
      while (!stack.empty()) {
        const auto [sr, xr] = stack.back();
        if ((xr - xl).norm() > opt.spacing && sr - sl > 1e-15) {
          const double sm = 0.5 * (sl + sr);
          stack.emplace_back(sm, advance(sm, k));
          continue;
        }
        stack.pop_back();
        if (!stack.empty()) {  // (sl, sr) is fine: emit sr and move on
          s2.push_back(sr);
          x2.push_back(xr);
        }
        sl = sr;
        xl = xr;
      }
      if (s2.size() > opt.max_points) m.truncated = true;
    }
    if (m.truncated) break;
    s2.push_back(s.back());
    x2.push_back(x.back());
    s.swap(s2);
    x.swap(x2);
    record(k);
    m.iterations_done = k;
  }
  return m;
}

}  // namespace tumble::cm
