#include "analysis/cylinder_segregation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tumble::analysis {

int CylinderFrame::slices() const {
  return std::max(1, static_cast<int>(std::lround(length / slice)));
}

namespace {
int slice_of(double z, const CylinderFrame& c, int n) {
  const int k = static_cast<int>(std::floor((z + 0.5 * c.length) / c.length * n));
  return std::min(std::max(k, 0), n - 1);
}
int column_count(const CylinderFrame& c) {
  return std::max(1, static_cast<int>(std::ceil(2 * c.radius / c.slice)));
}
int column_of(double x, const CylinderFrame& c, int n) {
  const int k = static_cast<int>(std::floor((x + c.radius) / c.slice));
  return std::min(std::max(k, 0), n - 1);
}
double volume(double r) { return r * r * r; }  // common factor 4π/3 cancels in fractions
}  // namespace

double axial_segregation(const Particles& p, const CylinderFrame& c) {
  const int n = c.slices();
  std::vector<double> nb(n, 0), ns(n, 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    (p.species[i] == 1 ? nb : ns)[slice_of(p.x[i].z, c, n)] += 1;
  double num = 0, den = 0;
  for (int q = 0; q < n; ++q) {
    num += std::fabs(c.b3 * nb[q] - ns[q]);
    den += c.b3 * nb[q] + ns[q];
  }
  return den > 0 ? num / den : 0;
}

double radial_segregation_index(const Particles& p) {
  // Sums per species s (0 small, 1 big) and all: count, Σx, Σy, Σ(x²+y²).
  double n[3] = {0, 0, 0}, sx[3] = {0, 0, 0}, sy[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& x = p.x[i];
    for (int g : {p.species[i] == 1 ? 1 : 0, 2}) {
      n[g] += 1;
      sx[g] += x.x;
      sy[g] += x.y;
      s2[g] += x.x * x.x + x.y * x.y;
    }
  }
  auto spread = [&](int g) {
    if (n[g] == 0) return 0.0;
    const double mx = sx[g] / n[g], my = sy[g] / n[g];
    return s2[g] / n[g] - (mx * mx + my * my);
  };
  const double all = spread(2);
  return all > 0 ? (spread(1) - spread(0)) / all : 0;
}

std::vector<double> axial_profile(const Particles& p, const CylinderFrame& c) {
  const int n = c.slices();
  std::vector<double> vb(n, 0), va(n, 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int q = slice_of(p.x[i].z, c, n);
    const double v = volume(p.radius[i]);
    va[q] += v;
    if (p.species[i] == 1) vb[q] += v;
  }
  std::vector<double> out(n, -1.0);
  for (int q = 0; q < n; ++q)
    if (va[q] > 0) out[q] = vb[q] / va[q];
  return out;
}

namespace {
// Highest centre per (slice, column) cell for the species selected by `which` (0 small, 1 big,
// 2 both), averaged over slices; NaN where no slice has a particle in that column.
std::vector<double> column_heights(const Particles& p, const CylinderFrame& c, int which) {
  const int ns = c.slices(), nc = column_count(c);
  const double lowest = -std::numeric_limits<double>::infinity();
  std::vector<double> top(static_cast<std::size_t>(ns) * nc, lowest);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (which != 2 && p.species[i] != which) continue;
    double& t =
        top[static_cast<std::size_t>(slice_of(p.x[i].z, c, ns)) * nc + column_of(p.x[i].x, c, nc)];
    t = std::max(t, p.x[i].y);
  }
  std::vector<double> h(nc, std::numeric_limits<double>::quiet_NaN());
  for (int k = 0; k < nc; ++k) {
    double s = 0;
    int m = 0;
    for (int q = 0; q < ns; ++q) {
      const double t = top[static_cast<std::size_t>(q) * nc + k];
      if (t > lowest) s += t, ++m;
    }
    if (m > 0) h[k] = s / m;
  }
  return h;
}
}  // namespace

SurfaceFit fit_surface(const Particles& p, const CylinderFrame& c) {
  SurfaceFit fit;
  const std::vector<double> h = column_heights(p, c, 2);
  const int nc = static_cast<int>(h.size());
  int first = -1, last = -1;
  for (int k = 0; k < nc; ++k)
    if (!std::isnan(h[k])) {
      if (first < 0) first = k;
      last = k;
    }
  if (first < 0) return fit;
  // Inner 2/3 of the occupied span, away from the curved wall.
  const double x0 = -c.radius + first * c.slice, x1 = -c.radius + (last + 1) * c.slice;
  const double cut = (x1 - x0) / 6.0;
  fit.x_lo = x0 + cut;
  fit.x_hi = x1 - cut;
  double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int k = first; k <= last; ++k) {
    const double x = -c.radius + (k + 0.5) * c.slice;
    if (std::isnan(h[k]) || x < fit.x_lo || x > fit.x_hi) continue;
    sw += 1, sx += x, sy += h[k], sxx += x * x, sxy += x * h[k];
  }
  const double det = sw * sxx - sx * sx;
  if (sw < 2 || det <= 0) return fit;
  fit.slope = (sw * sxy - sx * sy) / det;
  fit.intercept = (sy - fit.slope * sx) / sw;
  fit.ok = true;
  return fit;
}

