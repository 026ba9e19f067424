#include "cm/integrator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tumble::cm {
namespace {

// Dormand & Prince (1980) RK5(4)7M tableau (the field is autonomous: no stage times needed).
constexpr double a21 = 1.0 / 5;
constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561,
                 a54 = -212.0 / 729;
constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                 a65 = -5103.0 / 18656;
constexpr double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784,
                 b6 = 11.0 / 84;
// b - b* (difference of the 5th- and 4th-order weights), for the error estimate.
constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200,
                 e6 = 22.0 / 525, e7 = -1.0 / 40;

struct Step {
  Vec3 p;
  double err;
};

// One step with the smooth field of one region (the field is autonomous).
template <class Field>
Step dp_step(const Vec3& p, double h, const Field& f, double tol) {
  const Vec3 k1 = f(p);
  const Vec3 k2 = f(p + h * a21 * k1);
  const Vec3 k3 = f(p + h * (a31 * k1 + a32 * k2));
  const Vec3 k4 = f(p + h * (a41 * k1 + a42 * k2 + a43 * k3));
  const Vec3 k5 = f(p + h * (a51 * k1 + a52 * k2 + a53 * k3 + a54 * k4));
  const Vec3 k6 = f(p + h * (a61 * k1 + a62 * k2 + a63 * k3 + a64 * k4 + a65 * k5));
  const Vec3 out = p + h * (b1 * k1 + b3 * k3 + b4 * k4 + b5 * k5 + b6 * k6);
  const Vec3 k7 = f(out);
  const Vec3 e = h * (e1 * k1 + e3 * k3 + e4 * k4 + e5 * k5 + e6 * k6 + e7 * k7);
  double err = 0;
  for (int i = 0; i < 3; ++i) err = std::max(err, std::abs(e[i]) / (tol * (1 + std::abs(p[i]))));
  return {out, err};
}

// Step length h* in (0, h] at which g = y + delta crosses zero, by the Illinois variant of
// regula falsi on g(step(p, h)); the step error at h* <= h is within tolerance already.
template <class Field>
double locate_event(const Vec3& p, double h, double g0, double g1, const Field& f, double eps,
                    double tol) {
  double lo = 0, hi = h, glo = g0, ghi = g1;
  int side = 0;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * (1 + h); ++it) {
    const double m = (lo * ghi - hi * glo) / (ghi - glo);
    const double gm = height_above_interface(dp_step(p, m, f, tol).p, eps);
    if ((gm > 0) == (glo > 0)) {
      lo = m, glo = gm;
      if (side == -1) ghi *= 0.5;
      side = -1;
    } else {
      hi = m, ghi = gm;
      if (side == +1) glo *= 0.5;
      side = +1;
    }
    if (gm == 0) return m;
  }
  return hi;  // the far side: the point has crossed
}

}  // namespace

Vec3 flow_z_integrated(const Vec3& p0, double t, double eps, const IntegratorOptions& opt,
                       IntegratorStats* stats) {
  const auto bulk = [](const Vec3& q) { return bulk_velocity(q); };
  const auto layer = [eps](const Vec3& q) { return layer_velocity(q, eps); };
  Vec3 p = p0;
  bool in_fl = in_layer(p, eps);
  double left = t, h = opt.h_initial;
  IntegratorStats local;
  while (left > 0) {
    if (++local.steps > opt.max_steps)
      throw std::runtime_error("flow_z_integrated: too many steps");
    h = std::min(h, left);
    const Step s = in_fl ? dp_step(p, h, layer, opt.tol) : dp_step(p, h, bulk, opt.tol);
    if (s.err > 1.0) {
      ++local.rejected;
      h *= std::max(0.2, 0.9 * std::pow(s.err, -0.2));
      continue;
    }
    const double g0 = height_above_interface(p, eps), g1 = height_above_interface(s.p, eps);
    // A crossing is a sign change to the other region's side; g0 on the wrong side by round-off
    // right after a switch is not a new crossing.
    const bool crossed = in_fl ? (g1 < 0 && g0 >= 0) : (g1 >= 0 && g0 < 0);
    if (crossed) {
      const double hs = in_fl ? locate_event(p, h, g0, g1, layer, eps, opt.tol)
                              : locate_event(p, h, g0, g1, bulk, eps, opt.tol);
      p = in_fl ? dp_step(p, hs, layer, opt.tol).p : dp_step(p, hs, bulk, opt.tol).p;
      left -= hs;
      in_fl = !in_fl;
      ++local.events;
      continue;  // keep h: the new field is as smooth as the old one
    }
    p = s.p;
    left -= h;
    h *= std::min(5.0, 0.9 * std::pow(std::max(s.err, 1e-10), -0.2));
  }
  if (stats) *stats = local;
  return p;
}

}  // namespace tumble::cm
