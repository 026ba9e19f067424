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
#include "scene/law_registry.hpp"
#include "scene/scene.hpp"

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

// The law as the engine and the scene layer see it (contact/laws.hpp lists the laws). Its
// parameters are the scene's contact.restitution, collision_time, friction, wall_friction and
// tangential_damping; it owns no key of its own.
struct Yu2022Law {
  static constexpr const char* kName = "yu2022";
  using Pair = Yu2022Pair;
  static constexpr int kHistoryDoubles = 3;      // the tangential spring β, one Vec3
  using History = Vec3;                          // what force() takes, kHistoryDoubles doubles
  static constexpr unsigned kHistoryFlip = 0x7;  // seen from the other particle: all three negated

  // Coefficients of species a against species b (0 small, 1 large): m_eff = m_a m_b / (m_a + m_b).
  static Pair make_pair(const Scene& s, int a, int b) {
    const double m[2] = {s.mass_small(), s.mass_large()};
    return yu2022_pair(s.restitution, s.collision_time, s.tangential_damping, s.friction,
                       m[a] * m[b] / (m[a] + m[b]));
  }
  // Species a against the wall: m_eff = m_a.
  static Pair make_wall(const Scene& s, int a) {
    const double m[2] = {s.mass_small(), s.mass_large()};
    return yu2022_pair(s.restitution, s.collision_time, s.tangential_damping, s.wall_friction,
                       m[a]);
  }
  // Whether the pair and the wall contacts have any tangential force (friction kernels).
  static bool pair_friction(const Scene& s) { return s.friction > 0; }
  static bool wall_friction(const Scene& s) { return s.wall_friction > 0; }

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

  // Time-step bound (scene/law_registry.hpp): the wall contact (m_eff = m) is the stiffest,
  // ω0² = (π/t_c)² + γ_n², γ = γ_n; pairs have k/m (m the lighter) smaller by m_eff / m_lighter.
  static double time_step_bound(const Scene& s) {
    const double gamma_n = -std::log(s.restitution) / s.collision_time;
    const double w2 = (kPi / s.collision_time) * (kPi / s.collision_time) + gamma_n * gamma_n;
    const double ms = s.mass_small(), ml = s.mass_large();
    double scale = 1;  // k/m relative to the wall contact's w2 (pairs: m_eff / lighter mass <= 1/2)
    for (double a : {ms, ml})
      for (double b : {ms, ml}) scale = std::max(scale, (a * b / (a + b)) / std::min(a, b));
    return damped_time_step_bound(scale * w2, scale * gamma_n);
  }
  // A small-small contact: k_n = [(π/t_c)² + γ_n²] m_s / 2.
  static double static_overlap(const Scene& s, double force) {
    const double gamma_n = -std::log(s.restitution) / s.collision_time;
    const double k = ((kPi / s.collision_time) * (kPi / s.collision_time) + gamma_n * gamma_n) *
                     0.5 * s.mass_small();
    return force / k;
  }
  // The overlap scales as 1/k ∝ t_c².
  static StifferHint stiffer(const Scene& s, double overlap) {
    return {"contact.collision_time",
            " <= ", s.collision_time * std::sqrt(kMaxWeightOverlap / overlap)};
  }
  // Fields of the cached-bed key beyond the common ones (io/bed_io.cpp): none (its parameters
  // are common keys, already in the key).
  static std::string bed_key_fields(const Scene&) { return ""; }
  // Settled beds press into the wall by up to the overlap the validator accepts.
  static double bed_wall_tolerance(const Scene& s, double r) {
    return std::max(0.1 * r, kMaxWeightOverlap * s.d_small);
  }

  static ContactLawSpec spec() {
    ContactLawSpec l;
    l.name = kName;
    l.time_from_collision_time = true;
    l.time_step_bound = &time_step_bound;
    l.static_overlap = &static_overlap;
    l.stiffer = &stiffer;
    return l;
  }
};

}  // namespace tumble::contact
