#pragma once
// Hertz-Mindlin (no-slip) with viscoelastic damping from the restitution coefficient, as LIGGGHTS'
// `pair_style gran model hertz tangential history` (Di Renzo & Di Maio 2004, Chem. Eng. Sci. 59,
// 525; LIGGGHTS normal_model_hertz.h and tangential_model_history.h). For a contact with overlap δ,
// effective mass m* (m_i for a wall), effective radius R* = r_i r_j / (r_i + r_j) (r_i for a wall),
// and the material's Young's modulus Y and Poisson ratio ν (the wall is of the particles'
// material):
//
//   Y* = 1 / ((1-ν_i²)/Y_i + (1-ν_j²)/Y_j),   G* = 1 / (2(2-ν_i)(1+ν_i)/Y_i + 2(2-ν_j)(1+ν_j)/Y_j)
//   S_n = 2 Y* sqrt(R* δ),   S_t = 8 G* sqrt(R* δ)
//   k_n = 4/3 Y* sqrt(R* δ)                 F_n = [k_n δ - γ_n (V·n)] n   (Hertz: F ∝ δ^{3/2})
//   k_t = S_t                               F_t = -(k_t ξ + γ_t V_t), |F_t| <= μ |F_n|
//   β = ln e / sqrt(ln² e + π²),   γ_n = -2 sqrt(5/6) β sqrt(S_n m*),   γ_t = -2 sqrt(5/6) β
//   sqrt(S_t m*)
//
// ξ = ∫ V_t dt is the tangential displacement since the contact began (the history, one Vec3 as
// the Yu law's spring). With these coefficients the damped Hertz oscillator
// m* δ'' = -4/3 Y* sqrt(R*) δ^{3/2} - γ_n δ' depends on β alone once scaled; integrated
// accurately (tests/test_hertz_mindlin.cpp) its restitution equals e to better than 1e-6 for
// e in [0.05, 0.99], so the DEM's deviation from e is its time discretisation only.
//
// Two choices differ from LIGGGHTS, both shared with the Yu kernel (contact/yu2022.hpp): the
// Coulomb cap applies to the whole tangential force (spring and damping), and a capped contact
// stores the spring that gives exactly the capped force. LIGGGHTS caps the spring alone and drops
// the damping while sliding, which gives the same |F_t| = μ|F_n| when sliding but lets the damping
// exceed the cap while sticking. The lever arm is the radius, as the Yu law.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "base/error.hpp"
#include "base/vec3.hpp"
#include "scene/law_registry.hpp"
#include "scene/scene.hpp"

