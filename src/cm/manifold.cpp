#include "cm/manifold.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tumble::cm {
namespace {

// The share of a manifold's work done, for progress lines. The work is period maps: an iteration
// steps every point of the curve once and maps each inserted point k times from the initial
// segment, so most of it is in the last iterations. The curve grows by a factor per iteration,
// |lambda|^(1/period) at first and then as observed over the last period (the images of a
// period-n point's segment stretch unevenly from one iteration to the next); the work left is
// predicted by growing the current curve until `iterations` or max_points, and re-predicted at
// every iteration.
class WorkShare {
 public:
  WorkShare(const PeriodicPoint& h, double initial_curve, const ManifoldOptions& opt)
      : period_(std::max(h.period, 1)),
        growth_(std::max(std::pow(std::abs(h.lambda), 1.0 / period_), 1.0)),
        sizes_{initial_curve},
        opt_(opt) {}
  void start_iteration(int k, double curve, double recorded) {
    double left = 0, n = curve, rec = recorded;
    for (int j = k; j <= opt_.iterations; ++j) {
      const double next = n * growth_;
      if (rec + next > static_cast<double>(opt_.max_points)) {
        left += n + std::max(static_cast<double>(opt_.max_points) - rec - n, 0.0) * j;
        break;
      }
      left += n + (next - n) * j;
      rec += next;
      n = next;
    }
    total_ = done_ + left;
  }
  void end_iteration(double curve) {
    sizes_.push_back(curve);
    const std::size_t k = sizes_.size() - 1, back = std::min<std::size_t>(period_, k);
    if (back > 0) growth_ = std::max(std::pow(curve / sizes_[k - back], 1.0 / back), 1.0);
  }
  void add(double maps) { done_ += maps; }
  // Never backwards, and short of 1 until the manifold is done.
  double share() {
    shown_ = std::max(shown_, std::min(done_ / std::max(total_, 1.0), 0.99));
    return shown_;
  }

 private:
  int period_;
  double growth_, done_ = 0, total_ = 1, shown_ = 0;
  std::vector<double> sizes_;  // curve size after each iteration (0: the initial segment)
  const ManifoldOptions& opt_;
};

}  // namespace

Manifold trace_manifold(const SectionMap& map, const PeriodicPoint& h, bool unstable,
                        const ManifoldOptions& opt, const Progress& progress) {
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
  std::size_t recorded = x.size();
  WorkShare work(h, x.size(), opt);
  for (int k = 1; k <= opt.iterations; ++k) {
    work.start_iteration(k, x.size(), recorded);
    for (auto& p : x) p = step(p);
    work.add(x.size());
    // Re-insert until neighbours are within `spacing` (new points can themselves be far apart).
    std::vector<double> s2;
    std::vector<Vec3> x2;
    // Would this iteration's curve (with its end point, appended last) take the manifold past
    // max_points? Checked at every insertion: one gap alone can stretch by |lambda|^k.
    const auto full = [&] { return recorded + s2.size() + 1 > opt.max_points; };
    for (std::size_t i = 0; i + 1 < x.size() && !m.truncated; ++i) {
      s2.push_back(s[i]);
      x2.push_back(x[i]);
      // Depth-first refinement of the gap (s[i], s[i+1]).
      std::vector<std::pair<double, Vec3>> stack{{s[i + 1], x[i + 1]}};
      double sl = s[i];
      Vec3 xl = x[i];
      while (!stack.empty()) {
        if (full()) {
          m.truncated = true;
          break;
        }
        const auto [sr, xr] = stack.back();
        if ((xr - xl).norm() > opt.spacing && sr - sl > 1e-15) {
          const double sm = 0.5 * (sl + sr);
          stack.emplace_back(sm, advance(sm, k));
          work.add(k);
          continue;
        }
        stack.pop_back();
        if (!stack.empty()) {  // (sl, sr) is fine: emit sr and move on
          s2.push_back(sr);
          x2.push_back(xr);
          if ((s2.size() & 1023) == 0) report(progress, work.share());
        }
        sl = sr;
        xl = xr;
      }
      if (full()) m.truncated = true;
    }
    if (m.truncated) break;
    s2.push_back(s.back());
    x2.push_back(x.back());
    work.end_iteration(x2.size());
    s.swap(s2);
    x.swap(x2);
    record(k);
    recorded += x.size();
    m.iterations_done = k;
    report(progress, work.share());
  }
  report(progress, 1.0);
  return m;
}

double manifold_memory_bytes(const ManifoldOptions& opt) {
  return static_cast<double>(opt.max_points) * (2 * 52 + 32 + 2 * 32 + 44);
}

}  // namespace tumble::cm
