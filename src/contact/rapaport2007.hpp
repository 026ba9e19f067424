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
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "base/error.hpp"
#include "base/vec3.hpp"
#include "scene/law_registry.hpp"
#include "scene/scene.hpp"

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

// The law as the engine and the scene layer see it (contact/laws.hpp lists the laws). It owns the
// keys below (MD units): k_n, γ_n, γ_s per species pair, μ_max (the largest μ; the others in the
// ratio of γ_s), k_g and the ratchet limit of |u|.
struct Rapaport2007Law {
  static constexpr const char* kName = "rapaport2007";
  using Pair = Rapaport2007Pair;
  static constexpr int kHistoryDoubles = 3;      // the accumulated displacement u, one Vec3
  using History = Vec3;                          // what force() takes, kHistoryDoubles doubles
  static constexpr unsigned kHistoryFlip = 0x7;  // seen from the other particle: all three negated

  static double kn(const Scene& s) { return s.law_value("contact.kn"); }
  static double gamma_n(const Scene& s) { return s.law_value("contact.gamma_n"); }
  static double gamma_s_ss(const Scene& s) { return s.law_value("contact.gamma_s_ss"); }
  static double gamma_s_sl(const Scene& s) { return s.law_value("contact.gamma_s_sl"); }
  static double gamma_s_ll(const Scene& s) { return s.law_value("contact.gamma_s_ll"); }
  static double mu_max(const Scene& s) { return s.law_value("contact.mu_max"); }
  static double kg(const Scene& s) { return s.law_value("contact.kg"); }
  static double ratchet(const Scene& s) { return s.law_value("contact.ratchet"); }

  // μ of a species pair is μ_max times its γ_s over the largest γ_s.
  static Pair make_pair(const Scene& s, int a, int b) {
    const double gs[2][2] = {{gamma_s_ss(s), gamma_s_sl(s)}, {gamma_s_sl(s), gamma_s_ll(s)}};
    const double gs_max = std::max({gamma_s_ss(s), gamma_s_sl(s), gamma_s_ll(s)});
    Pair c;
    c.kn = kn(s);
    c.gn = gamma_n(s);
    c.gs = gs[a][b];
    c.mu = gs_max > 0 ? mu_max(s) * gs[a][b] / gs_max : mu_max(s);
    c.kg = kg(s);
    c.ratchet = ratchet(s);
    return c;
  }
  // "The particle-wall values are identical": the walls use the like-species values.
  static Pair make_wall(const Scene& s, int a) { return make_pair(s, a, a); }
  static bool pair_friction(const Scene& s) {
    const double gs_max = std::max({gamma_s_ss(s), gamma_s_sl(s), gamma_s_ll(s)});
    return mu_max(s) > 0 && (gs_max > 0 || kg(s) > 0);
  }
  static bool wall_friction(const Scene& s) { return pair_friction(s); }

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

  // Time-step bound (scene/law_registry.hpp): k_n and γ_n are the same for every pair, so the
  // lightest particle against the wall (m_eff = m) is the stiffest mode, m the smallest mass of
  // either species.
  static double time_step_bound(const Scene& s) {
    const double ds = s.d_small - s.size_spread, dl = s.d_large - s.size_spread;
    const double m = s.density * kPi / 6.0 * std::min(ds * ds * ds, s.density_ratio * dl * dl * dl);
    return damped_time_step_bound(kn(s) / m, gamma_n(s) / (2.0 * m));
  }
  static double static_overlap(const Scene& s, double force) { return force / kn(s); }
  // The overlap scales as 1/k_n.
  static StifferHint stiffer(const Scene& s, double overlap) {
    return {"contact.kn", " >= ", kn(s) * overlap / kMaxWeightOverlap};
  }
  static void check(const Scene& s) {
    if (s.dt <= 0)
      throw InputError(
          "scene error: key 'time.dt' must be set (> 0) for contact.law = 'rapaport2007' (MD "
          "units, e.g. 5e-3)");
  }
  // Fields of the cached-bed key beyond the common ones (io/bed_io.cpp): exactly the text the
  // key had before the laws were split out, so cached beds keep their names.
  static std::string bed_key_fields(const Scene& s) {
    std::ostringstream os;
    os.precision(17);
    os << ";rap=" << kn(s) << "," << gamma_n(s) << "," << gamma_s_ss(s) << "," << gamma_s_sl(s)
       << "," << gamma_s_ll(s) << "," << mu_max(s) << "," << kg(s) << "," << ratchet(s) << ","
       << s.size_spread << "," << s.integrator;
    return os.str();
  }
  // The soft particles (k_n = 1000) press into the wall by up to half a radius (measured: 0.52 r
  // in run #E's bed): only the centre must be in.
  static double bed_wall_tolerance(const Scene&, double r) { return r; }

  static ContactLawSpec spec() {
    using K = KeySpec;
    ContactLawSpec l;
    l.name = kName;
    l.keys = {
        {"contact.kn", K::Real, 1e-9, 1e12, {}, "rapaport2007: normal stiffness k_n", 1000, kName},
        {"contact.gamma_n", K::Real, 0, 1e9, {}, "rapaport2007: normal damping gamma_n", 5, kName},
        {"contact.gamma_s_ss",
         K::Real,
         0,
         1e9,
         {},
         "rapaport2007: gamma_s small-small (and wall)",
         2,
         kName},
        {"contact.gamma_s_sl", K::Real, 0, 1e9, {}, "rapaport2007: gamma_s small-large", 2, kName},
        {"contact.gamma_s_ll",
         K::Real,
         0,
         1e9,
         {},
         "rapaport2007: gamma_s large-large (and wall)",
         10,
         kName},
        {"contact.mu_max",
         K::Real,
         0,
         2,
         {},
         "rapaport2007: friction of the pair with the largest gamma_s (others scale with gamma_s)",
         0.5,
         kName},
        {"contact.kg",
         K::Real,
         0,
         1e12,
         {},
         "rapaport2007: tangential restoring stiffness k_g",
         500,
         kName},
        {"contact.ratchet",
         K::Real,
         1e-12,
         1e6,
         {},
         "rapaport2007: |u| above which u resets to 0",
         0.1,
         kName},
    };
    // Provenance texts written before hertz_mindlin list these keys for every scene.
    l.keys_in_every_text = true;
    l.size_spread = true;
    l.time_step_bound = &time_step_bound;
    l.static_overlap = &static_overlap;
    l.stiffer = &stiffer;
    l.check = &check;
    return l;
  }
};

}  // namespace tumble::contact
