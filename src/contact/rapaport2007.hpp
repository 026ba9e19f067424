#pragma once
// Rapaport 2007 (Phys. Rev. E 75, 031301), Sec. II: the granular force of the rotating-cylinder
// study, in its MD units. For a pair with overlap d_ij - r_ij > 0:
//
//   f_v = k_n (d_ij - r_ij) r̂            linear repulsion, the same k_n for every pair
//   f_d = -γ_n (r̂·v_ij) r̂                normal damping, the same γ_n for every pair
//   f_s = -min(γ_s |v_s|, μ |f_n|) v̂_s    frictional damping, γ_s and μ per species pair
//   f_g = -k_g u,  |f_g| <= μ |f_n|       tangential restoring force, u = ∫ v_s dτ over the
//   contact,
//                                         reset to 0 when |u| > 0.1 (the paper's ratchet)
//
// with f_n = f_v + f_d and the surface velocity v_s = v_ij - (r̂·v_ij) r̂ - ((d_i ω_i + d_j ω_j) /
// (d_i + d_j)) × r_ij (Eq. 4: the contact point divides r_ij in the ratio of the diameters, so the
// lever arms are d_i r_ij / (d_i + d_j), slightly shorter than the radii while particles overlap).
// u is accumulated as the paper says, a plain sum of v_s δt (no rotation into the tangent plane):
// the ratchet bounds it. The transverse force is f_t = f_s + f_g, each term capped on its own.
// Walls use the same terms (the curved wall, "rough"); smooth end caps use f_v + f_d only.
#include <cmath>

#include "base/vec3.hpp"

namespace tumble::contact {

struct Rapaport2007Pair {
  double kn = 0;       // k_n, normal stiffness
  double gn = 0;       // γ_n, normal damping
  double gs = 0;       // γ_s of this species pair, frictional damping
  double mu = 0;       // μ of this species pair (Coulomb cap of f_s and f_g)
  double kg = 0;       // k_g, tangential restoring stiffness (0: the paper's runs #M, #N, #O)
  double ratchet = 0;  // |u| above which u is reset to 0 (the paper's 0.1)
};

// Normal force only: the smooth end caps (f_v + f_d). n points from the partner into the particle.
inline double rapaport2007_normal(const Rapaport2007Pair& p, double overlap, double vn) {
  return p.kn * overlap - p.gn * vn;
}

// Full contact kernel, the same interface as yu2022_force: `vs_in` is the relative velocity of the
// contact points (rotation included), `u` the accumulated displacement (updated in place); returns
// the force on i and sets ft, its transverse part. kFriction = false compiles f_v + f_d only.
template <bool kFriction>
inline Vec3 rapaport2007_force(const Rapaport2007Pair& p, const Vec3& n, double overlap,
                               const Vec3& vrel, Vec3& u, double dt, Vec3& ft) {
  const double vn = dot(vrel, n);
  const double fn_mag = rapaport2007_normal(p, overlap, vn);
  Vec3 force = fn_mag * n;
  if constexpr (kFriction) {
    const Vec3 vs = vrel - vn * n;
    const double cap = p.mu * std::fabs(fn_mag);
    ft = Vec3{};
    const double vs2 = norm2(vs);
    if (vs2 > 0) {
      const double vs_mag = std::sqrt(vs2);
      const double fs_mag = std::fmin(p.gs * vs_mag, cap);
      ft = (-fs_mag / vs_mag) * vs;
    }
    u += dt * vs;
    if (norm2(u) > p.ratchet * p.ratchet) u = Vec3{};  // the ratchet
    const double fg2 = p.kg * p.kg * norm2(u);
    if (fg2 > 0) {
      const double scale = fg2 > cap * cap ? cap / std::sqrt(fg2) : 1.0;
      ft -= (scale * p.kg) * u;
    }
    force += ft;
  } else {
    (void)u;
    (void)dt;
    ft = Vec3{};
  }
  return force;
}

}  // namespace tumble::contact
