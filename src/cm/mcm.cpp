#include "cm/mcm.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cm/exact_map.hpp"
#include "cm/shell_chart.hpp"

namespace tumble::cm {

Vec3 mcm_flow_z(const Vec3& p0, double t, double eps, double q, const DriftGrid& grid,
                const McmOptions& opt, std::mt19937_64& rng) {
  Vec3 p = p0;
  bool layer = in_layer(p, eps);
  double left = t;
  const double zmax = q * (1 - 1e-12);
  for (int guard = 0; left > 0 && guard < 10000000; ++guard) {
    if (!layer) {
      const BulkEntry e = bulk_entry(p, eps);
      if (left < e.time) return rotate_bulk(p, left);
      left -= e.time;
      p = layer_point(e.a, 0.0, p.z(), eps);
      layer = true;
      continue;
    }
    LayerCoords lc = layer_coords(p, eps);
    double z = p.z();
    // Step through the layer transit; drift and kicks are evaluated at the start of a step.
    while (left > 0) {
      const double h = std::min({opt.dt, eps * (kPi - lc.s), left});
      if (h <= 0) break;
      const double x = -lc.a * std::cos(lc.s);
      double dz = opt.drift ? grid.v(x, z) * h : 0.0;
      if (opt.c != 0) {
        const double sign = (rng() & 1u) ? 1.0 : -1.0;
        dz += opt.c * sign * grid.sigma(x, z) * std::sqrt(opt.dt_ref * h);
      }
      lc.s += h / eps;
      z = std::clamp(z + dz, -zmax, zmax);
      lc.a = std::sqrt(std::max(q * q - z * z, 0.0));
      left -= h;
    }
    if (lc.s < kPi * (1 - 1e-14) || left <= 0)
      return layer_point(lc.a, std::min(lc.s, kPi), z, eps);
    p = {lc.a, -layer_depth(lc.a, z, eps), z};  // transit done: back into the bulk
    layer = false;
  }
  return p;
}

McmResult run_mcm(const Protocol& pr, const DriftGrid& grid, const McmOptions& opt,
                  const Progress& progress) {
  const ShellChart chart(opt.r, pr.eps);
  std::mt19937_64 rng(opt.seed);
  McmResult res;
  res.initial = chart.random_seeds(opt.tracers, rng);
  std::vector<Vec3> x = res.initial;
  const int last = std::max(opt.snapshot, opt.cumulative_to);
  // Reserved whole: growing by doubling would need up to three times the records at a copy.
  const std::size_t records = static_cast<std::size_t>(mcm_cumulative_records(opt)) * x.size();
  res.cumulative.reserve(records);
  res.cumulative_iteration.reserve(records);
  const auto phase = [&](Axis a, const Vec3& p) {
    const Vec3 f = to_frame(a, p);
    return to_lab(a, mcm_flow_z(f, pr.theta(a), pr.eps, chart.footprint(), grid, opt, rng));
  };
  const double work = std::max(1.0, static_cast<double>(last) * x.size());
  // The positions after n iterations, where the options ask for them (n = 0: the seeds; --snapshot
  // 0 gave an empty snapshot and --cumulative 0,N began at 1).
  const auto record = [&](int n) {
    if (n == opt.snapshot) res.snapshot = x;
    if (n >= opt.cumulative_from && n <= opt.cumulative_to &&
        (n - opt.cumulative_from) % std::max(opt.cumulative_stride, 1) == 0) {
      res.cumulative.insert(res.cumulative.end(), x.begin(), x.end());
      res.cumulative_iteration.insert(res.cumulative_iteration.end(), x.size(), n);
    }
  };
  record(0);
  for (int n = 1; n <= last; ++n) {
    for (std::size_t k = 0; k < x.size(); ++k) {
      x[k] = phase(Axis::X, phase(Axis::Z, x[k]));
      if ((k & 255) == 255) report(progress, ((n - 1.0) * x.size() + k + 1) / work);
    }
    report(progress, n * static_cast<double>(x.size()) / work);
    record(n);
  }
  return res;
}

int mcm_cumulative_records(const McmOptions& opt) {
  if (opt.cumulative_to < opt.cumulative_from) return 0;
  return (opt.cumulative_to - opt.cumulative_from) / std::max(opt.cumulative_stride, 1) + 1;
}

double mcm_memory_bytes(const McmOptions& opt) {
  const double tracers = opt.tracers;
  return tracers * (3 * sizeof(Vec3) + mcm_cumulative_records(opt) * (28.0 + 60.0));
}

double mcm_peclet(const DriftGrid& grid, const McmOptions& opt, double island_length) {
  const double v = opt.drift ? grid.mean_abs_v() : 0.0;
  const double d = std::pow(opt.c * grid.mean_sigma(), 2) * opt.dt_ref;
  if (d > 0) return island_length * v / d;
  return v > 0 ? INFINITY : NAN;  // no diffusion: drift wins; neither: undefined
}

std::string peclet_text(double peclet) {
  if (std::isnan(peclet)) return "none";
  if (std::isinf(peclet)) return peclet > 0 ? "infinite" : "-infinite";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", peclet);
  return buf;
}

}  // namespace tumble::cm
