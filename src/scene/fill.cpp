#include "scene/fill.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "base/error.hpp"

namespace tumble {

// Placement: a cubic lattice of sites of side 1.02 d_large covers the tumbler; a site holds one
// large particle or a k x k x k block of small ones (slots). Sites are visited bottom first and
// filled until every particle is placed, so the bed starts near its final shape and settles in a
// fraction of a second. Slots and large particles must lie inside the sphere individually, so the
// curved wall is filled down to the size of the small particles.
BedPlan plan_bed(const Scene& s) {
  BedPlan plan;
  const double R = s.radius;
  const double v_small = kPi / 6.0 * std::pow(s.d_small, 3);
  const double v_large = kPi / 6.0 * std::pow(s.d_large, 3);
  const double v_solid = s.packing_fraction * s.fill_level * 4.0 / 3.0 * kPi * R * R * R;
  plan.n_large = std::llround(s.large_fraction * v_solid / v_large);
  plan.n_small = std::llround((1.0 - s.large_fraction) * v_solid / v_small);

  const double a = 1.02 * s.d_large;
  const int k = std::max(1, static_cast<int>(std::floor(a / (1.01 * s.d_small))));
  const double sub = a / k;
  plan.site = a;
  plan.small_per_side = k;
  const double reach_large = R - 0.51 * s.d_large;
  const double reach_small = R - 0.51 * s.d_small;

  std::vector<Vec3> sites;
  const int m = static_cast<int>(std::ceil(R / a));
  for (int i = -m; i < m; ++i)
    for (int j = -m; j < m; ++j)
      for (int l = -m; l < m; ++l) {
        const Vec3 c{(i + 0.5) * a, (j + 0.5) * a, (l + 0.5) * a};
        if (norm(c) < reach_small + 0.87 * a) sites.push_back(c);
      }
  // Bottom first (gravity is -y); ties broken by x then z so the order is fully determined.
  std::sort(sites.begin(), sites.end(), [](const Vec3& p, const Vec3& q) {
    if (p.y != q.y) return p.y < q.y;
    if (p.x != q.x) return p.x < q.x;
    return p.z < q.z;
  });

  Rng rng(static_cast<std::uint64_t>(s.seed));
  std::int64_t large_left = plan.n_large, small_left = plan.n_small;
  // For the "large_top" start the small particles go first, so the large ones end up on top.
  const bool small_first = s.start == Start::large_top;
  const double k3 = static_cast<double>(k) * k * k;
  std::vector<Vec3> smalls;
  for (const Vec3& c : sites) {
    if (large_left == 0 && small_left == 0) break;
    const bool fits_large = norm(c) < reach_large;
    bool put_large = false;
    if (fits_large && large_left > 0) {
      if (s.start == Start::mixed)  // chance proportional to the sites each species still needs
        put_large = rng.uniform() * (large_left + small_left / k3) < large_left;
      else if (s.start == Start::large_xneg)
        put_large = c.x < 0 || small_left == 0;
      else
        put_large = small_left == 0;
    }
    if (small_first && small_left > 0) put_large = false;
    if (put_large) {
      plan.position.push_back(c);
      plan.species.push_back(1);
      --large_left;
      continue;
    }
    for (int x = 0; x < k && small_left > 0; ++x)
      for (int y = 0; y < k && small_left > 0; ++y)
        for (int z = 0; z < k && small_left > 0; ++z) {
          const Vec3 q = c + Vec3{(x + 0.5) * sub - 0.5 * a, (y + 0.5) * sub - 0.5 * a,
                                  (z + 0.5) * sub - 0.5 * a};
          if (norm(q) < reach_small) {
            smalls.push_back(q);
            --small_left;
          }
        }
  }
  if (large_left > 0 || small_left > 0) {
    std::ostringstream os;
    os << "scene error: the bed does not fit in the tumbler: " << plan.n_large << " large and "
       << plan.n_small << " small particles (particles.fill_level = " << s.fill_level
       << ", particles.packing_fraction = " << s.packing_fraction << "), " << large_left
       << " large and " << small_left
       << " small left over once the loose start lattice fills the tumbler; lower "
          "particles.fill_level or particles.packing_fraction, or enlarge tumbler.radius";
    throw InputError(os.str());
  }
  for (const Vec3& q : smalls) {
    plan.position.push_back(q);
    plan.species.push_back(0);
  }
  return plan;
}

std::int64_t planned_particle_count(const Scene& s) {
  if (s.cylinder()) return s.count;
  const BedPlan plan = plan_bed(s);
  return plan.n_large + plan.n_small;
}

void set_species_properties(const Scene& s, Particles& p) {
  const double ms = s.mass_small(), ml = s.mass_large();
  const double rho[2] = {s.density, s.density * s.density_ratio};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool large = p.species[i] == 1;
    double m = large ? ml : ms;
    if (s.size_spread > 0) {  // polydisperse: the radius is the particle's own
      const double d = 2.0 * p.radius[i];
      m = rho[large ? 1 : 0] * kPi / 6.0 * d * d * d;
    } else {
      p.radius[i] = 0.5 * (large ? s.d_large : s.d_small);
    }
    p.inv_mass[i] = 1.0 / m;
    p.inv_inertia[i] = 1.0 / (0.4 * m * p.radius[i] * p.radius[i]);
  }
}

Particles make_bed(const Scene& s) {
  const BedPlan plan = plan_bed(s);
  // The jitter draws continue the plan's stream from a second, independent generator.
  Rng rng(static_cast<std::uint64_t>(s.seed) ^ 0xA5A5A5A5DEADBEEFull);
  const double sub = plan.site / plan.small_per_side;
  const double slack[2] = {0.45 * (sub - s.d_small), 0.45 * (plan.site - s.d_large)};
  const double reach[2] = {s.radius - 0.5 * s.d_small, s.radius - 0.5 * s.d_large};
  Particles p;
  p.resize(plan.position.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int sp = plan.species[i];
    const double amp = slack[sp];
    Vec3 x = plan.position[i] + Vec3{amp * (2 * rng.uniform() - 1), amp * (2 * rng.uniform() - 1),
                                     amp * (2 * rng.uniform() - 1)};
    if (norm(x) >= reach[sp]) x = plan.position[i];  // jitter never pushes into the wall
    p.x[i] = x;
    p.species[i] = sp;
    p.id[i] = static_cast<std::int64_t>(i);
  }
  set_species_properties(s, p);
  return p;
}

}  // namespace tumble