namespace tumble::contact {

// Coefficients of one species pair (or species-wall pair), computed once per scene; the powers of
// δ are taken per contact.
struct HertzMindlinPair {
  double kn = 0;  // 4/3 Y* sqrt(R*): elastic normal force kn δ^{3/2}
  double kt = 0;  // 8 G* sqrt(R*): tangential stiffness kt δ^{1/2}
  double gn = 0;  // -2 sqrt(5/6) β sqrt(2 Y* sqrt(R*) m*): normal damping gn δ^{1/4}
  double gt = 0;  // -2 sqrt(5/6) β sqrt(8 G* sqrt(R*) m*): tangential damping gt δ^{1/4}
  double mu = 0;  // Coulomb friction coefficient
};

// One material (Y, ν) on both sides, restitution e, Coulomb μ, effective mass and radius.
inline HertzMindlinPair hertz_mindlin_pair(double youngs, double poisson, double restitution,
                                           double mu, double m_eff, double r_eff) {
  const double y_eff = 1.0 / (2.0 * (1.0 - poisson * poisson) / youngs);
  const double g_eff = 1.0 / (2.0 * 2.0 * (2.0 - poisson) * (1.0 + poisson) / youngs);
  const double log_e = std::log(restitution);
  const double beta = log_e / std::sqrt(log_e * log_e + kPi * kPi);
  const double sqrt_five_sixths = std::sqrt(5.0 / 6.0);
  const double sqrt_r = std::sqrt(r_eff);
  HertzMindlinPair p;
  p.kn = 4.0 / 3.0 * y_eff * sqrt_r;
  p.kt = 8.0 * g_eff * sqrt_r;
  p.gn = -2.0 * sqrt_five_sixths * beta * std::sqrt(2.0 * y_eff * sqrt_r * m_eff);
  p.gt = -2.0 * sqrt_five_sixths * beta * std::sqrt(p.kt * m_eff);
  p.mu = mu;
  return p;
}

// Normal force only (the smooth end caps): kn δ^{3/2} - gn δ^{1/4} vn.
inline double hertz_mindlin_normal(const HertzMindlinPair& p, double overlap, double vn) {
  const double root = std::sqrt(overlap);
  return p.kn * overlap * root - p.gn * std::sqrt(root) * vn;
}

// Contact kernel, the interface of yu2022_force: n points from the partner to particle i;
// `vrel` is the velocity of i's contact point relative to the partner's; `xi` the tangential
// displacement (updated in place). Returns the force on i and sets ft, its tangential part.
template <bool kFriction>
inline Vec3 hertz_mindlin_force(const HertzMindlinPair& p, const Vec3& n, double overlap,
                                const Vec3& vrel, Vec3& xi, double dt, Vec3& ft) {
  const double root = std::sqrt(overlap);  // δ^{1/2}
  const double root4 = std::sqrt(root);    // δ^{1/4}
  const double vn = dot(vrel, n);
  const double fn_mag = p.kn * overlap * root - p.gn * root4 * vn;
  Vec3 force = fn_mag * n;
  if constexpr (kFriction) {
    const Vec3 vt = vrel - vn * n;
    const double kt = p.kt * root, gt = p.gt * root4;
    xi -= dot(xi, n) * n;  // into the current tangent plane (as LIGGGHTS; see yu2022_force)
    xi += dt * vt;
    ft = -(kt * xi + gt * vt);
    const double ft2 = norm2(ft);
    const double cap = p.mu * std::fabs(fn_mag);
    if (ft2 > cap * cap) {
      ft *= cap / std::sqrt(ft2);
      xi = (-1.0 / kt) * (ft + gt * vt);  // the displacement of the capped force (sliding)
    }
    force += ft;
  } else {
    (void)xi;
    (void)dt;
    ft = Vec3{};
  }
  return force;
}

// The law as the engine and the scene layer see it (contact/laws.hpp lists the laws). Shared keys:
// contact.restitution, friction, wall_friction; its own keys below.
struct HertzMindlinLaw {
  static constexpr const char* kName = "hertz_mindlin";
  using Pair = HertzMindlinPair;
  static constexpr int kHistoryDoubles = 3;      // the tangential displacement ξ, one Vec3
  using History = Vec3;                          // what force() takes, kHistoryDoubles doubles
  static constexpr unsigned kHistoryFlip = 0x7;  // seen from the other particle: all three negated

  static constexpr const char* kYoungsKey = "contact.youngs_modulus";
  static constexpr const char* kPoissonKey = "contact.poisson_ratio";
  static constexpr const char* kImpactKey = "contact.max_impact_speed";
  static double youngs(const Scene& s) { return s.law_value(kYoungsKey); }
  static double poisson(const Scene& s) { return s.law_value(kPoissonKey); }

  static Pair make_pair(const Scene& s, int a, int b) {
    const double m[2] = {s.mass_small(), s.mass_large()};
    const double r[2] = {0.5 * s.d_small, 0.5 * s.d_large};
    return hertz_mindlin_pair(youngs(s), poisson(s), s.restitution, s.friction,
                              m[a] * m[b] / (m[a] + m[b]), r[a] * r[b] / (r[a] + r[b]));
  }
  // A flat wall of the particles' material: m* = m_a, R* = r_a.
  static Pair make_wall(const Scene& s, int a) {
    const double m[2] = {s.mass_small(), s.mass_large()};
    const double r[2] = {0.5 * s.d_small, 0.5 * s.d_large};
    return hertz_mindlin_pair(youngs(s), poisson(s), s.restitution, s.wall_friction, m[a], r[a]);
  }
  static bool pair_friction(const Scene& s) { return s.friction > 0; }
  static bool wall_friction(const Scene& s) { return s.wall_friction > 0; }

  static double lever(double r, double /*dist*/, double /*rsum*/) { return r; }
  template <bool kFriction>
  static Vec3 force(const Pair& p, const Vec3& n, double overlap, const Vec3& vrel, Vec3& history,
                    double dt, Vec3& ft) {
    return hertz_mindlin_force<kFriction>(p, n, overlap, vrel, history, dt, ft);
  }
  static double normal(const Pair& p, double overlap, double vn) {
    return hertz_mindlin_normal(p, overlap, vn);
  }
  // ∫ kn δ^{3/2} dδ = 2/5 kn δ^{5/2}; the tangential spring k_t |ξ|² / 2 at the current k_t.
  static double elastic_energy(const Pair& p, double overlap, const Vec3& history) {
    const double root = std::sqrt(overlap);
    return 0.4 * p.kn * overlap * overlap * root + 0.5 * p.kt * root * norm2(history);
  }

