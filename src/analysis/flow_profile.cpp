#include "analysis/flow_profile.hpp"

#include <cmath>
#include <limits>

#include "base/vec3.hpp"

namespace tumble::analysis {

FlowProfile flow_profile(const Particles& p, std::size_t count, const FlowFrame& fr) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Vec3 up{0, 1, 0};
  const Vec3 eh = cross(up, fr.axis);
  const double R = fr.radius;
  const int nb = std::max(1, static_cast<int>(std::floor(2 * R / fr.bin)));
  const double w = 2 * R / nb;
  FlowProfile out;
  out.h.resize(nb);
  out.speed.assign(nb, nan);
  for (int b = 0; b < nb; ++b) out.h[b] = -R + (b + 0.5) * w;
  auto bin_of = [&](double h) {
    const int b = static_cast<int>(std::floor((h + R) / w));
    return b < 0 || b >= nb ? -1 : b;
  };
  // Highest particle top per bin in the central slab.
  // (The fit uses each top particle's own h, not the bin centre: no offset of half a bin's rise.)
  std::vector<double> top(nb, -1e300), top_h(nb, 0);
  for (std::size_t i = 0; i < count; ++i) {
    if (std::abs(dot(p.x[i], fr.axis)) > fr.slab * R) continue;
    const double h = dot(p.x[i], eh);
    const int b = bin_of(h);
    if (b >= 0 && p.x[i].y + p.radius[i] > top[b]) {
      top[b] = p.x[i].y + p.radius[i];
      top_h[b] = h;
    }
  }
  // Least-squares line v = a + s h through the bins of the fit window.
  double n = 0, sh = 0, sv = 0, shh = 0, shv = 0;
  for (int b = 0; b < nb; ++b) {
    if (top[b] < -1e299 || std::abs(out.h[b]) > fr.fit * R) continue;
    n += 1;
    sh += top_h[b];
    sv += top[b];
    shh += top_h[b] * top_h[b];
    shv += top_h[b] * top[b];
  }
  const double den = n * shh - sh * sh;
  if (n < 3 || den <= 0) {
    out.repose_deg = out.surface_speed = nan;
    return out;
  }
  const double s = (n * shv - sh * sv) / den, a = (sv - s * sh) / n;
  out.repose_deg = std::atan(std::abs(s)) * 180 / kPi;
  // Downhill tangent in the (e_h, up) plane: along the line, pointing to lower v.
  Vec3 t = (1 / std::sqrt(1 + s * s)) * (eh + s * up);
  if (s > 0) t = -t;
  std::vector<double> sum(nb, 0), cnt(nb, 0);
  for (std::size_t i = 0; i < count; ++i) {
    if (std::abs(dot(p.x[i], fr.axis)) > fr.slab * R) continue;
    const double h = dot(p.x[i], eh);
    const int b = bin_of(h);
    if (b < 0) continue;
    const double below = a + s * h - (p.x[i].y + p.radius[i]);
    if (below > fr.depth || below < -fr.depth) continue;
    sum[b] += dot(p.v[i], t);
    cnt[b] += 1;
  }
  double cs = 0, cn = 0;
  for (int b = 0; b < nb; ++b) {
    if (cnt[b] == 0) continue;
    out.speed[b] = sum[b] / cnt[b];
    if (std::abs(out.h[b]) < 0.3 * R) {
      cs += sum[b];
      cn += cnt[b];
    }
  }
  out.surface_speed = cn > 0 ? cs / cn : nan;
  return out;
}

}  // namespace tumble::analysis
