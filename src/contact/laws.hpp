#pragma once
// The contact laws as compile-time policies for the engine's kernels: each names its coefficient
// struct, its force kernel, its elastic energy and how the contact-point velocity and the torque
// lever are taken. The engine instantiates its pair and wall loops once per law, so no contact
// ever branches on which law is in use.
#include "contact/rapaport2007.hpp"
#include "contact/yu2022.hpp"

namespace tumble::contact {

struct Yu2022Law {
  using Pair = Yu2022Pair;
  // Contact history: the tangential spring, one Vec3 per contact (as LAMMPS's `dnum`).
  static constexpr int kHistoryDoubles = 3;
  // Lever arm of the contact point from the centre of a particle of radius r when the centres are
  // `dist` apart with radii summing to `rsum`: the radius (Yu 2022, as LAMMPS granular).
  static double lever(double r, double /*dist*/, double /*rsum*/) { return r; }
  template <bool kFriction>
  static Vec3 force(const Pair& p, const Vec3& n, double overlap, const Vec3& vrel, Vec3& history,
                    double dt, Vec3& ft) {
    return yu2022_force<kFriction>(p, n, overlap, vrel, history, dt, ft);
  }
  static double normal(const Pair& p, double overlap, double vn) {
    return p.kn * overlap - p.dn * vn;
  }
  static double elastic_energy(const Pair& p, double overlap, const Vec3& history) {
    return 0.5 * p.kn * overlap * overlap + 0.5 * p.kt * norm2(history);
  }
};

struct Rapaport2007Law {
  using Pair = Rapaport2007Pair;
  // Contact history: the tangential displacement u, one Vec3 per contact.
  static constexpr int kHistoryDoubles = 3;
  // Eq. 4 of Rapaport 2007: the contact point divides the centre line in the ratio of the
  // diameters, so the lever is r dist / rsum.
  static double lever(double r, double dist, double rsum) { return r * dist / rsum; }
  template <bool kFriction>
  static Vec3 force(const Pair& p, const Vec3& n, double overlap, const Vec3& vrel, Vec3& history,
                    double dt, Vec3& ft) {
    return rapaport2007_force<kFriction>(p, n, overlap, vrel, history, dt, ft);
  }
  static double normal(const Pair& p, double overlap, double vn) {
    return rapaport2007_normal(p, overlap, vn);
  }
  // The restoring force -k_g u stores k_g |u|^2 / 2 while it is below its cap.
  static double elastic_energy(const Pair& p, double overlap, const Vec3& history) {
    return 0.5 * p.kn * overlap * overlap + 0.5 * p.kg * norm2(history);
  }
};

}  // namespace tumble::contact