std::vector<double> radial_profile(const Particles& p, const CylinderFrame& c, const SurfaceFit& s,
                                   int bins) {
  std::vector<double> out(bins, -1.0);
  if (!s.ok) return out;
  // Unit vectors along the surface and normal to it (upwards) in the section plane.
  const double inv = 1.0 / std::sqrt(1 + s.slope * s.slope);
  const double tx = inv, ty = s.slope * inv, nx = -s.slope * inv, ny = inv;
  // Along-surface coordinates of the fitted range's ends, measured from (0, intercept).
  const double along_lo = s.x_lo * (tx + s.slope * ty), along_hi = s.x_hi * (tx + s.slope * ty);
  std::vector<double> vb(bins, 0), va(bins, 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double dx = p.x[i].x, dy = p.x[i].y - s.intercept;
    const double along = dx * tx + dy * ty;
    if (along < along_lo || along > along_hi) continue;
    const double depth = -(dx * nx + dy * ny);
    const int k = static_cast<int>(std::floor(depth / c.slice));
    if (k < 0 || k >= bins) continue;
    const double v = volume(p.radius[i]);
    va[k] += v;
    if (p.species[i] == 1) vb[k] += v;
  }
  for (int k = 0; k < bins; ++k)
    if (va[k] > 0) out[k] = vb[k] / va[k];
  return out;
}

int band_count(const std::vector<double>& profile, double mean_fraction, double threshold) {
  const int n = static_cast<int>(profile.size());
  int bands = 0, last = 0;
  for (int q = 0; q < n; ++q) {
    double s = 0;
    int m = 0;
    for (int k = std::max(q - 1, 0); k <= std::min(q + 1, n - 1); ++k)
      if (profile[k] >= 0) s += profile[k], ++m;
    if (m == 0) continue;
    const double dev = s / m - mean_fraction;
    const int sign = dev > threshold ? 1 : (dev < -threshold ? -1 : 0);
    if (sign != 0 && sign != last) {
      ++bands;
      last = sign;
    }
  }
  return bands;
}

SurfaceProfiles surface_profiles(const Particles& p, const CylinderFrame& c) {
  SurfaceProfiles out;
  out.large = column_heights(p, c, 1);
  out.small = column_heights(p, c, 0);
  for (std::size_t k = 0; k < out.large.size(); ++k)
    out.x.push_back(-c.radius + (k + 0.5) * c.slice);
  return out;
}

double large_volume_fraction(const Particles& p) {
  double vb = 0, va = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double v = volume(p.radius[i]);
    va += v;
    if (p.species[i] == 1) vb += v;
  }
  return va > 0 ? vb / va : 0;
}

void sample_cylinder(const Particles& p, const CylinderFrame& c, double time, double revolutions,
                     double kinetic_energy, CylinderSeries& out) {
  const std::vector<double> ax = axial_profile(p, c);
  const SurfaceFit fit = fit_surface(p, c);
  const int depth_bins = std::max(1, static_cast<int>(std::ceil(2 * c.radius / c.slice)));
  const std::vector<double> rad = radial_profile(p, c, fit, depth_bins);
  const SurfaceProfiles sp = surface_profiles(p, c);
  out.time.push_back(time);
  out.revolutions.push_back(revolutions);
  out.sa.push_back(axial_segregation(p, c));
  out.sr.push_back(radial_segregation_index(p));
  out.bands.push_back(band_count(ax, large_volume_fraction(p)));
  out.surface_slope.push_back(fit.ok ? fit.slope : std::numeric_limits<double>::quiet_NaN());
  out.kinetic_energy.push_back(kinetic_energy);
  out.axial.insert(out.axial.end(), ax.begin(), ax.end());
  out.radial.insert(out.radial.end(), rad.begin(), rad.end());
  out.surface_large.insert(out.surface_large.end(), sp.large.begin(), sp.large.end());
  out.surface_small.insert(out.surface_small.end(), sp.small.begin(), sp.small.end());
  out.surface_x = sp.x;
  out.axial_cols = static_cast<int>(ax.size());
  out.radial_cols = depth_bins;
  out.surface_cols = static_cast<int>(sp.x.size());
}

}  // namespace tumble::analysis