  // Time-step bound (scene/law_registry.hpp). A Hertz contact stiffens as it is pressed: its
  // tangent stiffness is S_n = dF/dδ = 2 Y* sqrt(R* δ). The bound uses S_n and γ_n at the largest
  // overlap of a head-on impact at contact.max_impact_speed v (the undamped Hertz maximum,
  // δ_max = (15 m* v² / (16 Y* sqrt(R*)))^{2/5}), for every pair and wall contact (ω0² = S_n / m,
  // γ = γ_n / 2m, m the lighter partner), and returns the smallest.
  static double time_step_bound(const Scene& s) {
    const double v = s.law_value(kImpactKey);
    const double m[2] = {s.mass_small(), s.mass_large()};
    const double r[2] = {0.5 * s.d_small, 0.5 * s.d_large};
    const double y_eff = youngs(s) / (2.0 * (1.0 - poisson(s) * poisson(s)));
    auto bound = [&](double m_eff, double r_eff, double m_light, const Pair& p) {
      const double overlap =
          std::pow(15.0 * m_eff * v * v / (16.0 * y_eff * std::sqrt(r_eff)), 0.4);
      const double stiffness = 2.0 * y_eff * std::sqrt(r_eff * overlap);
      const double damping = p.gn * std::pow(overlap, 0.25);
      return damped_time_step_bound(stiffness / m_light, damping / (2.0 * m_light));
    };
    double dt = 1e300;
    for (int a = 0; a < 2; ++a) {
      dt = std::min(dt, bound(m[a], r[a], m[a], make_wall(s, a)));
      for (int b = 0; b < 2; ++b)
        dt = std::min(dt, bound(m[a] * m[b] / (m[a] + m[b]), r[a] * r[b] / (r[a] + r[b]),
                                std::min(m[a], m[b]), make_pair(s, a, b)));
    }
    return dt;
  }
  // A small-small contact pressed by `force`: δ = (force / (4/3 Y* sqrt(R*)))^{2/3}.
  static double static_overlap(const Scene& s, double force) {
    return std::pow(force / make_pair(s, 0, 0).kn, 2.0 / 3.0);
  }
  // The static overlap scales as Y^{-2/3}.
  static StifferHint stiffer(const Scene& s, double overlap) {
    return {kYoungsKey, " >= ", youngs(s) * std::pow(overlap / kMaxWeightOverlap, 1.5)};
  }
  static void check(const Scene& s) {
    if (s.dt <= 0)
      throw InputError(
          "scene error: key 'time.dt' must be set (> 0) for contact.law = 'hertz_mindlin' (its "
          "stiffness comes from contact.youngs_modulus, not from contact.collision_time)");
  }
  static std::string bed_key_fields(const Scene& s) {
    std::ostringstream os;
    os.precision(17);
    os << ";hm=" << youngs(s) << "," << poisson(s);
    return os.str();
  }
  static double bed_wall_tolerance(const Scene& s, double r) {
    return std::max(0.1 * r, kMaxWeightOverlap * s.d_small);
  }

  static ContactLawSpec spec() {
    using K = KeySpec;
    ContactLawSpec l;
    l.name = kName;
    l.keys = {
        {kYoungsKey,
         K::Real,
         1e3,
         1e12,
         {},
         "hertz_mindlin: Young's modulus Y of particles and walls [Pa] (DEM practice: reduced, "
         "as LIGGGHTS' examples' 5e6)",
         5e6,
         kName},
        {kPoissonKey, K::Real, 0, 0.5, {}, "hertz_mindlin: Poisson ratio nu", 0.3, kName},
        {kImpactKey,
         K::Real,
         1e-6,
         1e3,
         {},
         "hertz_mindlin: largest expected impact speed [m/s] (sets the stiffness of the "
         "time-step bound)",
         1,
         kName},
    };
    l.time_step_bound = &time_step_bound;
    l.static_overlap = &static_overlap;
    l.stiffer = &stiffer;
    l.check = &check;
    return l;
  }
};

}  // namespace tumble::contact
