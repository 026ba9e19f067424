#pragma once
// Yu et al. 2022, Appendix C: linear spring-dashpot normal force and a tangential spring with a
// Coulomb cap. One kernel for particle-particle and particle-wall contacts (walls use m_eff = m_i).
//
//   F_n = [k_n ζ − 2 γ_n m_eff (V·n)] n,     k_n = [(π/t_c)² + γ_n²] m_eff,   γ_n = −ln(e)/t_c
//   F_t = −(k_t β + 2 γ_t m_eff V_t), capped at μ|F_n|,  k_t = 2/7 k_n,  β = ∫ V_t dt from contact
//   start
//
// The paper leaves γ_t unspecified; it is a scene key (contact.tangential_damping, default 0).
// The spring β is projected into the current tangent plane every step and, when
// the Coulomb cap is active, replaced by the spring that gives exactly the capped force, so that
// sliding contacts do not store energy that a later unloading could release (no energy gain at
// grazing incidence).
#include <cmath>

#include "base/vec3.hpp"

namespace tumble::contact {

// Coefficients of one species pair (or species-wall pair), computed once per scene.
struct Yu2022Pair {
  double kn = 0;  // normal stiffness k_n [N/m]
  double dn = 0;  // normal damping 2 γ_n m_eff [kg/s]
  double kt = 0;  // tangential stiffness k_t = 2/7 k_n
  double dt = 0;  // tangential damping 2 γ_t m_eff
  double mu = 0;  // Coulomb friction coefficient
};

inline Yu2022Pair yu2022_pair(double restitution, double collision_time, double gamma_t, double mu,
                              double m_eff) {
  const double gamma_n = -std::log(restitution) / collision_time;
  const double w = kPi / collision_time;
  Yu2022Pair p;
  p.kn = (w * w + gamma_n * gamma_n) * m_eff;
  p.dn = 2.0 * gamma_n * m_eff;
  p.kt = 2.0 / 7.0 * p.kn;
  p.dt = 2.0 * gamma_t * m_eff;
  p.mu = mu;
  return p;
}

// Contact kernel. n points from the partner to particle i; `overlap` > 0; `vrel` is the velocity of
// i's contact point relative to the partner's. Returns the force on i; `spring` (β as seen from i)
// is updated in place. kFriction=false compiles the normal force only (μ = 0 scenes).
template <bool kFriction>
inline Vec3 yu2022_force(const Yu2022Pair& p, const Vec3& n, double overlap, const Vec3& vrel,
                         Vec3& spring, double dt, Vec3& ft) {
  const double vn = dot(vrel, n);
  const double fn_mag = p.kn * overlap - p.dn * vn;
  Vec3 force = fn_mag * n;
  if constexpr (kFriction) {
    const Vec3 vt = vrel - vn * n;
    // Rotate the stored spring into the current tangent plane by projection. Between two steps
    // the normal turns by ~|V_t| δt / r (< 1e-3 rad), so the projection shortens the spring by a
    // relative ~1e-7 per step: as LAMMPS gran/hooke/history and LIGGGHTS, no rescaling (it would
    // cost a sqrt and a division per contact per step).
    spring -= dot(spring, n) * n;
    spring += dt * vt;
    ft = -(p.kt * spring + p.dt * vt);
    const double ft2 = norm2(ft);
    const double cap = p.mu * std::fabs(fn_mag);
    if (ft2 > cap * cap) {
      ft *= cap / std::sqrt(ft2);
      // Store the spring consistent with the capped force (sliding).
      spring = (-1.0 / p.kt) * (ft + p.dt * vt);
    }
    force += ft;
  } else {
    (void)spring;
    (void)dt;
    ft = Vec3{};
  }
  return force;
}

}  // namespace tumble::contact
